// envmap/lights.h: dominant lights (the sun, a window, a lamp) found in an environment, fitted as
// directional lights with a colour and a small angular radius, and removed from the map so that
// only the smooth residual goes into SH (docs/budget.md).
//
// A light is the light in a compact region of very bright samples ABOVE the background around
// it: for region R with local background radiance b (per channel),
//   flux      Phi_c = sum_{i in R} (L_ic - b_c) Omega_i                (radiance x sr)
//   vector    V_c   = sum_{i in R} (L_ic - b_c) Omega_i w_i
// the direction d = V_Y / |V_Y| (Y = Rec.709 luminance) and the angular radius alpha of the
// uniform cap with the same mean cosine: |V_Y| / Phi_Y = (1 + cos alpha) / 2. In the residual
// map the region's samples are set to b, so residual + light keep the map's flux exactly and its
// irradiance exactly for every normal that sees the whole region (E(n) = n . V is linear in the
// light; the cap differs only near the light's horizon).
//
// Shading (render/realtime.h and budget.h): the light's irradiance is that of a uniform cap,
// E_c(n) = Phi_c / Omega_cap * integral over the cap of max(0, n.w) dw, closed form of Snyder
// 1996 ("Area light sources for real-time graphics", MSR-TR-96-11; also Lagarde and de Rousiers
// 2014, "Moving Frostbite to PBR", sec. 4.7.2); the specular lobe is the material's BRDF at the
// cap's centre times that irradiance.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "envmap/environment.h"

