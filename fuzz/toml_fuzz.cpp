// Harness: the TOML reader (core/toml.h over toml++) and every reader built on it: scene files
// (render::parse_scene), material files (brdf::parse_material), fabric files
// (weave::parse_weave) and a tool's --config file (app::parse with TomlConfig), all on the same
// bytes. Each must return or throw inlight::Error; the config must give exit code 0 or 2.
#include <CLI/CLI.hpp>

#include "brdf/brdf.h"
#include "core/app.h"
#include "core/check.h"
#include "core/log.h"
#include "core/toml.h"
#include "fuzz.h"
#include "render/scene.h"
#include "weave/weave.h"

namespace {

void typed_reads(const inlight::toml::Document& doc, const inlight::toml::Table& table) {
    const inlight::toml::Reader r(doc, table);
    for (const auto& entry : table.values) {
        const std::string& key = entry.first;  // a named copy: lambdas cannot capture bindings
        inlight::fuzz::expect_error_or_success([&] { r.get_double(key, 0); });
        inlight::fuzz::expect_error_or_success([&] { r.get_int(key, 0); });
        inlight::fuzz::expect_error_or_success([&] { r.get_bool(key, false); });
        inlight::fuzz::expect_error_or_success([&] { r.get_string(key, ""); });
        inlight::fuzz::expect_error_or_success(
            [&] { r.get_vector(key, 3, Eigen::VectorXd::Zero(3), true); });
    }
    inlight::fuzz::expect_error_or_success([&] { r.finish(); });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    inlight::fuzz::expect_error_or_success([&] {
        const inlight::toml::Document doc = inlight::toml::parse(text, "fuzz.toml");
        typed_reads(doc, doc.root);
        for (const auto& [name, table] : doc.tables) typed_reads(doc, table);
        for (const auto& [name, list] : doc.table_arrays) {
            for (const auto& table : list) typed_reads(doc, table);
        }
    });
    inlight::fuzz::expect_error_or_success(
        [&] { inlight::render::parse_scene(text, "scene.toml", "/nonexistent"); });
    inlight::fuzz::expect_error_or_success(
        [&] { inlight::brdf::parse_material(text, "material.toml"); });
    inlight::fuzz::expect_error_or_success(
        [&] { inlight::weave::parse_weave(text, "fabric.toml"); });

    // A --config file of a tool with options of each kind.
    const std::string config = inlight::fuzz::write_temp("config.toml", data, size);
    CLI::App app{"fuzz", "fuzz-tool"};
    inlight::app::CommonArgs common;
    double gain = 1;
    int count = 0;
    std::string name;
    std::vector<double> list;
    bool flag = false;
    app.add_option("--gain", gain)->check(CLI::Range(0.0, 10.0));
    app.add_option("--count", count);
    app.add_option("--name", name);
    app.add_option("--list", list);
    app.add_flag("--flag", flag);
    inlight::app::setup(app, common, "fuzz-tool --config c.toml");
    std::string a0 = "fuzz-tool", a1 = "--config", a2 = config;
    char* argv[] = {a0.data(), a1.data(), a2.data()};
    inlight::log::set_level(inlight::log::Level::kQuiet);
    const auto code = inlight::app::parse(app, 3, argv);
    INLIGHT_CHECK(!code || *code == inlight::app::kExitUsage) << "exit code " << *code;
    return 0;
}
