// render/capture_cli.h: render's synthetic BTF capture mode (render FABRIC.toml --btf-capture -o
// DIR), registered here so apps/render/main.cpp only maps flags to options (docs/btf.md).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "core/report.h"
#include "render/btf_capture.h"

namespace inlight::render {

/// The capture flags, as given.
struct CaptureArgs {
    bool enabled = false;     ///< --btf-capture
    std::string lights;       ///< --btf-lights: direction file; "" = the UBO2003 dome
    std::string views;        ///< --btf-views: direction file; "" = the UBO2003 dome
    std::string pairs;        ///< --btf-pairs: (light, view) pair file instead of lights x views
    std::string format = "png";  ///< --btf-format: png (8-bit sRGB) | exr (float, linear)
    double irradiance_w_m2 = 3.14159265358979323846;  ///< --irradiance-w-m2
    int default_spp = 16;  ///< used when --spp is not given
};

/// Registers --btf-capture, --btf-lights, --btf-views, --btf-pairs, --btf-format and
/// --irradiance-w-m2 on `app`.
void add_capture_options(CLI::App& app, CaptureArgs& args);

/// Reads the fabric and the direction files (UsageError naming the option and the file's
/// problem: duplicates, non-unit vectors, NaN, directions below the sample), captures every
/// (light, view) image into `out_dir` (UBO2003 names, one folder per view, plus capture.json
/// describing the frame, irradiance and units), and fills the report's metrics.
void run_capture(const CaptureArgs& args, const std::string& fabric, const std::string& out_dir,
                 const CaptureOptions& options, Report& report);

}  // namespace inlight::render
