// brdf/grid.h: the grids of normals over which brdf-sh-bake tabulates BRDF SH coefficients, and
// the bilinear lookup the GLES shader performs (this C++ is the specification of the emitted
// GLSL: same float operations, same order; see glsl.h).
//
// Normals are unit vectors in the DEVICE frame (core/conventions.h: +z out of the screen toward
// the viewer). Table layout for every grid: row i1 in [0, rows), column i2 in [0, cols), flat
// node index i1 * cols + i2 (the report's brdfIndex = 45 i1 + 9 i2 + k for 5x5 and 9 coefficients).
//
// Grids:
//  - report5x5: the inlight report's nodes, theta_s = (i1 - 2) pi/4, phi_s = (i2 - 2) pi/4 with
//    theta_s, phi_s in [-pi/2, pi/2] and normal = (sin theta_s cos phi_s, sin theta_s sin phi_s,
//    cos theta_s). A negative theta_s is the normal at |theta_s| and phi_s + pi, so these
//    "signed-theta" nodes cover the whole upper hemisphere. The report's own lookup
//    (acos, atan(y/x)) reaches only rows 2..4 and, for x < 0, returns the coefficients of the
//    mirrored normal (-x, -y, z); at the pole atan(0/0) is NaN. lookup() here folds phi with
//    atan2 instead: phi outside [-pi/2, pi/2] becomes phi -+ pi with theta_s = -theta.
//  - thetaphi:RxC[@DEG]: theta_max = DEG degrees (default 90), theta_i1 = theta_max i1 / (R - 1)
//  (row 0 is the pole: its C nodes are one
//    normal, baked once), phi_i2 = 2 pi i2 / C, periodic: interpolation wraps from column C-1
//    to column 0.
//  - octa:N: hemi-octahedral map (no pole, no seam): p = (x, y) / (|x| + |y| + z), rotated 45
//    degrees to the square (u, v) = (p.x + p.y, p.x - p.y) in [-1, 1]^2; node (i1, i2) at
//    u = -1 + 2 i2 / (N - 1), v = -1 + 2 i1 / (N - 1). The square's edges are the horizon.
//    The map is only C0 across x = 0 and y = 0 (the octant folds), so bilinear interpolation
//    of a smooth function is first order there: error O(h), not O(h^2) (docs/brdf.md).
//  - disk:N: orthographic hemisphere, (u, v) = (x, y) in [-1, 1]^2, node (i1, i2) at
//    u = -1 + 2 i2 / (N - 1), v = -1 + 2 i1 / (N - 1), normal (u, v, sqrt(1 - u^2 - v^2));
//    nodes outside the unit disk hold the horizon normal normalize(u, v, 0). Smooth (no pole,
//    no seam, no fold): second-order interpolation except near the horizon, where a fixed
//    angular step spans ever smaller (u, v) steps.
#pragma once

#include <Eigen/Core>
#include <string>

#include "core/conventions.h"

namespace inlight::brdf {

enum class GridKind { kReport5x5, kThetaPhi, kOcta, kDisk };

/// A grid of normals; see the file comment for each kind.
struct Grid {
    GridKind kind = GridKind::kOcta;
    int rows = 9;                ///< i1 count (theta for thetaphi, v for octa)
    int cols = 9;                ///< i2 count (phi for thetaphi, u for octa)
    double theta_max = kPi / 2;  ///< thetaphi: polar angle of the last row (radians)
    int node_count() const { return rows * cols; }
};

/// Parses "report5x5", "thetaphi:RxC[@DEG]" (R >= 2, C >= 3, 0 < DEG <= 180), "octa:N" or
/// "disk:N" (N >= 2).
/// Throws UsageError.
Grid parse_grid(const std::string& spec);
/// The spec string parse_grid() reads back.
std::string to_string(const Grid& grid);

/// Unit normal (device frame) of node (i1, i2). Precondition: indices in range (checked).
Eigen::Vector3d grid_node_normal(const Grid& grid, int i1, int i2);

/// The four nodes and weights of bilinear interpolation at a normal.
struct GridCoord {
    int r0 = 0, r1 = 0, c0 = 0, c1 = 0;  ///< rows and columns of the 2x2 cell
    float fr = 0, fc = 0;                ///< fractions toward r1 and c1, in [0, 1]
};

/// Where normal n (any non-zero length, device frame) falls in the grid, computed in float
/// exactly as the emitted GLSL brdf_grid_coord() does. Normals beyond the grid (z < 0; theta
/// > theta_max) clamp to its edge. Never NaN for a non-zero n, including the poles.
GridCoord grid_coord(const Grid& grid, const Eigen::Vector3f& n);

/// The inlight report's sph2index(cart2sph(n)) verbatim: (acos(z/|n|) 4/pi + 2,
/// atan(y/x) 4/pi + 2), for tests and docs that show its quadrant loss; NaN at the pole.
Eigen::Vector2f report_original_index(const Eigen::Vector3f& n);

}  // namespace inlight::brdf
