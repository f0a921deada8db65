// render/environment.h: the distant environment light of the path tracer: a lat-long radiance
// map (Blender/Cycles parameterisation, core/conventions.h) with rotation and intensity, looked
// up by nearest pixel, and its importance sampling.
//
// Sampling (Pharr, Jakob and Humphreys, PBR 3rd ed. sec. 14.2.4, with exact solid angles instead
// of the sin(theta) at the pixel centre): pixel (col, row) is chosen with probability
//   p(col, row) = w(col, row) Omega_row / sum(w Omega),   w = 0.2126|R| + 0.7152|G| + 0.0722|B|,
// where Omega_row is the exact solid angle of a pixel in that row, then a direction uniform in
// solid angle inside the pixel (uniform in cos(theta) over the row's band and in phi over the
// column). The density in solid angle is therefore p(col, row) / Omega_row, constant over each
// pixel. w > 0 exactly where the pixel has non-zero radiance, so every direction that carries
// light can be sampled (the slightly negative pixels of real EXRs are sampled by |value| and
// keep their sign in the estimate). The seam (u = 0 / 1, facing -x) needs nothing special:
// columns wrap by construction and directions map back through latlong_uv.
#pragma once

#include <Eigen/Core>
#include <string>

#include "envmap/environment.h"
#include "image/image.h"
#include "render/sampling.h"

namespace inlight::render {

/// Reads a lat-long environment (any 2:1 float image, 3 channels of linear_srgb radiance)
/// through lib/envmap's loader. Throws Error naming the file if it is not 2:1 or holds NaN/Inf.
image::Image load_latlong(const std::string& path);

/// Reads any full-sphere environment envmap-project reads ("latlong", "cube": a 6:1 strip
/// +X -X +Y -Y +Z -Z in the OpenGL orientation, "angular": Debevec's light probe) and returns
/// it as a lat-long map in the file's own frame. Cube and angular maps are resampled: each
/// lat-long pixel averages 4x4 directions spread uniformly in solid angle over the pixel, each
/// looked up at its nearest source texel. `latlong_height` 0 = automatic: 2N rows for N x N
/// cube faces, S/2 rows for an S x S angular map (the source's angular density at its centre).
/// Fisheye frames cover part of the sphere only and are rejected (UsageError).
image::Image load_environment_latlong(const std::string& path, const std::string& layout,
                                      int latlong_height = 0);

/// The source texel (x, y) that direction `dir` (in the file's frame) falls in, for a map of
/// the given layout and size (exposed for tests of the resampling).
Eigen::Vector2i environment_texel(envmap::Layout layout, const Eigen::Vector3d& dir, int width,
                                  int height);

/// A distant environment. Immutable after construction; safe to share between threads.
class EnvironmentLight {
  public:
    /// `latlong`: 2:1 (width = 2 height) map with >= 3 channels in linear_srgb; its frame is
    /// turned into the world frame by `world_from_env` (a rotation) and radiance is multiplied
    /// by `intensity` (>= 0). Throws Error (naming `source`) on a bad shape or non-finite pixels.
    EnvironmentLight(const image::Image& latlong, const Eigen::Matrix3d& world_from_env,
                     double intensity, const std::string& source);
    /// A constant environment of the given radiance (a 2x1 map).
    static EnvironmentLight constant(const Eigen::Vector3d& radiance);

    /// Radiance (W sr^-1 m^-2 per linear_srgb channel) arriving from world direction `dir`
    /// (pointing away from the scene, toward the environment). Nearest pixel, so that it is
    /// consistent with the piecewise-constant sampling density. Precondition: dir non-zero.
    Eigen::Vector3d eval(const Eigen::Vector3d& dir) const;

    struct Sample {
        Eigen::Vector3d dir = Eigen::Vector3d::Zero();  ///< world frame, unit
        Eigen::Vector3d radiance = Eigen::Vector3d::Zero();
        double pdf = 0;  ///< solid angle density, 1/sr
    };
    /// Importance-samples a direction (see the file comment). u in [0, 1)^2. Returns pdf = 0
    /// when the map is black everywhere.
    Sample sample(const Eigen::Vector2d& u) const;
    /// Density (1/sr) of sample() producing world direction `dir`.
    double pdf(const Eigen::Vector3d& dir) const;

    /// The pixel (col, row) of the map that world direction `dir` falls in.
    Eigen::Vector2i pixel_of(const Eigen::Vector3d& dir) const;
    /// Probability that sample() picks pixel (col, row).
    double pixel_probability(int col, int row) const { return m_dist.pmf(col, row); }
    /// Solid angle (sr) of a pixel in `row`.
    double pixel_solid_angle(int row) const { return m_row_solid_angle[static_cast<size_t>(row)]; }

    int width() const { return m_width; }
    int height() const { return m_height; }
    /// Radiance of a map pixel after intensity (env frame).
    Eigen::Vector3d pixel(int col, int row) const;
    const Eigen::Matrix3d& world_from_env() const { return m_world_from_env; }
    /// Mean radiance over the sphere (solid-angle weighted), per channel.
    Eigen::Vector3d mean_radiance() const;

  private:
    int m_width = 0, m_height = 0;
    std::vector<float> m_rgb;  ///< width * height * 3, intensity applied
    std::vector<double> m_row_solid_angle;
    std::vector<double> m_pdf;  ///< width * height: solid-angle density of each pixel, 1/sr
    Eigen::Matrix3d m_world_from_env = Eigen::Matrix3d::Identity();
    Distribution2D m_dist;
};

}  // namespace inlight::render
