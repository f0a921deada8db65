// btf/sh_lighting.h: the app's per-frame lighting (SH coefficients, dominant lights) turned into
// the weights of a BTF's light directions (btf/lighting.h), in closed form.
//
// The weight of light direction k under a rule (CellRule) is linear in the radiance:
//   W_k = integral over the upper hemisphere of L(w) kappa_k(w) dw,
// kappa_k the rule's kernel (the cell's indicator; times cos(theta) / cos(theta_k) for kCosine;
// the barycentric hat for kBarycentric). For SH lighting L(w) = sum_j c_j Y_j(w) this is
//   W_k = sum_j A(k, j) c_j,   A(k, j) = integral of Y_j kappa_k,
// so the app spends K x bands^2 multiply-adds per colour per frame (81 x 9 = 729 for the Bonn
// dome at 3 bands) instead of integrating a map. A is computed once per light set, rule and
// rotation by integrate_dome_cells() over lat-long maps of the basis functions, so it carries
// exactly the quadrature of the map path (the same cells, the same horizon handling).
//
// A dominant light (envmap::DirectionalLight: a direction and the irradiance E_perp it delivers
// facing it) is a delta in L: W_k = E_perp kappa_k(d) (kCosine: cos(theta_d) / cos(theta_k) for
// the cell that holds d, whatever its size), nothing when d is at or below the sample's plane.
//
// Frames: coefficients and light directions in the environment's frame (the device frame for
// the app), rotated into the sample frame by options.sample_from_env, as for a map.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "btf/dome.h"
#include "btf/lighting.h"

namespace inlight::btf {

/// A (lights.size() x sh_bands^2): W_k = sum_j A(k, j) c_j per channel, c in sh/sh.h order
/// (real SH without Condon-Shortley phase, index l (l + 1) + m), environment frame. sh_bands in
/// 1..9 and map_height in 16..2048 (the basis maps are 2 map_height x map_height; quadrature
/// error falls as 1 / map_height^2 inside cells) are checked (Error). Deterministic for any
/// thread count.
Eigen::MatrixXd sh_light_weight_matrix(const std::vector<Direction>& lights, int sh_bands,
                                       const DomeLightingOptions& options = {},
                                       int map_height = 256);

/// The weights one directional light adds: `direction` (unit, environment frame; checked),
/// `irradiance` E_perp per linear_srgb channel (finite; checked). Returns the per-light weights
/// (solid_angle_sr all 0; below_horizon = irradiance when the light is at or below the plane).
DomeLighting directional_light_weights(const std::vector<Direction>& lights,
                                       const Eigen::Vector3d& direction,
                                       const Eigen::Vector3d& irradiance,
                                       const DomeLightingOptions& options = {});

/// directional_light_weights for many point lights over one set of light directions (an
/// extended light spread as points, every frame): the light vectors, the cells' eligibility and
/// the rule's partners or triangulation are built once. Throws Error as directional_light_weights
/// does (no light directions, all within 0.5 deg of the horizon under the cosine rules).
class PointLightWeights {
public:
    PointLightWeights(const std::vector<Direction>& lights, const DomeLightingOptions& options = {});
    ~PointLightWeights();
    PointLightWeights(PointLightWeights&&) noexcept;
    PointLightWeights& operator=(PointLightWeights&&) noexcept;
    /// Adds the weights of a point light at `direction` (unit, environment frame; checked) of
    /// irradiance E_perp (finite; checked) to `weight` (one per light direction). Returns false,
    /// adding nothing, when the light is at or below the sample's plane. `hint` (the triangulated
    /// rules): the triangle to try first, updated to the one found, so nearby points (a cap's)
    /// search little; the result does not depend on it.
    bool add(const Eigen::Vector3d& direction, const Eigen::Vector3d& irradiance,
             std::vector<Eigen::Vector3d>& weight, size_t* hint = nullptr) const;

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace inlight::btf
