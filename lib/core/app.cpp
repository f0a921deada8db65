#include "core/app.h"

#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>
#include <new>
#include <stdexcept>
#include <thread>

#include "core/fs.h"
#include "core/log.h"
#include "core/memory.h"
#include "core/number.h"
#include "core/parallel.h"
#include "core/toml.h"
#include "core/validators.h"

namespace inlight::app {
namespace {

/// The value of `name` in argv ("--name X" or "--name=X"), or "" (the last one wins, as in
/// CLI11).
std::string option_value_in(int argc, char** argv, const std::string& name) {
    std::string value;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == name && i + 1 < argc) value = argv[++i];
        if (a.rfind(name + "=", 0) == 0) value = a.substr(name.size() + 1);
    }
    return value;
}

/// CLI11's own config reader replaced by core/toml.h (toml++), so a --config file is real TOML
/// and every error names the file, the line and the key: syntax errors (also a binary file) with
/// line and column, unknown keys with the options the tool has, tables (a config file is flat).
class TomlConfig : public CLI::Config {
  public:
    explicit TomlConfig(const CLI::App& app) : m_app(app) {}
    /// The file name for messages (CLI11 hands from_config only the stream).
    void set_source(std::string source) { m_source = std::move(source); }

    std::string to_config(const CLI::App* app, bool defaults, bool write_description,
                          std::string prefix) const override {
        return CLI::ConfigTOML().to_config(app, defaults, write_description, std::move(prefix));
    }

    std::vector<CLI::ConfigItem> from_config(std::istream& in) const override {
        const std::string source = m_source.empty() ? "--config" : m_source;
        // A FIFO or /dev/zero would be read forever; a config file is a few lines.
        if (!m_source.empty()) {
            if (const std::string kind = fs::special_file_kind(m_source); !kind.empty())
                throw CLI::ConfigError(str(source, ": is ", kind, ", not a regular file"));
        }
        std::string text(kMaxConfigBytes + 1, '\0');
        in.read(text.data(), static_cast<std::streamsize>(text.size()));
        text.resize(static_cast<size_t>(in.gcount()));
        if (text.size() > kMaxConfigBytes) {
            throw CLI::ConfigError(str(source, ": larger than ", kMaxConfigBytes >> 20,
                                       " MiB: not a --config file of options"));
        }
        toml::Document doc;
        try {
            doc = toml::parse(text, source);
        } catch (const Error& e) {
            throw CLI::ConfigError(e.what());
        }
        const toml::Table* table = nullptr;
        for (const auto& [name, t] : doc.tables) {
            if (!table || t.line < table->line) table = &t;
        }
        for (const auto& [name, list] : doc.table_arrays) {
            if (!table || list.front().line < table->line) table = &list.front();
        }
        if (table) {
            throw CLI::ConfigError(str(source, ":", table->line, ": [",
                                       table->name, "]: a --config file has no tables; its keys "
                                       "are the tool's long option names"));
        }
        std::vector<CLI::ConfigItem> items;
        for (const auto& [key, value] : doc.root.values) {
            const CLI::Option* opt = m_app.get_option_no_throw("--" + key);
            if (!opt) opt = m_app.get_option_no_throw(key);  // a positional, as CLI11 allows
            const std::string where = str(source, ":", value.line, ": ");
            if (!opt || key == "config") {
                throw CLI::ConfigError(str(where, "unknown key '", key, "': not an option of ",
                                           m_app.get_name(), " (keys are long option names "
                                           "without '--'; see --help)"));
            }
            CLI::ConfigItem item;
            item.name = key;
            if (const auto* array = std::get_if<toml::Array>(&value.data)) {
                for (const toml::Value& v : *array) item.inputs.push_back(scalar(v, where, key));
            } else {
                item.inputs.push_back(scalar(value, where, key));
            }
            items.push_back(std::move(item));
        }
        return items;
    }

  private:
    static constexpr size_t kMaxConfigBytes = size_t(1) << 20;

