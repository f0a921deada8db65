// gles/harness_testing.h: what the harness tests share (harness_test.cpp: the exported
// variants against the CPU model; seed_shader_test.cpp: the report's shader): the criterion,
// one EGL context per GLES version, smooth tables, probe normals and meshes, and compare().
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "brdf/glsl.h"
#include "gles/gles_testing.h"
#include "gles/harness.h"
#include "image/color.h"
#include "image/image.h"
#include "render/material.h"
#include "render/realtime.h"
#include "render/realtime_lights.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::gles::harness_testing {

// The's criterion.
constexpr double kRelTolerance = 1e-3;      // relative, float target
constexpr int kCodeTolerance = 1;           // 8-bit target, codes
constexpr double kMinPassFraction = 0.999;  // of pixels (all three channels)
// Radiances below 1% of the image's median are held to 1e-3 of that 1% instead of their own
// size: float rounding in the SH sums scales with the terms (~ the median), not with a sum that
// cancels to ~0 (relative 1e-7 of the terms, 100x below this floor).
constexpr double kFloorFractionOfMedian = 0.01;
constexpr int kWidth = 32, kHeight = 24;  // 768 pixels: one failure would break 99.9%
constexpr double kHdrScale = 40.0;        // lighting x 40: radiance well above 1

inline Context& context3() {
    static Context c(3);
    return c;
}
inline Context& context2() {
    static Context c(2);
    return c;
}

/// A table whose coefficients are a smooth function of the node's normal (random linear and
/// quadratic terms), so that nodes that are one normal (the thetaphi pole row, report5x5's
/// signed-theta duplicates, octa's folds) hold one value and lookups are continuous.
inline brdf::Table smooth_table(const std::string& grid, int bands, int channels, unsigned seed) {
    brdf::Table t = testing::random_table(grid, bands, channels, seed);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.3, 0.3);
    for (int ch = 0; ch < channels; ++ch) {
        for (int k = 0; k < t.coeff_count(); ++k) {
            const double a = 0.35 + u(rng), bx = u(rng), by = u(rng), bz = u(rng), q = u(rng);
            for (int i1 = 0; i1 < t.grid.rows; ++i1) {
                for (int i2 = 0; i2 < t.grid.cols; ++i2) {
                    const Eigen::Vector3d n = brdf::grid_node_normal(t.grid, i1, i2);
                    t.coeffs[t.index(ch, i1, i2, k)] = static_cast<float>(
                        a + bx * n.x() + by * n.y() + bz * n.z() + q * n.x() * n.y());
                }
            }
        }
    }
    return t;
}

/// Normals that stress the lookup: the pole, the thetaphi seam (phi = 0 and just either side),
/// the horizon, the x = 0 and y = 0 folds, every grid node and cell centre on or above the
/// horizon, then random upper-hemisphere normals.
inline std::vector<Eigen::Vector3d> probe_normals(const brdf::Grid& grid, size_t count, unsigned seed) {
    std::vector<Eigen::Vector3d> n = {Eigen::Vector3d::UnitZ()};
    for (double theta : {0.01, 0.3, 0.8, 1.2, kPi / 2}) {
        for (double phi : {0.0, 1e-4, -1e-4, 2 * kPi - 1e-6, kPi / 2, kPi, -kPi / 2, kPi / 4}) {
            n.push_back(direction_from_spherical(theta, phi));
        }
    }
    for (int i1 = 0; i1 < grid.rows; ++i1) {
        for (int i2 = 0; i2 < grid.cols; ++i2) {
            const Eigen::Vector3d a = brdf::grid_node_normal(grid, i1, i2);
            if (a.z() >= 0) n.push_back(a);
            const Eigen::Vector3d b = brdf::grid_node_normal(grid, std::min(i1 + 1, grid.rows - 1),
                                                             std::min(i2 + 1, grid.cols - 1));
            const Eigen::Vector3d mid = (a + b).normalized();
            if ((a + b).norm() > 1e-6 && mid.z() >= 0) n.push_back(mid);
        }
    }
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    while (n.size() < count) {
        Eigen::Vector3d d(g(rng), g(rng), std::abs(g(rng)));
        n.push_back(d.normalized());
    }
    n.resize(count);
    return n;
}

