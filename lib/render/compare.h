// render/compare.h: the real-time model against the path tracer: per-pixel error maps
// (relative error; CIEDE2000 after a stated exposure), summary metrics, side-by-side PNGs
// (ground truth | real-time | relative-error heat map), the error by SH band count with the
// model's time per frame, and both shading modes (render/realtime.h).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdf/bake.h"
#include "image/figure.h"
#include "image/image.h"
#include "image/metrics.h"
#include "render/path_tracer.h"
#include "render/realtime.h"
#include "render/scene.h"

namespace inlight::render {

struct CompareOptions {
    /// Linear scale applied before CIELAB (dE2000) and before the PNG panels; 0 = automatic:
    /// 0.18 / (mean luminance of the ground truth), i.e. the image average maps to middle grey.
    double exposure = 0;
    double heat_max_rel = 0.5;     ///< relative error shown at the top of the heat map's scale
    double rel_floor = 1e-3;       ///< relative errors divide by max(|truth|, rel_floor)
    int max_bands = 5;             ///< band sweep 1..max_bands (lighting and BRDF table)
    int bake_samples = 4096;       ///< brdf::bake integrand evaluations per normal
    std::string grid = "octa:17";  ///< brdf::parse_grid spec of the BRDF table
    int supersample = 4;           ///< real-time fragments per pixel side (see RealtimeOptions)
    /// The BRDF tables to validate, one per scene material in scene order (render
    /// --brdf-table: what brdf-sh-bake wrote), each with at least the bands the compare uses.
    /// Empty: each material is baked here at `grid` and `bake_samples` for the camera's view.
    std::vector<brdf::Table> tables;
    /// render compare's GLES column (gles::compare_scene): the texture filter of the variants it
    /// draws and of the CPU model (one fragment per pixel) it compares them with.
    TextureFilter gles_texture_filter = TextureFilter::kBilinear;
};

/// The bake options of the compare's own BRDF tables: `bands` (at most brdf::kMaxBakeBands),
/// options' samples, the view toward the camera's position.
brdf::BakeOptions compare_bake_options(const Scene& scene, const CompareOptions& options,
                                       int bands);
/// One BRDF table per scene material at `bands`: options.tables' first `bands` bands when
/// given (Error when one has fewer, or their count is not the materials'), else baked with
/// compare_bake_options on options.grid.
std::vector<brdf::Table> compare_tables(const Scene& scene, const CompareOptions& options,
                                        int bands);
/// Where the compare's tables come from, for the report: {"source": "given", "grid", "sh_bands"}
/// or {"source": "baked", "grid", "samples", "why"}.
nlohmann::json compare_tables_json(const CompareOptions& options);

/// Error images and metrics of `test` against `truth` (same size, linear_srgb).
struct Comparison {
    image::Metrics metrics;
    image::Image rel_error;     ///< 1 channel, data
    image::Image de2000;        ///< 1 channel, data, after `exposure`
    image::Image side_by_side;  ///< 3 panels, linear_srgb, already multiplied by exposure
};
Comparison compare_images(const image::Image& truth, const image::Image& test, double exposure,
                          const CompareOptions& options);

/// The side-by-side PNG as people read it (docs/render.md, "Comparison images"): c.side_by_side's
/// panels (truth | `model` | relative-error heat map) captioned, enlarged to >= 256 px
/// (image::figure), under a title saying what is compared, with the heat map's colour bar
/// (0 to options.heat_max_rel, relative error). `extra` panels (same height) go between the
/// truth and the model, e.g. the CPU model before the GLES one.
image::Image comparison_figure(const Comparison& c, const std::string& model,
                               const CompareOptions& options,
                               const std::vector<image::FigurePanel>& extra = {});

/// Report form of image::Metrics (PSNR null when infinite).
nlohmann::json metrics_json(const image::Metrics& m);

/// The exposure CompareOptions::exposure = 0 stands for: 0.18 / mean luminance (1 if black).
double auto_exposure(const image::Image& truth);

/// An output file written by compare_realtime.
struct WrittenFile {
    std::string path, kind, color_space;
};

/// Runs the real-time model on `scene` (lighting projected from its environment, a BRDF table
/// baked per material for the view -camera direction) in both modes and for 1..max_bands, and
/// compares each with `truth`. Writes <prefix>_rt_<mode>.exr, <prefix>_compare_<mode>.png,
/// <prefix>_relerr_<mode>.exr and <prefix>_de2000_<mode>.exr; returns the metrics JSON and
/// appends the files to `written`.
nlohmann::json compare_realtime(const Scene& scene, const RenderResult& truth,
                                const CompareOptions& options, const std::string& prefix,
                                std::vector<WrittenFile>& written);

/// The console summary of compare_realtime's JSON (docs/report.md, "Console summary"): per
/// shading mode the model's error against the path-traced truth and a verdict from the mean
/// CIEDE2000: "below a just-noticeable difference" up to kJndDe2000, "visible" above it.
void print_compare_summary(const nlohmann::json& realtime);

/// The mean CIEDE2000 taken as one just-noticeable difference (Sharma et al. 2005: a Delta E
/// 2000 of 1 is about the smallest difference an observer sees side by side).
constexpr double kJndDe2000 = 1.0;

}  // namespace inlight::render
