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
    d.materials.push_back(ggx("ggx"));
    ObjectSpec o;
    o.shape.kind = ShapeKind::kSphere;
    o.shape.radius = 0.6;
    o.material = "ggx";
    d.objects.push_back(o);
    d.environment.image = band_limited_sky(64, 32);
    const Scene scene(d);
    const RenderResult truth = pixel_centre_truth(scene, 16);
    const RealtimeLighting lighting = testscenes::one_material_lighting(scene, 3, "octa:5", 256);
    const Decomposition dec = decompose_error(scene, truth, lighting, small_options());
    // The sphere's normals fall between the 5x5 grid's nodes; the view differs off-centre.
    EXPECT_GT(dec.by_bands[2].grid_interpolation, 1e-3);
    EXPECT_GT(dec.fixed_view, 1e-3);
    // M0 is render_realtime at pixel centres: its error against the truth, computed here.
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
    // Float image against double sums: a few roundings of 6e-8 relative.
    EXPECT_NEAR(dec.by_bands[2].total, std::sqrt(sum / static_cast<double>(n)) / mean, 1e-6);
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

}  // namespace
}  // namespace inlight::render
