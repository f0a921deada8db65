// render/reference.h: references for the path tracer's error: a converged render, an image read
// back from a file, or, for a Lambert sphere, the exact image from brute-force irradiance (the
// issue-13 comparison: mean relative error against brute force).
//
// Brute force: the environment is the renderer's own piecewise-constant lat-long map (nearest
// pixel), so E(n) = sum over pixels of L_pixel * integral over the pixel of max(0, n . w) dw.
// Each pixel is split into sub x sub cells of equal solid angle (uniform in cos theta over the
// row band and in phi over the column) and the clamped cosine is taken at the cell centre; the
// only error is the midpoint rule on cells that the horizon cuts.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/environment.h"
#include "render/scene.h"

namespace inlight::render {

/// E(n) (per linear_srgb channel) of `env` at world normal `n` (unit), each pixel split into
/// sub x sub cells (sub >= 1).
Eigen::Vector3d brute_force_irradiance(const EnvironmentLight& env, const Eigen::Vector3d& n,
                                       int sub);

/// The same sums for many normals: per row of cells, prefix sums over columns of L, L cos(phi)
/// and L sin(phi), so that the cells above a normal's horizon (a circular range of columns,
/// from the cosine's zero crossing) cost O(1) per row: O(rows) per normal instead of O(cells).
/// Equals brute_force_irradiance up to rounding (and to cells whose centre lies on the horizon
/// within rounding, which add ~0).
class IrradianceTable {
  public:
    IrradianceTable(const EnvironmentLight& env, int sub);
    Eigen::Vector3d irradiance(const Eigen::Vector3d& n) const;

  private:
    int m_cols = 0, m_rows = 0;  ///< cells per row, rows of cells
    Eigen::Matrix3d m_env_from_world;
    std::vector<double> m_z;       ///< cos(theta) of each row of cells
    /// Per row: (m_cols + 1) prefix entries of 9 values (L rgb, L cos phi rgb, L sin phi rgb),
    /// solid angle of the cell included.
    std::vector<double> m_prefix;
};

/// Cells per pixel side that keep every cell within kMaxCellDeg of arc (sub for a map of
/// `height` rows).
int brute_force_subdivision(int height);
/// 0.71 deg cells (5.6-degree pixels / 8): the clamped cosine's kink at the horizon costs < 1e-4 relative (midpoint rule
/// on the cut cells; checked against cells of half the size, differences ~2e-6).
inline constexpr double kMaxCellDeg = 0.71;

/// What an error is measured against.
struct ConvergenceReference {
    std::string kind;          ///< "render" | "brute_force_irradiance" | "file"
    image::Image radiance;     ///< 3 channels, linear_srgb
    image::Image std_error;    ///< 3 channels; zeros for an exact reference
    int spp = 0;               ///< "render": its samples per pixel
    double rel_error = 0;      ///< its own relative noise (0 when exact)
    /// Pixels whose centre ray hits the scene's geometry (where mean_rel_error is taken).
    std::vector<uint8_t> object_mask;
};

/// Which pixels' centre rays hit geometry (the camera of `scene`).
std::vector<uint8_t> object_pixels(const Scene& scene);

/// The exact image at pixel centres of a scene whose only object is one untextured Lambert
/// sphere (convex: no interreflection, L = albedo / pi * E(n)); escaping rays see the map.
/// Parallel over pixels, deterministic. Throws UsageError naming the scene otherwise.
ConvergenceReference irradiance_reference(const Scene& scene);

/// A reference read from `path` (an EXR of the scene's size) and, when it exists, its standard
/// error `<stem>_stderr.exr` (else zeros). Throws Error naming the file on a size mismatch.
ConvergenceReference file_reference(const Scene& scene, const std::string& path);

}  // namespace inlight::render
