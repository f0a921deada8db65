#include "render/capture_cli.h"

#include <algorithm>
#include <cmath>

#include "core/json_in.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/json_out.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/validators.h"
#include "btf/compressed.h"
#include "render/btf_shade.h"
#include "render/weave_geometry.h"

#include <filesystem>
#include <numeric>
#include <sstream>

namespace inlight::render {
namespace {

/// Reads a direction file, naming the option in the error.
template <typename Fn>
auto read_option_file(const std::string& option, const std::string& path, Fn read) {
    try {
        return read(path);
    } catch (const Error& e) {
        throw UsageError(str(option, ": ", e.what()));
    }
}

bool same_directions(const std::vector<btf::Direction>& a, const std::vector<btf::Direction>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (btf::angle_between_deg(a[i], b[i]) > 1e-6) return false;
    return true;
}

std::vector<int> compressed_components(const btf::CompressedBtf& c) {
    std::vector<int> out;
    for (size_t g = 0; g < c.manifest().at("groups").size(); ++g) out.push_back(c.components(int(g)));
    return out;
}

/// The bytes a client receives: every file of the folder but the streaming curve's.
uint64_t folder_bytes(const std::string& dir) {
    uint64_t b = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.is_regular_file() && e.path().stem() != "streaming") b += e.file_size();
    return b;
}

/// Bytes a client holds after `n` components of the stream: the row of the folder's
/// streaming.tsv (written by btf-pca: components_sent, bytes_sent, rmse_linear), its last
/// row past the end. Error naming the file when it is missing or malformed.
uint64_t stream_bytes(const std::string& dir, int64_t n) {
    const std::string path = dir + "/streaming.tsv";
    std::istringstream in(fs::read_file(path));
    std::string line;
    uint64_t bytes = 0;
    bool any = false;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream row(line);
        int64_t sent = 0;
        if (!(row >> sent >> bytes)) throw Error(str(path, ": malformed row '", line, "'"));
        any = true;
        if (sent >= n) break;
    }
    if (!any) throw Error(str(path, ": no rows"));
    return bytes;
}

/// The compressed shading against the raw BTF's: RMSE over every pixel and channel relative to
/// the raw image's mean.
nlohmann::json compressed_vs_raw(const image::Image& c, const image::Image& raw) {
    double sq = 0, sum = 0;
    for (size_t i = 0; i < raw.pixels.size(); ++i) {
        sq += std::pow(double(c.pixels[i]) - raw.pixels[i], 2);
        sum += raw.pixels[i];
    }
    const double n = double(std::max<size_t>(raw.pixels.size(), 1));
    return {{"rel_rmse", sum > 0 ? std::sqrt(sq / n) / (sum / n) : 0.0}};
}

}  // namespace

void add_capture_options(CLI::App& app, CaptureArgs& a) {
    app.add_option("--btf-lights", a.lights,
                   "Capture: light directions file (theta_deg phi_deg or x y z per line; default "
                   "the UBO2003 dome)")
        ->check(CLI::ExistingFile);
    app.add_option("--btf-light-set", a.light_set,
                   "Capture: the light directions when no --btf-lights: ubo2003 (the Bonn dome, 81), "
                   "ubo2003-horizon (the dome plus rings of 24 at 80, 84, 87 and 89 deg, 177: light from "
                   "near the horizon measured, not extrapolated) or fibonacci-N (N directions of equal "
                   "solid angle from the pole down to 89 deg, 16 <= N <= 4096; fibonacci-600 shades "
                   "wool, denim and satin within 1% of the truth under 13 rooms and skies where "
                   "ubo2003-horizon is off by up to 3.5%, for 3.4x its images; docs/btf.md \"Light "
                   "beyond the last ring\")")
        ->check(CLI::Validator(
            [](std::string& name) -> std::string {
                try {
                    btf::named_direction_set(name);
                } catch (const Error& e) {
                    return e.what();
                }
                return {};
            },
            "SET"))
        ->excludes("--btf-lights")
        ->capture_default_str();
    app.add_option("--btf-views", a.views, "Capture: view directions file (default the dome)")
        ->check(CLI::ExistingFile);
    app.add_option("--btf-pairs", a.pairs,
                   "Capture: (light, view) pairs file (theta_l phi_l theta_v phi_v per line) "
                   "instead of every light for every view")
        ->check(CLI::ExistingFile)
        ->excludes("--btf-lights")
        ->excludes("--btf-light-set")
        ->excludes("--btf-views");
    app.add_option("--btf-format", a.format,
                   "Capture: png (8-bit sRGB, as Bonn ships) or exr (float, linear_srgb)")
        ->check(CLI::IsMember({"png", "exr"}))
        ->capture_default_str();
    app.add_option("--irradiance-w-m2", a.irradiance_w_m2,
                   "Capture: the point light's irradiance perpendicular to it; images hold "
                   "radiance, btf = image / irradiance (default pi: a white Lambertian plate lit "
                   "from the normal reads 1)")
        ->check(app::finite_range(1e-6, 1e6));
}

