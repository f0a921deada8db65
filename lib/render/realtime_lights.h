// render/realtime_lights.h: the dominant lights that envmap-project extracts (envmap/lights.h),
// shaded analytically in the CPU real-time model, and the lighting file that carries them.
//
// Per fragment of normal n and BRDF parameters m (the material after its textures), a light
// j of direction d_j, flux Phi_j (per linear_srgb channel) and angular radius alpha_j adds
//   m.albedo / pi * E_j(n)  +  f_s(n; v, d_j) * E_j(n)
// where E_j(n) = Phi_j * cap_cosine_integral(n.d_j, alpha_j) / (2 pi (1 - cos alpha_j)) is the
// exact irradiance of a uniform cap (envmap::light_irradiance, Snyder 1996) and f_s is
// brdf::eval_specular, the same lobe the BRDF SH table was baked from, evaluated at the cap's
// centre for the table's fixed view v (the model's view direction; the specular term exists
// only where the SH model has one: a non-Lambert material with a table). The SH lighting then
// holds only the residual map (the map with the lights' regions set to their background).
//
// File (docs/formats.md, "SH coefficients with lights"): what envmap-project --max-error
// writes, an inlight.sh_coefficients JSON document with a "lights" array.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "envmap/lights.h"
#include "sh/sh_io.h"

namespace inlight::render {

/// Radiance the lights add at a fragment: normal n (unit, world), BRDF parameters `material`
/// (albedo and lobe after textures), `view` the fixed view (unit, world) or null for no
/// specular term. Linear_srgb per channel.
Eigen::Vector3d shade_lights(const std::vector<envmap::DirectionalLight>& lights,
                             const Eigen::Vector3d& n, const brdf::Material& material,
                             const Eigen::Vector3d* view);

/// A lighting file: SH coefficients of the residual and the extracted lights.
struct LightingFile {
    sh::CoefficientSet sh;
    std::vector<envmap::DirectionalLight> lights;
};

/// Reads an envmap-project JSON (with or without "lights": none = pure SH). Throws Error naming
/// the file (and the light's index) on a malformed document or a bad light.
LightingFile read_lighting_file(const std::string& path);

}  // namespace inlight::render
