// btf/lighting.h: a lat-long environment turned into the weights of a BTF's light directions:
// each light direction owns a cell of the hemisphere (the directions nearer to it than to any
// other light, a spherical Voronoi cell) and its weight is the environment's radiance
// integrated over that cell.
//
// Why this weight: a BTF image of light l is the reflected radiance divided by the irradiance
// E_perp that the distant light delivers perpendicular to its own direction, so it already
// holds the cosine, shadowing and inter-reflection: btf(x, l, v) = L_r / E_perp (1/sr). Under
// an environment L_env the reflected radiance is the integral over the hemisphere of
// btf(x, l, v) L_env(l) dl, which the BTF's light set turns into the sum
//   L_r(x, v) ~= sum_k btf(x, l_k, v) W_k,   W_k = integral over cell k of L_env(l) dl,
// i.e. btf is taken constant over each cell (the thesis' discrete rendering equation, section
// 2; Sattler, Sarlette and Klein 2003 shade BTFs under environments this way): CellRule::kConstant.
// But btf holds the cosine of its own light direction, and a cell of the outer ring reaches down
// to the horizon, where the true cosine goes to 0: the constant rule lights a Lambertian plate
// under a uniform sky 5.9% too bright, and a room lit from near the horizon far more. The default
// CellRule::kCosine divides the cosine out and integrates it exactly over the cell,
//   W_k = integral over cell k of L_env(l) cos(theta_l) / cos(theta_k) dl,
// so btf / cos is what is taken constant: exact for any Lambertian BTF under any environment,
// and light near the horizon fades with its cosine as it does on the real sample. Light
// directions within 0.5 deg of the horizon own no cell (their images are black and the division
// would blow up): their neighbours take it. Light arriving from below the sample's plane (z <= 0
// in the sample frame) reaches no light direction and is dropped (reported in below_horizon).
//
// Frames: the map follows Blender/Cycles (core/conventions.h), in its own frame; `sample_from_env`
// turns those directions into the BTF sample frame (docs/conventions.md, +z the sample normal).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "btf/dataset.h"
#include "btf/dome.h"
#include "image/image.h"

