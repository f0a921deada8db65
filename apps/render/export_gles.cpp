// render export-gles: GLES shaders, manifests and BRDF tables of every material of a scene for
// the app (docs/gles.md). No path tracing: only the materials and the camera's view direction
// (each table is baked for the view toward the camera) are used.
#include <memory>

#include "gles/cli.h"
#include "gles/scene.h"
#include "modes.h"

namespace inlight::render_cli {
namespace {

struct ExportGlesArgs {
    std::string scene;
    gles::ExportArgs gles;
    render::CompareOptions bake;  ///< grid and bake_samples
};

}  // namespace

ModeBody add_export_gles(CLI::App& app, const app::CommonArgs&) {
    auto a = std::make_shared<ExportGlesArgs>();
    app.add_option("scene", a->scene, "Scene file (.toml, see docs/render.md)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", a->gles.dir,
                   "Folder of the GLES vertex + fragment shaders, manifests (index.json) and "
                   "BRDF data of every variant (docs/gles.md)")
        ->required();
    a->gles.dir_option = "-o";
    gles::add_export_options(app, a->gles, false);
    add_bake_options(app, a->bake, "");
    return [a](Report& report) {
        report.add_input(a->scene);
        gles::SceneExportOptions options;
        options.set = a->gles.prepare(report);
        options.grid = a->bake.grid;
        options.bake_samples = a->bake.bake_samples;
        const auto scene = load_scene(a->scene, 0, 0, report);
        // Every variant is built first on tables of the baked shape, so one that does not fit is
        // refused before the bakes.
        gles::check_before_work([&] { gles::check_scene_export(*scene, options); }, "");
        ScopedStage stage(report, "export gles");
        const auto exports = gles::export_scene(*scene, options);
        for (const auto& path : gles::write_exports(a->gles.dir, exports)) {
            report.add_output(path, "gles_export");
        }
        report.metrics()["gles_export"] = {{"dir", a->gles.dir}, {"variants", exports.size()}};
    };
}

}  // namespace inlight::render_cli