    /// A TOML value as the command-line word CLI11 converts (integers without a decimal point,
    /// floats round-tripping, nan and inf spelled so the finite() checks reject them by name).
    static std::string scalar(const toml::Value& v, const std::string& where,
                              const std::string& key) {
        if (const auto* b = std::get_if<bool>(&v.data)) return *b ? "true" : "false";
        if (const auto* s = std::get_if<std::string>(&v.data)) return *s;
        if (const auto* d = std::get_if<double>(&v.data)) {
            if (v.is_integer) return std::to_string(static_cast<long long>(*d));
            if (std::isnan(*d)) return "nan";
            if (std::isinf(*d)) return *d > 0 ? "inf" : "-inf";
            char buffer[32];
            std::snprintf(buffer, sizeof buffer, "%.17g", *d);
            return buffer;
        }
        throw CLI::ConfigError(str(where, key, ": nested arrays are not option values"));
    }

    const CLI::App& m_app;
    std::string m_source;
};

}  // namespace

void setup(CLI::App& app, CommonArgs& common, const std::string& example) {
    app.add_flag_callback(
        "--version",
        [&app]() {
            std::cout << version_line(app.get_name()) << "\n";
            throw CLI::Success();
        },
        "Print the version and exit");
    app.set_config("--config", "", "TOML file of options; keys are long option names (e.g. "
                                   "threads = 2); flags given on the command line override it");
    app.allow_config_extras(false);
    app.config_formatter(std::make_shared<TomlConfig>(app));
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

namespace {

/// Whether `path` is the same file as an existing file named on the command line (other than as
/// the value of --report): such a file may be an input, and the report must not overwrite it.
bool is_argv_file(const std::string& path, int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--report") {
            ++i;
            continue;
        }
        if (a.rfind("--report=", 0) == 0) continue;
        const size_t eq = a.find('=');
        if (a.rfind("--", 0) == 0 && eq != std::string::npos) a = a.substr(eq + 1);
        std::error_code ec;
        if (std::filesystem::is_regular_file(a, ec) && fs::same_file(a, path)) return true;
    }
    return false;
}

/// The tool's name for its report: the first word of the app's name ("calibrate geometry" ->
/// "calibrate"), without a directory.
std::string tool_name(const CLI::App& app) {
    std::string name = app.get_name();
    name = name.substr(0, name.find(' '));
    const size_t slash = name.rfind('/');
    return slash == std::string::npos ? name : name.substr(slash + 1);
}

/// Writes `report` to `path` ("-" = stdout), unless `path` is a file named on the command line
/// (argv). Returns false (message printed) if it does not.
bool write_report(const Report& report, const std::string& path, const std::string& status,
                  int code, int argc, char** argv) {
    if (path != "-" && is_argv_file(path, argc, argv)) {
        log::error(str(report.tool(), ": error: --report '", path,
                       "' is a file named on the command line (an input?): report not written"));
        return false;
    }
    const std::string text = report.to_json(status, code, log::take_warnings()).dump(2) + "\n";
    try {
        if (path == "-") {
            std::cout << text;
        } else {
            fs::write_text_atomic(path, text);
        }
    } catch (const std::exception& e) {
        log::error(str(report.tool(), ": error: ", e.what()));
        return false;
    }
    return true;
}

/// The `report` key of the --config file named in argv, or "": a run the parser rejects (for a
/// bad value in that very file) still writes the report the file asks for.
std::string report_in_config(int argc, char** argv) {
    const std::string config = option_value_in(argc, argv, "--config");
    std::error_code ec;
    if (config.empty() || !std::filesystem::is_regular_file(config, ec) ||
        std::filesystem::file_size(config, ec) > (size_t(1) << 20))
        return "";
    try {
        const toml::Document doc = toml::parse(fs::read_file(config), config);
        const auto it = doc.root.values.find("report");
        if (it == doc.root.values.end()) return "";
        if (const auto* s = std::get_if<std::string>(&it->second.data)) return *s;
    } catch (const std::exception&) {  // the parser's own error is the one reported
    }
    return "";
}

/// Throws Error unless a file can be created at `path` (its folder is created if missing, as
/// the report's writer does): found before a run's outputs are committed.
void check_report_writable(const std::string& path) {
    namespace stdfs = std::filesystem;
    std::error_code ec;
    const stdfs::path parent = stdfs::path(path).parent_path();
    if (!parent.empty()) {
        stdfs::create_directories(parent, ec);
        if (ec) {
            throw Error(str("--report '", path, "': cannot create its folder: ", ec.message(),
                            "; no output was written"));
        }
    }
    const std::string tmp = fs::temp_sibling(path);
    std::ofstream out(tmp, std::ios::binary);
    out << "{}\n";
    out.close();
    const bool ok = static_cast<bool>(out);
    stdfs::remove(tmp, ec);
    if (!ok) throw Error(str("--report '", path, "': cannot be written there; no output was written"));
}

}  // namespace

