#include "brdf/grid.h"

#include <algorithm>
#include <cmath>
#include <regex>

#include "core/check.h"
#include "core/error.h"

namespace inlight::brdf {
namespace {

// The float constants the GLSL uses (glsl.cpp prints these same values).
constexpr float kPiF = 3.14159265f;
constexpr float kHalfPiF = 1.57079633f;
constexpr float kTwoPiF = 6.28318531f;
constexpr float kFourOverPiF = 1.27323954f;

}  // namespace

Grid parse_grid(const std::string& spec) {
    std::smatch m;
    Grid g;
    if (spec == "report5x5") {
        g.kind = GridKind::kReport5x5;
        g.rows = g.cols = 5;
        return g;
    }
    if (std::regex_match(spec, m,
                         std::regex(R"(thetaphi:(\d{1,4})x(\d{1,4})(@([0-9]+(\.[0-9]*)?))?)"))) {
        g.kind = GridKind::kThetaPhi;
        g.rows = std::stoi(m[1]);
        g.cols = std::stoi(m[2]);
        if (g.rows < 2 || g.cols < 3) {
            throw UsageError(str("grid '", spec, "': thetaphi needs >= 2 rows and >= 3 columns"));
        }
        if (m[3].matched) {
            const double deg = std::stod(m[4]);
            if (!(deg > 0 && deg <= 180)) {
                throw UsageError(str("grid '", spec, "': theta_max must be in (0, 180] degrees"));
            }
            g.theta_max = deg * kPi / 180.0;
        }
        return g;
    }
    if (std::regex_match(spec, m, std::regex(R"((octa|disk):(\d{1,4}))"))) {
        g.kind = m[1] == "octa" ? GridKind::kOcta : GridKind::kDisk;
        g.rows = g.cols = std::stoi(m[2]);
        if (g.rows < 2) throw UsageError(str("grid '", spec, "': needs N >= 2"));
        return g;
    }
    throw UsageError(
        str("unknown grid '", spec, "' (expected report5x5, thetaphi:RxC, octa:N or disk:N)"));
}

std::string to_string(const Grid& g) {
    switch (g.kind) {
        case GridKind::kReport5x5:
            return "report5x5";
        case GridKind::kThetaPhi: {
            const double deg = g.theta_max * 180.0 / kPi;
            if (std::abs(deg - 90.0) < 1e-9) return str("thetaphi:", g.rows, "x", g.cols);
            return str("thetaphi:", g.rows, "x", g.cols, "@", deg);
        }
        case GridKind::kOcta:
            return str("octa:", g.rows);
        case GridKind::kDisk:
            return str("disk:", g.rows);
    }
    return "?";
}

Eigen::Vector3d grid_node_normal(const Grid& g, int i1, int i2) {
    INLIGHT_CHECK(i1 >= 0 && i1 < g.rows && i2 >= 0 && i2 < g.cols)
        << "node (" << i1 << ", " << i2 << ") outside " << to_string(g);
    switch (g.kind) {
        case GridKind::kReport5x5:
            return direction_from_spherical((i1 - 2) * kPi / 4, (i2 - 2) * kPi / 4);
        case GridKind::kThetaPhi:
            // Row 0 is the pole for every column: the same normal, whatever phi.
            if (i1 == 0) return Eigen::Vector3d::UnitZ();
            return direction_from_spherical(g.theta_max * i1 / (g.rows - 1),
                                            2.0 * kPi * i2 / g.cols);
        case GridKind::kOcta: {
            const double u = -1.0 + 2.0 * i2 / (g.cols - 1);
            const double v = -1.0 + 2.0 * i1 / (g.rows - 1);
            const double px = 0.5 * (u + v), py = 0.5 * (u - v);
            return Eigen::Vector3d(px, py, 1.0 - std::abs(px) - std::abs(py)).normalized();
        }
        case GridKind::kDisk: {
            const double u = -1.0 + 2.0 * i2 / (g.cols - 1);
            const double v = -1.0 + 2.0 * i1 / (g.rows - 1);
            const double r2 = u * u + v * v;
            if (r2 <= 1.0) return Eigen::Vector3d(u, v, std::sqrt(1.0 - r2));
            return Eigen::Vector3d(u, v, 0.0).normalized();
        }
    }
    return Eigen::Vector3d::UnitZ();
}

GridCoord grid_coord(const Grid& g, const Eigen::Vector3f& n_in) {
    // GLSL: vec3 m = normalize(n);
    const float len = std::sqrt(n_in.x() * n_in.x() + n_in.y() * n_in.y() + n_in.z() * n_in.z());
    const float mx = n_in.x() / len, my = n_in.y() / len, mz = n_in.z() / len;
    const float last_r = static_cast<float>(g.rows - 1);
    const float last_c = static_cast<float>(g.cols - 1);
    float r = 0, c = 0;
    bool wrap_cols = false;
    switch (g.kind) {
        case GridKind::kReport5x5: {
            float theta = std::acos(std::clamp(mz, -1.0f, 1.0f));
            float phi = (std::abs(mx) + std::abs(my) > 0.0f) ? std::atan2(my, mx) : 0.0f;
            if (phi > kHalfPiF) {
                phi -= kPiF;
                theta = -theta;
            } else if (phi < -kHalfPiF) {
                phi += kPiF;
                theta = -theta;
            }
            r = std::clamp(theta * kFourOverPiF + 2.0f, 0.0f, 4.0f);
            c = std::clamp(phi * kFourOverPiF + 2.0f, 0.0f, 4.0f);
            break;
        }
        case GridKind::kThetaPhi: {
            const float theta = std::acos(std::clamp(mz, -1.0f, 1.0f));
            float phi = (std::abs(mx) + std::abs(my) > 0.0f) ? std::atan2(my, mx) : 0.0f;
            if (phi < 0.0f) phi += kTwoPiF;
            const float row_scale = last_r / static_cast<float>(g.theta_max);
            const float col_scale = static_cast<float>(g.cols) / kTwoPiF;
            r = std::clamp(theta * row_scale, 0.0f, last_r);
            c = phi * col_scale;
            wrap_cols = true;
            break;
        }
        case GridKind::kOcta: {
            const float z = std::max(mz, 0.0f);
            const float d = std::max(std::abs(mx) + std::abs(my) + z, 1e-20f);
            const float px = mx / d, py = my / d;
            const float u = px + py, v = px - py;
            c = std::clamp((u * 0.5f + 0.5f) * last_c, 0.0f, last_c);
            r = std::clamp((v * 0.5f + 0.5f) * last_r, 0.0f, last_r);
            break;
        }
        case GridKind::kDisk: {
            float u = mx, v = my;
            if (mz < 0.0f) {  // below the horizon: the horizon normal of the same azimuth
                const float q = std::max(std::sqrt(mx * mx + my * my), 1e-20f);
                u = mx / q;
                v = my / q;
            }
            c = std::clamp((u * 0.5f + 0.5f) * last_c, 0.0f, last_c);
            r = std::clamp((v * 0.5f + 0.5f) * last_r, 0.0f, last_r);
            break;
        }
    }
    GridCoord out;
    const float rf = std::floor(r), cf = std::floor(c);
    out.r0 = static_cast<int>(rf);
    out.r1 = std::min(out.r0 + 1, g.rows - 1);
    out.fr = r - rf;
    if (wrap_cols) {
        out.c0 = static_cast<int>(cf) % g.cols;
        out.c1 = (out.c0 + 1) % g.cols;
    } else {
        out.c0 = static_cast<int>(cf);
        out.c1 = std::min(out.c0 + 1, g.cols - 1);
    }
    out.fc = c - cf;
    return out;
}

Eigen::Vector2f report_original_index(const Eigen::Vector3f& n) {
    const float theta = std::acos(n.z() / n.norm());
    const float phi = std::atan(n.y() / n.x());
    return {theta * kFourOverPiF + 2.0f, phi * kFourOverPiF + 2.0f};
}

}  // namespace inlight::brdf
