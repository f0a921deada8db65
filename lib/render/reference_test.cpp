// Tests of render/reference.h: the brute-force irradiance against the closed form of a uniform
// upper-hemisphere sky, the exact Lambert-sphere image, its refusals, and the convergence
// study's error metrics against references whose answer is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/conventions.h"
#include "core/error.h"
#include "image/image.h"
#include "render/path_tracer.h"
#include "render/reference.h"
#include "render/render_testing.h"
#include "testing/testing.h"

namespace inlight::render {
namespace {

/// A lat-long map of 1 on the upper hemisphere (rows with theta < 90 deg) and 0 below: the
/// boundary falls on a row edge, so the map is exactly the hemisphere and
/// E(n) = pi (1 + n_z) / 2 (the clamped cosine over a uniform half sky).
image::Image upper_sky(int w, int h) {
    image::Image img(w, h, 3);
    for (int row = 0; row < h / 2; ++row)
        for (int col = 0; col < w; ++col)
            for (int c = 0; c < 3; ++c) img.at(col, row, c) = 1.0f;
    return img;
}

double upper_sky_irradiance(const Eigen::Vector3d& n) { return kPi * (1 + n.z()) / 2; }

/// The midpoint rule on 0.7-degree cells cut by the horizon (reference.h, kMaxCellDeg).
constexpr double kQuadratureRel = 1e-4;

SceneDesc sphere_scene(int px, const std::string& model) {
    SceneDesc d = testscenes::base_scene(px);
    d.environment.image = upper_sky(64, 32);
    SurfaceMaterial m;
    m.name = "m";
    m.brdf.specular = brdf::model_from_string(model);
    m.brdf.albedo = {0.8, 0.5, 0.3};
    return testscenes::with_object(d, m, ShapeKind::kSphere);
}

TEST(BruteForceIrradiance, UpperSkyClosedForm) {
    const EnvironmentLight env(upper_sky(64, 32), Eigen::Matrix3d::Identity(), 1.0, "sky");
    ASSERT_EQ(brute_force_subdivision(32), 8);  // 5.625-degree pixels -> 0.70-degree cells
    for (double theta_deg : {0.0, 20.0, 45.0, 77.0, 90.0, 120.0, 160.0, 180.0}) {
        for (double phi_deg : {0.0, 33.0, 200.0}) {
            const Eigen::Vector3d n =
                direction_from_spherical(theta_deg * kPi / 180, phi_deg * kPi / 180);
            const Eigen::Vector3d e = brute_force_irradiance(env, n, 8);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(e[c], upper_sky_irradiance(n), kQuadratureRel * kPi)
                    << "theta " << theta_deg << " phi " << phi_deg;
            }
        }
    }
}

TEST(BruteForceIrradiance, TableEqualsTheCellByCellSum) {
    // A random map (values in [-0.1, 5]: the blender EXRs hold slightly negative pixels),
    // rotated so that no axis is special, against the direct sum over every cell.
    const image::Image img = testing::random_image<image::Image>(48, 24, 3, -0.1f, 5.0f, 7u,
                                                                 image::ColorSpace::kLinearSrgb);
    const EnvironmentLight env(img, parse_rotation("z=70,x=-25"), 1.3, "random");
    std::mt19937 rng(11);
    std::normal_distribution<double> g;
    for (int sub : {1, 3}) {
        const IrradianceTable table(env, sub);
        std::vector<Eigen::Vector3d> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}};
        for (int i = 0; i < 40; ++i) normals.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
        for (const auto& n : normals) {
            const Eigen::Vector3d direct = brute_force_irradiance(env, n, sub);
            // Rounding of ~1e5 cell sums in double (prefix differences lose ~1e-13 relative).
            constexpr double kRoundingRel = 1e-10;
            EXPECT_LT((table.irradiance(n) - direct).norm(), kRoundingRel * (1 + direct.norm()))
                << "sub " << sub << " n " << n.transpose();
        }
    }
}

TEST(BruteForceIrradiance, Subdivision) {
    EXPECT_EQ(brute_force_subdivision(512), 1);  // 0.35-degree pixels
    EXPECT_EQ(brute_force_subdivision(256), 1);  // 0.70 degrees exactly
    EXPECT_EQ(brute_force_subdivision(128), 2);
    EXPECT_EQ(brute_force_subdivision(1), 254);
}

