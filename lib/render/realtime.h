// render/realtime.h: the app's real-time shading computed on the CPU, term for term what the
// exported fragment shader does, so that its error against the path tracer can be measured.
//
// Inputs per fragment: the normal (normal map in the tangent frame, render/material.h), the
// albedo (material albedo x tiled texture, bilinear), lighting SH coefficients L_lm (3
// channels, device/world frame, sh/sh.h convention) and the BRDF SH table B_lm(n) of the
// material's specular lobe (brdf/table.h, bilinear lookup over its grid of normals).
//
// Modes:
//  - kConsistent (physically consistent): radiance = albedo / pi * E(n) + S(n) per channel, with
//    E(n) = n^T M n from the irradiance matrix M (Ramamoorthi and Hanrahan 2001, eq. 12) when
//    sh_bands = 3, else E(n) = sum_lm A_l L_lm Y_lm(n) (eq. 7-8) for any band count, and
//    S(n) = sum_lm L_lm B_lm(n) over min(sh_bands, table bands)^2 coefficients. Lambert
//    materials have no specular lobe (S = 0).
//  - kSeed: the inlight report's shader (section 2.6) as written: the matrix M_c of each
//    channel multiplied entry by entry by the BRDF coefficients (m[i][j] = M[i][j] * B_k for
//    the k of that entry, m[3][3] = c4L00 B_0 - c5L20 B_6 with the shader's 0.743125 and
//    0.247708), specular_c = n^T m_c n * 0.05, and diffuse = mean_c(n^T M_c n) * 0.3 * albedo.
//    Only 3 bands exist in this mode. With the report's two slips: its getBRDF takes phi =
//    atan(y/x), so a normal with x < 0 reads the table at its mirror (-x, -y, z) (brdf::lookup
//    there; at the pole, where the report divides 0 by 0, the pole's value); and its L_lm carry
//    the Condon-Shortley phase (its Figure 6) that R&H's matrix does not expect, so the gray
//    irradiance is E(-x, -y, z) (the phases cancel in the specular products L_lm B_lm).
// Fragments are shaded at `supersample` x `supersample` stratified positions per pixel and
// averaged (the box filter of the path tracer; 1 = the pixel centre, as a GPU does).
// Texture filtering (TextureFilter): bilinear on the texture (level 0 only, which aliases when
// minified), or trilinear on its mip atlas (render/mip.h) at the level of detail of the uv
// derivatives, taken as a GPU takes them (render/mip.h, "Derivatives"): differences across
// the 2 x 2 quad of the fragment grid (one pixel / supersample apart), the partner fragment's
// uv read on the hit primitive's plane (primitive_uv()), so that at supersample 1 they are
// the exported shader's dFdx / dFdy of v_uv. Normal variance (NormalVariance, consistent mode only): with the filtered
// normal's length r, 1/kappa = render::vmf_inv_kappa(r); the irradiance's band l scales by
// f_l = vmf_band_factor(l, 1/kappa), and with kDiffuseSpecular the specular sum's band l by
// vmf_band_factor(l, specular_spread / kappa) (the reflected direction spreads twice the
// normal's angle: a vMF of kappa / 4 in the small-angle limit, specular_spread = 4).
#pragma once

#include <Eigen/Core>
#include <string>

#include "brdf/table.h"
#include "envmap/lights.h"
#include "image/image.h"
#include "render/mip.h"
#include "render/scene.h"

namespace inlight::render {

enum class RealtimeMode { kConsistent, kSeed };
/// "consistent" | "seed"; throws UsageError otherwise.
RealtimeMode realtime_mode_from_string(const std::string& name);
std::string to_string(RealtimeMode mode);

enum class NormalVariance { kNone, kDiffuse, kDiffuseSpecular };

struct RealtimeOptions {
    RealtimeMode mode = RealtimeMode::kConsistent;
    int sh_bands = 3;     ///< lighting bands used (<= the coefficients given); kSeed needs 3
    int supersample = 4;  ///< fragments per pixel side
    TextureFilter texture_filter = TextureFilter::kBilinear;
    NormalVariance normal_variance = NormalVariance::kNone;
    MipFilter mip_filter = MipFilter::kBilinear;  ///< how the mip levels are built
    bool box_matched_lod = true;  ///< render::box_matched_lod, else the GL lod (mip_lod)
    double specular_spread = 4;  ///< 1/kappa multiplier of the specular bands (> 0)
};

/// The real-time model's inputs that do not depend on the pixel.
struct RealtimeLighting {
    Eigen::MatrixXd coeffs;           ///< count(bands) x 3 lighting coefficients, world frame
    std::vector<brdf::Table> tables;  ///< one per scene material (same order), may be empty
    /// Extracted lights shaded analytically (render/realtime_lights.h; consistent mode only),
    /// world frame; `coeffs` then hold the residual map's SH.
    std::vector<envmap::DirectionalLight> lights;
};

/// Lighting coefficients of the scene's environment (as the path tracer sees it: the same
/// pixels after intensity, the same rotation), by lib/envmap's exact box-filter projection.
Eigen::MatrixXd project_environment(const EnvironmentLight& env, int sh_bands);

/// Shades one fragment: normal n (unit, world = device frame), albedo (linear_srgb). The
/// table may be null (no specular). Returns linear_srgb radiance.
/// `normal_length` is the filtered normal's length (1 = no spread; used with
/// options.normal_variance).
Eigen::Vector3d shade_realtime(const Eigen::Vector3d& n, const Eigen::Vector3d& albedo,
                               bool has_specular, const Eigen::MatrixXd& coeffs,
                               const brdf::Table* table, const RealtimeOptions& options,
                               double normal_length = 1);

/// The uv that the primitive `hit` lies on gives where `ray` meets its plane, extrapolated
/// beyond its edges (what a GPU interpolates for a helper fragment of the quad): patches and
/// mesh triangles (their affine uv; a mesh without uv: hit.uv). Curved shapes have no plane:
/// the ray's own hit when it is on the same shape, else hit.uv.
Eigen::Vector2d primitive_uv(const Scene& scene, const SurfaceHit& hit, const Ray& ray);

/// Renders the scene's camera view with the real-time model. Rays that miss show the
/// environment (nearest pixel, as the path tracer). Parallel and deterministic. A mapped
/// normal facing away from the model's view (the material table's view, else +z: the exported
/// shader's VIEW) falls back to the geometric normal, as in the shader.
/// Throws UsageError when options ask for more bands than `lighting` has, or kSeed without 3
/// bands or with lights (the report's shader has none).
image::Image render_realtime(const Scene& scene, const RealtimeLighting& lighting,
                             const RealtimeOptions& options);

}  // namespace inlight::render
