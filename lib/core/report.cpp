#include "core/report.h"

#include <ctime>
#include <filesystem>

#include "core/error.h"
#include "core/fs.h"
#include "core/log.h"
#include "core/sha256.h"

namespace inlight {

namespace {
std::string utc_now() {
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[32];
    std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}
}  // namespace

Report::Report(std::string tool)
    : m_tool(std::move(tool)), m_started_utc(utc_now()), m_start(std::chrono::steady_clock::now()) {}

void Report::set_argv(int argc, char** argv) {
    m_argv.assign(argv, argv + argc);
}

bool Report::has_input(const std::string& path) const {
    for (const auto& in : m_inputs) {
        if (in["path"] == path) return true;
    }
    return false;
}

void Report::add_input(const std::string& path) {
    if (!has_input(path)) add_input(path, sha256_file(path));
}

void Report::add_input(const std::string& path, const std::string& sha256) {
    if (has_input(path)) return;
    fs::declare_input(path);
    m_inputs.push_back({{"path", path}, {"sha256", sha256}});
}

void Report::add_output(const std::string& path, const std::string& kind,
                        const std::string& color_space) {
    nlohmann::json o = {{"path", path}, {"kind", kind}};
    if (!color_space.empty()) o["color_space"] = color_space;
    m_outputs.push_back(o);
}

void Report::add_stage_time(const std::string& stage, double seconds) {
    m_stages[stage] = m_stages.value(stage, 0.0) + seconds;
}

nlohmann::json Report::to_json(const std::string& status, int exit_code,
                               const std::vector<std::string>& warnings) const {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start)
                            .count();
    return {{"tool", m_tool},
            {"version", version_string()},
            {"commit", build_commit()},
            {"status", status},
            {"exit_code", exit_code},
            {"argv", m_argv},
            {"config", m_config},
            {"seed", m_seed ? nlohmann::json(*m_seed) : nlohmann::json(nullptr)},
            {"threads", m_threads ? nlohmann::json(*m_threads) : nlohmann::json(nullptr)},
            {"started_utc", m_started_utc},
            {"wall_time_s", wall},
            {"stage_time_s", m_stages},
            {"inputs", m_inputs},
            {"outputs", m_outputs},
            {"metrics", m_metrics},
            {"warnings", warnings},
            {"error", m_error ? nlohmann::json(*m_error) : nlohmann::json(nullptr)}};
}

ScopedStage::ScopedStage(Report& report, std::string stage)
    : m_report(report), m_stage(std::move(stage)), m_start(std::chrono::steady_clock::now()) {
    log::info(str("[", m_report.tool(), "] ", m_stage, "..."));
}

double ScopedStage::elapsed_s() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

ScopedStage::~ScopedStage() {
    const double s = elapsed_s();
    m_report.add_stage_time(m_stage, s);
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.3f", s);
    log::info(str("[", m_report.tool(), "] ", m_stage, " done (", buf, " s)"));
}

}  // namespace inlight