/// One pixel-sized quad per pixel, normal constant over it, uv linear over the frame.
inline Mesh probe_mesh(const std::vector<Eigen::Vector3d>& normals, const Eigen::Vector3d& tangent) {
    Mesh m;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const Eigen::Vector3f n = normals[y * kWidth + x].cast<float>();
            const int corners[6][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
            for (const auto& c : corners) {
                const float wx = static_cast<float>(x + c[0]), wy = static_cast<float>(y + c[1]);
                m.position.emplace_back(2 * wx / kWidth - 1, 1 - 2 * wy / kHeight, 0.0f);
                m.normal.push_back(n);
                m.tangent.push_back(tangent.cast<float>());
                m.uv.emplace_back(wx / kWidth, wy / kHeight);
            }
        }
    }
    return m;
}

inline Texture8 random_texture(int w, int h, unsigned seed, bool normal_map) {
    Texture8 t;
    t.width = w;
    t.height = h;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.7, 0.7);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int i = 0; i < w * h; ++i) {
        if (normal_map) {  // unit normals with z >= 0.4: never near the facing-away fallback
            const double x = u(rng), y = u(rng);
            const double z = std::max(0.4, std::sqrt(std::max(0.0, 1 - x * x - y * y)));
            const Eigen::Vector3d n = Eigen::Vector3d(x, y, z).normalized();
            for (int c = 0; c < 3; ++c) {
                t.rgba.push_back(static_cast<uint8_t>(std::lround((n[c] * 0.5 + 0.5) * 255)));
            }
        } else {
            for (int c = 0; c < 3; ++c) t.rgba.push_back(static_cast<uint8_t>(byte(rng)));
        }
        t.rgba.push_back(255);
    }
    return t;
}

/// The texture as render::load_textures reads the same PNG: sRGB-decoded or data, linear float.
inline std::shared_ptr<image::Image> as_image(const Texture8& t, bool srgb) {
    auto img = std::make_shared<image::Image>(t.width, t.height, 3);
    for (int y = 0; y < t.height; ++y) {
        for (int x = 0; x < t.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const float v = t.rgba[(static_cast<size_t>(y) * t.width + x) * 4 + c] / 255.0f;
                img->at(x, y, c) = srgb ? image::srgb_decode(v) : v;
            }
        }
    }
    return img;
}

inline Eigen::MatrixXd lighting(int bands, unsigned seed) {
    Eigen::MatrixXd l(sh::count(bands), 3);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.35, 0.35);
    for (int k = 0; k < l.rows(); ++k) {
        const int band = static_cast<int>(std::sqrt(static_cast<double>(k)));
        for (int c = 0; c < 3; ++c) l(k, c) = u(rng) / (1 + band);
    }
    l.row(0) << 1.0, 0.9, 0.8;
    return l;
}

struct Case {
    std::string grid;
    int table_bands, channels;
    bool textured;
};

struct Outcome {
    double pass_fraction = 0, worst = 0;
    int non_finite = 0;  ///< pixels with a NaN or infinite channel (counted as failing)
};

/// Dominant lights, the material whose lobe shades them and the probe normals for them.
struct LightSetup {
    brdf::Material brdf;
    std::vector<envmap::DirectionalLight> lights;
    std::vector<Eigen::Vector3d> normals;  ///< kWidth * kHeight
};