void check_capture_folder(const std::string& out_dir) {
    namespace stdfs = std::filesystem;
    std::error_code ec;
    if (stdfs::exists(out_dir, ec)) {
        if (!stdfs::is_directory(out_dir, ec)) {
            throw UsageError(str("-o '", out_dir, "' is an existing file: a capture writes a folder"));
        }
        if (const size_t stale = fs::remove_stale_temporaries(out_dir); stale > 0) {
            log::info(str("render: removed ", log::count(int64_t(stale), "temporary file"),
                          " that a killed capture left in ", out_dir));
        }
        for (stdfs::recursive_directory_iterator it(out_dir, ec), end; !ec && it != end;
             it.increment(ec)) {
            if (!it->is_directory(ec)) {
                throw UsageError(str("-o '", out_dir, "' holds files (", it->path().string(),
                                     "): a capture writes into a new or empty folder"));
            }
        }
    }
    for (const char* f : {"capture.json", "lights.txt", "views.txt"})
        fs::declare_output((stdfs::path(out_dir) / f).string(), "-o");
}

void run_capture(const CaptureArgs& a, const std::string& fabric, const std::string& out_dir,
                 const CaptureOptions& options, Report& report) {
    std::vector<CaptureJob> jobs;
    std::vector<btf::Direction> lights, views;  // the full sets (not --btf-pairs)
    if (!a.pairs.empty()) {
        report.add_input(a.pairs);
        jobs = pair_jobs(read_option_file("--btf-pairs", a.pairs, btf::read_direction_pairs));
    } else {
        lights = btf::named_direction_set(a.light_set);
        views = btf::ubo2003_dome();
        if (!a.lights.empty()) {
            report.add_input(a.lights);
            lights = read_option_file("--btf-lights", a.lights, btf::read_directions);
        }
        if (!a.views.empty()) {
            report.add_input(a.views);
            views = read_option_file("--btf-views", a.views, btf::read_directions);
        }
        jobs = full_jobs(views, lights);
    }
    double max_theta = 0;
    for (const auto& j : jobs) {
        if (!(j.view.vector().z() > 1e-9)) {
            throw UsageError(str(a.pairs.empty() ? "--btf-views" : "--btf-pairs", ": view (",
                                 j.view.theta_deg, ", ", j.view.phi_deg,
                                 ") deg lies in the sample's plane and cannot see it"));
        }
        max_theta = std::max(max_theta, j.view.theta_deg);
        for (const auto& l : j.lights) max_theta = std::max(max_theta, std::min(l.theta_deg, 89.0));
    }
    report.add_input(fabric);
    CaptureOptions opt = options;
    opt.irradiance_w_m2 = a.irradiance_w_m2;
    std::unique_ptr<CaptureScene> scene;
    {
        ScopedStage stage(report, "build fabric");
        auto weave = std::make_shared<weave::Weave>(weave::build(weave::load_weave(fabric)));
        scene = std::make_unique<CaptureScene>(std::move(weave), opt, max_theta);
    }
    CaptureWriteOptions wo;
    wo.extension = a.format;
    CaptureResult r;
    {
        ScopedStage stage(report, "capture");
        // Views finish in order on this thread (capture_btf parallelises inside a view).
        Progress bar("capture views", static_cast<int64_t>(jobs.size()));
        r = capture_btf(*scene, jobs, out_dir, wo, [&bar](int done, int total) {
            bar.add();
            log::verbose(str("capture: view ", done, " / ", total));
        });
    }
    const weave::Weave& w = scene->weave();
    nlohmann::json meta = {
        {"fabric", fabric},
        {"width_px", opt.width_px},
        {"height_px", opt.height_px},
        {"window_mm", {opt.origin_mm.x(), opt.origin_mm.y(), w.period_x_mm, w.period_y_mm}},
        {"irradiance_w_m2", opt.irradiance_w_m2},
        {"values", "reflected radiance, W sr^-1 m^-2, linear_srgb (png: sRGB-encoded, clipped "
                   "to 1); btf = value / irradiance_w_m2"},
        {"frame", "docs/conventions.md, BTF sample frame: +z normal, +x image right, +y image up"},
        {"spp", opt.spp},
        {"seed", opt.seed},
        {"max_depth", opt.max_depth},
        {"views", jobs.size()},
        {"images", r.images}};
    // A set other than the dome travels with the folder: btf::FolderBtf::open reads it from
    // here, so every tool indexes the capture without being told its directions.
    const auto& dome = btf::ubo2003_dome();
    const std::pair<const char*, const std::vector<btf::Direction>*> sets[] = {{"lights", &lights},
                                                                               {"views", &views}};
    for (const auto& [what, set] : sets) {
        if (set->empty() || same_directions(*set, dome)) continue;
        const std::string file = str(what, ".txt");
        fs::write_text_atomic(out_dir + "/" + file,
                              btf::format_directions(*set, str("the capture's ", what, " (theta_deg phi_deg)")));
        meta[str(what == std::string("lights") ? "light" : "view", "_directions")] = file;
    }
    const std::string meta_path = out_dir + "/capture.json";
    fs::write_text_atomic(meta_path, dump_finite(meta, 2, meta_path));
    report.add_output(out_dir, "btf_folder", a.format == "png" ? "srgb" : "linear_srgb");
    report.add_output(meta_path, "btf_capture_metadata", "");
    auto& m = report.metrics();
    m["capture"] = to_json(r);
    m["capture"]["views"] = jobs.size();
    m["capture"]["width_px"] = opt.width_px;
    m["capture"]["height_px"] = opt.height_px;
    m["capture"]["spp"] = opt.spp;
    m["capture"]["segments"] = scene->segments();
    m["capture"]["margin_mm"] = scene->margin_mm();
    m["capture"]["period_mm"] = {w.period_x_mm, w.period_y_mm};
    log::summary("render", "captured",
                 str(log::count(r.images, "image"), " (", log::count(int64_t(jobs.size()), "view"),
                     ") in ", log::num(r.wall_time_s, 3), " s (", log::num(r.images_per_s, 3),
                     " images/s), relative noise median ", log::num(r.rel_error_median), ", p90 ",
                     log::num(r.rel_error_p90)));
}

