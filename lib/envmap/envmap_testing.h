// envmap/envmap_testing.h: synthetic environments for lib/envmap's tests (header-only, tests only).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "core/conventions.h"
#include "envmap/environment.h"
#include "envmap/lights.h"
#include "envmap/validate.h"

namespace inlight::envmap::testmaps {

using Fn = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

/// A smooth-cap light of the given geometry and flux.
inline DirectionalLight smooth_light(const Eigen::Vector3d& direction, double radius,
                                     const Eigen::Vector3d& flux) {
    DirectionalLight l;
    l.direction = direction;
    l.angular_radius = radius;
    l.flux = flux;
    l.shading = LightShading::kSmoothCap;
    return l;
}

/// The analytic irradiance of sh_bands of SH plus lights at each normal (normals x 3).
inline Eigen::MatrixXd sh_and_lights_irradiance(const Eigen::MatrixXd& coeffs, int sh_bands,
                                                const std::vector<DirectionalLight>& lights,
                                                const std::vector<Eigen::Vector3d>& normals) {
    Eigen::MatrixXd e = sh_irradiance(coeffs, sh_bands, normals);
    for (const auto& l : lights)
        for (size_t i = 0; i < normals.size(); ++i)
            e.row(static_cast<Eigen::Index>(i)) += light_irradiance(l, normals[i]).transpose();
    return e;
}

inline Environment latlong(int w, int h, const Fn& f) {
    Environment env;
    env.layout = Layout::kLatLong;
    env.source = "synthetic";
    env.radiance = image::Image(w, h, 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const Eigen::Vector3d v = f(latlong_direction((x + 0.5) / w, (y + 0.5) / h));
            for (int c = 0; c < 3; ++c) env.radiance.at(x, y, c) = static_cast<float>(v[c]);
        }
    }
    return env;
}

inline Environment cube(int n, const Fn& f) {
    Environment env;
    env.layout = Layout::kCube;
    env.source = "synthetic-cube";
    env.radiance = image::Image(6 * n, n, 3);
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const Eigen::Vector3d v = f(cube_direction(face, (i + 0.5) / n, (j + 0.5) / n));
                for (int c = 0; c < 3; ++c) env.radiance.at(face * n + i, j, c) = float(v[c]);
            }
        }
    }
    return env;
}

inline Environment angular(int n, const Fn& f) {
    Environment env;
    env.layout = Layout::kAngular;
    env.source = "synthetic-angular";
    env.radiance = image::Image(n, n, 3);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            double u = -1 + 2.0 * (x + 0.5) / n, v = 1 - 2.0 * (y + 0.5) / n;
            const double r = std::sqrt(u * u + v * v);
            if (r > 1) u /= r, v /= r;
            const Eigen::Vector3d val = f(angular_direction(u, v));
            for (int c = 0; c < 3; ++c) env.radiance.at(x, y, c) = float(val[c]);
        }
    }
    return env;
}

// --- Convention pins, written out by hand from the published definitions (never computed with
// cube_direction or angular_direction, which they check). docs/conventions.md states them.

/// A texel of a cube strip with 2 x 2 texels per face and its direction (unnormalised), from the
/// OpenGL ES 3.0.6 specification, section 3.8.10, table 3.21 (face selection): the face is the
/// major axis ma of the direction r, and s = (sc / |ma| + 1) / 2, t = (tc / |ma| + 1) / 2 with
///   +X: sc = -rz, tc = -ry     -X: sc = +rz, tc = -ry
///   +Y: sc = +rx, tc = +rz     -Y: sc = +rx, tc = -rz
///   +Z: sc = +rx, tc = -ry     -Z: sc = -rx, tc = -ry
/// Row 0 of a face is t = 0 (the image's top row). Texel (i, j) of a 2 x 2 face has its centre at
/// sc = i - 0.5, tc = j - 0.5, so each direction below is the table solved for r with |ma| = 1.
struct CubePin {
    int face, i, j;  ///< face 0..5 = +X -X +Y -Y +Z -Z (the strip's order), column i, row j
    double x, y, z;
};
inline constexpr CubePin kCubePins[] = {
    // +X: rx = 1, ry = -tc, rz = -sc
    {0, 0, 0, 1, 0.5, 0.5}, {0, 1, 0, 1, 0.5, -0.5}, {0, 0, 1, 1, -0.5, 0.5}, {0, 1, 1, 1, -0.5, -0.5},
    // -X: rx = -1, ry = -tc, rz = sc
    {1, 0, 0, -1, 0.5, -0.5}, {1, 1, 0, -1, 0.5, 0.5}, {1, 0, 1, -1, -0.5, -0.5}, {1, 1, 1, -1, -0.5, 0.5},
    // +Y: ry = 1, rx = sc, rz = tc
    {2, 0, 0, -0.5, 1, -0.5}, {2, 1, 0, 0.5, 1, -0.5}, {2, 0, 1, -0.5, 1, 0.5}, {2, 1, 1, 0.5, 1, 0.5},
    // -Y: ry = -1, rx = sc, rz = -tc
    {3, 0, 0, -0.5, -1, 0.5}, {3, 1, 0, 0.5, -1, 0.5}, {3, 0, 1, -0.5, -1, -0.5}, {3, 1, 1, 0.5, -1, -0.5},
    // +Z: rz = 1, rx = sc, ry = -tc
    {4, 0, 0, -0.5, 0.5, 1}, {4, 1, 0, 0.5, 0.5, 1}, {4, 0, 1, -0.5, -0.5, 1}, {4, 1, 1, 0.5, -0.5, 1},
    // -Z: rz = -1, rx = -sc, ry = -tc
    {5, 0, 0, 0.5, 0.5, -1}, {5, 1, 0, -0.5, 0.5, -1}, {5, 0, 1, 0.5, -0.5, -1}, {5, 1, 1, -0.5, -0.5, -1},
};

