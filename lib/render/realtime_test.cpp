// Tests of the real-time model: it reproduces envmap-project's irradiance exactly on a Lambert
// patch, equals the path tracer when the lighting is band-limited (so SH at 3 bands is exact),
// and its seed mode is the report's shader formula (the cosine applied twice, gray x 0.3,
// specular x 0.05).
#include "render/realtime.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "brdf/bake.h"
#include "core/conventions.h"
#include "core/error.h"
#include "envmap/project.h"
#include "image/color.h"
#include "render/path_tracer.h"
#include "render/render_testing.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::render {
namespace {

/// Relative agreement of float images with double computations (float has 6e-8 relative
/// precision; a few roundings).
constexpr double kFloatRel = 1e-6;

using testscenes::band_limited_sky;

using testscenes::patch_scene;

SurfaceMaterial lambert(const Eigen::Vector3d& albedo) {
    SurfaceMaterial m;
    m.name = "m";
    m.brdf.specular = brdf::Model::kLambert;
    m.brdf.albedo = albedo;
    return m;
}

TEST(Realtime, ReproducesEnvmapProjectIrradianceOnLambertPatch) {
    const std::string dir = testing::blender_hdri_dir();
    INLIGHT_SKIP_IF_MISSING(dir, "blender-data HDRIs");
    const std::string rotation = "z=40,x=-30";
    const double intensity = 0.7;
    SurfaceMaterial m = lambert({0.7, 0.5, 0.3});
    // A constant tilted normal map: n = normalize(2 rgb - 1) in the patch's frame (= device).
    const std::string tmp = testing::temp_dir("realtime_normal");
    image::Image normal(2, 2, 3, image::ColorSpace::kData);
    for (size_t i = 0; i < normal.pixels.size(); i += 3) {
        normal.pixels[i] = 0.7f;
        normal.pixels[i + 1] = 0.4f;
        normal.pixels[i + 2] = 0.9f;
    }
    image::write_image(tmp + "/n.exr", normal);
    m.normal_texture_path = tmp + "/n.exr";
    SceneDesc d = patch_scene(m, 8);
    d.environment.path = dir + "/courtyard.exr";
    d.environment.rotation = rotation;
    d.environment.intensity = intensity;
    const Scene scene(d);

    // envmap-project's route, independently: load, rotate, scale, project, irradiance.
    envmap::LoadOptions lo;
    lo.rotate = rotation;
    lo.intensity = intensity;
    const envmap::Environment env = envmap::load_environment(dir + "/courtyard.exr", lo);
    const Eigen::MatrixXd coeffs = envmap::project(env, {}).coeffs;
    const Eigen::Vector3d n = Eigen::Vector3d(0.4, -0.2, 0.8).normalized();

    RealtimeLighting lighting;
    lighting.coeffs = project_environment(scene.environment(), 3);
    RealtimeOptions ro;
    ro.supersample = 1;
    const image::Image rt = render_realtime(scene, lighting, ro);
    for (int c = 0; c < 3; ++c) {
        const double e = sh::irradiance(3, coeffs.col(c).data(), n);
        const double expect = m.brdf.albedo[c] / kPi * e;
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 8; ++x) {
                ASSERT_NEAR(rt.at(x, y, c), expect, kFloatRel * expect)
                    << x << "," << y << "," << c;
            }
        }
    }
}

TEST(Realtime, AnyBandCountMatchesTheSeriesAndThreeBandsTheMatrix) {
    const EnvironmentLight env(band_limited_sky(64, 32), parse_rotation("x=20"), 1.0, "sky");
    const Eigen::MatrixXd coeffs = project_environment(env, 6);
    const Eigen::Vector3d n = Eigen::Vector3d(0.3, 0.5, 0.8).normalized();
    const Eigen::Vector3d albedo(0.5, 0.6, 0.7);
    for (int bands = 1; bands <= 6; ++bands) {
        RealtimeOptions ro;
        ro.sh_bands = bands;
        const Eigen::Vector3d rt = shade_realtime(n, albedo, false, coeffs, nullptr, ro);
        for (int c = 0; c < 3; ++c) {
            // sum_lm A_l L_lm Y_lm(n), written out here.
            const std::vector<double> y = sh::eval(bands, n);
            double e = 0;
            for (int l = 0; l < bands; ++l) {
                for (int mm = -l; mm <= l; ++mm) {
                    e += sh::cosine_zonal(l) * coeffs(sh::index(l, mm), c) *
                         y[static_cast<size_t>(sh::index(l, mm))];
                }
            }
            EXPECT_NEAR(rt[c], albedo[c] / kPi * e, 1e-12) << "bands " << bands;
        }
    }
}

