// gles/btf_export.h: OpenGL ES shaders that draw a PCA-compressed BTF (btf/compressed.h, a
// btf-pca folder, linear fit space) under spherical-harmonics lighting, as docs/btf-gles.md
// describes.
//
// Per group g the folder holds L_g = [mean | components] (8-bit codes, value = offset + scale x
// code / 255). The export packs them 4 per RGBA8 texel into one atlas per group: W x (H x S)
// texels, S = ceil((1 + C) / 4) slabs stacked top to bottom, slab s holding columns 4s .. 4s + 3
// of L_g (unused channels code 0, scale 0, offset 0). The fragment shader reads, for the 3 group
// slots of a frame, every slab at the pixel of UV (wrapped, nearest texel) and dots the texels
// t (code / 255) with the frame's weights u_weight per colour, plus u_bias:
//   radiance_ch(uv) = sum_slot sum_k (offset_k + scale_k t_k(uv)) w_slot,ch,k
//                   = u_bias_ch + sum_slot sum_k t_k(uv) u_weight_slot,ch,k,
// the folder's decode folded into u_weight = scale x w and u_bias = sum offset x w per frame.
// The app computes the weights once per frame (btf_frame_weights): the view's 3 nearest views
// v (inverse-angle weights alpha_v, render::select_views), and for each view's group slot
//   w_slot,ch = sum_{v in slot's group} alpha_v M_v,ch c_ch,
// M_v,ch = CompressedBtf::lighting_matrix (shipped in one float32 file), c the lighting's SH
// coefficients in the fabric's frame; components not yet streamed get weight 0.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "btf/compressed.h"
#include "btf/lighting.h"
#include "btf/sh_lighting.h"
#include "gles/export.h"
#include "gles/harness.h"

