// weave/weave.h: procedural woven fabrics that tile exactly: the interlacing pattern (plain,
// twill, satin or a drawn matrix), the yarns' centre-lines as closed (periodic) uniform cubic
// B-splines with their radii, per-thread colours, the yarn material and the optional ply twist,
// read from a small TOML fabric file (configs/fabrics/*.toml, docs/btf.md).
//
// Frame (the BTF sample frame of docs/conventions.md, lengths in millimetres): the fabric's
// mid-plane is z = 0 with +z its normal. Warp threads run along +y (up the rectified image) and
// are spaced along x; weft threads run along +x and are spaced along y. The repeat (one tile)
// is [0, period_x_mm) x [0, period_y_mm); warp thread i has its axis at x = (i + 1/2) warp
// spacing, weft thread j at y = (j + 1/2) weft spacing. Where warp i crosses weft j, the yarn on
// top has its centre at z = +crimp_mm and the other at z = -crimp_mm.
//
// Centre-lines: along a thread the height is a uniform cubic B-spline with one control point
// per crossing (the control heights are solved so that the curve passes through +-crimp_mm at
// the crossings exactly; de Boor, "A Practical Guide to Splines", ch. IX, periodic case). The
// along-thread coordinate s is linear in the spline parameter (uniform control points reproduce
// linear functions), so a centre-line is point(s) = (x_i, s, z(s)) for a warp thread and
// (s, y_j, z(s)) for a weft thread, C2 and periodic in s with the repeat's period: the geometry
// tiles exactly. Embree's RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE uses the same basis
// (control points (x, y, z, radius), 4 per segment), so control_points() feeds it directly.
//
// Patterns (over(i, j) = warp thread i passes over weft thread j):
//   plain           (i + j) even; repeat 2 x 2.
//   twill a/b       ((j - i) mod (a + b)) < a: warp floats over a wefts, under b, the float
//                   moving up one weft per warp thread to the right (a Z twill); (a+b) x (a+b).
//   satin H/m       warp-faced: warp i goes under weft j only for j = m i (mod H); H x H,
//                   m coprime with H and 2 <= m <= H - 2 (so no two interlacings touch).
//   matrix          rows of '1' (warp over) and '0' separated by '/', drawn as seen in the
//                   image: the first row is the top weft (largest j), columns left to right are
//                   warp threads. "1" is the single-thread weave: one straight warp over one
//                   straight weft.
// The tile holds lcm(pattern repeat, colour sequence length) threads each way.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "brdf/brdf.h"