TEST(Realtime, ConsistentModeEqualsPathTracerForBandLimitedLighting) {
    // Lighting with l <= 2 only: sum_lm L_lm B_lm over 3 bands is the exact reflection
    // integral, and R&H's irradiance is exact. The patch faces the ortho camera (normal on a
    // grid node of the octa table), so the model must match the path tracer up to noise, the
    // BRDF bake's quadrature and the lat-long pixelation of the smooth map.
    SurfaceMaterial m;
    m.name = "ggx";
    m.brdf.specular = brdf::Model::kGgx;
    m.brdf.alpha = 0.4;
    m.brdf.f0 = {0.5, 0.4, 0.3};
    m.brdf.albedo = {0.3, 0.2, 0.1};
    SceneDesc d = patch_scene(m, 4);
    d.environment.image = band_limited_sky(256, 128);
    d.environment.rotation = "z=25";
    const Scene scene(d);
    RenderOptions po;
    po.spp = 4096;
    po.jitter = false;
    const RenderResult gt = render(scene, po);

    const RealtimeLighting lighting = testscenes::one_material_lighting(scene, 3, "octa:9", 4096);
    RealtimeOptions ro;
    ro.supersample = 1;
    const image::Image rt = render_realtime(scene, lighting, ro);
    // Pixelation: the midpoint rule over 256x128 pixels errs O(h^2) ~ (pi/128)^2 = 6e-4 of the
    // integral at most; the Gauss-Legendre bake is converged to ~1e-6. 1e-3 covers both.
    constexpr double kModelRel = 1e-3;
    constexpr double kSigmas = 5.0;  // 48 pixel-channels, 4096 spp: ~normal; 1e-3 family-wise
    Eigen::Vector3d diff_sum = Eigen::Vector3d::Zero(), var_sum = Eigen::Vector3d::Zero(),
                    truth_sum = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < rt.pixels.size(); ++i) {
        const double truth = gt.radiance.pixels[i];
        EXPECT_NEAR(rt.pixels[i], truth, kSigmas * gt.std_error.pixels[i] + kModelRel * truth)
            << "pixel " << i / 3 << " channel " << i % 3;
        diff_sum[static_cast<int>(i % 3)] += rt.pixels[i] - truth;
        var_sum[static_cast<int>(i % 3)] +=
            static_cast<double>(gt.std_error.pixels[i]) * gt.std_error.pixels[i];
        truth_sum[static_cast<int>(i % 3)] += truth;
    }
    // Every pixel sees the same normal and view: the average over the 16 pixels is a sharper
    // test (3 channels, 1e-3 family-wise: 3.6 sigmas; 4 used).
    constexpr double kAggregateSigmas = 4.0;
    for (int c = 0; c < 3; ++c) {
        EXPECT_LE(std::abs(diff_sum[c]),
                  kAggregateSigmas * std::sqrt(var_sum[c]) + kModelRel * truth_sum[c])
            << "channel " << c << ": mean difference " << diff_sum[c] / 16 << ", se "
            << std::sqrt(var_sum[c]) / 16;
    }
}

