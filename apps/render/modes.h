// apps/render/modes.h: render's subcommands (docs/render.md "Usage"). Each registers only its own
// options on its CLI::App and returns its body, a thin function over lib/render and lib/gles that
// app::run calls; the path tracer's options are registered by one helper shared by trace,
// compare and convergence.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/app.h"
#include "core/report.h"
#include "render/compare.h"
#include "render/path_tracer.h"
#include "render/scene.h"

namespace inlight::render_cli {

/// A subcommand's body, run inside app::run after parsing.
using ModeBody = std::function<void(Report&)>;

/// The flags of a path-traced image: the scene, -o and the path tracer's options.
struct TraceArgs {
    std::string scene, output, stderr_output, strategy = "mis", sampler = "sobol";
    int width_px = 0, height_px = 0;  ///< camera overrides, 0 = the scene's
    bool no_jitter = false;
    double max_rel_error = 0;  ///< quality gate on the final relative noise, 0 = off
    render::RenderOptions opt;
};

/// Registers --width-px and --height-px (0 = the scene's camera; `what` ends the help text).
void add_size_options(CLI::App& app, int& width_px, int& height_px, const std::string& what);

/// Registers --max-depth, --rr-depth, --tile-px and --no-jitter.
void add_path_options(CLI::App& app, render::RenderOptions& opt, bool& no_jitter);

/// Registers SCENE, -o, --stderr-output, the sizes, the path options, --spp and its stop rules,
/// --strategy, --sampler, the adaptive sampling options and --max-rel-error.
void add_trace_options(CLI::App& app, TraceArgs& args);

/// Registers --exposure and --heat-max-rel (the PNG panels and dE2000 of compare and shade-btf).
void add_image_compare_options(CLI::App& app, render::CompareOptions& cmp);

/// Registers --<prefix>grid and --<prefix>bake-samples (the BRDF tables baked per material).
void add_bake_options(CLI::App& app, render::CompareOptions& cmp, const std::string& prefix);

/// Before any work: resolves args.opt from the flags and --seed, checks -o and --stderr-output
/// (default <output>_stderr.exr) and declares them the run's outputs.
void prepare_trace(TraceArgs& args, uint64_t seed, Report& report);

/// Loads the scene file with the camera overrides (0 = the scene's), its files as inputs.
std::unique_ptr<render::Scene> load_scene(const std::string& path, int width_px, int height_px,
                                          Report& report);

/// Path traces `scene`, writes the radiance and its standard error, sets the render metrics and
/// prints the summary line.
render::RenderResult trace(const render::Scene& scene, const TraceArgs& args, Report& report);

/// --max-rel-error: throws app::QualityGateFailed (exit 3, outputs kept) when the final relative
/// noise exceeds it.
void check_quality_gate(const TraceArgs& args, const render::RenderResult& result);

// The subcommands (one file each): register the options on `app` and return the body.
ModeBody add_trace(CLI::App& app, const app::CommonArgs& common);
ModeBody add_compare(CLI::App& app, const app::CommonArgs& common);
ModeBody add_convergence(CLI::App& app, const app::CommonArgs& common);
ModeBody add_capture_btf(CLI::App& app, const app::CommonArgs& common);
ModeBody add_shade_btf(CLI::App& app, const app::CommonArgs& common);
ModeBody add_export_gles(CLI::App& app, const app::CommonArgs& common);

}  // namespace inlight::render_cli