void add_shade_options(CLI::App& app, ShadeArgs& a) {
    app.add_option("--btf", a.btf,
                   "The raw captured BTF: a `render capture-btf` folder of the positional fabric "
                   "(docs/btf.md)")
        ->required()
        ->check(CLI::ExistingDirectory);
    app.add_option("--environment", a.environments,
                   "BTF shading: lat-long environment (EXR/HDR, +z the fabric normal); repeatable")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("--light-directions", a.light_directions,
                   "BTF shading: the --btf folder's light directions file (default: the set its "
                   "capture.json names, else the UBO2003 dome)")
        ->check(CLI::ExistingFile);
    app.add_option("--view-directions", a.view_directions,
                   "BTF shading: the --btf folder's view directions file (default: the set its "
                   "capture.json names, else the UBO2003 dome)")
        ->check(CLI::ExistingFile);
    app.add_option("--shade-views", a.views,
                   "BTF shading: view directions file (default (0,0), (45,40), (75,0) deg)")
        ->check(CLI::ExistingFile);
    app.add_option("--view-neighbours", a.view_neighbours,
                   "BTF shading: BTF views blended per view (1 nearest, 3 by inverse angle)")
        ->check(CLI::IsMember({1, 3}))
        ->capture_default_str();
    app.add_option("--view-interp", a.view_interp,
                   "BTF shading: blend the BTF's views by angular interpolation instead (thesis: "
                   "three closest per ring; delaunay: spherical Delaunay triangle)")
        ->check(CLI::IsMember({"thesis", "delaunay"}))
        ->excludes("--view-neighbours");
    app.add_option("--light-cells", a.cell_rule,
                   "BTF shading: a light direction's weight: cosine-barycentric (the image's ratio to "
                   "the cosine linear over the light directions' triangles: exact for a Lambertian "
                   "sample, a light between directions spread over three) or cosine (that ratio "
                   "constant over each direction's cell) or constant (the image constant over the "
                   "cell, the thesis' rule: too bright where light comes from near the horizon) or "
                   "barycentric (images linear over the triangles, black at the horizon) or "
                   "extrapolated (cosine, with the ratio continued linearly beyond the last ring); "
                   "measured against each other in docs/btf.md")
        ->check(CLI::IsMember({"constant", "cosine", "barycentric", "extrapolated", "cosine-barycentric"}))
        ->capture_default_str();
    app.add_option("--cell-subsamples", a.subsamples,
                   "BTF shading: directions per map pixel side when integrating light cells")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    app.add_option("--btf-compressed", a.compressed,
                   "BTF shading: a btf-pca output folder of the same BTF, shaded beside the raw one "
                   "(environment folded into component weights) and compared; repeatable")
        ->check(CLI::ExistingDirectory);
    app.add_option("--shade-stream", a.stream_points,
                   "BTF shading: also shade each --btf-compressed folder from the first n components "
                   "of its stream, for each n in this list (error against bytes sent)")
        ->delimiter(',')
        ->check(CLI::Range(int64_t(0), int64_t(1) << 40))
        ->needs("--btf-compressed");
    app.add_option("--gles-bands", a.gles_bands,
                   "BTF shading: also draw each --btf-compressed folder through its exported GLES "
                   "shaders (btf-pca export-gles, docs/btf-gles.md) on this machine's OpenGL ES, "
                   "lit by this many SH bands of the environment, at every --shade-stream point "
                   "and for the whole stream, and compare with the truth (1..9; 0 = not)")
        ->check(CLI::Range(0, 9))
        ->needs("--btf-compressed");
    app.add_option("--gles-lights", a.gles_lights,
                   "BTF shading: with --gles-bands, take up to this many dominant lights out of each "
                   "environment first (as envmap-project's light extraction) and light the GLES pictures "
                   "with them plus the residual's SH (0..8)")
        ->check(CLI::Range(0, 8))
        ->needs("--gles-bands")
        ->capture_default_str();
}

