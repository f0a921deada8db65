// Tests of the trilinear texture filter of the GLES export (gles/export.h, render/mip.h): the
// exported atlas is the CPU model's, its manifest states what an app binds, and the shader drawn
// on the driver (gles::render_scene, one fragment per pixel) equals the CPU model with
// TextureFilter::kTrilinear at one fragment per pixel within one 8-bit code on every pixel, on
// a minified stripe texture (16x and 64x: the levels' mean, where bilinear reads one stripe),
// a pure-noise normal map, a grazing perspective view, 1 x 1 textures and non-power-of-two
// textures, for GLSL ES 1.00 and 3.00.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "core/error.h"
#include "gles/harness_testing.h"
#include "gles/scene.h"
#include "render/mip.h"
#include "render/realtime.h"
#include "render/render_testing.h"
#include "render/scene.h"

namespace inlight::gles {
namespace {

using harness_testing::as_image;
using harness_testing::context2;
using harness_testing::context3;
using harness_testing::random_texture;

// The criterion: one 8-bit code of linear radiance (radiance kept below 1, so no clamping).
constexpr int kCodeTolerance = 1;

Texture8 stripes(int w, int h) {
    Texture8 t;
    t.width = w;
    t.height = h;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c) t.rgba.push_back(x % 2 ? 255 : 0);
            t.rgba.push_back(255);
        }
    }
    return t;
}

/// A normal map of random unit normals tilted at most `max_tilt_deg` from +z.
Texture8 gentle_normals(int w, int h, unsigned seed, double max_tilt_deg) {
    Texture8 t;
    t.width = w;
    t.height = h;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < w * h; ++i) {
        const double tilt = max_tilt_deg * kPi / 180.0 * std::sqrt(u(rng)), phi = 2 * kPi * u(rng);
        const Eigen::Vector3d n(std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt));
        for (int c = 0; c < 3; ++c) t.rgba.push_back(static_cast<uint8_t>(std::lround((n[c] * 0.5 + 0.5) * 255)));
        t.rgba.push_back(255);
    }
    return t;
}

struct TexturedPatch {
    render::SurfaceMaterial material;
    render::Camera camera;
    Eigen::Vector2d patch_size{1, 1};
    Eigen::Vector3d patch_center{0, 0, 0};
    Eigen::Vector3d sky{1, 1, 1};  ///< constant environment radiance (< 1 per channel: no clamping)
    double varying_sky = 0;  ///< > 0: render_testing's band-limited sky (l <= 2) at this intensity
    const brdf::Table* table = nullptr;  ///< the material's BRDF table (GGX) or null (Lambert)
};

struct Drawn {
    image::Image gpu, cpu;
    int worst_code = 0;       ///< largest code difference over pixels and channels
    double worst_abs = 0;     ///< largest |gpu - cpu| (linear radiance)
    double max_radiance = 0;  ///< of the CPU image
};

render::SceneDesc scene_of(const TexturedPatch& s) {
    render::SceneDesc d;
    d.camera = s.camera;
    d.environment.radiance = s.sky;
    if (s.varying_sky > 0) {
        d.environment.image = render::testscenes::band_limited_sky(32, 16);
        d.environment.intensity = s.varying_sky;
    }
    d.materials.push_back(s.material);
    render::ObjectSpec o;
    o.shape.kind = render::ShapeKind::kPatch;
    o.shape.size = s.patch_size;
    o.shape.center = s.patch_center;
    o.material = s.material.name;
    d.objects.push_back(o);
    return d;
}

