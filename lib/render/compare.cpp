#include "render/compare.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "brdf/bake.h"
#include "brdf/grid.h"
#include "core/error.h"
#include "core/log.h"
#include "sh/sh.h"

namespace inlight::render {

double auto_exposure(const image::Image& truth) {
    double sum = 0;
    for (size_t i = 0; i < truth.pixel_count(); ++i) {
        const float* p = &truth.pixels[i * static_cast<size_t>(truth.channels)];
        sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
    const double mean = sum / static_cast<double>(std::max<size_t>(1, truth.pixel_count()));
    return mean > 0 ? 0.18 / mean : 1.0;
}

Comparison compare_images(const image::Image& truth, const image::Image& test, double exposure,
                          const CompareOptions& options) {
    Comparison c;
    image::CompareOptions co;
    co.rel_floor = options.rel_floor;
    co.exposure = exposure;
    c.metrics = image::compare(test, truth, co);
    c.rel_error = image::relative_error_map(test, truth, options.rel_floor);
    c.de2000 = image::delta_e2000_map(test, truth, exposure);
    const image::Image heat = image::heat_map(c.rel_error, options.heat_max_rel);
    const int w = truth.width, h = truth.height;
    c.side_by_side = image::Image(3 * w, h, 3, image::ColorSpace::kLinearSrgb);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int ch = 0; ch < 3; ++ch) {
                c.side_by_side.at(x, y, ch) = static_cast<float>(truth.at(x, y, ch) * exposure);
                c.side_by_side.at(w + x, y, ch) = static_cast<float>(test.at(x, y, ch) * exposure);
                c.side_by_side.at(2 * w + x, y, ch) = heat.at(x, y, ch);
            }
        }
    }
    return c;
}

void print_compare_summary(const nlohmann::json& realtime) {
    for (const auto& [mode, e] : realtime["modes"].items()) {
        const double de = e["mean_de2000"].get<double>();
        log::summary("render", str("real-time model vs path-traced truth (", mode, ", 3 SH bands)"),
                     str("mean relative error ", log::num(e["mean_rel"].get<double>()),
                         ", max ", log::num(e["max_rel"].get<double>()), ", mean Delta E 2000 ",
                         log::num(de), ": ",
                         de <= kJndDe2000 ? "below a just-noticeable difference"
                                          : "visible (above 1 Delta E 2000)"));
    }
}

image::Image comparison_figure(const Comparison& c, const std::string& model,
                               const CompareOptions& options,
                               const std::vector<image::FigurePanel>& extra) {
    const int w = c.side_by_side.width / 3, h = c.side_by_side.height;
    std::vector<image::Image> parts(3, image::Image(w, h, 3, image::ColorSpace::kLinearSrgb));
    for (int i = 0; i < 3; ++i)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int ch = 0; ch < 3; ++ch) parts[i].at(x, y, ch) = c.side_by_side.at(i * w + x, y, ch);
    std::vector<image::FigurePanel> panels = {{&parts[0], "path-traced truth"}};
    panels.insert(panels.end(), extra.begin(), extra.end());
    panels.push_back({&parts[1], model});
    panels.push_back({&parts[2], "relative error"});
    const image::ColorBar bar{options.heat_max_rel, "rel. error"};
    return image::figure(str("relative error |", model, " - truth| / truth"), panels, &bar);
}

