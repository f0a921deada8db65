// render/capture_cli.h: render's synthetic BTF capture and raw-BTF shading subcommands
// (render capture-btf FABRIC.toml -o DIR, render shade-btf FABRIC.toml --btf DIR ...), registered
// here so apps/render only maps flags to options (docs/btf.md).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "core/report.h"
#include "render/btf_capture.h"
#include "render/compare.h"

namespace inlight::render {

/// The capture flags, as given.
struct CaptureArgs {
    std::string lights;       ///< --btf-lights: direction file; "" = --btf-light-set
    std::string light_set = "ubo2003";  ///< --btf-light-set: btf::named_direction_set
    std::string views;        ///< --btf-views: direction file; "" = the UBO2003 dome
    std::string pairs;        ///< --btf-pairs: (light, view) pair file instead of lights x views
    std::string format = "png";  ///< --btf-format: png (8-bit sRGB) | exr (float, linear)
    double irradiance_w_m2 = 3.14159265358979323846;  ///< --irradiance-w-m2
    int default_spp = 16;  ///< used when --spp is not given
};

/// Registers --btf-lights, --btf-light-set, --btf-views, --btf-pairs, --btf-format and
/// --irradiance-w-m2 on `app` (render capture-btf).
void add_capture_options(CLI::App& app, CaptureArgs& args);

/// Checks a capture's -o folder before any work: a new folder, or an existing one without files
/// (empty folders inside it are fine). Temporaries that a killed capture left there (its process
/// is gone) are removed first, so a rerun needs no rm -rf. Throws UsageError for an existing
/// file or a folder holding other files. Declares OUT_DIR/capture.json as the run's output.
void check_capture_folder(const std::string& out_dir);

/// Reads the fabric and the direction files (UsageError naming the option and the file's
/// problem: duplicates, non-unit vectors, NaN, directions below the sample), captures every
/// (light, view) image into `out_dir` (UBO2003 names, one folder per view, plus capture.json
/// describing the frame, irradiance and units), and fills the report's metrics.
void run_capture(const CaptureArgs& args, const std::string& fabric, const std::string& out_dir,
                 const CaptureOptions& options, Report& report);

/// The raw-BTF shading flags (render shade-btf FABRIC.toml --btf BTF_DIR --environment ENV.exr
/// -o PREFIX): the BTF captured from FABRIC shaded under each environment and compared with the
/// path-traced truth of the same geometry (render/btf_shade.h).
struct ShadeArgs {
    std::string btf;                        ///< --btf: a capture folder (capture.json)
    /// --light-directions / --view-directions: the folder's direction files (btf::OpenOptions);
    /// "" = the sets its capture.json names, else the UBO2003 dome.
    std::string light_directions, view_directions;
    std::vector<std::string> environments;  ///< --environment (repeatable): lat-long EXR/HDR
    std::string views;  ///< --shade-views: direction file; "" = (0, 0), (45, 40), (75, 0)
    int view_neighbours = 1;  ///< --view-neighbours: BTF views blended per view (1 or 3)
    std::string view_interp;  ///< --view-interp: thesis | delaunay (btf/interp.h), replaces it
    int subsamples = 4;       ///< --cell-subsamples: per map pixel side (btf/lighting.h)
    std::string cell_rule = "cosine-barycentric";  ///< --light-cells: btf::CellRule by name
    /// --btf-compressed (repeatable): btf-pca folders of the same BTF, shaded beside it in the
    /// compressed domain (CompressedBtf::combine) and compared with the truth and the raw BTF.
    std::vector<std::string> compressed;
    /// --shade-stream: also shade each compressed BTF from only the first n components of its
    /// stream (the client's progressive state), for each n, against truth and raw BTF.
    std::vector<int64_t> stream_points;
    /// --gles-bands: also draw each --btf-compressed folder through its exported GLES shaders
    /// (btf-pca export-gles) under this many SH bands of the environment; 0 = not.
    int gles_bands = 0;
    /// --gles-lights: dominant lights taken out of each environment first (envmap's extraction,
    /// as envmap-project --lights), folded into the GLES frame's weights, the rest in SH.
    int gles_lights = 0;
};
void add_shade_options(CLI::App& app, ShadeArgs& args);

/// One exported GLES variant's picture of a compressed BTF (render/btf_shade.h's image).
struct GlesPicture {
    std::string variant;  ///< e.g. "btf-es300-highp"
    image::Image radiance;
    int lights = 0;       ///< dominant lights it was lit by (beside the SH)
};
/// What draws the compressed folders through their GLES shaders (supplied by the app, which
/// links lib/gles). `prepare` exports folder `folder` (index into ShadeArgs::compressed) for the
/// capture's irradiance, before any shading (Error naming a folder it cannot export); `draw`
/// draws it for the environment (lat-long, sample frame), the view and the stream entries
/// arrived, one picture per variant that can show that prefix.
struct GlesDrawer {
    std::function<void(size_t folder, double irradiance_w_m2)> prepare;
    std::function<std::vector<GlesPicture>(size_t folder, const std::string& env_path, const image::Image& env,
                                           const btf::Direction& view, int64_t sent)>
        draw;
};

/// Writes, per environment and view, <prefix>_<env>_tv<theta>_pv<phi>_{btf,truth}.exr, _relerr.exr
/// and _compare.png (truth | BTF | heat map of the relative error), and the metrics (as render
/// compare reports them, plus the relative difference of the mean luminance) into the report.
/// With `gles` (required when args.gles_bands > 0), each compressed folder's GLES pictures at
/// every stream point and for the whole stream are compared with the truth too.
void run_shade(const ShadeArgs& args, const std::string& fabric, const std::string& prefix,
               const CaptureOptions& truth_options, const CompareOptions& compare, Report& report,
               const GlesDrawer* gles = nullptr);

}  // namespace inlight::render