/// The trilinear variant of `version` drawn on the driver and the CPU model, both at one
/// fragment per pixel, and how far apart they are.
Drawn draw_both(const TexturedPatch& s, GlslVersion version, TextureFilter filter = TextureFilter::kTrilinear) {
    const render::Scene scene(scene_of(s));
    Context& ctx = version == GlslVersion::kEs300 ? context3() : context2();
    const render::SurfaceMaterial& m = scene.materials().at(0);
    MaterialInputs in;
    in.name = "m";
    in.brdf = m.brdf;
    in.uv_scale = m.uv_scale.cast<float>();
    if (m.albedo_texture) in.albedo_texture_px = {m.albedo_texture->width, m.albedo_texture->height};
    if (m.normal_texture) in.normal_texture_px = {m.normal_texture->width, m.normal_texture->height};
    Variant v;
    v.version = version;
    v.texture_filter = filter;
    const Export e = export_variant(s.table, in, v, ctx.info().limits);
    render::RealtimeLighting lighting;
    lighting.coeffs = render::project_environment(scene.environment(), 3);
    if (e.table_as_bound) lighting.tables.push_back(*e.table_as_bound);
    render::RealtimeOptions ro;
    ro.supersample = 1;
    ro.texture_filter = filter;
    Drawn out;
    out.cpu = render::render_realtime(scene, lighting, ro);
    out.gpu = render_scene(ctx, scene, {e}, lighting.coeffs).radiance;
    for (size_t i = 0; i < out.cpu.pixels.size(); ++i) {
        const double want = out.cpu.pixels[i], got = out.gpu.pixels[i];
        out.max_radiance = std::max(out.max_radiance, want);
        out.worst_abs = std::max(out.worst_abs, std::abs(got - want));
        if (!std::isfinite(got)) {
            out.worst_code = 255;
            continue;
        }
        const long a = std::lround(std::clamp(want, 0.0, 1.0) * 255);
        const long b = std::lround(std::clamp(got, 0.0, 1.0) * 255);
        out.worst_code = std::max(out.worst_code, static_cast<int>(std::labs(a - b)));
    }
    return out;
}

void expect_match(const TexturedPatch& s, const std::string& what) {
    for (GlslVersion version : {GlslVersion::kEs100, GlslVersion::kEs300}) {
        const Drawn d = draw_both(s, version);
        EXPECT_LT(d.max_radiance, 1.0) << what << ": radiance must stay below 1 (no clamping)";
        EXPECT_LE(d.worst_code, kCodeTolerance)
            << what << ", ES " << to_string(version) << ": worst |GLES - CPU| = " << d.worst_abs;
        if (std::getenv("TRILINEAR_DEBUG")) {
            for (int y = 0; y < d.cpu.height; ++y)
                for (int x = 0; x < d.cpu.width; ++x)
                    for (int c = 0; c < 3; ++c)
                        if (std::abs(d.cpu.at(x, y, c) - d.gpu.at(x, y, c)) > 1e-3)
                            std::printf("  px %d,%d c%d cpu %.5f gpu %.5f\n", x, y, c, d.cpu.at(x, y, c), d.gpu.at(x, y, c));
        }
        std::printf("[ trilinear ] %s ES %s: worst %d code(s), |GLES - CPU| <= %.3g\n", what.c_str(),
                    to_string(version).c_str(), d.worst_code, d.worst_abs);
    }
}

render::SurfaceMaterial lambert(const Eigen::Vector3d& albedo) {
    render::SurfaceMaterial m;
    m.name = "m";
    m.brdf.specular = brdf::Model::kLambert;
    m.brdf.albedo = albedo;
    return m;
}

/// An orthographic camera looking down -z at the patch, `px` square, `height` world units high.
render::Camera ortho(int px, double height) {
    render::Camera c;
    c.projection = render::Projection::kOrthographic;
    c.position = {0, 0, 2};
    c.ortho_height = height;
    c.width_px = c.height_px = px;
    return c;
}

TEST(GlesTrilinear, MinifiedStripesReadTheMeanWhereBilinearReadsOneStripe) {
    // render/realtime_test's case on the driver: one-texel stripes 0 and 1, minified 16x and
    // 64x (uv_scale), pixel centres on texel centres. Every level above 0 holds the mean 1/2
    // (stored as its sRGB code); the lod (3.2 and 5.2 levels) reads two of them.
    const Texture8 tex = stripes(64, 64);
    const float mean_stored = image::srgb_decode(std::round(image::srgb_encode(0.5f) * 255.0f) / 255.0f);
    for (const double minified : {16.0, 64.0}) {
        TexturedPatch s;
        s.material = lambert({0.9, 0.9, 0.9});
        s.material.albedo_texture = as_image(tex, true);
        s.material.uv_scale = Eigen::Vector2d::Constant(minified / (0.05 * 64));  // 0.05 uv per pixel
        s.camera = ortho(16, 0.8);
        const double half_texel = 0.5 / (64 * s.material.uv_scale.x());
        s.camera.position.x() += half_texel;
        s.camera.look_at.x() += half_texel;
        expect_match(s, str("stripes minified ", minified, "x"));
        for (GlslVersion version : {GlslVersion::kEs100, GlslVersion::kEs300}) {
            const Drawn tri = draw_both(s, version);
            // The mean, times the albedo (a constant sky of 1: radiance = albedo x texture).
            // Float rounding of the lookups only: 1e-5.
            for (float g : tri.gpu.pixels) EXPECT_NEAR(g, 0.9 * mean_stored, 1e-5) << minified << "x";
            const Drawn bil = draw_both(s, version, TextureFilter::kBilinear);
            for (float g : bil.gpu.pixels) EXPECT_GT(std::abs(g - 0.45), 0.44) << minified << "x, bilinear";
        }
    }
}