TEST(IrradianceReference, LambertSphereClosedForm) {
    constexpr int kPx = 24;
    const Scene scene(sphere_scene(kPx, "lambert"));
    const ConvergenceReference ref = irradiance_reference(scene);
    EXPECT_EQ(ref.kind, "brute_force_irradiance");
    const Eigen::Vector3d albedo(0.8, 0.5, 0.3);
    int on_sphere = 0;
    for (int y = 0; y < kPx; ++y) {
        for (int x = 0; x < kPx; ++x) {
            // Orthographic view down -z of a unit-diameter sphere: the pixel centre's distance
            // from the axis gives the normal's z.
            const double sx = (2.0 * (x + 0.5) / kPx - 1) * 0.6, sy = (1 - 2.0 * (y + 0.5) / kPx) * 0.6;
            const double rho2 = (sx * sx + sy * sy) / 0.25;
            const size_t i = static_cast<size_t>(y) * kPx + x;
            ASSERT_EQ(ref.object_mask[i] != 0, rho2 < 1) << x << "," << y;
            for (int c = 0; c < 3; ++c) {
                const double want = rho2 < 1 ? albedo[c] / kPi *
                                                   upper_sky_irradiance({0, 0, std::sqrt(1 - rho2)})
                                             : 0.0;  // the ray escapes along -z: black
                EXPECT_NEAR(ref.radiance.at(x, y, c), want, kQuadratureRel * albedo[c] + 1e-7);
                EXPECT_EQ(ref.std_error.at(x, y, c), 0.0f);
            }
            on_sphere += rho2 < 1;
        }
    }
    EXPECT_GT(on_sphere, 200);
}

TEST(IrradianceReference, RefusesScenesWithoutAClosedForm) {
    EXPECT_THROW(irradiance_reference(Scene(sphere_scene(8, "ggx"))), UsageError);
    SceneDesc two = sphere_scene(8, "lambert");
    two.objects.push_back(two.objects[0]);
    two.objects[1].shape.center = {2, 0, 0};
    EXPECT_THROW(irradiance_reference(Scene(two)), UsageError);
    SceneDesc patch = sphere_scene(8, "lambert");
    patch.objects[0].shape.kind = ShapeKind::kPatch;
    const std::string msg = testing::error_of([&] { irradiance_reference(Scene(patch)); });
    EXPECT_NE(msg.find("one untextured Lambert sphere"), std::string::npos) << msg;
}

TEST(ConvergenceStudy, MetricsAgainstKnownReferences) {
    // BSDF sampling of a Lambert sphere under a constant sky: every path returns exactly
    // albedo x L (cosine sampling cancels the cosine), so the render equals the reference.
    SceneDesc d = sphere_scene(16, "lambert");
    d.environment.image = image::Image();
    d.environment.radiance = {1.5, 1.0, 0.5};
    const Scene scene(d);
    RenderOptions o;
    o.strategy = Strategy::kBsdf;
    o.jitter = false;
    ConvergenceReference ref = irradiance_reference(scene);
    const ConvergenceResult exact = convergence_study(scene, o, ref, {1, 4});
    ASSERT_EQ(exact.points.size(), 2u);
    EXPECT_EQ(exact.reference_kind, "brute_force_irradiance");
    for (const auto& p : exact.points) {
        EXPECT_LT(p.mean_rel_error, kQuadratureRel) << p.spp;
        EXPECT_LT(p.rel_rmse, kQuadratureRel) << p.spp;
    }
    // A reference 10% too bright: every object pixel is off by 0.1 / 1.1 of the reference.
    for (size_t i = 0; i < ref.radiance.pixels.size(); ++i)
        ref.radiance.pixels[i] *= ref.object_mask[i / 3] ? 1.1f : 1.0f;
    const ConvergenceResult off = convergence_study(scene, o, ref, {4});
    constexpr double kFloatAndQuadrature = 2e-4;  // float pixels and the quadrature bound
    EXPECT_NEAR(off.points[0].mean_rel_error, 0.1 / 1.1, kFloatAndQuadrature);
}

TEST(FileReference, NamesTheFileOnASizeMismatch) {
    const Scene scene(sphere_scene(8, "lambert"));
    const std::string dir = testing::temp_dir("file_reference");
    const std::string path = dir + "/ref.exr";
    image::write_image(path, image::Image(9, 8, 3));
    const std::string msg = testing::error_of([&] { file_reference(scene, path); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    image::Image ok(8, 8, 3);
    ok.at(3, 4, 1) = 2.5f;
    image::write_image(path, ok);
    const ConvergenceReference ref = file_reference(scene, path);
    EXPECT_EQ(ref.kind, "file");
    EXPECT_EQ(ref.radiance.at(3, 4, 1), 2.5f);
    EXPECT_EQ(ref.std_error.at(3, 4, 1), 0.0f);  // no ref_stderr.exr beside it
}

}  // namespace
}  // namespace inlight::render
