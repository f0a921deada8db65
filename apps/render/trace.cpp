// render trace: the path-traced image and its per-pixel standard error.
#include <memory>

#include "modes.h"

namespace inlight::render_cli {

ModeBody add_trace(CLI::App& app, const app::CommonArgs& common) {
    auto a = std::make_shared<TraceArgs>();
    add_trace_options(app, *a);
    return [a, &common](Report& report) {
        prepare_trace(*a, common.seed, report);
        const auto scene = load_scene(a->scene, a->width_px, a->height_px, report);
        const render::RenderResult r = trace(*scene, *a, report);
        check_quality_gate(*a, r);
    };
}

}  // namespace inlight::render_cli