void run_shade(const ShadeArgs& a, const std::string& fabric, const std::string& prefix,
               const CaptureOptions& truth_options, const CompareOptions& compare,
               Report& report, const GlesDrawer* gles) {
    if (a.gles_bands > 0 && !gles) throw Error("render shade-btf: --gles-bands needs a GLES drawer");
    std::vector<btf::Direction> views = {{0, 0}, {45, 40}, {75, 0}};
    if (!a.views.empty()) {
        report.add_input(a.views);
        views = read_option_file("--shade-views", a.views, btf::read_directions);
    }
    const std::string meta_path = a.btf + "/capture.json";
    const nlohmann::json meta = json_in::read_file(meta_path);
    report.add_input(meta_path);
    report.add_input(fabric);
    double irradiance = 0;
    std::vector<double> window;
    try {  // value() throws on a key of another type or on a document that is not an object
        irradiance = meta.value("irradiance_w_m2", 0.0);
        window = meta.value("window_mm", std::vector<double>{});
    } catch (const nlohmann::json::exception& e) {
        throw Error(str(meta_path, ": not a capture description: ", e.what()));
    }
    if (!(irradiance > 0) || window.size() != 4) {
        throw Error(str(meta_path, ": needs irradiance_w_m2 > 0 and window_mm [x, y, w, h]"));
    }
    std::unique_ptr<btf::FolderBtf> btf;
    {
        ScopedStage stage(report, "open BTF");
        btf::OpenOptions open;
        open.light_directions = a.light_directions;
        open.view_directions = a.view_directions;
        for (const std::string* f : {&a.light_directions, &a.view_directions})
            if (!f->empty()) report.add_input(*f);
        btf = btf::FolderBtf::open(a.btf, open);
    }
    std::vector<std::unique_ptr<btf::CompressedBtf>> compressed;
    for (const std::string& dir : a.compressed) {
        ScopedStage stage(report, "open " + dir);
        fs::declare_input(dir, "--btf-compressed");
        compressed.push_back(btf::CompressedBtf::open(dir));
        const btf::BtfShape &c = compressed.back()->shape(), &r = btf->shape();
        if (c.width != r.width || c.height != r.height || !same_directions(c.lights, r.lights) ||
            !same_directions(c.views, r.views))
            throw UsageError(str("--btf-compressed ", dir, ": its image size or directions differ from ", a.btf, "'s"));
    }
    if (a.gles_bands > 0) {
        ScopedStage stage(report, "export GLES shaders");
        for (size_t i = 0; i < compressed.size(); ++i) gles->prepare(i, irradiance);
    }
    auto weave = std::make_shared<weave::Weave>(weave::build(weave::load_weave(fabric)));
    if (std::abs(weave->period_x_mm - window[2]) > 1e-9 ||
        std::abs(weave->period_y_mm - window[3]) > 1e-9) {
        throw UsageError(str("--btf: ", a.btf, " was captured from a ", window[2], " x ",
                             window[3], " mm repeat, not ", fabric, "'s ", weave->period_x_mm,
                             " x ", weave->period_y_mm, " mm"));
    }
    CaptureOptions topt = truth_options;
    topt.width_px = btf->shape().width;
    topt.height_px = btf->shape().height;
    topt.origin_mm = {window[0], window[1]};
    std::unique_ptr<btf::DirectionInterpolator> view_interp;
    if (!a.view_interp.empty())
        view_interp = btf::make_interpolator(btf::interp_scheme_from_string(a.view_interp), btf->shape().views);
    nlohmann::json results = nlohmann::json::array();
    for (const std::string& env_path : a.environments) {
        report.add_input(env_path);
        EnvironmentSpec env;
        env.image = load_latlong(env_path);
        btf::DomeLightingOptions lo;
        lo.subsamples = a.subsamples;
        lo.rule = btf::cell_rule_from_string(a.cell_rule);
        const btf::DomeLighting lighting =
            btf::integrate_dome_cells(env.image, btf->shape().lights, lo);
        const std::string stem = std::filesystem::path(env_path).stem().string();
        for (const btf::Direction& view : views) {
            ScopedStage stage(report, str("shade ", stem, " ", btf::ubo2003_view_folder(view)));
            const ViewBlend blend = view_interp ? interpolate_views(*view_interp, view)
                                                : select_views(btf->shape().views, view, a.view_neighbours);
            const image::Image shaded = shade_btf(*btf, lighting, blend, irradiance);
            double truth_noise = 0;
            const image::Image truth =
                truth_under_environment(weave, topt, env, view, &truth_noise);
            const double exposure = compare.exposure > 0 ? compare.exposure : auto_exposure(truth);
            const Comparison c = compare_images(truth, shaded, exposure, compare);
            const std::string base = str(prefix, "_", stem, "_", btf::ubo2003_view_folder(view));
            image::WriteOptions exr;
            image::write_image(base + "_btf.exr", shaded, exr);
            image::write_image(base + "_truth.exr", truth, exr);
            image::write_image(base + "_relerr.exr", c.rel_error, exr);
            image::write_image(base + "_compare.png", comparison_figure(c, "shaded BTF", compare));
            report.add_output(base + "_btf.exr", "radiance", "linear_srgb");
            report.add_output(base + "_truth.exr", "radiance", "linear_srgb");
            report.add_output(base + "_relerr.exr", "relative_error", "data");
            report.add_output(base + "_compare.png", "comparison", "srgb");
            auto mean_y = [](const image::Image& img) {
                double s = 0;
                for (size_t i = 0; i < img.pixel_count(); ++i)
                    s += 0.2126 * img.pixels[3 * i] + 0.7152 * img.pixels[3 * i + 1] +
                         0.0722 * img.pixels[3 * i + 2];
                return s / static_cast<double>(img.pixel_count());
            };
            const double ty = mean_y(truth), by = mean_y(shaded);
            nlohmann::json j = metrics_json(c.metrics);
            j["environment"] = env_path;
            j["view_deg"] = {view.theta_deg, view.phi_deg};
            j["btf_views"] = blend.views.size();
            j["mean_luminance_rel_diff"] = ty > 0 ? (by - ty) / ty : 0.0;
            j["truth_rel_error"] = std::isfinite(truth_noise) ? nlohmann::json(truth_noise)
                                                              : nlohmann::json();
            j["exposure"] = exposure;
            j["compressed"] = nlohmann::json::array();
            for (size_t i = 0; i < compressed.size(); ++i) {
                const image::Image cs = shade_btf(*compressed[i], lighting, blend, irradiance);
                const Comparison cc = compare_images(truth, cs, exposure, compare);
                const std::string path = str(base, "_pca", i, ".exr");
                image::write_image(path, cs, exr);
                report.add_output(path, "radiance", "linear_srgb");
                nlohmann::json cj = metrics_json(cc.metrics);
                cj["folder"] = a.compressed[i];
                cj["components_per_group"] = compressed_components(*compressed[i]);
                cj["stored_bytes"] = folder_bytes(a.compressed[i]);
                cj["mean_luminance_rel_diff"] = ty > 0 ? (mean_y(cs) - ty) / ty : 0.0;
                cj["vs_raw"] = compressed_vs_raw(cs, shaded);
                cj["stream"] = nlohmann::json::array();
                const auto terms = btf::shading_terms(lighting, blend.views, blend.weights, irradiance);
                for (int64_t n : a.stream_points) {
                    const image::Image ps = compressed[i]->combine_streamed(terms, n);
                    const Comparison pc = compare_images(truth, ps, exposure, compare);
                    cj["stream"].push_back({{"components_sent", std::min(n, compressed[i]->stream_length())},
                                            {"bytes_sent", stream_bytes(a.compressed[i], n)},
                                            {"mean_rel", pc.metrics.mean_rel},
                                            {"mean_de2000", pc.metrics.mean_de2000},
                                            {"mean_luminance_rel_diff", ty > 0 ? (mean_y(ps) - ty) / ty : 0.0},
                                            {"vs_raw", compressed_vs_raw(ps, shaded)}});
                }
                if (a.gles_bands > 0) {
                    // The exported shaders' pictures: at every stream point, then the whole stream
                    // (n < 0), each beside the compressed CPU shading at the same prefix.
                    cj["gles"] = nlohmann::json::array();
                    std::vector<int64_t> points = a.stream_points;
                    points.push_back(-1);
                    for (int64_t n : points) {
                        const int64_t sent = n < 0 ? compressed[i]->stream_length()
                                                   : std::min(n, compressed[i]->stream_length());
                        const image::Image cpu = compressed[i]->combine_streamed(terms, sent);
                        for (const GlesPicture& pic : gles->draw(i, env_path, env.image, view, sent)) {
                            const Comparison gc = compare_images(truth, pic.radiance, exposure, compare);
                            nlohmann::json gj = metrics_json(gc.metrics);
                            gj["variant"] = pic.variant;
                            gj["sh_bands"] = a.gles_bands;
                            gj["lights"] = pic.lights;
                            gj["components_sent"] = sent;
                            gj["bytes_sent"] = stream_bytes(a.compressed[i], sent);
                            gj["mean_luminance_rel_diff"] = ty > 0 ? (mean_y(pic.radiance) - ty) / ty : 0.0;
                            gj["vs_cpu_compressed"] = compressed_vs_raw(pic.radiance, cpu);
                            if (n < 0) {
                                const std::string pic_path = str(base, "_pca", i, "_", pic.variant, ".exr");
                                image::write_image(pic_path, pic.radiance, exr);
                                report.add_output(pic_path, "radiance", "linear_srgb");
                            }
                            cj["gles"].push_back(gj);
                        }
                    }
                }
                j["compressed"].push_back(cj);
            }
            j["below_horizon_share"] =
                lighting.below_horizon.sum() /
                std::max(1e-30, lighting.below_horizon.sum() +
                                    std::accumulate(lighting.weight.begin(), lighting.weight.end(),
                                                    Eigen::Vector3d(Eigen::Vector3d::Zero()))
                                        .sum());
            log::summary("render", str("shaded BTF vs path-traced truth (", stem, ", view ",
                                       view.theta_deg, "/", view.phi_deg, ")"),
                         str("mean relative error ", log::num(c.metrics.mean_rel),
                             ", mean luminance ", log::num(100 * (by - ty) / std::max(ty, 1e-30), 3),
                             "% off (truth noise ", log::num(truth_noise, 3), ")"));
            results.push_back(j);
        }
    }
    report.metrics()["btf_shade"] = {{"spp", topt.spp},
                                      {"view_neighbours", a.view_neighbours},
                                      {"view_interp", a.view_interp},
                                      {"results", results}};
}

}  // namespace inlight::render