namespace inlight::gles {

struct BtfGlesOptions {
    std::vector<GlslVersion> versions{GlslVersion::kEs100, GlslVersion::kEs300};
    int sh_bands = 3;              ///< lighting bands the matrices take, 1..9
    /// The capture's irradiance E (image = btf x E), > 0; 0 = the folder's own (btf-pca.json's
    /// irradiance_w_m2, which btf-pca records from a capture's capture.json), else 1.
    double irradiance_w_m2 = 0;
    int map_height = 128;          ///< sh_light_weight_matrix's quadrature, 16..2048
    /// Rule of the light weights: cosine-barycentric by default (btf / cos interpolated over the
    /// light triangles: a light between directions is spread, not moved; docs/btf.md).
    btf::DomeLightingOptions lighting{btf::CellRule::kCosineBarycentric};
    /// Write the atlas PNGs (files()). false: the app assembles them from the btf-pca folder's
    /// mean and component PNGs by the manifest's textures.groups[g].channels[k].file (a fabric
    /// bundle, which streams those PNGs already: no bytes twice); the manifest says which.
    bool write_atlases = true;
};

/// One shader variant.
struct BtfGlesVariant {
    GlslVersion version = GlslVersion::kEs300;
    std::string name;  ///< "btf-es300-highp"
    std::string vertex_source, fragment_source;
    int slabs_used = 0;        ///< slabs of the atlas the shader reads: all of them
    int fragment_uniform_vectors = 0;  ///< btf_fragment_uniform_vectors(slabs_used)
    /// Export (the harness' view of it): the manifest's "variant", "textures" (u_group0..2)
    /// and the sources, for gles::draw.
    Export as_export;
};

/// A dominant light (envmap-project's lighting files, lights.h), in the fabric frame:
/// `direction` unit towards the light's centre, `irradiance_w_m2` per linear_srgb channel its
/// radiance times its solid angle (lights.h's flux Phi: the irradiance a point light would give
/// a surface facing it), `angular_radius` (radians, < pi/2) of the uniform cap it stands for.
/// A cap is spread as kBtfCapSamples equal point lights at Fibonacci points of equal solid
/// angle; each point light goes to the light directions by the export's cell rule
/// (directional_light_weights). Folded into a frame's weights on the CPU; the shader is unchanged.
struct BtfLight {
    Eigen::Vector3d direction{0, 0, 1};
    Eigen::Vector3d irradiance_w_m2{0, 0, 0};
    double angular_radius = 0;
};
constexpr int kBtfCapSamples = 256;

/// The whole export of one folder.
struct BtfGlesExport {
    int width = 0, height = 0, slabs = 0;  ///< image size, slabs per atlas (all groups alike)
    int sh_bands = 0;
    std::vector<int> components;           ///< per group
    std::vector<Texture8> atlases;         ///< per group, width x (height x slabs)
    std::vector<std::vector<float>> scale, offset;  ///< per group, 4 x slabs (decode of each channel)
    std::vector<float> matrices;           ///< every view's M_v,ch (layout: matrices_offset)
    std::vector<int64_t> matrices_offset;  ///< per view, in floats: M_v,ch(r, j) at + (ch (1 + C) + r) J + j
    std::vector<btf::Direction> views;
    /// For dominant lights (not a file: the app forms them from weights.bin): per view, the
    /// rows [1^T; V_v,ch^T] / E, (1 + C) x K per channel (K light directions) at
    /// light_rows_offset[v] + (ch (1 + C) + r) K + k, i.e. lighting_matrix with A = identity.
    std::vector<float> light_rows;
    std::vector<int64_t> light_rows_offset;
    std::vector<btf::Direction> lights;  ///< the BTF's light directions (sample frame)
    btf::DomeLightingOptions lighting;   ///< the cell rule lights are spread by
    /// That rule's spread, built once at export (a triangulation is a qhull run: not per frame).
    std::shared_ptr<const btf::PointLightWeights> light_spread;
    std::vector<std::pair<int, int>> stream;  ///< [group, component], the folder's order
    std::vector<BtfGlesVariant> variants;
    bool atlas_files = true;               ///< BtfGlesOptions::write_atlases
    nlohmann::json manifest;               ///< btf-gles.json (deterministic)
    /// file name -> bytes: btf-gles.json, shaders, atlases (PNG, when atlas_files),
    /// lighting-matrices.bin.
    std::vector<std::pair<std::string, std::string>> files() const;
};

/// Exports `dir` (a btf-pca folder). Throws Error naming the file for a folder that is not one,
/// a fit space other than linear, components that are not 8-bit PNG, or a variant that does not
/// fit its version's guaranteed limits (naming the resource and both numbers).
BtfGlesExport export_btf_gles(const std::string& dir, const BtfGlesOptions& options);

/// btf-gles.json's "load": which exported variant an app loads for each GL capability, in the
/// shape of the BRDF shaders' index.json "load" (export.h load_choices): one entry per
/// capability ("OpenGL ES 3.0 or later", "OpenGL ES 2.0 with GL_FRAGMENT_PRECISION_HIGH",
/// "OpenGL ES 2.0 without GL_FRAGMENT_PRECISION_HIGH") with capability, variant (an exported
/// variant's name or null), manifest, validated and why. When btf-es100-highp needs more
/// fragment uniform vectors than ES 2.0 guarantees (16: more than 3 components in a group), its
/// entry carries requires.max_fragment_uniform_vectors and a fourth entry names no variant for an
/// ES 2.0 device that reports fewer; without highp fragments nothing (mediump is refused,
/// docs/btf-gles.md "Precision").
nlohmann::json btf_load_choices(const BtfGlesExport& e);

/// The uniforms of one frame: u_weight (9 x slabs_used vec4, index (slot x 3 + ch) x S + s,
/// channel k = scale_k x w_slot,ch[4 s + k]), u_bias (vec4: per colour the sum of offset_k x
/// w_slot,ch[k], then 0) and which group each of the 3 slots shows (unused slots: weight 0,
/// bound to slot 0's group's atlas).
struct BtfFrame {
    std::vector<int> slot_group;  ///< 3 entries
    std::vector<float> weight;    ///< u_weight
    std::vector<float> bias;      ///< u_bias, 4 floats
};

/// Fragment uniform vectors of a variant that reads `slabs` slabs: 9 slabs (u_weight) + 1 (u_bias).
int btf_fragment_uniform_vectors(int slabs);
/// The app's per-frame computation: `view` (sample frame), `sh` (bands^2 x 3, fabric frame),
/// `sent` stream entries arrived (the means always), `lights` dominant lights added to the SH
/// (each spread over the light directions by the export's cell rule, btf/sh_lighting.h
/// directional_light_weights; one at or below the sample's plane adds nothing). Throws Error
/// when the arrived components need more slabs than `variant` reads (a variant made by hand:
/// the exported ones read every slab) or a light is not finite or its direction not unit.
BtfFrame btf_frame_weights(const BtfGlesExport& e, const BtfGlesVariant& variant,
                           const btf::Direction& view, const Eigen::MatrixXd& sh, int64_t sent,
                           const std::vector<BtfLight>& lights = {});

/// The weights `lights` give the BTF's light directions (one per light direction, per colour):
/// what btf_frame_weights folds through [1^T; V_v,ch^T] / E. Throws Error for a light that is not
/// finite, a direction that is not unit or a radius outside [0, pi/2).
std::vector<Eigen::Vector3d> btf_light_weights(const BtfGlesExport& e, const std::vector<BtfLight>& lights);

/// The harness bindings of a frame (textures u_group0..2, the uniform arrays).
Bindings btf_bindings(const BtfGlesExport& e, const BtfFrame& frame);

}  // namespace inlight::gles