nlohmann::json metrics_json(const image::Metrics& m) {
    return {{"mae", m.mae},
            {"rmse", m.rmse},
            {"psnr_db", std::isfinite(m.psnr_db) ? nlohmann::json(m.psnr_db) : nlohmann::json()},
            {"mean_rel", m.mean_rel},
            {"max_rel", m.max_rel},
            {"mean_de76", m.mean_de76},
            {"mean_de2000", m.mean_de2000},
            {"max_de2000", m.max_de2000}};
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

brdf::BakeOptions compare_bake_options(const Scene& scene, const CompareOptions& options,
                                       int bands) {
    brdf::BakeOptions bo;
    bo.sh_bands = std::min(bands, brdf::kMaxBakeBands);
    bo.samples = options.bake_samples;
    const Camera& cam = scene.camera();
    bo.view = (cam.position - cam.look_at).normalized();
    return bo;
}

std::vector<brdf::Table> compare_tables(const Scene& scene, const CompareOptions& options,
                                        int bands) {
    const auto& materials = scene.desc().materials;
    std::vector<brdf::Table> out;
    if (!options.tables.empty()) {
        if (options.tables.size() != materials.size()) {
            throw Error(str("compare: ", options.tables.size(), " BRDF tables given for ",
                            materials.size(), " scene materials (one each, in scene order)"));
        }
        for (size_t i = 0; i < materials.size(); ++i) {
            if (options.tables[i].sh_bands < bands) {
                throw Error(str("compare: BRDF table ", i + 1, " has ", options.tables[i].sh_bands,
                                " SH bands; this comparison needs ", bands));
            }
            out.push_back(brdf::first_bands(options.tables[i], bands));
        }
        return out;
    }
    const brdf::BakeOptions bo = compare_bake_options(scene, options, bands);
    const brdf::Grid grid = brdf::parse_grid(options.grid);
    for (const SurfaceMaterial& m : materials) out.push_back(brdf::bake(m.brdf, grid, bo));
    return out;
}

nlohmann::json compare_tables_json(const CompareOptions& options) {
    if (options.tables.empty()) {
        return {{"source", "baked"},
                {"grid", options.grid},
                {"samples", options.bake_samples},
                {"why", "no --brdf-table given: each material baked here for the camera's view; "
                        "give the tables brdf-sh-bake wrote to validate those"}};
    }
    nlohmann::json grids = nlohmann::json::array(), bands = nlohmann::json::array();
    for (const brdf::Table& t : options.tables) {
        grids.push_back(brdf::to_string(t.grid));
        bands.push_back(t.sh_bands);
    }
    return {{"source", "given"}, {"grid", grids}, {"sh_bands", bands}};
}

nlohmann::json compare_realtime(const Scene& scene, const RenderResult& truth,
                                const CompareOptions& options, const std::string& prefix,
                                std::vector<WrittenFile>& written) {
    if (options.max_bands < 3 || options.max_bands > brdf::kMaxBakeBands) {
        throw UsageError(str("compare: max_bands must be in [3, ", brdf::kMaxBakeBands, "], got ",
                             options.max_bands));
    }
    const double exposure = options.exposure > 0 ? options.exposure : auto_exposure(truth.radiance);
    nlohmann::json out = {
        {"exposure", exposure},
        {"exposure_rule", options.exposure > 0 ? "given" : "0.18 / mean luminance"},
        {"heat_max_rel", options.heat_max_rel},
        {"rel_floor", options.rel_floor},
        {"supersample", options.supersample},
        {"ground_truth_spp", truth.spp},
        {"ground_truth_rel_error",
         std::isfinite(truth.rel_error) ? nlohmann::json(truth.rel_error) : nlohmann::json()}};

    // Inputs of the model: lighting (exact projection of the same environment pixels) and one
    // BRDF table per material, baked for the camera's view direction.
    RealtimeLighting lighting;
    auto t0 = std::chrono::steady_clock::now();
    lighting.coeffs = project_environment(scene.environment(), options.max_bands);
    const double project_s = seconds_since(t0);
    const brdf::BakeOptions bo = compare_bake_options(scene, options, options.max_bands);
    t0 = std::chrono::steady_clock::now();
    lighting.tables = compare_tables(scene, options, options.max_bands);
    out["inputs"] = {{"lighting_sh_bands", options.max_bands},
                     {"project_time_s", project_s},
                     {"brdf_tables", compare_tables_json(options)},
                     {"brdf_grid", options.tables.empty()
                                       ? options.grid
                                       : brdf::to_string(options.tables.front().grid)},
                     {"brdf_bake_samples", options.bake_samples},
                     {"brdf_bake_time_s", seconds_since(t0)},
                     {"view", {bo.view.x(), bo.view.y(), bo.view.z()}}};
    for (size_t i = 0; i < options.tables.size(); ++i) {
        const double cos_angle = std::clamp(options.tables[i].view.normalized().dot(bo.view), -1.0, 1.0);
        if (cos_angle < std::cos(0.5 * M_PI / 180)) {
            log::warn(str("compare: BRDF table ", i + 1, " was baked for a view ",
                          std::acos(cos_angle) * 180 / M_PI,
                          " deg from the camera's: the model uses it as the app would"));
        }
    }
    if (scene.camera().projection == Projection::kPerspective) {
        log::warn(
            "compare: perspective camera: the BRDF table assumes one view direction "
            "(toward the camera's position), as the app does");
    }

    // Both modes at 3 bands: images, maps, side-by-side PNGs.
    nlohmann::json modes = nlohmann::json::object();
    for (RealtimeMode mode : {RealtimeMode::kConsistent, RealtimeMode::kSeed}) {
        RealtimeOptions ro;
        ro.mode = mode;
        ro.sh_bands = 3;
        ro.supersample = options.supersample;
        const image::Image rt = render_realtime(scene, lighting, ro);
        const Comparison c = compare_images(truth.radiance, rt, exposure, options);
        const std::string name = to_string(mode);
        image::write_image(prefix + "_rt_" + name + ".exr", rt);
        written.push_back({prefix + "_rt_" + name + ".exr", "realtime_radiance", "linear_srgb"});
        image::write_image(prefix + "_compare_" + name + ".png",
                           comparison_figure(c, str("model (", name, ")"), options));
        written.push_back({prefix + "_compare_" + name + ".png", "side_by_side", "srgb"});
        image::write_image(prefix + "_relerr_" + name + ".exr", c.rel_error);
        written.push_back({prefix + "_relerr_" + name + ".exr", "relative_error", "data"});
        image::write_image(prefix + "_de2000_" + name + ".exr", c.de2000);
        written.push_back({prefix + "_de2000_" + name + ".exr", "delta_e2000", "data"});
        modes[name] = metrics_json(c.metrics);
    }
    out["modes"] = modes;

    // Textured scenes: the model at one fragment per pixel (as the GPU draws it) with each
    // texture filter and normal-variance rule (render/realtime.h), beside the supersampled
    // figure above; ratio = its mean relative error over the supersampled one's.
    bool textured = false;
    for (const SurfaceMaterial& m : scene.materials())
        textured = textured || m.albedo_texture || m.normal_texture;
    if (textured) {
        struct Filtering {
            const char* name;
            TextureFilter filter;
            NormalVariance variance;
            MipFilter levels;
            bool gl_lod;
        };
        static constexpr Filtering kFilterings[] = {
            {"bilinear", TextureFilter::kBilinear, NormalVariance::kNone, MipFilter::kBilinear, false},
            {"trilinear_gl_lod", TextureFilter::kTrilinear, NormalVariance::kNone,
             MipFilter::kBilinear, true},
            {"trilinear_box_levels", TextureFilter::kTrilinear, NormalVariance::kNone,
             MipFilter::kBox, false},
            {"trilinear", TextureFilter::kTrilinear, NormalVariance::kNone, MipFilter::kBilinear, false},
            {"trilinear_vmf_diffuse", TextureFilter::kTrilinear, NormalVariance::kDiffuse,
             MipFilter::kBilinear, false},
            {"trilinear_vmf", TextureFilter::kTrilinear, NormalVariance::kDiffuseSpecular,
             MipFilter::kBilinear, false}};
        const double graded = modes["consistent"]["mean_rel"].get<double>();
        nlohmann::json one = nlohmann::json::object();
        for (const Filtering& f : kFilterings) {
            RealtimeOptions ro;
            ro.supersample = 1;
            ro.texture_filter = f.filter;
            ro.normal_variance = f.variance;
            ro.mip_filter = f.levels;
            ro.box_matched_lod = !f.gl_lod;
            const Comparison c =
                compare_images(truth.radiance, render_realtime(scene, lighting, ro), exposure, options);
            nlohmann::json j = metrics_json(c.metrics);
            j["ratio_to_supersampled"] = graded > 0 ? nlohmann::json(c.metrics.mean_rel / graded)
                                                    : nlohmann::json();
            one[f.name] = j;
        }
        out["consistent_one_fragment_per_pixel"] = one;
    }

    // Error and time per frame against the band count (consistent mode). Time per frame is
    // measured with one fragment per pixel (what the GPU shades); error with the supersampling.
    nlohmann::json by_bands = nlohmann::json::array();
    for (int bands = 1; bands <= options.max_bands; ++bands) {
        RealtimeOptions ro;
        ro.sh_bands = bands;
        ro.supersample = 1;
        t0 = std::chrono::steady_clock::now();
        const image::Image once = render_realtime(scene, lighting, ro);
        const double frame_s = seconds_since(t0);
        ro.supersample = options.supersample;
        const image::Image rt =
            options.supersample == 1 ? once : render_realtime(scene, lighting, ro);
        const Comparison c = compare_images(truth.radiance, rt, exposure, options);
        nlohmann::json j = metrics_json(c.metrics);
        j["sh_bands"] = bands;
        j["frame_time_ms"] = 1e3 * frame_s;
        by_bands.push_back(j);
    }
    out["consistent_by_sh_bands"] = by_bands;
    return out;
}

}  // namespace inlight::render
