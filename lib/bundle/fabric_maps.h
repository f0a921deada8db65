// bundle/fabric_maps.h: a fabric's textures in the formats the app loads: the albedo as 8-bit
// sRGB PNG, the normal map as linear 8-bit PNG (given, or derived from the albedo's weave by
// image::height_from_albedo and image::normal_map_from_height), and a catalogue thumbnail.
#pragma once

#include <string>

#include "core/report.h"

namespace inlight::bundle {

struct FabricMapsOptions {
    std::string albedo_texture;   ///< any 8/16-bit or float image (sRGB-decoded if integer)
    std::string normal_texture;   ///< optional tangent-space normal map (read as data)
    double relief_texels = 1.5;   ///< derived normals: height range of the weave, in texels
    int blur_px = 1;              ///< derived normals: box blur radius before differencing
    int max_size_px = 1024;       ///< textures larger than this are box-filtered down
    int thumbnail_px = 128;       ///< thumbnail: longer side in pixels
    std::string name;             ///< the fabric's name for the catalogue (echoed in the report)
    double tile_size_m = 0.05;    ///< physical width of one texture tile, metres (echoed)
};

/// Writes OUT/albedo.png, OUT/normal.png and OUT/thumbnail.png. Everything is computed before
/// the first file is written, each file is written atomically, and a failure removes what this
/// call wrote. Records inputs, outputs and metrics (sizes, derived or given) in `report`.
/// Throws Error naming the file for unreadable or non-finite textures, UsageError for bad
/// option values.
void write_fabric_maps(const FabricMapsOptions& options, const std::string& out_dir,
                       Report& report);

}  // namespace inlight::bundle
