#include "render/compare_lights.h"

#include <algorithm>
#include <cmath>

#include "brdf/bake.h"
#include "brdf/grid.h"
#include "core/error.h"
#include "core/log.h"
#include "envmap/budget.h"

namespace inlight::render {

namespace {

/// The file's provenance against the scene's environment: warn on a frame or scale mismatch.
void check_frame(const Scene& scene, const LightingFile& file) {
    const EnvironmentSpec& env = scene.desc().environment;
    const nlohmann::json& meta = file.sh.metadata;
    if (meta.contains("rotate") && meta["rotate"].is_string() &&
        meta["rotate"].get<std::string>() != env.rotation)
        log::warn(str("compare: the lighting file was projected with --rotate ",
                      meta["rotate"].get<std::string>(), ", the scene's environment has rotation ",
                      env.rotation));
    if (meta.contains("intensity") && meta["intensity"].is_number() &&
        std::abs(meta["intensity"].get<double>() - env.intensity) > 1e-12 * env.intensity)
        log::warn(str("compare: the lighting file was projected with --intensity ",
                      meta["intensity"].get<double>(), ", the scene's environment has intensity ",
                      env.intensity));
}

}  // namespace

RealtimeLighting compare_lighting(const Scene& scene, const CompareOptions& options, int bands) {
    RealtimeLighting lighting;
    lighting.coeffs = project_environment(scene.environment(), bands);
    lighting.tables = compare_tables(scene, options, bands);
    return lighting;
}

nlohmann::json compare_lighting_file(const Scene& scene, const RenderResult& truth,
                                     const CompareOptions& options, const LightingFile& file,
                                     const std::string& prefix, std::vector<WrittenFile>& written) {
    check_frame(scene, file);
    const int bands = file.sh.sh_bands;
    const double exposure = options.exposure > 0 ? options.exposure : auto_exposure(truth.radiance);
    RealtimeLighting pure = compare_lighting(scene, options, bands);
    RealtimeLighting lit;
    lit.coeffs = file.sh.coeffs;
    lit.lights = file.lights;
    lit.tables = pure.tables;
    RealtimeOptions ro;
    ro.sh_bands = bands;
    ro.supersample = options.supersample;
    const image::Image rt = render_realtime(scene, lit, ro);
    const Comparison with = compare_images(truth.radiance, rt, exposure, options);
    image::write_image(prefix + "_rt_lights.exr", rt);
    written.push_back({prefix + "_rt_lights.exr", "realtime_radiance", "linear_srgb"});
    image::write_image(prefix + "_compare_lights.png",
                       comparison_figure(with, "model (SH + lights)", options));
    written.push_back({prefix + "_compare_lights.png", "side_by_side", "srgb"});

    const Comparison without =
        compare_images(truth.radiance, render_realtime(scene, pure, ro), exposure, options);

    // Shader cost per fragment (envmap/budget.h's count), for the scene's first specular table.
    envmap::CostModel cost_model;
    for (size_t i = 0; i < lit.tables.size(); ++i) {
        if (scene.desc().materials[i].brdf.specular == brdf::Model::kLambert) continue;
        cost_model = {lit.tables[i].sh_bands, lit.tables[i].channels};
        break;
    }
    if (!file.lights.empty()) cost_model.light_shading = file.lights[0].shading;
    auto cost = [&](int lights) {
        const envmap::ShaderCost c = envmap::shader_cost(bands, lights, cost_model);
        return nlohmann::json{{"operations", c.operations},
                              {"lighting_floats", c.lighting_floats},
                              {"texture_fetches", c.texture_fetches}};
    };
    nlohmann::json lights = nlohmann::json::array();
    for (const auto& l : file.lights) lights.push_back(envmap::to_json(l));
    return {{"sh_bands", bands},
            {"lights", lights},
            {"exposure", exposure},
            {"with_lights", metrics_json(with.metrics)},
            {"with_lights_cost", cost(static_cast<int>(file.lights.size()))},
            {"pure_sh_same_bands", metrics_json(without.metrics)},
            {"pure_sh_cost", cost(0)}};
}

}  // namespace inlight::render