namespace inlight::btf {

/// How a light direction's weight treats the cosine inside its BTF image (see above).
enum class CellRule {
    kConstant,     ///< btf constant over the cell: W_k = integral of L over the cell (the thesis)
    kCosine,       ///< btf / cos constant: W_k = integral of L cos(theta) / cos(theta_k)
    /// btf linear over the spherical Delaunay triangles of the light directions and a ring of
    /// horizon points (every 5 deg at theta 90) where btf is 0: W_k = integral of L beta_k,
    /// beta_k the barycentric weight of light k (those of the horizon points are dropped).
    kBarycentric,
    /// kCosine, and beyond the outermost ring (theta > theta_k of an outer light k, where its
    /// cell is one-sided) btf / cos extrapolated linearly in theta from k and its inner partner
    /// j (the nearest light of the next ring in): btf / cos = rho_k (1 + t) - rho_j t,
    /// t = (theta - theta_k) / (theta_k - theta_j). Its weights may be negative for j.
    kExtrapolated,
    /// btf / cos linear over the same triangles as kBarycentric: W_k = integral of L beta_k
    /// cos(theta) / cos(theta_k). A horizon point (and a light within 0.5 deg of the horizon)
    /// takes the btf / cos of its nearest light, so beyond the last ring it is kCosine
    /// interpolated in azimuth. Exact for a Lambertian BTF, like kCosine; a light between
    /// directions is spread over the three around it instead of moving to the nearest.
    kCosineBarycentric,
};

struct DomeLightingOptions {
    CellRule rule = CellRule::kCosine;
    /// Each map pixel is split into subsamples x subsamples directions, uniform in solid angle
    /// over the pixel (uniform in cos theta over the row's band and in phi over the column),
    /// each assigned whole to its nearest light direction. 1..64.
    int subsamples = 4;
    /// Rotation from the map's frame into the sample frame (determinant 1, checked).
    Eigen::Matrix3d sample_from_env = Eigen::Matrix3d::Identity();
};

/// The environment seen through a BTF's light set.
struct DomeLighting {
    /// Per light direction: the map's radiance integrated over its cell (with kCosine, weighted
    /// by cos(theta) / cos(theta_k)), W m^-2 per linear_srgb channel. Multiplies btf = L_r /
    /// E_perp (1/sr).
    std::vector<Eigen::Vector3d> weight;
    /// Per light direction: the solid angle of its cell, sr (they sum to 2 pi; 0 for a light
    /// direction within 0.5 deg of the horizon under kCosine).
    std::vector<double> solid_angle_sr;
    /// The integral over the lower hemisphere (sample frame z <= 0), which no light sees.
    Eigen::Vector3d below_horizon = Eigen::Vector3d::Zero();
};

/// Integrates `latlong` (2:1, >= 3 channels, linear_srgb radiance, finite: checked, Error) over
/// each light direction's cell. `lights` must be non-empty (Error) and in the upper hemisphere.
/// Deterministic for any thread count (rows are summed in a fixed order).
DomeLighting integrate_dome_cells(const image::Image& latlong, const std::vector<Direction>& lights,
                                  const DomeLightingOptions& options = {});

/// integrate_dome_cells' weights for every channel of `map` (>= 1 channels, linear_srgb, finite;
/// the same checks): out(k, c) is channel c integrated over light k's cell, exactly the value
/// integrate_dome_cells gives for a 3-channel map. Each of the map's directions is placed in its
/// cell (or triangle) once for all channels: the SH weight matrix passes all bands^2 basis
/// functions in one map (sh_lighting.h).
Eigen::MatrixXd integrate_dome_cells_channels(const image::Image& map, const std::vector<Direction>& lights,
                                              const DomeLightingOptions& options = {});

/// The shaded image of a BTF as terms of BtfSource::combine: L = sum_k btf_k W_k with
/// btf = image / irradiance_w_m2, for each view `views[i]` blended with `view_weights[i]`.
/// Term weight W_k * view_weight / irradiance per channel; view-major, lights in order. On a
/// btf-pca folder (CompressedBtf::combine) the environment so folds into C coefficients per
/// group and channel: C multiply-adds per pixel and view, whatever the number of lights.
/// Precondition: views and view_weights of equal size, irradiance_w_m2 > 0 (checked).
std::vector<ImageTerm> shading_terms(const DomeLighting& lighting, const std::vector<int>& views,
                                     const std::vector<double>& view_weights, double irradiance_w_m2);

/// Index of the light direction whose cell holds unit vector `d` (largest cosine; ties go to the
/// lowest index). `light_vectors` are unit vectors in the sample frame; those whose `eligible`
/// entry is false (when given) own no cell.
int nearest_light(const std::vector<Eigen::Vector3d>& light_vectors, const Eigen::Vector3d& d,
                  const std::vector<char>* eligible = nullptr);

/// The triangles CellRule::kBarycentric and kCosineBarycentric interpolate over, as another
/// implementation (an app's, from a manifest) needs them: a direction d above the sample's plane
/// lies in a triangle (a, b, c) whose w = (d.(b x c), a.(d x c), a.(b x d)) are all >= 0 (on an
/// edge either triangle gives the same weights); vertex i of it takes beta_i = w_i / sum(w) and
/// passes it to owner[i] (none when -1); under kCosineBarycentric light k so receives
/// beta d_z / k_z.
struct LightTriangulation {
    /// Unit vectors in the sample frame: the light directions in order, then the horizon points
    /// (theta 90 deg, phi every 5 deg, those not within 1e-3 deg of a light).
    std::vector<Eigen::Vector3d> vertices;
    /// Per vertex, the light its weight goes to: itself for a light; for a horizon point, none
    /// under kBarycentric (btf is 0 there) and the nearest light more than 0.5 deg above the
    /// horizon under kCosineBarycentric, which is also where a light within 0.5 deg of the
    /// horizon passes its weight.
    std::vector<int> owner;
    std::vector<std::array<int, 3>> triangles;  ///< spherical Delaunay, indices into vertices
};
/// Precondition: rule is kBarycentric or kCosineBarycentric and lights are not all within 0.5
/// deg of the horizon (Error otherwise).
LightTriangulation light_triangulation(const std::vector<Direction>& lights, CellRule rule);

/// "constant" | "cosine" | "barycentric" | "extrapolated" | "cosine-barycentric", and back
/// (Error naming the value).
std::string to_string(CellRule rule);
CellRule cell_rule_from_string(const std::string& name);

}  // namespace inlight::btf