namespace inlight::envmap {

/// How a light's irradiance is shaded (docs/formats.md, "SH coefficients with lights").
enum class LightShading {
    kCap,        ///< the uniform cap's exact irradiance (Snyder 1996): acos, atan, sqrt
    kSmoothCap,  ///< the cap's irradiance above the horizon band, a quadratic across it
};
/// "cap" | "smooth-cap"; throws UsageError otherwise (an option value).
LightShading light_shading_from_string(const std::string& name);
std::string to_string(LightShading shading);

/// A directional light with a colour and an angular radius (world frame, linear_srgb).
struct DirectionalLight {
    Eigen::Vector3d direction{0, 0, 1};  ///< unit, toward the light, world frame
    Eigen::Vector3d flux{0, 0, 0};       ///< Phi_c: radiance x sr above the background
    double angular_radius = 0;           ///< alpha, radians, of the equivalent uniform cap
    LightShading shading = LightShading::kCap;  ///< the irradiance formula (light_irradiance)
    // What the fit saw (for the report; shading uses only the three fields above).
    Eigen::Vector3d background{0, 0, 0};  ///< b_c, the radiance left in the region
    double peak_radiance = 0;             ///< largest luminance in the region
    double solid_angle_sr = 0;            ///< of the region's samples
    int64_t samples = 0;                  ///< pixels in the region
    int64_t saturated_samples = 0;        ///< of them, clipped in the camera frame
    /// Fraction of Phi_Y carried by clipped pixels, at their clipped (lower-bound) radiance.
    double saturated_flux_fraction = 0;
    /// True when the flux is only a lower bound: clipped pixels, or the region touches the edge
    /// of the observed field (a fisheye frame's rim) so part of the light is not seen.
    bool flux_is_lower_bound = false;
    bool at_field_edge = false;  ///< the region touches unobserved pixels
    /// direction, flux and radius were fitted to the brute-force irradiance (light_fit.h); the
    /// fields above it then describe the extracted region the fit started from.
    bool fitted = false;
};

/// Luminance flux Phi_Y of a light.
double luminance_flux(const DirectionalLight& light);

/// Integral over a uniform cap of half-angle alpha of max(0, n.w) dw, for a cap centred at
/// angle beta from n (cos_beta = cos(beta)), in sr: pi sin^2(alpha) cos(beta) when the cap is
/// wholly above n's horizon, 0 when wholly below, Snyder's closed form in between.
/// Preconditions: 0 <= alpha <= pi/2, cos_beta in [-1, 1].
double cap_cosine_integral(double cos_beta, double alpha);

/// The smooth cap's stand-in for cap_cosine_integral / (pi sin^2 alpha): with t = cos_beta and
/// s = sin(alpha), t for t >= s, 0 for t <= -s and (t + s)^2 / (4 s) between: the quadratic
/// through the horizon band that meets both sides with their value and slope (C1). It differs
/// from the exact cap only in that band, by at most 0.038 s (radii <= 0.8 rad; `SmoothCap.*`).
double smooth_cap_cosine(double cos_beta, double alpha);

/// Irradiance (per linear_srgb channel) of `light` on a surface of unit normal n:
/// kCap: Phi_c * cap_cosine_integral(n.d, alpha) / (2 pi (1 - cos alpha));
/// kSmoothCap: Phi_c (1 + cos alpha) / 2 * smooth_cap_cosine(n.d, alpha) (the same above the
/// horizon band); for alpha -> 0 both tend to Phi_c max(0, n.d).
Eigen::Vector3d light_irradiance(const DirectionalLight& light, const Eigen::Vector3d& n);

/// The specular radiance of `light` toward `view` (unit, world frame) from a surface of unit
/// normal n: f_s(n; view, d) E(n) per channel, f_s = brdf::eval_specular in n's local frame
/// (world_from_local), E = light_irradiance. 0 for a Lambert material (no specular lobe).
Eigen::Vector3d light_specular(const DirectionalLight& light, const Eigen::Vector3d& n,
                               const Eigen::Vector3d& view, const brdf::Material& material);

/// Detection and fitting parameters (defaults: docs/budget.md, and the hard-case tests).
struct ExtractOptions {
    int max_lights = 3;  ///< at most this many lights, strongest (by Phi_Y) first; 0 = none
    /// A region starts at a sample whose luminance is at least this many times the background
    /// around the region ("very bright"; the sun is ~1e4, a window 20-100, a lamp 100+).
    double min_peak_contrast = 20;
    /// A region grows (its threshold falls from the seed's luminance by sqrt(2) per step) while
    /// the threshold stays at least this many times the background around the region: the halo
    /// around a sun is part of the light down to this contrast.
    double grow_contrast = 2;
    /// A region wider than this (the fitted cap's radius, degrees) is not compact: not a light.
    double max_radius_deg = 20;
    /// A region carrying less than this fraction of the map's luminance flux is not worth a light.
    double min_flux_fraction = 0.01;
};

/// The lights found and what is needed to remove any prefix of them from the map.
struct Extraction {
    std::vector<DirectionalLight> lights;  ///< strongest first
    double median_luminance = 0;           ///< solid-angle weighted, over observed samples
    double total_luminance_flux = 0;       ///< integral of Y over the observed samples
    int regions_examined = 0;              ///< candidate regions (accepted or not)
    /// Per light: the sample (pixel) indices of its region.
    std::vector<std::vector<int64_t>> region_samples;
};

/// Finds up to options.max_lights dominant lights. `saturated` (optional, 1 channel, same size as
/// env.radiance, > 0 = clipped) marks camera pixels whose radiance is a lower bound. Works on any
/// layout (regions are grown on the sphere, so they cross the lat-long seam and poles). A map
/// without compact very bright regions (an overcast sky) gives no light. Deterministic.
Extraction extract_lights(const Environment& env, const ExtractOptions& options = {},
                          const image::Image* saturated = nullptr);

/// The map with the regions of the first `count` lights set to their backgrounds (the residual
/// that goes into SH). count <= extraction.lights.size().
Environment residual_environment(const Environment& env, const Extraction& extraction, int count);

/// Report form: direction (and theta/phi in degrees), flux, colour (flux / Phi_Y), radius in
/// degrees, and the fit details above.
nlohmann::json to_json(const DirectionalLight& light);
/// Reads what to_json wrote (direction, flux, angular_radius_deg). Throws Error naming `where`
/// on missing, non-finite or out-of-range values.
DirectionalLight light_from_json(const nlohmann::json& j, const std::string& where);

}  // namespace inlight::envmap
