#include "core/app.h"

#include <iostream>
#include <limits>

#include "core/fs.h"
#include "core/log.h"
#include "core/number.h"
#include "core/parallel.h"
#include "core/validators.h"

namespace inlight::app {

void setup(CLI::App& app, CommonArgs& common, const std::string& example) {
    app.add_flag_callback(
        "--version",
        [&app]() {
            std::cout << app.get_name() << " " << version_string() << "\n";
            throw CLI::Success();
        },
        "Print the version and exit");
    app.set_config("--config", "", "TOML file of options; keys are long option names (e.g. "
                                   "threads = 2); flags given on the command line override it");
    app.allow_config_extras(false);
    app.add_option("--report", common.report_path,
                   "Write the JSON run report here ('-' = stdout)");
    app.add_option("--threads", common.threads, "Worker threads (0 = all cores)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    app.add_option("--seed", common.seed, "Random seed (same seed, same output, any --threads)")
        ->check(parses_with(
            [](const std::string& s) {
                parse_integer(s, "--seed", 0, std::numeric_limits<long long>::max());
            },
            "INT >= 0"))
        ->capture_default_str();
    app.add_flag("-q,--quiet", common.quiet, "Print only errors");
    app.add_flag("-v,--verbose", common.verbose, "Print extra detail");
    app.footer("Example:\n  " + example +
               "\nExit codes: 0 ok, 1 runtime error, 2 usage error, 3 quality gate failed.");
}

std::optional<int> parse(CLI::App& app, int argc, char** argv) {
    // Safety net: every floating-point option rejects NaN and Inf, whether or not the tool gave
    // it one of the finite checks of core/validators.h (CLI11's Range lets NaN through).
    for (CLI::Option* opt : app.get_options()) {
        if (opt->get_type_name().rfind("FLOAT", 0) == 0) opt->check(finite());
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kExitOk : kExitUsage;
    }
    return std::nullopt;
}

nlohmann::json resolved_config(const CLI::App& app) {
    nlohmann::json out = nlohmann::json::object();
    for (const CLI::Option* opt : app.get_options()) {
        std::string name = opt->get_single_name();
        if (name.empty() || name == "help" || name == "version" || name == "config") continue;
        for (char& c : name) {
            if (c == '-') c = '_';
        }
        if (opt->get_expected_max() == 0) {  // a flag: record whether it was given
            out[name] = opt->count() > 0;
            continue;
        }
        std::vector<std::string> values =
            opt->count() > 0 ? opt->results() : std::vector<std::string>{};
        if (values.empty() && !opt->get_default_str().empty())
            values.push_back(opt->get_default_str());
        auto to_json = [](const std::string& s) -> nlohmann::json {
            nlohmann::json j = nlohmann::json::parse(s, nullptr, false);
            if (!j.is_discarded() && (j.is_number() || j.is_boolean())) return j;
            return s;
        };
        if (values.empty()) {
            out[name] = nullptr;
        } else if (values.size() == 1 && opt->get_expected_max() <= 1) {
            out[name] = to_json(values[0]);
        } else {
            nlohmann::json arr = nlohmann::json::array();
            for (const auto& v : values) arr.push_back(to_json(v));
            out[name] = arr;
        }
    }
    return out;
}

int run(const std::string& tool, const CLI::App& app, const CommonArgs& common, int argc,
        char** argv, const std::function<void(Report&)>& body) {
    log::set_level(common.quiet ? log::Level::kQuiet
                   : common.verbose ? log::Level::kVerbose
                                    : log::Level::kNormal);
    Report report(tool);
    report.set_argv(argc, argv);
    report.set_config(resolved_config(app));
    report.set_seed(common.seed);
    report.set_threads(parallel::set_thread_count(common.threads));

    int code = kExitOk;
    std::string status = "ok";
    try {
        body(report);
    } catch (const QualityGateFailed& e) {
        code = kExitQualityGate;
        status = "quality_gate_failed";
        log::error(str(tool, ": quality gate failed: ", e.what()));
    } catch (const UsageError& e) {
        code = kExitUsage;
        status = "failed";
        log::error(str(tool, ": error: ", e.what()));
    } catch (const std::exception& e) {
        code = kExitRuntime;
        status = "failed";
        log::error(str(tool, ": error: ", e.what()));
    }

    if (!common.report_path.empty()) {
        const std::string text = report.to_json(status, code, log::take_warnings()).dump(2) + "\n";
        try {
            if (common.report_path == "-") {
                std::cout << text;
            } else {
                fs::write_text_atomic(common.report_path, text);
            }
        } catch (const std::exception& e) {
            log::error(str(tool, ": error: ", e.what()));
            if (code == kExitOk) code = kExitRuntime;
        }
    }
    return code;
}

}  // namespace inlight::app
