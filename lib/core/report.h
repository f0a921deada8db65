// core/report.h: the JSON run report every tool writes with --report PATH.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/version.h"

namespace inlight {

/// Collects what a run did: inputs (with sha256), outputs, resolved options, time per stage,
/// metrics and warnings. Keys are snake_case with unit suffixes. Thread-compatible, not
/// thread-safe: fill it from the tool's main thread.
class Report {
  public:
    explicit Report(std::string tool);

    void set_argv(int argc, char** argv);
    /// The resolved options (CLI over config over defaults), echoed so the run can be replayed.
    void set_config(nlohmann::json config) { m_config = std::move(config); }
    void set_seed(uint64_t seed) { m_seed = seed; }
    void set_threads(int threads) { m_threads = threads; }

    /// Records an input file and its SHA-256, and declares it to the run's output transaction
    /// (fs::declare_input), so no output of the run may overwrite it. Throws Error if the file
    /// cannot be read, UsageError if it is one of the run's outputs.
    void add_input(const std::string& path);
    /// As add_input, with the SHA-256 the caller computed (e.g. on another thread while the file
    /// was being decoded: envmap-project).
    void add_input(const std::string& path, const std::string& sha256);
    /// Records an output file with its kind ("sh_coefficients", "image", ...) and colour space
    /// (empty when not an image).
    void add_output(const std::string& path, const std::string& kind,
                    const std::string& color_space = "");
    /// Forgets the outputs (a failed run's outputs were removed, so the report lists none).
    void clear_outputs() { m_outputs = nlohmann::json::array(); }
    /// The error message of a failed run ("error" in the report; null when the run succeeded).
    void set_error(std::string message) { m_error = std::move(message); }
    /// Adds the wall time of a named stage (seconds); repeated names accumulate.
    void add_stage_time(const std::string& stage, double seconds);

    /// Metrics object: report.metrics()["reproj_rms_px"] = 0.21.
    nlohmann::json& metrics() { return m_metrics; }
    const nlohmann::json& metrics() const { return m_metrics; }

    /// The complete report (schema and status values: docs/report.md). status is "ok",
    /// "failed" or "quality_gate_failed". Seed and threads are null until set.
    nlohmann::json to_json(const std::string& status, int exit_code,
                           const std::vector<std::string>& warnings) const;

    const std::string& tool() const { return m_tool; }

  private:
    bool has_input(const std::string& path) const;
    std::string m_tool;
    std::vector<std::string> m_argv;
    nlohmann::json m_config = nlohmann::json::object();
    nlohmann::json m_inputs = nlohmann::json::array();
    nlohmann::json m_outputs = nlohmann::json::array();
    nlohmann::json m_stages = nlohmann::json::object();
    nlohmann::json m_metrics = nlohmann::json::object();
    std::optional<uint64_t> m_seed;
    std::optional<int> m_threads;
    std::optional<std::string> m_error;
    std::string m_started_utc;
    std::chrono::steady_clock::time_point m_start;
};

/// Times a stage: prints "[tool] stage..." at start and "done (1.2 s)" at the end to stderr
/// (unless -q), and adds the time to the report.
class ScopedStage {
  public:
    ScopedStage(Report& report, std::string stage);
    ~ScopedStage();
    ScopedStage(const ScopedStage&) = delete;
    ScopedStage& operator=(const ScopedStage&) = delete;
    /// Seconds since the stage began.
    double elapsed_s() const;

  private:
    Report& m_report;
    std::string m_stage;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace inlight
