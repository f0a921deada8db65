// btf/dome.h: the direction sets of a bidirectional texture function (BTF): the Bonn UBO2003
// hemisphere dome, direction lists and light/view pair lists read from text files, and the
// UBO2003 file naming (tl<theta_l> pl<phi_l> tv<theta_v> pv<phi_v>).
//
// Frame (docs/conventions.md, "BTF sample frame"): +z is the sample's normal; +x points along the
// rectified image's columns (to the right), +y toward the image's top row, so (x, y, z) is
// right-handed. theta is the polar angle from +z and phi the azimuth from +x toward +y, both in
// degrees at I/O (file names, direction files) and radians in vectors' maths.
// Reference: the BTF thesis, section 2 (the Bonn database: 81 x 81 directions, 6 theta rings).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace inlight::btf {

/// One direction on the sample's hemisphere, stored as the angles it was named with.
struct Direction {
    double theta_deg = 0;  ///< polar angle from the sample normal (+z), [0, 90]
    double phi_deg = 0;    ///< azimuth from +x toward +y, [0, 360)

    /// Unit vector in the sample frame. At theta = 0 every phi gives (0, 0, 1).
    Eigen::Vector3d vector() const;
    /// The angles of a unit vector (phi in [0, 360); phi = 0 at the pole).
    /// Precondition: v is unit length to 1e-6 and v.z >= -1e-12 (checked; throws Error).
    static Direction from_vector(const Eigen::Vector3d& v);
};

/// Angle between two directions, degrees (exact at the pole, stable for tiny angles).
double angle_between_deg(const Direction& a, const Direction& b);

/// The Bonn UBO2003 dome: 81 directions, theta = 0, 15, ..., 75 degrees with 1, 6, 12, 18, 20
/// and 24 azimuths spaced evenly from phi = 0. Ordered ring by ring, phi ascending.
const std::vector<Direction>& ubo2003_dome();

/// The UBO2003 dome plus kHorizonRingThetasDeg.size() rings of 24 light directions (phi every 15
/// deg from 0) between its last ring (75 deg) and the horizon: 177 directions, the dome's 81
/// first. A BTF measures nothing of light beyond its last ring, where rooms are lit (windows,
/// lamps) and where a woven sample's btf / cos rises (the yarns' sides face the light):
/// docs/btf.md "Light beyond the last ring". For synthetic captures (render capture-btf
/// --btf-light-set).
const std::vector<Direction>& ubo2003_horizon_dome();
inline constexpr double kHorizonRingThetasDeg[] = {80.0, 84.0, 87.0, 89.0};

/// n light directions spread evenly over the hemisphere down to theta kFibonacciMaxThetaDeg: the
/// spherical Fibonacci lattice (Marques et al. 2013) with both ends included, point i at
/// cos(theta) = 1 - i / (n - 1) (1 - cos(kFibonacciMaxThetaDeg)) and phi = 360 i / golden ratio
/// (mod 360): the first exactly at the pole (the frontal light, `tl000 pl000`, that tools take
/// the albedo from), the last exactly at kFibonacciMaxThetaDeg.
/// Equal solid angle per direction and no rings, so light from near the horizon is sampled as
/// densely as light from above: with 600 directions the shaded BTF's mean luminance is within
/// 2% of the path-traced truth under the 13 environments of docs/btf.md "Light beyond the last
/// ring" for every fabric measured, where the dome with horizon rings (177) is not. For
/// synthetic captures.
/// Precondition: n >= 2 (checked).
std::vector<Direction> fibonacci_hemisphere(int n);
inline constexpr double kFibonacciMaxThetaDeg = 89.0;

/// A named light set: "ubo2003", "ubo2003-horizon" or "fibonacci-N" with N in [16, 4096]
/// (Error naming the value otherwise).
std::vector<Direction> named_direction_set(const std::string& name);

/// Writes a direction set as read_directions reads it (`theta_deg phi_deg` per line, exact to
/// the last bit), with a comment line first.
std::string format_directions(const std::vector<Direction>& dirs, const std::string& comment);

/// Reads a direction set: a text file with one direction per line, either `theta_deg phi_deg`
/// or a unit vector `x y z` in the sample frame; blank lines and `#` comments are ignored.
/// Throws Error naming the file and line for: a malformed line, NaN or Inf, theta outside
/// [0, 90], a vector that is not unit length (|1 - |v|| > 1e-6) or points below the surface,
/// and a direction that duplicates an earlier one (within 1e-6 degrees; both lines named).
std::vector<Direction> read_directions(const std::string& path);

/// A light and a view direction.
struct DirectionPair {
    Direction light;
    Direction view;
};

/// Reads a list of (light, view) pairs: one pair per line, `theta_l phi_l theta_v phi_v` in
/// degrees or two unit vectors `lx ly lz vx vy vz`. The same checks as read_directions apply to
/// each direction; a pair that duplicates an earlier pair is an error.
std::vector<DirectionPair> read_direction_pairs(const std::string& path);

/// The file stem of one BTF image in UBO2003 naming: "tl015 pl060 tv030 pv090". Whole-degree
/// angles are written with three digits; others with three decimals ("tl012.500").
std::string ubo2003_stem(const Direction& light, const Direction& view);

/// The folder of one view, as the Bonn distribution groups images: "tv030_pv090".
std::string ubo2003_view_folder(const Direction& view);

/// The light and view angles in a file name or path, found by pattern (not fixed offsets):
/// `tl<deg>`, `pl<deg>`, `tv<deg>`, `pv<deg>` in that order, separated by any non-digit
/// characters, with or without a prefix ("00123 tl015 pl060 tv030 pv090.jpg",
/// "tv030_pv090/tl015_pl060_tv030_pv090.png"). Only the file-name part of a path is read.
/// std::nullopt when the name holds no such pattern.
std::optional<DirectionPair> parse_ubo2003_name(const std::string& name);

/// Index of the direction in `set` within tol_deg of `d`, or std::nullopt.
std::optional<int> find_direction(const std::vector<Direction>& set, const Direction& d,
                                  double tol_deg = 1e-6);

}  // namespace inlight::btf
