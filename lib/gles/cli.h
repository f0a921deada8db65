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
    /// --gles-albedo-texture / --gles-normal-texture: the 8-bit PNGs the bundle ships (albedo:
    /// sRGB codes; normal map: data, n = 2 rgb - 1), bound byte for byte by the shaders.
    std::string albedo_texture, normal_texture;
    double tile_size_m = 0;  ///< --gles-tile-size-m: a_uv in metres, u_uv_scale = 1 / this; 0 = a_uv in tiles
    /// The parsed set (the options' validators have already checked every list), with the
    /// lighting file's lights read (render::read_lighting_file; errors name the file).
    ExportSet set() const;
    /// Before any work: declares DIR/index.json an output and the lighting file an input of
    /// `report`, and returns set().
    ExportSet prepare(Report& report) const;
    /// The textures and uv unit of --gles-albedo-texture, --gles-normal-texture and
    /// --gles-tile-size-m into `material` (texels as the files store them, alpha 255). With an
    /// albedo texture, the texture is the albedo: material.brdf.albedo (u_albedo) becomes 1, as
    /// in the validation scene (docs/pipelines.md). Throws
    /// UsageError naming the option when a file is not an 8-bit image (the shader binds bytes;
    /// a 16-bit or float file would be quantised behind the user's back), Error when it cannot
    /// be read; declares the files inputs of `report`.
    void add_textures(MaterialInputs& material, Report& report) const;
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

/// Adds --gles-albedo-texture FILE, --gles-normal-texture FILE and --gles-tile-size-m M (for a
/// tool whose material has no textures of its own: brdf-sh-bake).
void add_texture_options(CLI::App& app, ExportArgs& args);

}  // namespace inlight::gles