namespace {

// Levenshtein distance, for the "did you mean" of an unknown option.
size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = up;
        }
    }
    return row[b.size()];
}

// Throws a usage error naming the first long option in args that `app` does not have (with the
// nearest one it has), before CLI11 parses: CLI11 first feeds such a word's value to the
// positional arguments and reports that instead ("inputs: File does not exist: 3" for
// `--bandz 3`). Words after "--" are positional.
void check_long_options(const CLI::App& app, int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if (word == "--") return;
        if (word.size() < 3 || word.compare(0, 2, "--") != 0) continue;
        const std::string name = word.substr(0, word.find('='));
        if (app.get_option_no_throw(name) != nullptr) continue;
        std::string nearest;
        size_t best = 4;  // suggest only a near miss: at most 3 edits
        for (const CLI::Option* opt : app.get_options()) {
            for (const std::string& known : opt->get_lnames()) {
                const size_t d = edit_distance(name.substr(2), known);
                if (d < best) best = d, nearest = "--" + known;
            }
        }
        throw CLI::ValidationError(
            name, nearest.empty() ? "unknown option (see --help)"
                                  : "unknown option (did you mean " + nearest + "?)");
    }
}

}  // namespace

namespace {

// While a run is on, SIGINT, SIGTERM and SIGHUP roll its outputs back before the process ends
// (with 128 + the signal, as a shell reports a death by that signal), so an interrupted run
// leaves its output folders as they were instead of the temporaries of every staged file. The
// signals are blocked in this thread, and so in every thread started later (they inherit the
// mask), and taken by a watcher thread; the destructor restores the mask.
class InterruptGuard {
  public:
    InterruptGuard(fs::OutputTransaction& outputs, std::string tool) {
        sigemptyset(&m_signals);
        for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&m_signals, s);
        pthread_sigmask(SIG_BLOCK, &m_signals, &m_previous);
        m_watcher = std::thread([this, &outputs, tool = std::move(tool)] {
            const timespec tick{0, 100'000'000};
            while (!m_stop.load()) {
                const int sig = sigtimedwait(&m_signals, nullptr, &tick);
                if (sig <= 0) continue;
                log::error(str(tool, ": interrupted (", strsignal(sig),
                               "): this run's unfinished outputs are removed"));
                outputs.abandon(0.2);
                std::_Exit(128 + sig);
            }
        });
    }
    ~InterruptGuard() {
        m_stop = true;
        m_watcher.join();
        pthread_sigmask(SIG_SETMASK, &m_previous, nullptr);
    }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

  private:
    sigset_t m_signals{}, m_previous{};
    std::atomic<bool> m_stop{false};
    std::thread m_watcher;
};

}  // namespace

