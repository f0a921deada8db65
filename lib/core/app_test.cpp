// Tests of core/app.h's run contract: a report for every run that asked for one (also when the
// parser rejects the command line), outputs committed only by a successful run (or one that
// failed its quality gate), and never a report written onto an input.
#include "core/app.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "core/fs.h"
#include "testing/testing.h"

namespace inlight {
namespace {

namespace stdfs = std::filesystem;

struct Args {
    std::vector<std::string> words;
    std::vector<char*> argv;
    explicit Args(std::vector<std::string> w) : words(std::move(w)) {
        for (auto& s : words) argv.push_back(s.data());
    }
    int argc() { return static_cast<int>(argv.size()); }
};

TEST(App, ParseFailureStillWritesTheReport) {
    const std::string dir = testing::temp_dir("app_parse_report");
    CLI::App cli{"t", "tool-x"};
    app::CommonArgs common;
    double intensity = 1;
    cli.add_option("--intensity", intensity);
    app::setup(cli, common, "tool-x");
    Args args({"tool-x", "--intensity", "nan", "--report", dir + "/r.json"});
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(app::parse(cli, args.argc(), args.argv.data()), app::kExitUsage);
    ::testing::internal::GetCapturedStderr();
    const auto j = nlohmann::json::parse(fs::read_file(dir + "/r.json"));
    EXPECT_EQ(j["tool"], "tool-x");
    EXPECT_EQ(j["status"], "failed");
    EXPECT_EQ(j["exit_code"], app::kExitUsage);
    EXPECT_NE(j["error"].get<std::string>().find("--intensity: 'nan' is not a finite number"),
              std::string::npos)
        << j["error"];
    EXPECT_EQ(j["argv"].size(), 5u);
    EXPECT_TRUE(j["outputs"].empty());
    EXPECT_TRUE(j["seed"].is_null());  // never parsed
}

TEST(App, ReportIsNeverWrittenOntoAFileOfTheCommandLine) {
    const std::string dir = testing::temp_dir("app_report_input");
    fs::write_text_atomic(dir + "/in.exr", "pixels");
    CLI::App cli{"t", "tool-x"};
    app::CommonArgs common;
    std::string input;
    cli.add_option("input", input);
    app::setup(cli, common, "tool-x");
    Args args({"tool-x", dir + "/in.exr", "--bogus", "--report", dir + "/in.exr"});
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(app::parse(cli, args.argc(), args.argv.data()), app::kExitUsage);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(fs::read_file(dir + "/in.exr"), "pixels");
    EXPECT_NE(err.find("report not written"), std::string::npos) << err;
}

/// Runs app::run with `body` and --report dir/r.json; returns the exit code.
int run_with(const std::string& dir, const std::function<void(Report&)>& body) {
    CLI::App cli{"t", "tool-x"};
    app::CommonArgs common;
    common.report_path = dir + "/r.json";
    Args args({"tool-x"});
    ::testing::internal::CaptureStderr();
    const int code = app::run("tool-x", cli, common, args.argc(), args.argv.data(), body);
    ::testing::internal::GetCapturedStderr();
    return code;
}

TEST(App, OutputsAppearOnlyWhenTheRunSucceeds) {
    const std::string dir = testing::temp_dir("app_txn");
    auto writes_then = [&](auto then) {
        return [&dir, then](Report& r) {
            fs::write_text_atomic(dir + "/out/a.json", "a");
            r.add_output(dir + "/out/a.json", "x");
            fs::write_text_atomic(dir + "/out/b.json", "b");
            r.add_output(dir + "/out/b.json", "x");
            then();
        };
    };
    EXPECT_EQ(run_with(dir, writes_then([] { throw Error("second step failed"); })),
              app::kExitRuntime);
    EXPECT_FALSE(stdfs::exists(dir + "/out"));  // neither file, nor the folder made for them
    auto report = nlohmann::json::parse(fs::read_file(dir + "/r.json"));
    EXPECT_EQ(report["status"], "failed");
    EXPECT_EQ(report["error"], "second step failed");
    EXPECT_TRUE(report["outputs"].empty());

    EXPECT_EQ(run_with(dir, writes_then([] { throw app::QualityGateFailed("gate"); })),
              app::kExitQualityGate);
    EXPECT_EQ(fs::read_file(dir + "/out/b.json"), "b");  // a failed gate keeps its outputs
    stdfs::remove_all(dir + "/out");

    EXPECT_EQ(run_with(dir, writes_then([] {})), app::kExitOk);
    EXPECT_EQ(fs::read_file(dir + "/out/a.json"), "a");
    report = nlohmann::json::parse(fs::read_file(dir + "/r.json"));
    EXPECT_EQ(report["outputs"].size(), 2u);
    EXPECT_TRUE(report["error"].is_null());
}

TEST(App, AnOutputOntoTheReportOrAnInputIsAUsageError) {
    const std::string dir = testing::temp_dir("app_collide");
    fs::write_text_atomic(dir + "/in.txt", "input");
    EXPECT_EQ(run_with(dir,
                       [&](Report& r) {
                           r.add_input(dir + "/in.txt");
                           fs::write_text_atomic(dir + "/in.txt", "clobbered");
                       }),
              app::kExitUsage);
    EXPECT_EQ(fs::read_file(dir + "/in.txt"), "input");
    // The report is not written onto the output either: a failed run's report under an
    // output's name would look like that output to make or Snakemake.
    stdfs::remove(dir + "/r.json");
    EXPECT_EQ(run_with(dir, [&](Report&) { fs::declare_output(dir + "/r.json", "-o"); }),
              app::kExitUsage);
    EXPECT_FALSE(stdfs::exists(dir + "/r.json"));
}

TEST(App, AReportThatCannotBeWrittenFailsTheRunBeforeItsOutputsAppear) {
    // /proc takes no new file, not even from root: the report's failure was found only after
    // the outputs had been committed, so a failed run left them behind.
    const std::string dir = testing::temp_dir("app_report_unwritable");
    CLI::App cli{"t", "tool-x"};
    app::CommonArgs common;
    common.report_path = "/proc/inlight_app_test_report.json";
    Args args({"tool-x"});
    ::testing::internal::CaptureStderr();
    const int code = app::run("tool-x", cli, common, args.argc(), args.argv.data(), [&](Report& r) {
        fs::write_text_atomic(dir + "/out.json", "a");
        r.add_output(dir + "/out.json", "x");
    });
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(code, app::kExitRuntime);
    EXPECT_FALSE(stdfs::exists(dir + "/out.json"));
    EXPECT_NE(err.find("--report '/proc/inlight_app_test_report.json': cannot be written"),
              std::string::npos) << err;
}

TEST(App, OutOfMemoryIsNamedNotJustStdBadAlloc) {
    const std::string dir = testing::temp_dir("app_bad_alloc");
    EXPECT_EQ(run_with(dir, [](Report&) { throw std::bad_alloc(); }), app::kExitRuntime);
    const auto report = nlohmann::json::parse(fs::read_file(dir + "/r.json"));
    EXPECT_EQ(report["error"].get<std::string>().rfind("out of memory (std::bad_alloc", 0), 0u)
        << report["error"];
}

TEST(App, ConfigFileErrorsNameTheFileLineAndKey) {
    // --config is read by core/toml.h (toml++): every message names the file and the line; a
    // value goes through the option's own checks, NaN included, as if given on the command line.
    const std::string dir = testing::temp_dir("app_config");
    auto message = [&](const std::string& name, const std::string& text) {
        fs::write_text_atomic(dir + "/" + name, text);
        CLI::App cli{"t", "tool-x"};
        app::CommonArgs common;
        double gain = 1;
        std::vector<std::string> inputs;
        cli.add_option("inputs", inputs);
        cli.add_option("--gain", gain);
        app::setup(cli, common, "tool-x");
        Args args({"tool-x", "--config", dir + "/" + name});
        ::testing::internal::CaptureStderr();
        const auto code = app::parse(cli, args.argc(), args.argv.data());
        const std::string err = ::testing::internal::GetCapturedStderr();
        if (!code) return std::string("accepted: gain ") + std::to_string(gain) + ", inputs " +
                          std::to_string(inputs.size());
        EXPECT_EQ(*code, app::kExitUsage) << err;
        return err;
    };
    auto contains = [](const std::string& text, const std::string& part) {
        return text.find(part) != std::string::npos;
    };
    EXPECT_EQ(message("ok.toml", "gain = 2.5\ninputs = [\"a\", \"b\"]\nthreads = 1\n"),
              "accepted: gain 2.500000, inputs 2");
    std::string m = message("syntax.toml", "gain = 2.5\ngain = = 3\n");
    EXPECT_TRUE(contains(m, "syntax.toml:2:")) << m;
    EXPECT_TRUE(contains(m, "TOML syntax error")) << m;
    // \r\n and \n end lines 1 and 2 of a PNG signature; its first NUL is on line 3.
    m = message("binary.toml", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
    EXPECT_TRUE(contains(m, "binary.toml:3: binary data (a NUL byte): not a TOML text file")) << m;
    m = message("typo.toml", "gain = 2\ngian = 3\n");
    EXPECT_TRUE(contains(m, "typo.toml:2: unknown key 'gian': not an option of tool-x")) << m;
    m = message("table.toml", "gain = 2\n[render]\nspp = 3\n");
    EXPECT_TRUE(contains(m, "table.toml:2: [render]: a --config file has no tables")) << m;
    m = message("nan.toml", "gain = nan\n");
    EXPECT_TRUE(contains(m, "--gain")) << m;
    EXPECT_TRUE(contains(m, "finite")) << m;
}

}  // namespace
}  // namespace inlight
