// core/app.h: behaviour shared by every CLI tool: common flags, config files, exit codes, the
// run report, and error handling. A tool's main() parses, calls the library inside app::run and
// writes its outputs.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "core/report.h"

namespace inlight::app {

inline constexpr int kExitOk = 0;           ///< success
inline constexpr int kExitRuntime = 1;      ///< I/O failure, bad data, no convergence
inline constexpr int kExitUsage = 2;        ///< bad flags, config or option values
inline constexpr int kExitQualityGate = 3;  ///< ran, outputs written, but a quality gate failed

/// Flags every tool has.
struct CommonArgs {
    std::string report_path;  ///< --report: JSON run report ("-" = stdout)
    int threads = 0;          ///< --threads: worker threads, 0 = all cores
    uint64_t seed = 1;        ///< --seed: random seed; same seed => same outputs for any threads
    bool quiet = false;       ///< -q: only errors on stderr
    bool verbose = false;     ///< -v: extra detail on stderr
};

/// Thrown by a tool body when a quality gate fails after outputs were written (exit 3).
class QualityGateFailed : public Error {
  public:
    explicit QualityGateFailed(const std::string& message) : Error(message) {}
};

/// Adds --version, --config FILE.toml (keys are long option names; unknown keys are errors),
/// the common flags, and the Example footer.
void setup(CLI::App& app, CommonArgs& common, const std::string& example);

/// Parses the command line (and --config) in argv[skip..] (skip = 1 for a mode word such as
/// `calibrate geometry`). Every FLOAT option first gets the finite() check of
/// core/validators.h, so NaN and Inf are usage errors even where a tool forgot. Returns an exit
/// code when the program should stop now (0 after --help or --version; kExitUsage on a usage
/// error, message printed, and the JSON report written when argv asks for one with --report),
/// std::nullopt otherwise.
std::optional<int> parse(CLI::App& app, int argc, char** argv, int skip = 0);

/// Runs `body` with a Report inside an fs::OutputTransaction: applies --threads and -q/-v, maps
/// exceptions to exit codes (Error -> 1, UsageError -> 2, QualityGateFailed -> 3), prints
/// "<tool>: error: <msg>" to stderr, commits the run's outputs on success or a failed quality
/// gate and removes them all otherwise, and writes the report (also when the run fails; never
/// onto an input). Returns the exit code.
int run(const std::string& tool, const CLI::App& app, const CommonArgs& common, int argc,
        char** argv, const std::function<void(Report&)>& body);

/// The resolved options of `app` as a JSON object with snake_case keys (for the report).
nlohmann::json resolved_config(const CLI::App& app);

}  // namespace inlight::app
