// core/conventions.h: the frames and parameterisations of docs/conventions.md, stated once.
//
// World / device frame: right-handed, +z up for environments; for the device, +z points out of
// the screen toward the viewer (the front camera's optical axis), +x right, +y up.
// Lat-long maps follow Blender/Cycles: theta = pi * v measured from +z, phi = pi * (1 - 2u),
// so the image centre (u = 0.5) faces +x, u = 0.25 faces +y, and the left/right edges face -x.
// Pixel centres lie at +0.5: u = (column + 0.5) / width, v = (row + 0.5) / height, row 0 on top.
#pragma once

#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace inlight {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 1.0 / kPi;

/// Unit vector for polar angle theta (from +z) and azimuth phi (from +x toward +y), radians.
Eigen::Vector3d direction_from_spherical(double theta, double phi);

/// theta in [0, pi] and phi in (-pi, pi] of a non-zero vector (atan2: every quadrant correct).
void spherical_from_direction(const Eigen::Vector3d& dir, double& theta, double& phi);

/// Lat-long (Cycles) direction of texture coordinates u, v in [0, 1] (u wraps).
Eigen::Vector3d latlong_direction(double u, double v);

/// Inverse of latlong_direction: u in [0, 1), v in [0, 1]. Precondition: dir non-zero.
Eigen::Vector2d latlong_uv(const Eigen::Vector3d& dir);

/// Exact solid angle (sr) of lat-long pixel row `row` of `height` rows spanning the full 2*pi:
/// (2*pi / width) * (cos theta0 - cos theta1) per pixel.
double latlong_pixel_solid_angle(int row, int width, int height);

/// Parses a rotation: "none"; "y-up" (a y-up frame into the z-up frame: +90 deg about x);
/// or a comma-separated list of axis=degrees applied left to right, e.g. "z=90" or
/// "x=90,z=-30". Returns world_from_input. Throws UsageError on bad syntax and on an angle that
/// is not a finite number in [-360, 360] ("z=nan", "x=inf", "y=1e300").
Eigen::Matrix3d parse_rotation(const std::string& spec);

}  // namespace inlight
