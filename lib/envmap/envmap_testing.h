// envmap/envmap_testing.h: synthetic environments for lib/envmap's tests (header-only, tests only).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <functional>

#include "core/conventions.h"
#include "envmap/environment.h"

namespace inlight::envmap::testmaps {

using Fn = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

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