TEST(GlesTrilinear, PureNoiseNormalMapMatchesTheCpuModel) {
    // Random unit normals per texel (harness_testing::random_texture), GGX with a smooth table,
    // under a sky that varies (the lighting's bands 1 and 2 see the normal), minified 1x to 8x
    // along a 45-degree perspective view.
    const brdf::Table table = harness_testing::smooth_table("octa:9", 3, 1, 5);
    TexturedPatch s;
    s.material = lambert({0.5, 0.45, 0.4});
    s.material.brdf.specular = brdf::Model::kGgx;
    s.material.normal_texture = as_image(random_texture(64, 64, 21, true), false);
    s.material.uv_scale = {8, 8};
    s.table = &table;
    s.patch_size = {8, 8};
    s.camera.projection = render::Projection::kPerspective;
    s.camera.position = {0, -1.2, 1.2};
    s.camera.fov_deg = 50;
    s.camera.width_px = s.camera.height_px = 32;
    s.varying_sky = 0.15;
    expect_match(s, "noise normal map");
}

TEST(GlesTrilinear, GrazingViewMatchesTheCpuModel) {
    // 80 degrees from the normal, perspective: the lod grows from ~1 to the last level up the
    // image, and the quad derivatives differ from the analytic ones by the uv's second
    // derivative (render/mip.h, "Derivatives").
    TexturedPatch s;
    s.material = lambert({0.9, 0.8, 0.7});
    s.material.albedo_texture = as_image(random_texture(32, 32, 31, false), true);
    // Normals tilted up to 60 degrees: many face away from the pixel's 80-degree view. Both
    // sides decide the fallback to the geometric normal by the model's constant view (the
    // shader's VIEW, +z here), not the pixel's (a CPU model that used the pixel's view failed
    // this test before 2026-11-28).
    s.material.normal_texture = as_image(gentle_normals(16, 16, 32, 60.0), false);
    // The patch lies wholly in front of the camera (y from -1.5 to 20, the camera at y = -1.97):
    // no near-plane clipping. 1 tile per unit.
    s.patch_size = {10, 21.5};
    s.patch_center = {0, 9.25, 0};
    s.material.uv_scale = s.patch_size;
    const double theta = 80.0 * kPi / 180.0;
    s.camera.projection = render::Projection::kPerspective;
    s.camera.position = {0, -2 * std::sin(theta), 2 * std::cos(theta)};
    s.camera.fov_deg = 16;  // the top row's rays at 88 degrees: the patch fills the view
    s.camera.width_px = 48;
    s.camera.height_px = 32;
    s.varying_sky = 0.3;
    expect_match(s, "grazing 80 degrees");
}

TEST(GlesTrilinear, OneTexelTexturesMatchTheCpuModel) {
    Texture8 albedo, normal;
    albedo.width = albedo.height = normal.width = normal.height = 1;
    albedo.rgba = {200, 120, 40, 255};
    normal.rgba = {160, 110, 230, 255};
    TexturedPatch s;
    s.material = lambert({0.9, 0.9, 0.9});
    s.material.albedo_texture = as_image(albedo, true);
    s.material.normal_texture = as_image(normal, false);
    s.material.uv_scale = {3, 3};
    s.camera = ortho(8, 0.8);
    s.sky = {0.8, 0.8, 0.8};
    expect_match(s, "1x1 textures");
}

TEST(GlesTrilinear, NonPowerOfTwoTexturesMatchTheCpuModel) {
    // 37 x 23 albedo and 29 x 19 normal map (ES 2.0: NPOT, NEAREST, CLAMP; the shader wraps
    // inside each level), minified ~2x to 5x by a tilted perspective view.
    TexturedPatch s;
    s.material = lambert({0.9, 0.85, 0.8});
    s.material.albedo_texture = as_image(random_texture(37, 23, 41, false), true);
    s.material.normal_texture = as_image(random_texture(29, 19, 42, true), false);
    s.material.uv_scale = {5, 7};
    s.patch_size = {3, 3};
    s.camera.projection = render::Projection::kPerspective;
    s.camera.position = {0.3, -1.0, 1.4};
    s.camera.fov_deg = 45;
    s.camera.width_px = 40;
    s.camera.height_px = 30;
    s.varying_sky = 0.3;
    expect_match(s, "NPOT textures");
}

}  // namespace
}  // namespace inlight::gles
