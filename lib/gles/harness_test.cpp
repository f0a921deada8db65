// The exported shaders run on the machine's GLES driver (llvmpipe here) and must compute what
// the CPU model (render/realtime.h) computes: >= 99.9% of pixels within 1e-3 relative in float
// and within 1 code in 8 bits, for every highp variant, at the poles, seams, folds and horizon of
// every grid kind, with normal-mapped and textured materials, and under HDR light.
#include "gles/harness.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <iostream>
#include <random>

#include "brdf/glsl.h"
#include "gles/gles_testing.h"
#include "image/color.h"
#include "image/image.h"
#include "render/material.h"
#include "render/realtime.h"
#include "render/realtime_lights.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::gles {
namespace {

// The criterion.
constexpr double kRelTolerance = 1e-3;      // relative, float target
constexpr int kCodeTolerance = 1;           // 8-bit target, codes
constexpr double kMinPassFraction = 0.999;  // of pixels (all three channels)
// Radiances below 1% of the image's median are held to 1e-3 of that 1% instead of their own
// size: float rounding in the SH sums scales with the terms (~ the median), not with a sum that
// cancels to ~0 (relative 1e-7 of the terms, 100x below this floor).
constexpr double kFloorFractionOfMedian = 0.01;
constexpr int kWidth = 32, kHeight = 24;  // 768 pixels: one failure would break 99.9%
constexpr double kHdrScale = 40.0;        // lighting x 40: radiance well above 1

Context& context3() {
    static Context c(3);
    return c;
}
Context& context2() {
    static Context c(2);
    return c;
}

/// A table whose coefficients are a smooth function of the node's normal (random linear and
/// quadratic terms), so that nodes that are one normal (the thetaphi pole row, report5x5's
/// signed-theta duplicates, octa's folds) hold one value and lookups are continuous.
brdf::Table smooth_table(const std::string& grid, int bands, int channels, unsigned seed) {
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
std::vector<Eigen::Vector3d> probe_normals(const brdf::Grid& grid, size_t count, unsigned seed) {
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
Mesh probe_mesh(const std::vector<Eigen::Vector3d>& normals, const Eigen::Vector3d& tangent) {
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

Texture8 random_texture(int w, int h, unsigned seed, bool normal_map) {
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
std::shared_ptr<image::Image> as_image(const Texture8& t, bool srgb) {
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

Eigen::MatrixXd lighting(int bands, unsigned seed) {
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
Outcome compare(Context& ctx, const Export& e, const Variant& v, const Case& s,
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

const std::vector<Case>& cases() {
    static const std::vector<Case> s = {{"thetaphi:9x16", 4, 1, false},
                                         {"thetaphi:9x32", 3, 1, false},  // 96 texels wide
                                         {"octa:9", 3, 3, false},
                                         {"report5x5", 3, 1, false},
                                         {"disk:7", 4, 1, false},
                                         {"octa:5", 3, 3, true}};
    return s;
}

TEST(GlesHarness, PrintsWhichDriverRan) {
    for (Context* c : {&context3(), &context2()}) {
        std::cout << "[gles] " << c->info().summary() << "\n";
        EXPECT_FALSE(c->info().renderer.empty());
        EXPECT_GE(c->info().limits.max_fragment_uniform_vectors, 16);
    }
}

TEST(GlesHarness, CompileErrorsNameTheVariant) {
    const brdf::Table t = smooth_table("octa:5", 3, 1, 1);
    Export e = export_variant(&t, MaterialInputs{}, Variant{}, testing::roomy_limits());
    e.fragment_source += "this is not GLSL;\n";
    Bindings b;
    b.sh = lighting(3, 1);
    Mesh m;
    const std::string msg = inlight::testing::error_of(
        [&] { draw(context3(), e, b, m, 1, 1, TargetFormat::kRgba8); });
    EXPECT_NE(msg.find("material-es300-consistent-b3-highp: the fragment shader does not compile"),
              std::string::npos)
        << msg;
}

// Every variant, mediump included, compiles and links on the driver.
TEST(GlesHarness, EveryVariantCompilesOnTheDriver) {
    for (const Case& s : cases()) {
        const brdf::Table t = smooth_table(s.grid, s.table_bands, s.channels, 2);
        MaterialInputs mat;
        if (s.textured) {
            mat.albedo_texture_px = {12, 10};
            mat.normal_texture_px = {9, 7};
        }
        for (const Variant& v : testing::all_variants(s.table_bands)) {
            Context& ctx = v.version == GlslVersion::kEs300 ? context3() : context2();
            const Export e = export_variant(&t, mat, v, ctx.info().limits);
            const Texture8 a = random_texture(12, 10, 1, false), n = random_texture(9, 7, 2, true);
            Bindings b;
            b.sh = lighting(s.table_bands, 1);
            b.albedo_texture = &a;
            b.normal_texture = &n;
            EXPECT_NO_THROW(draw(ctx, e, b, Mesh{}, 1, 1, TargetFormat::kRgba8)) << e.name;
        }
    }
}

// What the mediump measurements on this driver mean: llvmpipe (Mesa 22.3) computes mediump
// floats as half floats, so its mediump figures are a half-float GPU's (docs/gles.md,
// "Precision"). 256^3 / 4096^2 = 1 at 32 bits; half floats overflow at 256^2 = 65536 > 65504.
TEST(GlesHarness, LlvmpipeComputesMediumpInHalfFloats) {
    Export e;
    e.name = "mediump probe";
    e.vertex_source =
        "#version 100\nattribute vec3 a_position;\nattribute vec3 a_normal;\nvarying vec3 "
        "v_normal;\nvoid main() {\n    v_normal = a_normal;\n    gl_Position = "
        "vec4(a_position, 1.0);\n}\n";
    e.fragment_source =
        "#version 100\nprecision mediump float;\nvarying vec3 v_normal;\nvoid main() {\n"
        "    float x = v_normal.z * 256.0;\n    float y = x * x * x / 4096.0 / 4096.0;\n"
        "    gl_FragColor = vec4(y, y, y, 1.0);\n}\n";
    e.manifest["variant"] = {{"glsl_version", "100"}, {"sh_bands", 1}};
    e.manifest["textures"] = nlohmann::json::array();
    Bindings b;
    b.sh = Eigen::MatrixXd::Zero(1, 3);
    const Mesh mesh = probe_mesh(std::vector<Eigen::Vector3d>(kWidth * kHeight,
                                                              Eigen::Vector3d::UnitZ()),
                                 Eigen::Vector3d::UnitX());
    const Readback r = draw(context2(), e, b, mesh, kWidth, kHeight, TargetFormat::kRgba32f);
    if (context2().info().renderer.find("llvmpipe") == std::string::npos) {
        GTEST_SKIP() << "skip: a statement about llvmpipe, the renderer is "
                     << context2().info().renderer;
    }
    EXPECT_TRUE(std::isinf(r.at(3, 5, 0)))
        << "llvmpipe computes mediump at 32 bits (" << r.at(3, 5, 0)
        << "): its mediump figures in docs/gles.md are not a half-float GPU's";
}

// The criterion for every highp variant, table layout, target and lighting level.
TEST(GlesHarness, MatchesTheCpuModel) {
    for (const Case& s : cases()) {
        const brdf::Table t = smooth_table(s.grid, s.table_bands, s.channels, 3);
        MaterialInputs mat;
        mat.name = s.textured ? "textured" : "probes";
        if (s.textured) {
            mat.albedo_texture_px = {12, 10};
            mat.normal_texture_px = {9, 7};
        }
        const Eigen::MatrixXd sh = lighting(s.table_bands, 4);
        for (const Variant& v : testing::all_variants(s.table_bands)) {
            if (v.precision != Precision::kHighp) continue;
            const bool es3 = v.version == GlslVersion::kEs300;
            Context& ctx = es3 ? context3() : context2();
            // ES 3.00 once as a uniform array (the driver's limits) and once as a float texture
            // (the ES 3.0 minimum); ES 1.00 is RGBA8 either way.
            // ES 1.00 once more at the ES 2.0 minimum (16 vectors, 64 texels): above 3 bands the
            // RGBA8 lighting texture, and tables wider than 64 texels wrapped (thetaphi:9x32);
            // ES 3.00 above 3 bands with 12 vectors: the RGBA32F lighting texture.
            std::vector<Limits> limits = {ctx.info().limits};
            if (es3) limits.push_back(Limits::minimum(GlslVersion::kEs300));
            if (!es3) {
                limits.push_back(Limits::minimum(GlslVersion::kEs100));  // wraps wide tables
            } else if (v.sh_bands > 3) {
                limits.push_back(ctx.info().limits);
                limits.back().max_fragment_uniform_vectors = 12;
            }
            for (const Limits& lim : limits) {
                const Export e = export_variant(&t, mat, v, lim);
                if (lim.max_fragment_uniform_vectors <= 16 && v.sh_bands > 3) {
                    EXPECT_NE(e.lighting_layout, LightingLayout::kUniformArray) << e.name;
                }
                if (lim.max_texture_size == 64) {  // the ES 2.0 minimum: wrapped within it
                    EXPECT_LE(std::max(e.data_width, e.data_height), 64) << e.name;
                }
                const std::string what = str(e.name, " (", s.grid, ", ", to_string(e.table_layout),
                                             " ", e.data_width, "x", e.data_height,
                                             ", lighting ", to_string(e.lighting_layout), ") on ",
                                             ctx.info().renderer);
                const Outcome byte = compare(ctx, e, v, s, sh, TargetFormat::kRgba8);
                EXPECT_GE(byte.pass_fraction, kMinPassFraction)
                    << what << ", 8-bit: worst " << byte.worst << " codes";
                if (!ctx.info().float_color_buffer) continue;
                for (double scale : {1.0, kHdrScale}) {
                    const Outcome f = compare(ctx, e, v, s, sh * scale, TargetFormat::kRgba32f);
                    EXPECT_GE(f.pass_fraction, kMinPassFraction)
                        << what << ", float, light x" << scale << ": worst relative " << f.worst;
                    std::cout << "[gles] " << what << " float x" << scale << ": "
                              << f.pass_fraction * 100 << "% within 1e-3, worst " << f.worst
                              << "; 8-bit worst " << byte.worst << " codes\n";
                }
            }
        }
    }
}

// ES 1.00 above 5 bands at the ES 2.0 minimum (16 vectors, 64 texels: the table's
// scale/offset and the lighting both in textures; octa:5 at 7 bands, 65 texels wide, wrapped
// into rows of 64, 49 coefficients: the last texel padded), and a table of more than 64 x 64
// texels (thetaphi:33x64, 6336) laid out within a GL_MAX_TEXTURE_SIZE of 128 given to the
// exporter (ES 1.00 RGBA8 and ES 3.00 RGBA32F, both wrapped into 128 x 50): the issue's
// criterion against the CPU model (HDR light is MatchesTheCpuModel's; one level here keeps the
// compiles of these large shaders to two per item).
TEST(GlesHarness, ManyBandsAndLargeTablesMatchTheCpuModel) {
    struct Item {
        Case c;
        GlslVersion version;
        int bands;
        int max_texture_size;
    };
    for (const Item& it : {Item{{"octa:5", 7, 1, false}, GlslVersion::kEs100, 7, 64},
                           Item{{"thetaphi:33x64", 3, 1, false}, GlslVersion::kEs100, 3, 128},
                           Item{{"thetaphi:33x64", 3, 1, false}, GlslVersion::kEs300, 3, 128}}) {
        const bool es3 = it.version == GlslVersion::kEs300;
        Context& ctx = es3 ? context3() : context2();
        const brdf::Table t = smooth_table(it.c.grid, it.c.table_bands, it.c.channels, 31);
        Limits lim = Limits::minimum(it.version);
        lim.max_texture_size = it.max_texture_size;
        ASSERT_LE(lim.max_texture_size, ctx.info().limits.max_texture_size);
        const Variant v{it.version, ShaderMode::kConsistent, it.bands, Precision::kHighp};
        MaterialInputs mat;
        mat.name = "probes";
        const Export e = export_variant(&t, mat, v, lim);
        EXPECT_LE(std::max(e.data_width, e.data_height), it.max_texture_size) << e.name;
        if (!es3 && it.bands > 5) {
            EXPECT_TRUE(e.table_scale_in_texture) << e.name;
            EXPECT_TRUE(e.table_wrapped) << e.name;
        }
        const Eigen::MatrixXd sh = lighting(it.bands, 32);
        const std::string what = str(e.name, " (", it.c.grid, ", ", to_string(e.table_layout), " ",
                                     e.data_width, "x", e.data_height,
                                     e.table_scale_in_texture ? ", scale/offset in the texture" : "",
                                     ", lighting ", to_string(e.lighting_layout), ") on ",
                                     ctx.info().renderer);
        const Outcome byte = compare(ctx, e, v, it.c, sh, TargetFormat::kRgba8);
        EXPECT_GE(byte.pass_fraction, kMinPassFraction) << what << ", 8-bit: worst " << byte.worst << " codes";
        if (!ctx.info().float_color_buffer) continue;
        const Outcome f = compare(ctx, e, v, it.c, sh, TargetFormat::kRgba32f);
        EXPECT_GE(f.pass_fraction, kMinPassFraction) << what << ", float: worst relative " << f.worst;
        std::cout << "[gles] " << what << " float: " << f.pass_fraction * 100 << "% within 1e-3, worst "
                  << f.worst << "; 8-bit worst " << byte.worst << " codes\n";
    }
}

envmap::DirectionalLight make_light(const Eigen::Vector3d& d, double radius_deg,
                                    const Eigen::Vector3d& normal_irradiance) {
    envmap::DirectionalLight l;
    l.direction = d.normalized();
    l.angular_radius = radius_deg * kPi / 180;
    l.flux = normal_irradiance * 2.0 / (1.0 + std::cos(l.angular_radius));
    return l;
}

/// Normals across each light's horizon band (|n.d| < 1.05 sin alpha, where the cap straddles
/// the horizon and the shader takes Snyder's formula) at several azimuths about d, the upper
/// hemisphere only; then the lookup's probe normals.
std::vector<Eigen::Vector3d> light_probe_normals(const brdf::Grid& grid,
                                                 const std::vector<envmap::DirectionalLight>& ls) {
    std::vector<Eigen::Vector3d> n;
    for (const auto& l : ls) {
        const Eigen::Vector3d d = l.direction;
        const Eigen::Vector3d a = d.unitOrthogonal(), b = d.cross(a);
        const double width = 1.05 * std::max(l.angular_radius, 1e-3);
        for (int i = 0; i < 48; ++i) {  // an even count: no normal exactly at n.d = 0
            const double beta = kPi / 2 - width + 2 * width * (i + 0.5) / 48;
            const double psi = 2 * kPi * i / 12.0;
            const Eigen::Vector3d w = std::cos(psi) * a + std::sin(psi) * b;
            const Eigen::Vector3d m = std::cos(beta) * d + std::sin(beta) * w;
            n.push_back(m.z() >= 0 ? m : Eigen::Vector3d(m.x(), m.y(), -m.z()));
        }
    }
    for (const Eigen::Vector3d& p : probe_normals(grid, kWidth * kHeight - n.size(), 15)) n.push_back(p);
    return n;
}

// Dominant lights in the shaders equal the CPU model's --rt-lighting shading
// (render::shade_lights: the cap's exact irradiance, the lobe at its centre) for each lobe
// model, both versions, on octa:9 at 3 bands and thetaphi:9x16 (whose lookup brings its own
// atan2) at 4: a sun
// at the horizon (HDR: 20x the sky), a 12-degree light 0.6 degrees off the pole and a point.
// Both irradiance formulas: the exact cap, and the smooth cap envmap-project's budget writes by
// default (a shader shading it as an exact cap differs across the horizon band by up to 0.038 s).
TEST(GlesHarness, LightsMatchTheCpuModel) {
    for (const envmap::LightShading shading :
           {envmap::LightShading::kCap, envmap::LightShading::kSmoothCap}) {
        std::vector<envmap::DirectionalLight> lights = {
            make_light(direction_from_spherical(kPi / 2, kPi / 6), 0.27, {20, 19, 17}),
            make_light(direction_from_spherical(0.01, 1.0), 12.0, {2.0, 2.2, 2.5}),
            make_light(direction_from_spherical(1.1, -2.0), 0.0, {3, 2, 1})};
        for (envmap::DirectionalLight& l : lights) l.shading = shading;
        brdf::Material ggx, report, charlie, lambert;
        ggx.specular = brdf::Model::kGgx;
        ggx.alpha = 0.25;
        ggx.f0 = {0.04, 0.05, 0.06};
        report.specular = brdf::Model::kCookTorranceReport;
        report.report_f = 0.3;  // a lobe far above the diffuse term, so that its errors show
        report.specular_scale = 20;
        charlie.specular = brdf::Model::kCharlie;
        charlie.alpha = 0.35;
        charlie.sheen_color = {0.9, 0.8, 0.7};
        charlie.specular_scale = 3;
        lambert.specular = brdf::Model::kLambert;
        for (const std::string grid : {"octa:9", "thetaphi:9x16"}) {
            brdf::Table t = smooth_table(grid, 4, 1, 6);
            t.view = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();  // an off-axis fixed view
            const Case s{grid, 4, 1, false};
            LightSetup ls;
            ls.lights = lights;
            ls.normals = light_probe_normals(t.grid, lights);
            for (const brdf::Material& lobe : {ggx, report, charlie, lambert}) {
                ls.brdf = lobe;
                MaterialInputs mat;
                mat.name = brdf::to_string(lobe.specular);
                mat.brdf = lobe;
                const bool with_table = lobe.specular != brdf::Model::kLambert;
                for (GlslVersion ver : {GlslVersion::kEs300, GlslVersion::kEs100}) {
                    Context& ctx = ver == GlslVersion::kEs300 ? context3() : context2();
                    {
                        const int bands = grid == "octa:9" ? 3 : 4;
                        const Variant v{ver,  ShaderMode::kConsistent, bands, Precision::kHighp, 3,
                                        shading};
                        const Export e = export_variant(with_table ? &t : nullptr, mat, v,
                                                        ctx.info().limits);
                        const std::string what = str(e.name, " (", grid, ") on ", ctx.info().renderer);
                        const Eigen::MatrixXd sh = lighting(bands, 7);
                        const Outcome byte = compare(ctx, e, v, s, sh, TargetFormat::kRgba8, &ls);
                        EXPECT_GE(byte.pass_fraction, kMinPassFraction)
                            << what << ", 8-bit: worst " << byte.worst << " codes";
                        if (!ctx.info().float_color_buffer) continue;
                        const Outcome f = compare(ctx, e, v, s, sh, TargetFormat::kRgba32f, &ls);
                        EXPECT_GE(f.pass_fraction, kMinPassFraction)
                            << what << ", float: worst relative " << f.worst;
                        std::cout << "[gles] " << what << " with 3 " << envmap::to_string(shading)
                                  << " lights, float: "
                                  << f.pass_fraction * 100 << "% within 1e-3, worst " << f.worst
                                  << "; 8-bit worst " << byte.worst << " codes\n";
                    }
                }
            }
        }
    }
}

// The mediump variants on llvmpipe, which computes them in half floats
// (LlvmpipeComputesMediumpInHalfFloats): the same inputs as MatchesTheCpuModel and
// LightsMatchTheCpuModel (every layout, both versions and modes, lights on all four lobes).
// No pixel may be NaN or infinite; the figures against the CPU model are printed for
// docs/gles.md ("Precision"), where they are quoted: mediump is exported only on request.
TEST(GlesHarness, MediumpVariantsAreFinite) {
    // One variant per hazard (mediump draws take ~8 s each on llvmpipe): sRGB albedo and
    // normal map (both versions), the RGBA8 lighting texture's float32 unpack, lights on GGX
    // and Charlie (horizon normals).
    struct Item {
        Case c;
        Variant v;
        const brdf::Material* lobe;  ///< with 3 lights, else none
    };
    brdf::Material ggx, charlie;
    ggx.specular = brdf::Model::kGgx;
    ggx.alpha = 0.25;
    charlie.specular = brdf::Model::kCharlie;
    charlie.alpha = 0.35;
    const Variant es1{GlslVersion::kEs100, ShaderMode::kConsistent, 3, Precision::kMediump};
    Variant es3 = es1, es1_b4 = es1, es1_l3 = es1, es3_l3 = es1;
    es3.version = es3_l3.version = GlslVersion::kEs300;
    es1_b4.sh_bands = 4;
    es1_l3.lights = es3_l3.lights = 3;
    const Case textured{"octa:5", 3, 3, true}, light_case{"octa:9", 3, 1, false};
    const std::vector<Item> items = {{textured, es1, nullptr},
                                     {textured, es3, nullptr},
                                     {{"thetaphi:9x16", 4, 1, false}, es1_b4, nullptr},
                                     {light_case, es3_l3, &ggx},
                                     {light_case, es1_l3, &charlie}};
    const std::vector<envmap::DirectionalLight> lights = {
        make_light(direction_from_spherical(kPi / 2, kPi / 6), 0.27, {20, 19, 17}),
        make_light(direction_from_spherical(0.01, 1.0), 12.0, {2.0, 2.2, 2.5}),
        make_light(direction_from_spherical(1.1, -2.0), 0.0, {3, 2, 1})};
    for (const Item& it : items) {
        brdf::Table t = smooth_table(it.c.grid, it.c.table_bands, it.c.channels, it.lobe ? 6 : 3);
        MaterialInputs mat;
        mat.name = it.lobe ? brdf::to_string(it.lobe->specular) : it.c.textured ? "textured" : "probes";
        if (it.c.textured) {
            mat.albedo_texture_px = {12, 10};
            mat.normal_texture_px = {9, 7};
        }
        LightSetup ls;
        if (it.lobe) {
            t.view = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
            mat.brdf = ls.brdf = *it.lobe;
            ls.lights = lights;
            ls.normals = light_probe_normals(t.grid, lights);
        }
        Context& ctx = it.v.version == GlslVersion::kEs300 ? context3() : context2();
        ASSERT_TRUE(ctx.info().float_color_buffer) << "NaN needs a float target";
        Limits lim = Limits::minimum(it.v.version);  // the data in textures where it must be
        lim.max_texture_size = 4096;
        const Export e = export_variant(&t, mat, it.v, lim);
        const Outcome f = compare(ctx, e, it.v, it.c, lighting(it.c.table_bands, 4),
                                  TargetFormat::kRgba32f, it.lobe ? &ls : nullptr);
        EXPECT_EQ(f.non_finite, 0) << e.name;
        std::cout << "[gles mediump] " << e.name << " (" << it.c.grid << ", "
                  << to_string(e.table_layout) << ", lighting " << to_string(e.lighting_layout)
                  << "): " << f.pass_fraction * 100 << "% within 1e-3 of the CPU model, worst "
                  << f.worst << ", " << f.non_finite << " non-finite pixels\n";
    }
}

// ---- The inlight report's shader written out from its text (section 2.6: Snippet 3 and the
// basis of its Figure 6), independently of the exporter and of the CPU model. ----

/// Figure 6's basis as printed, signs included (the Condon-Shortley phase: Y_1,1 = -0.4886 x).
std::array<double, 9> report_figure6_basis(const Eigen::Vector3d& d) {
    const double x = d.x(), y = d.y(), z = d.z();
    return {0.282095,          -0.488603 * y,           0.488603 * z,
            -0.488603 * x,     1.092548 * x * y,        -1.092548 * y * z,
            0.315392 * (3 * z * z - 1), -1.092548 * z * x, 0.546274 * (x * x - y * y)};
}

/// Per coefficient, the report's basis function over inlight's (sh/sh.h): +1 or -1, at a
/// direction where none vanishes. The report projects lighting and BRDF with its own basis, so
/// its L_k and B_k are inlight's times this.
std::array<double, 9> report_phase() {
    const Eigen::Vector3d d = Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
    const std::array<double, 9> r = report_figure6_basis(d);
    const std::vector<double> y = sh::eval(3, d);
    std::array<double, 9> phase{};
    for (int k = 0; k < 9; ++k) {
        phase[k] = std::round(r[k] / y[k]);
        EXPECT_NEAR(r[k] / y[k], phase[k], 1e-5) << k;  // Figure 6 prints 6 digits
    }
    return phase;
}

/// Snippet 3's getBRDF on the report's 5 x 5 table (`b225[45 i1 + 9 i2 + k]`, brdfIndex):
/// cart2sph (theta = acos(z / |n|), phi = atan(y / x), not atan2), sph2index (angle x 4 / pi +
/// 2), corners by floor and ceil, mixed as written. The angles in float, as the shader's (its pi
/// = 3.14159265358 rounds to float pi, above pi: in double the horizon's index would be
/// 4 + 4e-12 and its ceil 5, off the grid). NaN where cart2sph divides 0 by 0 or off the grid.
std::array<double, 9> report_get_brdf(const std::vector<double>& b225, const Eigen::Vector3d& n) {
    const float pi = 3.14159265358f;  // as in sph2index
    const Eigen::Vector3f nf = n.cast<float>();
    const float sx = std::acos(nf.z() / nf.norm()), sy = std::atan(nf.y() / nf.x());
    const double ix = sx * (4.0f / pi) + 2.0f, iy = sy * (4.0f / pi) + 2.0f;
    std::array<double, 9> b;
    b.fill(std::numeric_limits<double>::quiet_NaN());
    if (!std::isfinite(ix) || !std::isfinite(iy)) return b;
    const int fx = static_cast<int>(std::floor(ix)), cx = static_cast<int>(std::ceil(ix));
    const int fy = static_cast<int>(std::floor(iy)), cy = static_cast<int>(std::ceil(iy));
    if (fx < 0 || fy < 0 || cx > 4 || cy > 4) return b;
    const double h = ix - std::floor(ix), v = iy - std::floor(iy);
    auto at = [&](int i1, int i2, int k) { return b225[45 * i1 + 9 * i2 + k]; };
    auto mix = [](double a, double c, double t) { return a * (1 - t) + c * t; };
    for (int k = 0; k < 9; ++k) {
        b[k] = mix(mix(at(fx, fy, k), at(cx, fy, k), h), mix(at(fx, cy, k), at(cx, cy, k), h), v);
    }
    return b;
}

/// Snippet 3's main() for one fragment: u_IrradianceMatrix[c] = R&H's matrix (eq. 12) of the
/// coefficients `l` (9 x 3), the texture = `albedo`, `brdf` null = no specular.
Eigen::Vector3d report_shader(const Eigen::Vector3d& n, const Eigen::Vector3d& albedo,
                              const Eigen::MatrixXd& l, const std::array<double, 9>* brdf) {
    const Eigen::Vector4d n4(n.x(), n.y(), n.z(), 1.0);
    Eigen::Vector3d spec = Eigen::Vector3d::Zero(), irr;
    for (int band = 0; band < 3; ++band) {
        const Eigen::VectorXd lc = l.col(band);
        const Eigen::Matrix4d u = sh::irradiance_matrix(lc.data());
        irr[band] = n4.dot(u * n4);
        if (!brdf) continue;
        const std::array<double, 9>& b = *brdf;
        const double c5l20 = (u(2, 2) / 0.743125) * 0.247708;
        const double c4l00 = u(3, 3) + c5l20;
        Eigen::Matrix4d m;
        m << u(0, 0) * b[8], u(0, 1) * b[4], u(0, 2) * b[7], u(0, 3) * b[3],  //
            u(1, 0) * b[4], u(1, 1) * b[8], u(1, 2) * b[5], u(1, 3) * b[1],   //
            u(2, 0) * b[7], u(2, 1) * b[5], u(2, 2) * b[6], u(2, 3) * b[2],   //
            u(3, 0) * b[3], u(3, 1) * b[1], u(3, 2) * b[2], c4l00 * b[0] - c5l20 * b[6];
        spec[band] = n4.dot(m * n4) * 0.05;
    }
    const double mean = irr.sum() / 3.0;
    return albedo * (mean * 0.3) + spec;
}

// The seed variants are the report's shader as written, slips included, and the
// consistent ones are fixed. The report (1) looks its BRDF up at phi = atan(y/x), which loses
// the quadrant, and (2) projects with Figure 6's basis (Condon-Shortley phase) while its
// irradiance matrix (R&H eq. 12) assumes none. On the report's own 5 x 5 grid, normals in all
// four quadrants, the axes and the pole: the driver's seed output equals the report's formula
// above (computed from the report's coefficients, inlight's times the phase), and it differs
// from the slip-free formula exactly where the report's formula does: the specular part (albedo
// 0) only at x < 0, the diffuse part (no table) everywhere but where E(x, y, z) = E(-x, -y, z).
TEST(GlesHarness, SeedIsTheReportShaderWithItsSlips) {
    const brdf::Table t = smooth_table("report5x5", 3, 1, 21);
    const std::array<double, 9> phase = report_phase();
    const Eigen::MatrixXd sh = lighting(3, 22);
    Eigen::MatrixXd sh_report = sh;
    for (int k = 0; k < 9; ++k) sh_report.row(k) *= phase[k];
    const std::vector<Eigen::Vector3d> normals = probe_normals(t.grid, kWidth * kHeight, 23);
    ASSERT_EQ(normals[0], Eigen::Vector3d::UnitZ());
    // At the pole cart2sph divides 0 by 0: the report's shader is undefined there (NaN here).
    // Its limit from every side is the pole's value (row 2 of the grid is five copies of the
    // pole), which the seed shader takes: the reference there is the formula just beside it.
    const Eigen::Vector3d beside_pole = Eigen::Vector3d(1e-9, 0, 1).normalized();

    struct Part {
        const char* what;
        bool table;
        Eigen::Vector3d albedo;
    };
    for (const Part& part : {Part{"whole shader", true, {0.8, 0.6, 0.5}},
                             Part{"specular only (albedo 0)", true, {0, 0, 0}},
                             Part{"diffuse only (no table)", false, {1, 1, 1}}}) {
        for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
            Context& ctx = ver == GlslVersion::kEs300 ? context3() : context2();
            if (!ctx.info().float_color_buffer) GTEST_SKIP() << "no float colour buffer";
            const Variant v{ver, ShaderMode::kSeed, 3, Precision::kHighp};
            const Export e = export_variant(part.table ? &t : nullptr, MaterialInputs{}, v,
                                            ctx.info().limits);
            // The report's table: the table as bound (ES 1.00: RGBA8-dequantised) times the
            // phase, in brdfIndex order.
            const brdf::Table& tb = part.table ? *e.table_as_bound : t;
            std::vector<double> b225(225);
            for (int i1 = 0; i1 < 5; ++i1) {
                for (int i2 = 0; i2 < 5; ++i2) {
                    for (int k = 0; k < 9; ++k) {
                        b225[45 * i1 + 9 * i2 + k] = tb.at(0, i1, i2, k) * phase[k];
                    }
                }
            }
            EXPECT_TRUE(std::isnan(report_get_brdf(b225, normals[0])[0]));
            // The report's formula, and the same formula without the two slips (inlight's
            // phase, brdf::lookup's atan2).
            std::vector<Eigen::Vector3d> report(normals.size()), fixed(normals.size());
            std::vector<double> magnitudes;
            for (size_t i = 0; i < normals.size(); ++i) {
                const Eigen::Vector3d& n = normals[i];
                const std::array<double, 9> b_report = report_get_brdf(b225, i == 0 ? beside_pole : n);
                float bf[9];
                brdf::lookup(tb, n.cast<float>(), 0, bf);
                std::array<double, 9> b_fixed;
                std::copy(bf, bf + 9, b_fixed.begin());
                report[i] = report_shader(n, part.albedo, sh_report, part.table ? &b_report : nullptr);
                fixed[i] = report_shader(n, part.albedo, sh, part.table ? &b_fixed : nullptr);
                for (int c = 0; c < 3; ++c) magnitudes.push_back(std::abs(report[i][c]));
            }
            std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                             magnitudes.end());
            const double floor = kFloorFractionOfMedian * magnitudes[magnitudes.size() / 2];
            auto rel = [floor](const Eigen::Vector3d& got, const Eigen::Vector3d& want) {
                double r = 0;
                for (int c = 0; c < 3; ++c) {
                    r = std::max(r, std::abs(got[c] - want[c]) / std::max(std::abs(want[c]), floor));
                }
                return r;
            };
            Bindings bind;
            bind.sh = sh;
            bind.albedo = part.albedo.cast<float>();
            const Readback gpu = draw(ctx, e, bind, probe_mesh(normals, Eigen::Vector3d::UnitX()),
                                      kWidth, kHeight, TargetFormat::kRgba32f);
            int pass = 0, shown = 0, predicted = 0, agree = 0, decided = 0;
            int quadrant_shown[4] = {0, 0, 0, 0};  // I (x > 0, y >= 0), II, III, IV
            double worst = 0;
            for (int y = 0; y < kHeight; ++y) {
                for (int x = 0; x < kWidth; ++x) {
                    const size_t i = static_cast<size_t>(y) * kWidth + x;
                    const Eigen::Vector3d got(gpu.at(x, y, 0), gpu.at(x, y, 1), gpu.at(x, y, 2));
                    const double r = rel(got, report[i]);
                    worst = std::max(worst, r);
                    if (!(r <= kRelTolerance)) {
                        std::cout << "[gles] off at normal " << normals[i].transpose() << ": "
                                  << got.transpose() << " vs " << report[i].transpose() << "\n";
                    }
                    pass += r <= kRelTolerance ? 1 : 0;
                    // Where the report's formula differs from the slip-free one by > 10x the
                    // tolerance, the driver's must differ by > 5x (it is within 1x of the
                    // report's); where they are equal (< 0.1x), the driver's must be within 2x.
                    const double pr = rel(report[i], fixed[i]), g = rel(got, fixed[i]);
                    if (pr > 10 * kRelTolerance) {
                        ++decided;
                        ++predicted;
                        if (g > 5 * kRelTolerance) {
                            ++agree;
                            ++shown;
                            const Eigen::Vector3d& n = normals[i];
                            ++quadrant_shown[n.x() > 0 ? (n.y() >= 0 ? 0 : 3) : (n.y() > 0 ? 1 : 2)];
                        }
                    } else if (pr < 0.1 * kRelTolerance) {
                        ++decided;
                        agree += g <= 2 * kRelTolerance ? 1 : 0;
                    }
                }
            }
            const std::string what = str(e.name, ", ", part.what, " on ", ctx.info().renderer);
            EXPECT_GE(pass / static_cast<double>(kWidth * kHeight), kMinPassFraction)
                << what << ": against the report's formula, worst relative " << worst;
            EXPECT_EQ(agree, decided) << what;
            EXPECT_GT(predicted, 0) << what;
            if (part.albedo.isZero()) {
                // The quadrant loss alone: the slip shows exactly at x < 0.
                EXPECT_EQ(quadrant_shown[0] + quadrant_shown[3], 0) << what;
                EXPECT_GT(quadrant_shown[1], 0) << what;
                EXPECT_GT(quadrant_shown[2], 0) << what;
            }
            std::cout << "[gles] " << what << ": " << pass * 100.0 / (kWidth * kHeight)
                      << "% within 1e-3 of the report's formula (worst " << worst
                      << "); differs from the slip-free formula at " << shown << " of "
                      << predicted << " predicted pixels (quadrants I-IV: " << quadrant_shown[0]
                      << ", " << quadrant_shown[1] << ", " << quadrant_shown[2] << ", "
                      << quadrant_shown[3] << "), " << agree << " of " << decided
                      << " pixels classified alike\n";
        }
    }
    // The consistent variants at the same normals are the CPU model (no slip).
    for (GlslVersion ver : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        Context& ctx = ver == GlslVersion::kEs300 ? context3() : context2();
        const Variant v{ver, ShaderMode::kConsistent, 3, Precision::kHighp};
        const Export e = export_variant(&t, MaterialInputs{}, v, ctx.info().limits);
        const Outcome f = compare(ctx, e, v, Case{"report5x5", 3, 1, false}, sh, TargetFormat::kRgba32f);
        EXPECT_GE(f.pass_fraction, kMinPassFraction) << e.name << ": worst " << f.worst;
    }
}

// The lookup snippet brdf-sh-bake ships (brdf/glsl.h, both its uniform-array and its
// texture path) computes brdf::lookup() on a real driver, at the nodes, cell centres, the
// thetaphi seam and pole and the report grid's folds.
TEST(BrdfGlslSnippet, EqualsLookupAtNodesSeamsAndPoles) {
    for (const Case& s : cases()) {
        if (s.textured) continue;
        const brdf::Table t = smooth_table(s.grid, 3, s.channels, 5);
        const std::vector<Eigen::Vector3d> normals =
            probe_normals(t.grid, kWidth * kHeight, 14);
        const Mesh mesh = probe_mesh(normals, Eigen::Vector3d::UnitX());
        const float range = *std::max_element(t.coeffs.begin(), t.coeffs.end()) -
                            *std::min_element(t.coeffs.begin(), t.coeffs.end());
        // Equal but for float rounding: atan2_f32 and libm differ by ~1e-7 relative, moving
        // the fractions by ~1e-6 of a cell, times at most the table's range per cell.
        const double tolerance = 1e-5 * range;
        for (bool use_texture : {false, true}) {
            for (int ch = 0; ch < t.channels; ++ch) {
                for (int k0 = 0; k0 < t.coeff_count(); k0 += 4) {
                    Export e;
                    e.name = str("lookup snippet ", s.grid, use_texture ? " texture" : " uniform");
                    e.vertex_source =
                        "#version 300 es\nin vec3 a_position;\nin vec3 a_normal;\nout vec3 "
                        "v_normal;\nvoid main() {\n    v_normal = a_normal;\n    gl_Position = "
                        "vec4(a_position, 1.0);\n}\n";
                    std::string out = "vec4(";
                    for (int i = 0; i < 4; ++i) {
                        out += i ? ", " : "";
                        out += k0 + i < t.coeff_count() ? str("c[", k0 + i, "]") : "0.0";
                    }
                    e.fragment_source =
                        str("#version 300 es\n", use_texture ? "#define BRDF_USE_TEXTURE\n" : "",
                            brdf::glsl_lookup_source(t),
                            "in vec3 v_normal;\nout vec4 o_value;\nvoid main() {\n"
                            "    float c[BRDF_NCOEFFS];\n    brdf_sh_lookup(v_normal, ",
                            ch, ", c);\n    o_value = ", out, ");\n}\n");
                    e.manifest["variant"] = {{"glsl_version", "300 es"}, {"sh_bands", 1}};
                    e.manifest["textures"] = nlohmann::json::array();
                    Bindings b;
                    b.sh = Eigen::MatrixXd::Zero(1, 3);
                    if (use_texture) {
                        e.manifest["textures"].push_back({{"uniform", "u_brdf_texture"}, {"unit", 0}});
                        e.table_layout = TableLayout::kFloatTexture;
                        e.table_texels = brdf::texture_texels(t);
                        const Eigen::Vector2i size = brdf::texture_size(t);
                        e.data_width = size.x();
                        e.data_height = size.y();
                    } else {
                        b.float_arrays.emplace_back("u_brdf_coeffs", t.coeffs);
                    }
                    const Readback gpu = draw(context3(), e, b, mesh, kWidth, kHeight,
                                              TargetFormat::kRgba32f);
                    double worst = 0;
                    for (int y = 0; y < kHeight; ++y) {
                        for (int x = 0; x < kWidth; ++x) {
                            float want[16];
                            brdf::lookup(t, normals[y * kWidth + x].cast<float>(), ch, want);
                            for (int i = 0; i < 4 && k0 + i < t.coeff_count(); ++i) {
                                const double d = std::abs(gpu.at(x, y, i) - want[k0 + i]);
                                worst = std::max(worst, d);
                                ASSERT_LE(d, tolerance)
                                    << e.name << " channel " << ch << " k " << k0 + i
                                    << " at normal " << normals[y * kWidth + x].transpose();
                            }
                        }
                    }
                    std::cout << "[gles] " << e.name << " ch " << ch << " k " << k0
                              << "..: worst |GLSL - lookup()| " << worst << "\n";
                }
            }
        }
    }
}

}  // namespace
}  // namespace inlight::gles