TEST(Realtime, SeedModeIsTheReportShader) {
    const EnvironmentLight env(band_limited_sky(64, 32), parse_rotation("z=10"), 1.0, "sky");
    const Eigen::MatrixXd coeffs = project_environment(env, 3);
    brdf::Material mat;
    mat.specular = brdf::Model::kCookTorranceReport;
    brdf::BakeOptions bo;
    bo.samples = 1024;
    const brdf::Table table = brdf::bake(mat, brdf::parse_grid("octa:9"), bo);
    const Eigen::Vector3d albedo(0.4, 0.5, 0.6);
    // One normal with x > 0 and one with x < 0 (where the report's atan(y/x) loses the quadrant).
    for (const Eigen::Vector3d& n : {Eigen::Vector3d(0.2, -0.3, 0.9).normalized(),
                                     Eigen::Vector3d(-0.4, 0.3, 0.8).normalized()}) {
        RealtimeOptions seed;
        seed.mode = RealtimeMode::kSeed;
        const Eigen::Vector3d rt = shade_realtime(n, albedo, true, coeffs, &table, seed);

        // The report's formula written out: gray irradiance x 0.3 x albedo, plus 0.05 x the
        // irradiance of the products L_k B_k (the entry-wise product applies the cosine lobe's
        // A_l to L_k B_k once more). Its slips: B looked up at phi = atan(y/x) (the mirror
        // (-x, -y, z) when x < 0), and L with the Condon-Shortley phase in R&H's matrix: the
        // gray irradiance taken at (-x, -y, z); in L_k B_k the two phases cancel.
        const Eigen::Vector3d mirror(-n.x(), -n.y(), n.z());
        float b[9];
        brdf::lookup(table, (n.x() < 0 ? mirror : n).cast<float>(), 0, b);
        double gray = 0;
        for (int c = 0; c < 3; ++c) gray += sh::irradiance(3, coeffs.col(c).data(), mirror) / 3.0;
        // The shader's c3 = 0.743125 and c5 = 0.247708 are rounded to 6 digits (relative ~1e-6).
        constexpr double kShaderConstRel = 1e-5;
        for (int c = 0; c < 3; ++c) {
            double lb[9];
            for (int k = 0; k < 9; ++k) lb[k] = coeffs(k, c) * b[k];
            const double expect = albedo[c] * gray * 0.3 + 0.05 * sh::irradiance(3, lb, n);
            EXPECT_NEAR(rt[c], expect, kShaderConstRel * std::abs(expect)) << c;
        }
        // And it is not the consistent model (which is several times brighter in specular).
        RealtimeOptions consistent;
        const Eigen::Vector3d ok = shade_realtime(n, albedo, true, coeffs, &table, consistent);
        EXPECT_GT((ok - rt).norm(), 0.1 * ok.norm());
    }
}

TEST(Realtime, TrilinearAtOneFragmentPerPixelAveragesAMinifiedTexture) {
    // A Lambert patch under a constant sky of 1 (radiance = albedo) with an albedo texture of
    // one-texel stripes, 0 and 1, minified 16x and 64x: every mip level above 0 holds the mean
    // 1/2 exactly (an even, aligned footprint over the stripes' bilinear reconstruction),
    // stored as its sRGB code. Drawn at one fragment per pixel, each pixel must be that value,
    // which needs the derivatives (one pixel = 0.1 uv) to reach a level above 0.
    SurfaceMaterial m = lambert({1, 1, 1});
    auto stripes = std::make_shared<image::Image>(64, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) stripes->at(x, y, c) = static_cast<float>(x % 2);
    m.albedo_texture = stripes;
    const float mean_stored =
        image::srgb_decode(std::round(image::srgb_encode(0.5f) * 255.0f) / 255.0f);
    for (const double minified : {16.0, 64.0}) {
        m.uv_scale = Eigen::Vector2d::Constant(minified / (0.1 * 64));
        SceneDesc d = patch_scene(m, 8);  // 0.8 wide, 8 px: 0.1 uv per pixel
        d.environment.radiance = {1, 1, 1};
        // Half a texel to the side: pixel centres on texel centres, where level 0 reads single
        // stripes (what the shipped bilinear lookup shows: 0 or 1 instead of 1/2).
        const double half_texel = 0.5 / (64 * m.uv_scale.x());
        d.camera.position.x() += half_texel;
        d.camera.look_at.x() += half_texel;
        const Scene scene(d);
        RealtimeLighting lighting;
        lighting.coeffs = project_environment(scene.environment(), 3);
        RealtimeOptions ro;
        ro.supersample = 1;
        ro.texture_filter = TextureFilter::kTrilinear;
        const image::Image img = render_realtime(scene, lighting, ro);
        for (float v : img.pixels) EXPECT_NEAR(v, mean_stored, kFloatRel) << minified << "x";
        ro.texture_filter = TextureFilter::kBilinear;
        for (float v : render_realtime(scene, lighting, ro).pixels)
            EXPECT_GT(std::abs(v - 0.5), 0.49) << minified << "x, bilinear: a single stripe";
    }
}

