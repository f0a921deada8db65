// render capture-btf and render shade-btf: the synthetic BTF capture of a fabric and the raw
// BTF shaded under environments against the path-traced truth (lib/render/capture_cli.h,
// docs/btf.md).
#include <filesystem>
#include <map>
#include <memory>

#include "core/error.h"
#include "core/fs.h"
#include "core/json_in.h"
#include "envmap/lights.h"
#include "envmap/project.h"
#include "gles/btf_draw.h"
#include "render/capture_cli.h"
#include "modes.h"

namespace inlight::render_cli {
namespace {

/// The path tracer's flags a capture or its truth uses.
struct CaptureTraceArgs {
    std::string fabric, output;
    int width_px = 0, height_px = 0, spp = 0;  ///< 0 = the capture's defaults (not given)
    bool no_jitter = false;
    render::RenderOptions opt;
};

void add_capture_trace_options(CLI::App& app, CaptureTraceArgs& a, const std::string& output_help,
                               int default_spp) {
    app.add_option("fabric", a.fabric, "Fabric file (configs/fabrics/*.toml, docs/btf.md)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", a.output, output_help)->required();
    render::CaptureOptions defaults;
    add_size_options(app, a.width_px, a.height_px,
                     str(defaults.width_px, " x ", defaults.height_px, ")"));
    app.add_option("--spp", a.spp, str("Samples per pixel (default ", default_spp, ")"))
        ->check(CLI::Range(1, 1 << 20));
    add_path_options(app, a.opt, a.no_jitter);
}

render::CaptureOptions capture_options(const CaptureTraceArgs& a, int default_spp,
                                       uint64_t seed) {
    render::CaptureOptions co;
    co.width_px = a.width_px > 0 ? a.width_px : co.width_px;
    co.height_px = a.height_px > 0 ? a.height_px : co.height_px;
    co.spp = a.spp > 0 ? a.spp : default_spp;
    co.seed = seed;
    co.max_depth = a.opt.max_depth;
    co.rr_depth = a.opt.rr_depth;
    co.jitter = !a.no_jitter;
    co.tile_px = a.opt.tile_px;
    return co;
}

/// shade-btf's GLES pictures: each --btf-compressed folder exported in memory as `btf-pca
/// export-gles` would (the shade's cell rule, the capture's irradiance) and drawn by every
/// variant that can show the prefix, each in a context of its own version. A folder that ships
/// its export (btf-gles.json beside btf-pca.json, as a bundle's btf/ does) must hold the same
/// bytes as this export, file for file, so what is graded is what ships.
class BtfGlesPictures {
public:
    explicit BtfGlesPictures(const render::ShadeArgs& a) : m_args(a) {}

    /// Exports folder `folder` (once).
    void prepare(size_t folder, double irradiance_w_m2) { exported(folder, irradiance_w_m2); }

    std::vector<render::GlesPicture> draw(size_t folder, const std::string& env_path, const image::Image& env,
                                          const btf::Direction& view, int64_t sent) {
        const gles::BtfGlesExport& e = m_exports.at(folder);
        auto it = m_lighting.find(env_path);
        if (it == m_lighting.end()) it = m_lighting.emplace(env_path, frame_lighting(env)).first;
        std::vector<render::GlesPicture> out;
        for (const gles::BtfGlesVariant& v : e.variants) {
            const gles::Context context(v.version == gles::GlslVersion::kEs300 ? 3 : 2);
            out.push_back({v.name, gles::draw_btf(context, e, v, view, it->second.sh, sent, nullptr, it->second.lights),
                           static_cast<int>(it->second.lights.size())});
        }
        return out;
    }

private:
    struct FrameLighting {
        Eigen::MatrixXd sh;
        std::vector<gles::BtfLight> lights;
    };
    /// The app's lighting of `env` (sample frame): its dominant lights (at most --gles-lights,
    /// envmap's extraction with its defaults) and the residual map's SH.
    FrameLighting frame_lighting(const image::Image& env) const {
        envmap::Environment map;
        map.radiance = env;
        FrameLighting f;
        if (m_args.gles_lights > 0) {
            envmap::ExtractOptions eo;
            eo.max_lights = m_args.gles_lights;
            const envmap::Extraction x = envmap::extract_lights(map, eo);
            for (const envmap::DirectionalLight& l : x.lights)
                f.lights.push_back({l.direction, l.flux, l.angular_radius});
            map = envmap::residual_environment(map, x, static_cast<int>(x.lights.size()));
        }
        f.sh = envmap::project_latlong(map.radiance, m_args.gles_bands);
        return f;
    }