/// Debevec's angular map ("Light Probe Image Gallery"): for a world direction D, the image
/// coordinates (u, v) in [-1, 1]^2 (v up) are (Dx r, Dy r) with
/// r = (1 / pi) acos(Dz) / sqrt(Dx^2 + Dy^2). Written out here, independently of the library.
inline Eigen::Vector2d debevec_angular_uv(const Eigen::Vector3d& dir) {
    const Eigen::Vector3d d = dir.normalized();
    const double len = std::hypot(d.x(), d.y());
    if (len == 0) return d.z() > 0 ? Eigen::Vector2d(0, 0) : Eigen::Vector2d(1, 0);  // centre; rim
    const double r = std::acos(std::clamp(d.z(), -1.0, 1.0)) / kPi / len;
    return {d.x() * r, d.y() * r};
}

/// Pairs (u, v) -> direction that follow from that definition with exact arithmetic: the centre
/// looks along +z, the circle r = 1/2 is the equator z = 0 (u to +x, v to +y), r = 1/4 is 45
/// degrees from +z, r = 3/4 is 135 degrees.
struct AngularPin {
    double u, v, x, y, z;
};
inline constexpr double kHalfSqrt2 = 0.70710678118654752440;
inline constexpr AngularPin kAngularPins[] = {
    {0, 0, 0, 0, 1},
    {0.5, 0, 1, 0, 0},
    {0, 0.5, 0, 1, 0},
    {-0.5, 0, -1, 0, 0},
    {0, -0.5, 0, -1, 0},
    {0.25, 0, kHalfSqrt2, 0, kHalfSqrt2},
    {0, 0.75, 0, kHalfSqrt2, -kHalfSqrt2},
    {-0.25 * kHalfSqrt2, 0.25 * kHalfSqrt2, -0.5, 0.5, kHalfSqrt2},
};

inline Fn constant(double value) {
    return [value](const Eigen::Vector3d&) { return Eigen::Vector3d::Constant(value); };
}

// A synthetic equidistant fisheye frame looking along +z with field of view 2 theta_max, cut
// from env_fn, with direction and solid-angle maps as calibrate writes them.
inline Environment fisheye_frame(int n, double theta_max, const Fn& env_fn) {
    const double f = (n / 2.0) / theta_max;
    Environment fe;
    fe.layout = Layout::kFisheye;
    fe.source = "synthetic-fisheye";
    fe.radiance = image::Image(n, n, 3);
    fe.directions = image::Image(n, n, 3, image::ColorSpace::kData);
    fe.solid_angle = image::Image(n, n, 1, image::ColorSpace::kData);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const double dx = x + 0.5 - n / 2.0, dy = n / 2.0 - (y + 0.5);
            const double theta = std::hypot(dx, dy) / f;
            if (theta > theta_max) continue;
            const double psi = std::atan2(dy, dx);
            const Eigen::Vector3d d(std::sin(theta) * std::cos(psi),
                                    std::sin(theta) * std::sin(psi), std::cos(theta));
            for (int c = 0; c < 3; ++c) {
                fe.directions.at(x, y, c) = float(d[c]);
                fe.radiance.at(x, y, c) = float(env_fn(d)[c]);
            }
            fe.solid_angle.at(x, y, 0) = float(std::sin(theta) / (f * f * theta));
        }
    }
    return fe;
}

}  // namespace inlight::envmap::testmaps