TEST(Realtime, PrimitiveUvExtrapolatesThePlanesAffineUv) {
    // What a GPU interpolates for a quad's helper fragment off the triangle: the uv of the
    // triangle's plane, extended. A patch (uv affine in x, y) and a one-triangle mesh whose uv
    // is an affine map of the plane's (x, y): rays that miss both give the map's value where
    // they meet the plane, exactly (double rounding: 1e-12).
    constexpr double kDoubleTol = 1e-12;
    const std::string dir = testing::temp_dir("primitive_uv");
    // uv = (0.25 + 0.5 x + 0.1 y, 0.75 - 0.2 x + 0.4 y) at the corners (0, 0), (1, 0), (0, 1).
    auto map = [](double x, double y) { return Eigen::Vector2d(0.25 + 0.5 * x + 0.1 * y, 0.75 - 0.2 * x + 0.4 * y); };
    std::ofstream(dir + "/tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                    << "vt " << map(0, 0).x() << " " << 1 - map(0, 0).y() << "\n"
                                    << "vt " << map(1, 0).x() << " " << 1 - map(1, 0).y() << "\n"
                                    << "vt " << map(0, 1).x() << " " << 1 - map(0, 1).y() << "\n"
                                    << "f 1/1 2/2 3/3\n";
    SceneDesc d = patch_scene(lambert({1, 1, 1}), 4);
    ObjectSpec mesh;
    mesh.shape.kind = ShapeKind::kMesh;
    mesh.mesh_path = dir + "/tri.obj";
    mesh.translate = {3, 0, -1};  // beside the patch, one unit below it
    mesh.material = d.materials[0].name;
    d.objects.push_back(mesh);
    const Scene scene(d);
    const Ray onto_patch{{0.1, 0.05, 2}, Eigen::Vector3d(0.02, -0.01, -1).normalized()};
    const Ray onto_mesh{{3.2, 0.2, 1}, Eigen::Vector3d(0.01, 0.03, -1).normalized()};
    for (const Ray* on : {&onto_patch, &onto_mesh}) {
        SurfaceHit hit;
        ASSERT_TRUE(scene.accel().intersect(*on, &hit));
        // Rays far off the primitive, toward its plane from above, and one from below it.
        for (const Eigen::Vector3d& dir_to : {Eigen::Vector3d(1.5, -0.7, -1), Eigen::Vector3d(-2, 3, -1),
                                              Eigen::Vector3d(0.4, 0.4, 1)}) {
            Ray r{on->origin - Eigen::Vector3d(0, 0, dir_to.z() > 0 ? 4 : 0), dir_to.normalized()};
            const double plane_z = on == &onto_patch ? 0.0 : -1.0;
            const double t = (plane_z - r.origin.z()) / r.dir.z();
            const Eigen::Vector3d p = r.origin + t * r.dir;
            const Eigen::Vector2d want = on == &onto_patch ? Eigen::Vector2d(p.x() + 0.5, 0.5 - p.y())
                                                           : map(p.x() - 3, p.y());
            EXPECT_LT((primitive_uv(scene, hit, r) - want).cwiseAbs().maxCoeff(), kDoubleTol)
                << (on == &onto_patch ? "patch" : "mesh") << " toward " << dir_to.transpose();
        }
    }
}

TEST(Realtime, RejectsImpossibleOptions) {
    const EnvironmentLight env(band_limited_sky(16, 8), Eigen::Matrix3d::Identity(), 1.0, "sky");
    SceneDesc d = patch_scene(lambert({1, 1, 1}), 4);
    d.environment.image = band_limited_sky(16, 8);
    const Scene scene(d);
    RealtimeLighting lighting;
    lighting.coeffs = project_environment(env, 3);
    RealtimeOptions ro;
    ro.sh_bands = 4;
    EXPECT_THROW(render_realtime(scene, lighting, ro), UsageError);
    lighting.coeffs = project_environment(env, 4);
    ro.mode = RealtimeMode::kSeed;
    EXPECT_THROW(render_realtime(scene, lighting, ro), UsageError);    for (const double spread : {0.0, -1.0, std::nan("")}) {
        RealtimeOptions bad;
        bad.specular_spread = spread;
        EXPECT_THROW(render_realtime(scene, lighting, bad), UsageError) << spread;
    }
}

}  // namespace
}  // namespace inlight::render
