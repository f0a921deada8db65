// gles/cli.h: the GLES export options shared by render (export-gles) and brdf-sh-bake
// (--export-gles), so both tools spell and validate them alike.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "core/report.h"
#include "gles/export.h"

namespace inlight::gles {

struct ExportArgs {
    std::string dir;  ///< --export-gles (render export-gles: -o); empty = no export
    std::string dir_option = "--export-gles";  ///< the option naming `dir`, for messages
    std::string versions = "100,300", modes = "consistent,seed", precisions = "highp";
    int max_sh_bands = 3;
    std::string lighting;  ///< --gles-lighting: a lighting file whose lights the shaders shade
    int max_texture_size = 0;  ///< --gles-max-texture-size: the device's; 0 = each version's minimum
    std::string texture_filter = "bilinear";  ///< --gles-texture-filter: bilinear | trilinear
    /// The parsed set (the options' validators have already checked every list), with the
    /// lighting file's lights read (render::read_lighting_file; errors name the file).
    ExportSet set() const;
    /// Before any work: declares DIR/index.json an output and the lighting file an input of
    /// `report`, and returns set().
    ExportSet prepare(Report& report) const;
};

/// Runs `check` (the export on tables of the baked shape, before any bake or rendering) and
/// names `option` (when not empty) in what it throws, keeping the type (UsageError: exit 2,
/// Error: exit 1).
void check_before_work(const std::function<void()>& check,
                       const std::string& option = "--export-gles");

/// Adds --gles-versions, --gles-modes, --gles-precisions, --gles-max-bands, --gles-lighting
/// FILE, --gles-max-texture-size N, --gles-texture-filter bilinear|trilinear, and (when `with_dir`) --export-gles DIR; without it the
/// tool fills args.dir and args.dir_option itself.
void add_export_options(CLI::App& app, ExportArgs& args, bool with_dir = true);

}  // namespace inlight::gles