    const gles::BtfGlesExport& exported(size_t folder, double irradiance_w_m2) {
        auto it = m_exports.find(folder);
        if (it != m_exports.end()) return it->second;
        const std::string& dir = m_args.compressed[folder];
        gles::BtfGlesOptions o;
        o.sh_bands = m_args.gles_bands;
        o.irradiance_w_m2 = irradiance_w_m2;
        o.lighting.rule = btf::cell_rule_from_string(m_args.cell_rule);
        o.lighting.subsamples = m_args.subsamples;
        const std::string shipped = dir + "/btf-gles.json";
        if (std::filesystem::exists(shipped)) {
            // A bundle ships no atlases (btf-pca export-gles --atlases none): export as shipped.
            const nlohmann::json m = json_in::read_file(shipped);
            const nlohmann::json::json_pointer atlas_files("/textures/atlas_files");
            o.write_atlases = !(m.contains(atlas_files) && m.at(atlas_files) == false);
        }
        gles::BtfGlesExport e = gles::export_btf_gles(dir, o);
        if (std::filesystem::exists(shipped)) {
            for (const auto& [name, bytes] : e.files()) {
                const std::string path = dir + "/" + name;
                if (fs::read_file(path) != bytes)
                    throw Error(str(path, ": differs from btf-pca export-gles of ", dir, " with --bands ",
                                    m_args.gles_bands, ", --irradiance-w-m2 ", irradiance_w_m2, " and the cell rule ",
                                    m_args.cell_rule, ": the shipped export is not the one drawn here"));
            }
        }
        return m_exports.emplace(folder, std::move(e)).first->second;
    }

    const render::ShadeArgs& m_args;
    std::map<size_t, gles::BtfGlesExport> m_exports;
    std::map<std::string, FrameLighting> m_lighting;
};

}  // namespace

ModeBody add_capture_btf(CLI::App& app, const app::CommonArgs& common) {
    auto t = std::make_shared<CaptureTraceArgs>();
    auto cap = std::make_shared<render::CaptureArgs>();
    add_capture_trace_options(app, *t,
                              "Capture folder: one image per (light, view) in UBO2003 naming, "
                              "one folder per view, and capture.json",
                              cap->default_spp);
    render::add_capture_options(app, *cap);
    return [t, cap, &common](Report& report) {
        render::check_capture_folder(t->output);
        render::run_capture(*cap, t->fabric, t->output,
                            capture_options(*t, cap->default_spp, common.seed), report);
    };
}

ModeBody add_shade_btf(CLI::App& app, const app::CommonArgs& common) {
    auto t = std::make_shared<CaptureTraceArgs>();
    auto shade = std::make_shared<render::ShadeArgs>();
    auto cmp = std::make_shared<render::CompareOptions>();
    const int default_spp = render::CaptureArgs{}.default_spp;
    add_capture_trace_options(app, *t,
                              "File prefix of the shaded, truth and comparison images",
                              default_spp);
    render::add_shade_options(app, *shade);
    add_image_compare_options(app, *cmp);
    return [t, shade, cmp, default_spp, &common](Report& report) {
        BtfGlesPictures pictures(*shade);
        render::GlesDrawer drawer;
        drawer.prepare = [&pictures](size_t folder, double irradiance_w_m2) { pictures.prepare(folder, irradiance_w_m2); };
        drawer.draw = [&pictures](size_t folder, const std::string& env_path, const image::Image& env,
                                  const btf::Direction& view, int64_t sent) {
            return pictures.draw(folder, env_path, env, view, sent);
        };
        render::run_shade(*shade, t->fabric, t->output, capture_options(*t, default_spp, common.seed), *cmp,
                          report, shade->gles_bands > 0 ? &drawer : nullptr);
    };
}

}  // namespace inlight::render_cli
