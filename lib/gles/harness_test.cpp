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

#include "gles/harness_testing.h"

namespace inlight::gles {
namespace {

using namespace harness_testing;

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
}  // namespace
}  // namespace inlight::gles
