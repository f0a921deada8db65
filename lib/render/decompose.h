// render/decompose.h: the real-time model's error against the path tracer taken apart (render
// compare --decompose; docs/render.md "Where the error comes from").
//
// At every fragment the compare renders (same rays, same supersampling), a chain of models
// replaces one approximation at a time by its exact counterpart:
//   M0  the consistent model at b bands (render/realtime.h): SH lighting, BRDF table looked up
//       bilinearly on its grid, the table's fixed view v0, no visibility;
//   M1  the table's coefficients at the fragment's own normal (brdf::project_normal with the
//       table's bake options) instead of the grid lookup;                 M0 - M1: grid
//   M2  exact integrals over the map instead of SH: albedo / pi E(n) with E the sum over the
//       map's pixels of L Omega max(0, n.w) (diffuse), and the sum of L Omega f_s(n; v0, w)
//       max(0, n.w) (specular) with the table's material;                 M1 - M2: SH
//       truncation, diffuse (lighting at b bands) and specular (lighting x table at b bands:
//       one cause, since sum_k L_k B_k = integral of (P_b L) f = integral of L (P_b f))
//   M2r the fragment's textured BRDF (roughness texture) in the specular;  M2 - M2r
//   M3  the true view direction at each fragment instead of v0;            M2r - M3
//   T   the path tracer: visibility (self-shadowing, inter-reflection) and its own noise.
// With dominant lights (lighting.lights, envmap-project --max-error: `coeffs` are then the SH of
// the map minus the lights' caps), the models add the lights as the real-time model shades
// them (render/realtime_lights.h: the cap's or the smooth cap's irradiance, the specular lobe
// at the cap's centre times it), and one step splits M1 - M2:
//   M1x the lights' exact integrals as uniform caps of radiance Phi / Omega_cap: Snyder's exact
//       irradiance, and the specular integral over the cap (quadrature below) instead of the
//       model's shading of them;                                       M1 - M1x: light shading
//   M1x - M2 is then the SH truncation of the residual (map minus caps), diffuse and specular;
//       it includes how far the map's bright regions are from uniform caps.
// Each part is the relative RMS of the luminance difference over the image,
//   sqrt(mean over pixels of (Y_a - Y_b)^2) / mean over pixels of Y_T,
// the same form as the truth's noise (RenderResult::rel_error), so independent noise adds in
// quadrature: visibility = sqrt(max(0, rms(M3 - T)^2 - noise^2)). The parts are the lengths of
// a telescoping sum M0 - T, so the total is at most their sum (triangle inequality).
// The exact integrals sum over the map box-filtered to `map_height` rows (each coarse pixel
// carries the summed L Omega of its block at its centre direction); their own discretisation
// is reported as the difference between map_height and map_height / 2 rows.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdf/bake.h"
#include "render/path_tracer.h"
#include "render/realtime.h"
#include "render/scene.h"

namespace inlight::render {

struct DecomposeOptions {
    int max_bands = 5;  ///< parts for 1 .. max_bands (lighting and table bands)
    /// Fragments per pixel side. 1 (pixel centres) for a truth rendered with --no-jitter: then
    /// every model and the truth sample the same points. A jittered truth averages each pixel's
    /// area, which ss x ss fragments only approximate: that difference (`pixel_footprint`)
    /// then also sits in the visibility part.
    int supersample = 1;
    int map_height = 128;    ///< rows of the box-filtered map of the exact integrals
    brdf::BakeOptions bake;  ///< the tables' bake options (view, samples, integrator)
};

/// The parts at one band count (relative RMS, see the file comment).
struct DecompositionBands {
    int sh_bands = 0;
    double total = 0;                   ///< M0 against T
    double grid_interpolation = 0;      ///< M0 - M1
    double sh_truncation_diffuse = 0;   ///< M1 - M2, diffuse term
    double sh_truncation_specular = 0;  ///< M1 - M2, specular term (with lights: M1x - M2)
};

struct Decomposition {
    std::vector<DecompositionBands> by_bands;
    int lights = 0;                      ///< dominant lights in the model
    double light_shading_diffuse = 0;    ///< M1 - M1x, diffuse (0 without lights)
    double light_shading_specular = 0;   ///< M1 - M1x, specular (0 without lights)
    double roughness_texture = 0;   ///< M2 - M2r
    double fixed_view = 0;          ///< M2r - M3
    double visibility = 0;          ///< M3 - T, truth noise removed in quadrature
    double truth_noise = 0;         ///< the truth's rel_error
    double exact_vs_truth = 0;      ///< rms(M3 - T) with the noise in it
    double map_discretisation = 0;  ///< M3 at map_height against M3 at map_height / 2
    /// M0 (min(3, max_bands) bands) at supersample against 4 x supersample per side; 0 when
    /// supersample = 1 (pixel centres, no footprint to approximate).
    double pixel_footprint = 0;
    int map_width = 0, map_height = 0;
    double mean_truth_luminance = 0;
    double time_s = 0;
};

/// Takes the error apart. `lighting` holds the coefficients (>= max_bands), one table per
/// material, baked with options.bake (the exact table step re-projects with those options),
/// and optionally dominant lights (see the file comment).
/// Deterministic for any thread count. Throws UsageError on bad options.
Decomposition decompose_error(const Scene& scene, const RenderResult& truth,
                              const RealtimeLighting& lighting, const DecomposeOptions& options);

/// Report form: per band count the parts, the shared parts, and the noise ratio.
nlohmann::json to_json(const Decomposition& d);

/// Integral over a uniform cap of radiance Phi / Omega (light's direction d, radius alpha) of
/// f_s(n; view, w) max(0, n.w) dw per channel: the light's exact specular, by the midpoint rule
/// on kCapQuadratureRings x kCapQuadratureSectors cells equal in solid angle (rings in
/// cos, sectors in azimuth). 0 for a
/// Lambert material or a view below n's horizon; the lobe at d times Phi max(0, n.d) at alpha 0.
Eigen::Vector3d cap_specular_exact(const envmap::DirectionalLight& light, const Eigen::Vector3d& n,
                                   const Eigen::Vector3d& view, const brdf::Material& material);
/// Rings x sectors of cap_specular_exact.
inline constexpr int kCapQuadratureRings = 24, kCapQuadratureSectors = 48;

}  // namespace inlight::render
