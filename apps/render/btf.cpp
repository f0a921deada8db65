// render capture-btf and render shade-btf: the synthetic BTF capture of a fabric and the raw
// BTF shaded under environments against the path-traced truth (lib/render/capture_cli.h,
// docs/btf.md).
#include <memory>

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
        render::run_shade(*shade, t->fabric, t->output,
                          capture_options(*t, default_spp, common.seed), *cmp, report);
    };
}

}  // namespace inlight::render_cli
