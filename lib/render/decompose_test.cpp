// Tests of render/decompose.h: each part vanishes where its approximation is exact and shows
// where it is not (band-limited lighting: no SH truncation at 3 bands; a patch facing an
// orthographic camera: no grid interpolation and no fixed-view error; a sphere seen in
// perspective: both; a sphere shadowing a patch under a constant sky: visibility only), and
// the first model of the chain is the real-time model itself.
#include "render/decompose.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "render/render_testing.h"

namespace inlight::render {
namespace {

using testscenes::band_limited_sky;

double luma(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

SurfaceMaterial ggx(const std::string& name) {
    SurfaceMaterial m;
    m.name = name;
    m.brdf.specular = brdf::Model::kGgx;
    m.brdf.alpha = 0.3;
    m.brdf.f0 = {0.5, 0.4, 0.3};
    m.brdf.albedo = {0.4, 0.3, 0.2};
    return m;
}

RenderResult pixel_centre_truth(const Scene& scene, int spp) {
    RenderOptions po;
    po.spp = spp;
    po.jitter = false;
    return render(scene, po);
}

DecomposeOptions small_options() {
    DecomposeOptions o;
    o.max_bands = 3;
    o.map_height = 32;
    o.bake.samples = 256;
    return o;
}

/// The real-time model at pixel centres against the truth: relative RMS of luminance.
double realtime_vs_truth(const Scene& scene, const RealtimeLighting& lighting,
                         const RenderResult& truth) {
    RealtimeOptions ro;
    ro.supersample = 1;
    const image::Image rt = render_realtime(scene, lighting, ro);
    double sum = 0, mean = 0;
    const size_t n = rt.pixel_count();
    for (size_t p = 0; p < n; ++p) {
        const double diff = luma(&rt.pixels[3 * p]) - luma(&truth.radiance.pixels[3 * p]);
        sum += diff * diff;
        mean += luma(&truth.radiance.pixels[3 * p]) / static_cast<double>(n);
    }
    return std::sqrt(sum / static_cast<double>(n)) / mean;
}

// rms(M3 - T) of pure noise over N pixels is noise x sqrt(chi2_N / N): at N = 64 its 1e-3
// upper quantile is 1.27 noise; 1.5 covers it. The exact integral over the 64x32 pixels of a
// smooth map errs ~(pi/32)^2 / 24 = 4e-4 of the mean: 2e-3 covers it.
constexpr double kNoiseQuantile = 1.5;
constexpr double kPixelation = 2e-3;

TEST(Decompose, PatchUnderBandLimitedLightingHasOnlyTruncationBelowThreeBands) {
    const SurfaceMaterial m = ggx("ggx");
    SceneDesc d = testscenes::patch_scene(m, 8);
    d.environment.image = band_limited_sky(64, 32);
    d.environment.rotation = "z=25";
    const Scene scene(d);
    const RenderResult truth = pixel_centre_truth(scene, 256);
    const DecomposeOptions o = small_options();
    const RealtimeLighting lighting = testscenes::one_material_lighting(scene, 3, "octa:9", 256);
    const Decomposition dec = decompose_error(scene, truth, lighting, o);
    ASSERT_EQ(dec.by_bands.size(), 3u);
    // The patch's normal (+z) is a grid node and the camera orthographic: exactly nothing.
    for (const auto& b : dec.by_bands) EXPECT_LT(b.grid_interpolation, 1e-7);
    EXPECT_EQ(dec.fixed_view, 0.0);
    EXPECT_EQ(dec.roughness_texture, 0.0);
    EXPECT_EQ(dec.pixel_footprint, 0.0);
    // Lighting with l <= 2: 3 bands hold it (up to the map's pixelation), 1 band does not.
    EXPECT_LT(dec.by_bands[2].sh_truncation_diffuse, kPixelation);
    EXPECT_LT(dec.by_bands[2].sh_truncation_specular, kPixelation);
    EXPECT_GT(dec.by_bands[0].sh_truncation_diffuse, 10 * kPixelation);
    // A flat patch under a distant sky: nothing occludes it, the rest is the truth's noise.
    EXPECT_LT(dec.exact_vs_truth, kNoiseQuantile * dec.truth_noise + kPixelation);
    EXPECT_GT(dec.truth_noise, 0.0);
    // 32 against 16 rows: the GGX lobe (alpha 0.3, ~17 deg wide) over 11-degree cells errs
    // ~(11 / 17)^2 / 24 = 1.7% of the specular by the midpoint rule; 2e-2 bounds it.
    EXPECT_GT(dec.map_discretisation, 0.0);
    EXPECT_LT(dec.map_discretisation, 2e-2);
}

TEST(Decompose, SphereInPerspectiveShowsGridAndFixedViewAndTheFirstModelIsTheRealtimeOne) {
    SceneDesc d;
    d.camera.projection = Projection::kPerspective;
    d.camera.position = {0, 0, 3};
    d.camera.fov_deg = 25;
    d.camera.width_px = d.camera.height_px = 12;
    d = testscenes::with_object(d, ggx("ggx"), ShapeKind::kSphere);
    d.objects[0].shape.radius = 0.6;
    d.environment.image = band_limited_sky(64, 32);
    const Scene scene(d);
    const RenderResult truth = pixel_centre_truth(scene, 16);
    const RealtimeLighting lighting = testscenes::one_material_lighting(scene, 3, "octa:5", 256);
    const Decomposition dec = decompose_error(scene, truth, lighting, small_options());
    // The sphere's normals fall between the 5x5 grid's nodes; the view differs off-centre.
    EXPECT_GT(dec.by_bands[2].grid_interpolation, 1e-3);
    EXPECT_GT(dec.fixed_view, 1e-3);
    // M0 is render_realtime at pixel centres (float image against double sums: a few
    // roundings of 6e-8 relative).
    EXPECT_NEAR(dec.by_bands[2].total, realtime_vs_truth(scene, lighting, truth), 1e-6);
}

TEST(Decompose, SphereShadowingAPatchUnderAConstantSkyIsVisibilityOnly) {
    // Lambert everywhere, a constant sky: SH at 1 band is exact for every normal, so the whole
    // error is the shadow (and inter-reflection) the model does not see.
    SurfaceMaterial white;
    white.name = "white";
    white.brdf.specular = brdf::Model::kLambert;
    white.brdf.albedo = {0.7, 0.7, 0.7};
    SceneDesc d = testscenes::patch_scene(white, 8);
    ObjectSpec ball;
    ball.shape.kind = ShapeKind::kSphere;
    ball.shape.center = {0, 0, 0.45};
    ball.shape.radius = 0.3;
    ball.material = "white";
    d.objects.push_back(ball);
    d.environment.radiance = {1, 1, 1};
    const Scene scene(d);
    const RenderResult truth = pixel_centre_truth(scene, 1024);
    RealtimeLighting lighting = testscenes::one_material_lighting(scene, 3, "octa:3", 64);
    const Decomposition dec = decompose_error(scene, truth, lighting, small_options());
    for (const auto& b : dec.by_bands) {
        EXPECT_LT(b.sh_truncation_diffuse, kPixelation) << b.sh_bands;  // the midpoint rule
        EXPECT_EQ(b.sh_truncation_specular, 0.0);
        EXPECT_EQ(b.grid_interpolation, 0.0);
    }
    EXPECT_GT(dec.visibility, 5 * dec.truth_noise);
    // M0 and M3 differ by the exact integral's midpoint rule only.
    EXPECT_NEAR(dec.by_bands[0].total, dec.exact_vs_truth, kPixelation);
}

TEST(Decompose, RejectsWhatItCannotDo) {
    SceneDesc d = testscenes::patch_scene(ggx("ggx"), 4);
    const Scene scene(d);
    const RenderResult truth = pixel_centre_truth(scene, 2);
    const RealtimeLighting lighting = testscenes::one_material_lighting(scene, 2, "octa:3", 64);
    DecomposeOptions o = small_options();  // 3 bands, the lighting has 2
    EXPECT_THROW(decompose_error(scene, truth, lighting, o), UsageError);
    o.max_bands = 2;
    EXPECT_THROW(decompose_error(scene, truth, RealtimeLighting{lighting.coeffs, {}, {}}, o),
                 UsageError);
}

// A sky of 1 with a disc of radiance 200 (radius 8 deg, theta 40 deg) rasterised at pixel
// centres, and the disc's light as the extraction fits it (envmap/lights.h): flux Phi = sum
// (L - 1) Omega, first moment V = sum (L - 1) Omega w, direction V / |V|, radius from
// |V| / Phi = (1 + cos alpha) / 2. The residual (disc set to the sky) is uniform.
struct SunOnASky {
    image::Image map, residual;
    envmap::DirectionalLight light;
    SunOnASky(int w, int h) : map(w, h, 3), residual(w, h, 3) {
        const Eigen::Vector3d sun(std::sin(0.7) * std::cos(0.5), std::sin(0.7) * std::sin(0.5),
                                  std::cos(0.7));
        Eigen::Vector3d v = Eigen::Vector3d::Zero();
        double phi = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const Eigen::Vector3d d = latlong_direction((x + 0.5) / w, (y + 0.5) / h);
                const bool in = d.dot(sun) >= std::cos(8 * kPi / 180);
                for (int c = 0; c < 3; ++c) {
                    map.at(x, y, c) = in ? 200.f : 1.f;
                    residual.at(x, y, c) = 1.f;
                }
                if (in) {
                    const double omega = latlong_pixel_solid_angle(y, w, h);
                    phi += 199 * omega;
                    v += 199 * omega * d;
                }
            }
        light.direction = v.normalized();
        light.flux = Eigen::Vector3d::Constant(phi);
        light.angular_radius = std::acos(2 * v.norm() / phi - 1);
        light.shading = envmap::LightShading::kCap;
    }
};

TEST(Decompose, SunAsAnExactCapLeavesTheResidualsTruncationAndTheFirstModelIsTheRealtimeOne) {
    const SunOnASky sky(256, 128);
    for (const bool specular : {false, true}) {
        SurfaceMaterial m = ggx("m");
        if (!specular) m.brdf.specular = brdf::Model::kLambert;
        SceneDesc d = testscenes::patch_scene(m, 6);
        d.environment.image = sky.map;
        const Scene scene(d);
        SceneDesc dr = d;
        dr.environment.image = sky.residual;
        const Scene residual_scene(dr);
        const RenderResult truth = pixel_centre_truth(scene, 64);
        RealtimeLighting lit = testscenes::one_material_lighting(residual_scene, 3, "octa:9", 256);
        lit.lights = {sky.light};
        DecomposeOptions o = small_options();
        o.map_height = 128;  // the map itself: M2 sums the disc's pixels as they are
        const Decomposition dec = decompose_error(scene, truth, lit, o);
        EXPECT_EQ(dec.lights, 1);
        // The model shades the light as the exact cap does: nothing between M1 and M1x.
        EXPECT_EQ(dec.light_shading_diffuse, 0.0);
        // The patch's normal (+z) sees the whole disc, so the cap's irradiance n.V (|V| /
        // Phi = (1 + cos alpha) / 2 makes Snyder's closed form n.V there) equals the disc's
        // pixel sum: the diffuse truncation is the uniform residual's, one band exact up to
        // the midpoint rule over 128 rows, (pi / 128)^2 / 24 = 2.5e-5 of pi; 1e-4 bounds it.
        for (const auto& b : dec.by_bands)
            EXPECT_LT(b.sh_truncation_diffuse, 1e-4) << b.sh_bands << " bands";
        // Without the light (pure SH of the map) 3 bands leave the sun's ringing.
        const Decomposition pure = decompose_error(
            scene, truth, testscenes::one_material_lighting(scene, 3, "octa:9", 256), o);
        EXPECT_GT(pure.by_bands[2].sh_truncation_diffuse, 30 * 1e-4);  // measured 7e-3
        if (specular) {  // the lobe at the cap's centre is not its integral over the cap
            EXPECT_GT(dec.light_shading_specular, 1e-4);
        } else {
            EXPECT_EQ(dec.light_shading_specular, 0.0);
        }
        // M0 is render_realtime with the light, at pixel centres (as above: 1e-6).
        EXPECT_NEAR(dec.by_bands[2].total, realtime_vs_truth(scene, lit, truth), 1e-6);
    }
}

TEST(CapSpecularExact, MatchesAFineQuadratureAndTendsToTheLobeAtTheCentre) {
    brdf::Material m = ggx("m").brdf;
    const Eigen::Vector3d n(0, 0, 1), view = Eigen::Vector3d(0.3, 0, 1).normalized();
    envmap::DirectionalLight l;
    l.flux = {2, 1.5, 1};
    // A cap astride the lobe and one crossing n's horizon (the max(0, n.w) kink inside it).
    for (const double theta : {0.3, 1.5}) {
        l.direction = Eigen::Vector3d(-std::sin(theta), 0.1, std::cos(theta)).normalized();
        l.angular_radius = 10 * kPi / 180;
        // Independent reference: a theta-phi grid about the cap's axis with sin-theta weights,
        // 2000 x 2000 cells (midpoint error ~ (alpha / 2000)^2, far below the tolerance).
        const Eigen::Vector3d d = l.direction, t1 = d.unitOrthogonal(), t2 = d.cross(t1);
        const Eigen::Matrix3d lw = brdf::world_from_local(n).transpose();
        Eigen::Vector3d ref = Eigen::Vector3d::Zero();
        const int nt = 2000, np = 2000;
        const double a = l.angular_radius;
        for (int i = 0; i < nt; ++i) {
            const double th = a * (i + 0.5) / nt;
            for (int j = 0; j < np; ++j) {
                const double ph = 2 * kPi * (j + 0.5) / np;
                const Eigen::Vector3d w =
                    std::cos(th) * d + std::sin(th) * (std::cos(ph) * t1 + std::sin(ph) * t2);
                const double c = n.dot(w);
                if (c <= 0) continue;
                ref += brdf::eval_specular(m, lw * view, lw * w) * c * std::sin(th) *
                       (a / nt) * (2 * kPi / np);
            }
        }
        ref = l.flux.cwiseProduct(ref) / (2 * kPi * (1 - std::cos(a)));
        const Eigen::Vector3d got = cap_specular_exact(l, n, view, m);
        // 24 x 48 cells: the midpoint rule on a lobe ~17 deg wide over 0.4-degree rings errs
        // ~(0.4 / 17)^2 / 24 = 2e-5; the horizon kink over a 7.5-degree sector, at most the
        // kinked cells' share, 2 / 48 of the rings' width squared: 1e-3 relative bounds both.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c] / ref[c], 1.0, 1e-3) << "theta " << theta << " channel " << c;
    }
    // Radius 0: the lobe at the centre times Phi max(0, n.d), what the model shades.
    l.angular_radius = 0;
    l.direction = Eigen::Vector3d(-0.3, 0.1, 1).normalized();
    const Eigen::Vector3d lobe = envmap::light_specular(l, n, view, m);
    EXPECT_LT((cap_specular_exact(l, n, view, m) - lobe).norm(), 1e-12 * lobe.norm());
    // Lambert: no lobe.
    m.specular = brdf::Model::kLambert;
    EXPECT_EQ(cap_specular_exact(l, n, view, m), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace inlight::render
