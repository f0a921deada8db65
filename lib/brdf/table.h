// brdf/table.h: a baked table of BRDF SH coefficients over a grid of normals, its lookup (the
// GLSL's bilinear interpolation, in C++), and its files: a little-endian binary, a JSON with
// metadata, and an RGBA32F texture image for the GLES shader.
//
// Binary format (docs/brdf.md), all little-endian:
//   offset 0   char[8]  magic "ILBRDFSH"
//          8   uint32   version = 1
//         12   uint32   header_bytes (= 64: offset of the first coefficient)
//         16   uint32   grid kind (0 report5x5, 1 thetaphi, 2 octa, 3 disk)
//         20   uint32   rows (i1 count)
//         24   uint32   cols (i2 count)
//         28   uint32   sh_bands
//         32   uint32   coeff_count = sh_bands^2
//         36   uint32   channels (1: achromatic lobe, 3: linear_srgb R, G, B)
//         40   float32  theta_max (radians; thetaphi only, else pi/2)
//         44   float32  view direction x, y, z (device frame)
//         56   uint32   reserved (0), 60 uint32 reserved (0)
//         64   float32  coefficients[channels][rows][cols][coeff_count]
// The float array is exactly the GLSL uniform array: flat index
// ((channel * rows + i1) * cols + i2) * coeff_count + k (for 1 channel, 5x5 and 9 coefficients
// this is the report's brdfIndex = 45 i1 + 9 i2 + k).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdf/grid.h"

namespace inlight::brdf {

/// SH coefficients (real, phase-free, index l(l+1)+m, sh/sh.h) of the cosine-weighted baked
/// lobe B_lm(n) = integral f_r(n; v, w) max(0, n.w) Y_lm(w) dw, w over the sphere in the device
/// frame, at each grid normal n, for the fixed view v. Units: 1/sr * sr = dimensionless per
/// unit radiance: sum_lm L_lm B_lm is the reflected radiance for lighting coefficients L_lm.
struct Table {
    Grid grid;
    int sh_bands = 3;
    int channels = 1;  ///< 1 (achromatic lobe) or 3 (linear_srgb)
    Eigen::Vector3d view{0, 0, 1};
    std::vector<float> coeffs;  ///< [channels][rows][cols][coeff_count()]

    int coeff_count() const { return sh_bands * sh_bands; }
    size_t index(int channel, int i1, int i2, int k) const {
        return ((static_cast<size_t>(channel) * grid.rows + i1) * grid.cols + i2) * coeff_count() +
               k;
    }
    float at(int channel, int i1, int i2, int k) const { return coeffs[index(channel, i1, i2, k)]; }
    /// Allocates zeroed coefficients for the current grid, bands and channels.
    void resize();
};

/// Interpolated coefficients at normal n (device frame, any non-zero length) for one channel
/// into out[0 .. coeff_count()): bilinear over grid_coord(n), in float, exactly the emitted
/// GLSL brdf_sh_lookup (mix(mix(c00, c01, fc), mix(c10, c11, fc), fr)).
void lookup(const Table& table, const Eigen::Vector3f& n, int channel, float* out);

/// The report's getBRDF verbatim (cart2sph with atan(y/x), floor/ceil corners) on a report5x5
/// table, channel 0. NaN or out-of-range indices are returned as NaN coefficients.
void lookup_report_original(const Table& table, const Eigen::Vector3f& n, float* out);

/// The table at its first `bands` bands: each node's first bands^2 coefficients (SH coefficients
/// are stored band by band, and each is projected on its own, so this equals a bake at `bands`).
/// Precondition: 1 <= bands <= table.sh_bands (checked: Error).
Table first_bands(const Table& table, int bands);

/// Writes the binary format above (atomically). Throws Error naming the file.
void write_binary(const std::string& path, const Table& table);
/// Reads it back. Throws Error naming the file on a bad magic, version, size or truncation.
Table read_binary(const std::string& path);

/// JSON: {"format":"inlight_brdf_sh_table","version":1,"grid":{...},"sh_bands","coeff_count",
/// "channels","view","sh_convention","layout","metadata":{...},"coefficients":[flat array]}.
nlohmann::json to_json(const Table& table, const nlohmann::json& metadata);
/// Writes to_json() atomically.
void write_json(const std::string& path, const Table& table, const nlohmann::json& metadata);

/// The RGBA32F texture layout: 4 coefficients per texel, ceil(K/4) texels per node side by side;
/// texel (x = i2 * ceil(K/4) + t, y = channel * rows + i1) holds coefficients 4t .. 4t+3
/// (missing ones 0). Returns {width, height}.
Eigen::Vector2i texture_size(const Table& table);
/// The texels, row-major (row y = 0 first), 4 floats each.
std::vector<float> texture_texels(const Table& table);
/// Writes the texture as a 4-channel float EXR (colour space "data") through lib/image.
void write_texture_exr(const std::string& path, const Table& table);

}  // namespace inlight::brdf