/// Draws `e` and compares it with the CPU model on the same inputs (with `ls`: its lights,
/// lobe and normals, the CPU model adding render::shade_lights as render_realtime does).
inline Outcome compare(Context& ctx, const Export& e, const Variant& v, const Case& s,
                const Eigen::MatrixXd& sh, TargetFormat format, const LightSetup* ls = nullptr) {
    const brdf::Grid grid = brdf::parse_grid(s.grid);
    const Texture8 albedo_tex = random_texture(12, 10, 11, false);
    const Texture8 normal_tex = random_texture(9, 7, 12, true);
    std::vector<Eigen::Vector3d> normals =
        ls ? ls->normals
        : s.textured ? std::vector<Eigen::Vector3d>(kWidth * kHeight, Eigen::Vector3d::UnitZ())
                     : probe_normals(grid, kWidth * kHeight, 13);
    const Eigen::Vector3d tangent = Eigen::Vector3d::UnitX();
    Bindings b;
    b.sh = sh;
    b.albedo = {0.8f, 0.6f, 0.5f};
    b.uv_scale = s.textured ? Eigen::Vector2f(2.5f, 1.5f) : Eigen::Vector2f(1, 1);
    if (s.textured) {
        b.albedo_texture = &albedo_tex;
        b.normal_texture = &normal_tex;
    }
    if (ls) b.lights = ls->lights;
    const Readback gpu = draw(ctx, e, b, probe_mesh(normals, tangent), kWidth, kHeight, format);
    // A lighting texture holds the coefficients as bound (RGBA8: 16 bits each).
    const Eigen::MatrixXd sh_bound = e.lighting_layout == LightingLayout::kUniformArray
                                         ? sh
                                         : bind_lighting(e, sh).as_bound;

    render::SurfaceMaterial m;
    if (ls) m.brdf = ls->brdf;
    m.brdf.albedo = b.albedo.cast<double>();
    if (!ls) m.brdf.specular = e.table_as_bound ? brdf::Model::kGgx : brdf::Model::kLambert;
    m.uv_scale = b.uv_scale.cast<double>();
    if (s.textured) {
        m.albedo_texture = as_image(albedo_tex, true);
        m.normal_texture = as_image(normal_tex, false);
    }
    render::RealtimeOptions opt;
    opt.mode = v.mode == ShaderMode::kSeed ? render::RealtimeMode::kSeed
                                           : render::RealtimeMode::kConsistent;
    opt.sh_bands = v.sh_bands;
    opt.supersample = 1;
    std::vector<Eigen::Vector3d> cpu(normals.size());
    std::vector<double> magnitudes;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            render::SurfaceHit hit;
            hit.ns = hit.ng = normals[y * kWidth + x];
            hit.dpdu = tangent;
            hit.uv = {(x + 0.5) / kWidth, (y + 0.5) / kHeight};
            const render::ShadingPoint sp = render::shade(m, hit, Eigen::Vector3d::UnitZ());
            const brdf::Table* table = e.table_as_bound ? &*e.table_as_bound : nullptr;
            Eigen::Vector3d r = render::shade_realtime(sp.world_from_local.col(2), sp.brdf.albedo,
                                                       table != nullptr, sh_bound, table, opt);
            if (ls) {
                r += render::shade_lights(ls->lights, sp.world_from_local.col(2), sp.brdf,
                                          table ? &table->view : nullptr);
            }
            cpu[y * kWidth + x] = r;
            for (int c = 0; c < 3; ++c) magnitudes.push_back(std::abs(r[c]));
        }
    }
    std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                     magnitudes.end());
    const double floor = kFloorFractionOfMedian * magnitudes[magnitudes.size() / 2];
    Outcome out;
    int pass = 0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            bool ok = true;
            for (int c = 0; c < 3; ++c) {
                const double want = cpu[y * kWidth + x][c];
                const double got = gpu.at(x, y, c);
                if (!std::isfinite(got)) {
                    ok = false;
                    ++out.non_finite;
                    continue;
                }
                if (format == TargetFormat::kRgba32f) {
                    const double rel = std::abs(got - want) / std::max(std::abs(want), floor);
                    out.worst = std::max(out.worst, rel);
                    ok = ok && rel <= kRelTolerance;
                } else {
                    const long code = std::lround(std::clamp(want, 0.0, 1.0) * 255);
                    const long diff = std::labs(std::lround(got * 255) - code);
                    out.worst = std::max(out.worst, static_cast<double>(diff));
                    ok = ok && diff <= kCodeTolerance;
                }
            }
            pass += ok ? 1 : 0;
        }
    }
    out.pass_fraction = pass / static_cast<double>(kWidth * kHeight);
    return out;
}

inline const std::vector<Case>& cases() {
    static const std::vector<Case> s = {{"thetaphi:9x16", 4, 1, false},
                                         {"thetaphi:9x32", 3, 1, false},  // 96 texels wide
                                         {"octa:9", 3, 3, false},
                                         {"report5x5", 3, 1, false},
                                         {"disk:7", 4, 1, false},
                                         {"octa:5", 3, 3, true}};
    return s;
}

}  // namespace inlight::gles::harness_testing