namespace inlight::weave {

enum class Pattern { kPlain, kTwill, kSatin, kMatrix };
/// "plain" | "twill" | "satin" | "matrix"; throws Error listing the names otherwise.
Pattern pattern_from_string(const std::string& name);
std::string to_string(Pattern pattern);

/// Ply twist, a shading-normal relief on the yarn surface (no geometry): `plies` ridges wound
/// around the yarn at `angle_deg` to its axis tilt the normal by up to `depth_deg` across them.
struct Twist {
    int plies = 0;          ///< 0 = no twist; 1..12
    double angle_deg = 30;  ///< helix angle of the plies to the yarn axis, [0, 80]
    double depth_deg = 20;  ///< largest normal tilt, [0, 60]
};

/// A fabric as its file describes it. Lengths in millimetres.
struct WeaveSpec {
    std::string name;
    Pattern pattern = Pattern::kPlain;
    int twill_over = 2, twill_under = 1;  ///< twill a/b, each >= 1
    int satin_harness = 5, satin_move = 2;
    std::string matrix;                                   ///< pattern = matrix: "10/01"
    double warp_spacing_mm = 0.5, weft_spacing_mm = 0.5;  ///< axis to axis, > 0
    double warp_radius_mm = 0.2, weft_radius_mm = 0.2;    ///< (0, spacing of its own set]
    /// Half the vertical distance between the two yarns' centres at a crossing, [0, 4 mm];
    /// negative = the default (warp_radius_mm + weft_radius_mm) / 2: round yarns that touch at
    /// every crossing.
    double crimp_mm = -1;
    /// Colours (linear_srgb albedo in [0, 1]) per thread: `warp_colors` is a sequence of
    /// palette letters 'a'..'h' repeated across the warp threads ("" = every warp thread has
    /// warp_albedo); likewise weft.
    Eigen::Vector3d warp_albedo{0.5, 0.5, 0.5}, weft_albedo{0.5, 0.5, 0.5};
    std::string warp_colors, weft_colors;
    /// palette[k] is letter 'a' + k; a letter the file leaves out is NaN (using it is an error)
    std::vector<Eigen::Vector3d> palette;
    /// The yarn surface's BRDF (albedo is replaced by each thread's colour).
    brdf::Material material;
    Twist twist;
    /// The holder plate under the fabric: a Lambertian plane just below the lowest yarn,
    /// linear albedo in [0, 1].
    Eigen::Vector3d backing_albedo{0.05, 0.05, 0.05};
};

/// Reads a fabric file (flat keys, plus a [material] table of brdf material keys,
/// brdf::read_material_keys). Keys: pattern, twill = [a, b], satin = [H, m], matrix,
/// spacing_mm (both sets) or warp_spacing_mm / weft_spacing_mm, yarn_radius_mm (both) or
/// warp_radius_mm / weft_radius_mm, crimp_mm, warp_albedo, weft_albedo, warp_colors,
/// weft_colors, color_a .. color_h, twist_plies, twist_angle_deg, twist_depth_deg,
/// backing_albedo, name, description. Throws Error "<file>:<line>: [<table>] <key>: <what>"
/// for a bad value, an unknown key or an inconsistent fabric (validate()).
WeaveSpec parse_weave(const std::string& toml_text, const std::string& source);
WeaveSpec load_weave(const std::string& path);

/// Checks a spec; throws Error prefixed by `context` naming the first bad parameter.
void validate(const WeaveSpec& spec, const std::string& context);

enum class ThreadSet { kWarp, kWeft };

/// One thread of the repeat: a closed centre-line along its own axis.
struct Yarn {
    ThreadSet set = ThreadSet::kWarp;
    int index = 0;         ///< i for warp, j for weft
    double offset_mm = 0;  ///< x of a warp axis, y of a weft axis
    double radius_mm = 0.2;
    double knot_spacing_mm = 0.5;      ///< along-thread distance between control points
    std::vector<double> control_z_mm;  ///< B-spline control heights, one per crossing (periodic)
    Eigen::Vector3d albedo{0.5, 0.5, 0.5};

    /// Length of one period along the thread (knots x knot spacing), mm.
    double period_mm() const;
    /// Height of the centre-line at along-thread coordinate s (any real; periodic), mm.
    double z(double s_mm) const;
    /// dz/ds.
    double dz_ds(double s_mm) const;
    /// Centre-line point at s in the sample frame, shifted by `shift` (x, y) mm.
    Eigen::Vector3d point(double s_mm, const Eigen::Vector2d& shift = {0, 0}) const;
    /// Embree-ready B-spline control points (x, y, z, radius) whose curve covers at least
    /// s in [s0_mm, s1_mm]; the first segment starts at the returned *s_start_mm (u = 0) and
    /// each of the (size - 3) segments spans knot_spacing_mm.
    std::vector<Eigen::Vector4d> control_points(double s0_mm, double s1_mm,
                                                const Eigen::Vector2d& shift,
                                                double* s_start_mm) const;
};

/// A built fabric: the repeat's size and its yarns.
struct Weave {
    WeaveSpec spec;
    int warp_count = 0, weft_count = 0;  ///< threads per tile
    double period_x_mm = 0, period_y_mm = 0;
    double crimp_mm = 0;                ///< resolved (spec.crimp_mm or its default)
    std::vector<Yarn> yarns;            ///< warp threads first, then weft threads
    double z_min_mm = 0, z_max_mm = 0;  ///< vertical extent of the yarn surfaces (bound)
    /// Whether warp i goes over weft j (indices wrap: any integers).
    bool over(int i, int j) const;
    std::vector<char> over_matrix;  ///< warp_count x weft_count, [j * warp_count + i]
};

/// Builds the tile: pattern, thread counts, centre-lines, colours. Calls validate().
Weave build(const WeaveSpec& spec);

/// The pattern alone: over(i, j) for i < pattern width, j < pattern height (its own repeat).
/// Returns the repeat size in *width, *height.
std::vector<char> pattern_matrix(const WeaveSpec& spec, int* width, int* height);

/// Uniform cubic B-spline basis at u in [0, 1] (weights of 4 consecutive control points) and
/// its first and second derivatives.
Eigen::Vector4d bspline_basis(double u);
Eigen::Vector4d bspline_basis_du(double u);
Eigen::Vector4d bspline_basis_du2(double u);

}  // namespace inlight::weave