std::optional<int> parse(CLI::App& app, int argc, char** argv, int skip) {
    // Safety net: every floating-point option rejects NaN and Inf, whether or not the tool gave
    // it one of the finite checks of core/validators.h (CLI11's Range lets NaN through).
    // Likewise every option checked to be an existing file or path refuses a FIFO, a device
    // or a socket (CLI::ExistingFile lets /dev/zero through, and reading it never ends).
    for (CLI::Option* opt : app.get_options()) {
        const std::string type = opt->get_type_name();
        if (type.rfind("FLOAT", 0) == 0) opt->check(finite());
        if (opt->check_name("--output") || type.find(":FILE") != std::string::npos ||
            type.find(":DIR") != std::string::npos ||
            type.find(":PATH(existing)") != std::string::npos) {
            opt->check(CLI::Validator(
                [](std::string& s) { return s.empty() ? std::string("an empty path") : ""; }, ""));
        }
        if (type.find(":FILE") != std::string::npos ||
            type.find(":PATH(existing)") != std::string::npos)
            opt->check(not_special_file());
    }
    if (auto config = std::dynamic_pointer_cast<TomlConfig>(app.get_config_formatter())) {
        config->set_source(option_value_in(argc, argv, "--config"));
    }
    try {
        check_long_options(app, argc - skip, argv + skip);
        app.parse(argc - skip, argv + skip);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e) == 0 ? kExitOk : kExitUsage;
        // A run rejected by the parser still gets the report it asked for.
        std::string report_path = option_value_in(argc, argv, "--report");
        if (report_path.empty()) report_path = report_in_config(argc, argv);
        if (code != kExitOk && !report_path.empty()) {
            Report report(tool_name(app));
            report.set_argv(argc, argv);
            report.set_config(resolved_config(app));
            report.set_error(e.what());
            write_report(report, report_path, "failed", code, argc, argv);
        }
        return code;
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

    int code = kExitOk;
    std::string status = "ok";
    // Why the report is not written, or "": it would overwrite an input or an output of the run,
    // or its path cannot take a file at all.
    std::string no_report;
    auto fail = [&](int exit_code, const std::string& prefix, const std::exception& e) {
        code = exit_code;
        status = exit_code == kExitQualityGate ? "quality_gate_failed" : "failed";
        report.set_error(e.what());
        log::error(str(tool, prefix, e.what()));
    };
    {
        // Every output of the run is staged and appears only if the run succeeds (or ran to a
        // failed quality gate, whose outputs are part of the contract).
        fs::OutputTransaction outputs;
        const InterruptGuard interrupts(outputs, tool);
        // After the guard: worker threads inherit its signal mask.
        report.set_threads(parallel::set_thread_count(common.threads));
        try {
            if (!common.report_path.empty() && common.report_path != "-") {
                try {
                    outputs.reserve(common.report_path, "--report");
                } catch (const UsageError&) {
                    no_report = "its path cannot take the report";
                    throw;
                }
            }
            // The config file is an input like any other: hashed in the report, never
            // overwritten.
            if (const CLI::Option* config = app.get_config_ptr(); config && config->count() > 0) {
                for (const std::string& path : config->results()) report.add_input(path);
            }
            body(report);
        } catch (const QualityGateFailed& e) {
            fail(kExitQualityGate, ": quality gate failed: ", e);
        } catch (const UsageError& e) {
            fail(kExitUsage, ": error: ", e);
        } catch (const std::bad_alloc&) {
            // An input or option asked for more memory than there is (a size read from a file,
            // an image or render size): "std::bad_alloc" alone names neither.
            fail(kExitRuntime, ": error: ",
                 Error(str("out of memory (std::bad_alloc, peak resident ", peak_rss_bytes() >> 20,
                           " MiB of ", physical_memory_bytes() >> 20, " MiB): an input or option "
                           "asks for more memory than this machine has; see the sizes in the "
                           "options (--width-px, --height-px, ...) and the input files' dimensions")));
        } catch (const std::length_error& e) {
            fail(kExitRuntime, ": error: ",
                 Error(str("a size asked by an input or option is too large to allocate (",
                           e.what(), ")")));
        } catch (const std::exception& e) {
            fail(kExitRuntime, ": error: ", e);
        }
        if (code == kExitOk || code == kExitQualityGate) {
            try {
                // The report is written after the outputs are in place: a report that cannot be
                // written must fail the run before they are, not leave them behind a failed run.
                if (no_report.empty() && !common.report_path.empty() && common.report_path != "-")
                    check_report_writable(common.report_path);
                outputs.commit();
            } catch (const std::exception& e) {
                fail(kExitRuntime, ": error: ", e);
            }
        }
        if (code != kExitOk && code != kExitQualityGate) {
            outputs.rollback();
            report.clear_outputs();
        }
        if (!common.report_path.empty() && common.report_path != "-") {
            if (outputs.is_input(common.report_path)) no_report = "it is an input of the run";
            else if (no_report.empty()) no_report = outputs.reserved_clash();
        }
    }

    if (!common.report_path.empty()) {
        if (!no_report.empty()) {  // never overwrite an input or an output, not even with the report
            log::error(str(tool, ": error: --report '", common.report_path, "': ", no_report,
                           ": report not written"));
        } else if (!write_report(report, common.report_path, status, code, argc, argv) &&
                   code == kExitOk) {
            code = kExitRuntime;
        }
    }
    return code;
}

}  // namespace inlight::app
