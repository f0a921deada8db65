// render: the ground-truth path tracer (Embree) and what is measured with it (docs/render.md).
//   render trace:        a scene -> float EXR (linear_srgb) and its per-pixel standard error,
//                        progressively, deterministically for a seed and any --threads
//   render compare:      trace + the real-time model (CPU and GLES) compared with it
//   render convergence:  trace + its error against samples per pixel
//   render capture-btf:  a fabric's synthetic BTF capture
//   render shade-btf:    a captured BTF shaded under environments against the path tracer
//   render export-gles:  GLES shaders and BRDF tables of a scene's materials
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "core/app.h"
#include "core/modes.h"
#include "modes.h"

namespace {

using inlight::render_cli::ModeBody;

struct Mode {
    const char* name;
    const char* purpose;
    const char* example;
    ModeBody (*add)(CLI::App&, const inlight::app::CommonArgs&);
};

const Mode kModes[] = {
    {"trace",
     "render trace: path trace a scene file into a float EXR (linear_srgb) and its per-pixel "
     "standard error",
     "render trace configs/scenes/patch_city.toml -o patch.exr --spp 256 --seed 7 --threads 2 "
     "--report patch.json",
     inlight::render_cli::add_trace},
    {"compare",
     "render compare: path trace, then run the real-time model (consistent and seed modes, bands "
     "1..--rt-max-bands) on the CPU and through the exported GLES shaders (EGL) and compare "
     "them with the path tracer: <output>_rt_*, _compare_*.png, _relerr_*, _de2000_*, "
     "_gles_*, _compare3_*.png, metrics.realtime",
     "render compare configs/scenes/patch_city.toml -o patch.exr --spp 64 --report patch.json",
     inlight::render_cli::add_compare},
    {"convergence",
     "render convergence: path trace, and measure the error against samples per pixel (1, 4, "
     "16, ... --spp) against a reference: metrics.convergence",
     "render convergence configs/scenes/sphere_furnace.toml -o furnace.exr --no-jitter --spp 256 "
     "--ref-irradiance --report furnace.json",
     inlight::render_cli::add_convergence},
    {"capture-btf",
     "render capture-btf: synthetic BTF capture of a fabric file: one image per (light, view) "
     "in UBO2003 naming, one folder per view (docs/btf.md)",
     "render capture-btf configs/fabrics/satin.toml -o out/satin_btf --btf-format exr",
     inlight::render_cli::add_capture_btf},
    {"shade-btf",
     "render shade-btf: shade a raw captured BTF under each --environment and compare it with "
     "the path-traced truth of the same geometry (docs/btf.md)",
     "render shade-btf configs/fabrics/satin.toml --btf out/satin_btf --environment sky.exr "
     "-o out/satin_shade",
     inlight::render_cli::add_shade_btf},
    {"export-gles",
     "render export-gles: GLES vertex + fragment shaders, manifests and BRDF tables of every "
     "material of a scene, without rendering (docs/gles.md)",
     "render export-gles configs/scenes/patch_city.toml -o out/gles",
     inlight::render_cli::add_export_gles},
};

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

/// A flag that chose a mode before the subcommands.
bool old_mode_flag(const std::string& a) {
    for (const char* f : {"--compare", "--rt-decompose", "--convergence-ref-", "--btf-capture",
                          "--btf-shade", "--export-gles"})
        if (starts_with(a, f)) return true;
    return false;
}

/// The subcommand an old command line (flags for a mode, no subcommand) meant.
const char* old_mode(int argc, char** argv) {
    const char* mode = "trace";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto starts = [&](const char* p) { return starts_with(a, p); };
        if (starts("--btf-capture")) return "capture-btf FABRIC -o FOLDER";
        if (starts("--btf-shade")) return "shade-btf FABRIC --btf FOLDER --environment ENV -o PREFIX";
        if (starts("--compare") || starts("--rt-") || starts("--brdf-table")) mode = "compare";
        if (starts("--convergence-ref")) return "convergence SCENE -o OUT --ref-spp N";
        if (starts("--export-gles") && std::strcmp(mode, "trace") == 0) mode = "export-gles";
    }
    if (std::strcmp(mode, "compare") == 0) return "compare SCENE -o OUT";
    if (std::strcmp(mode, "export-gles") == 0) return "export-gles SCENE -o DIR";
    return "trace SCENE -o OUT";
}

}  // namespace

int main(int argc, char** argv) {
    using namespace inlight;
    const std::string mode = argc > 1 ? argv[1] : "";
    for (const Mode& md : kModes) {
        if (mode != md.name) continue;
        CLI::App app{md.purpose, std::string("render ") + md.name};
        app::CommonArgs common;
        const ModeBody body = md.add(app, common);
        app::setup(app, common, md.example);
        if (auto code = app::parse(app, argc, argv, 1)) return *code;
        return app::run("render", app, common, argc, argv, body);
    }

    // A scene file or a mode's flags without a subcommand: the command line of an older render.
    bool old = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help" || a == "--version") break;
        const bool scene = !a.empty() && a[0] != '-' &&
                           (std::filesystem::is_regular_file(a) ||
                            std::filesystem::path(a).extension() == ".toml");
        if (scene || old_mode_flag(a)) old = true;
    }
    if (old) {
        std::cerr << "render: modes are subcommands now: use 'render " << old_mode(argc, argv)
                  << "' (see render --help)\n";
        return app::kExitUsage;
    }

    std::vector<app::ModeHelp> modes;
    for (const Mode& md : kModes) modes.push_back({md.name, md.purpose, md.example});
    return app::list_modes("render",
                           "render: ground-truth path tracer (Embree) of a scene file, and what "
                           "is measured with it",
                           modes, "0 ok, 1 runtime error, 2 usage error, 3 quality gate failed.",
                           argc, argv);
}
