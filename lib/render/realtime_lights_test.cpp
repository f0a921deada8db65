// Tests of render/realtime_lights.h: an extracted light shaded by the real-time model equals
// brute-force integration of its uniform cap (the diffuse term exactly, the specular lobe to the
// lobe's curvature over the cap), render_realtime adds exactly that term, and the lighting file
// envmap-project writes reads back (bad lights name the file and the light).
#include "render/realtime_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "brdf/bake.h"
#include "brdf/grid.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"
#include "envmap/validate.h"
#include "render/realtime.h"
#include "render/render_testing.h"
#include "testing/testing.h"

namespace inlight::render {
namespace {

/// Brute force: the cap of `light` as a uniform radiance Phi / Omega_cap, integrated over a
/// polar grid about its centre (midpoint rule, nt x np cells) against
/// (albedo / pi + f_s(wo, w)) max(0, n.w). `view` null: the diffuse term only.
Eigen::Vector3d brute_force_cap(const envmap::DirectionalLight& light, const Eigen::Vector3d& n,
                                const brdf::Material& m, const Eigen::Vector3d* view, int nt,
                                int np) {
    const double a = light.angular_radius;
    const Eigen::Vector3d radiance = light.flux / (2 * kPi * (1 - std::cos(a)));
    const Eigen::Matrix3d cap_frame = brdf::world_from_local(light.direction);
    const Eigen::Matrix3d local_from_world = brdf::world_from_local(n).transpose();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < nt; ++i) {
        const double t = a * (i + 0.5) / nt;
        const double dw = std::sin(t) * (a / nt) * (2 * kPi / np);
        for (int j = 0; j < np; ++j) {
            const double p = 2 * kPi * (j + 0.5) / np;
            const Eigen::Vector3d w =
                cap_frame *
                Eigen::Vector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
            const double c = n.dot(w);
            if (c <= 0) continue;
            Eigen::Vector3d f = m.albedo * kInvPi;
            if (view && m.specular != brdf::Model::kLambert)
                f += brdf::eval_specular(m, local_from_world * *view, local_from_world * w);
            sum += radiance.cwiseProduct(f) * c * dw;
        }
    }
    return sum;
}

envmap::DirectionalLight light_at(double theta_deg, double phi_deg, double radius_deg) {
    envmap::DirectionalLight l;
    l.direction = direction_from_spherical(theta_deg * kPi / 180, phi_deg * kPi / 180);
    l.flux = {3.0, 2.0, 1.0};
    l.angular_radius = radius_deg * kPi / 180;
    return l;
}

TEST(ShadeLights, DiffuseIsTheBruteForceIrradianceOfTheCapOnEitherSideOfTheHorizon) {
    // A 10-degree cap: many normals see it cut by their horizon (Snyder's branch).
    const envmap::DirectionalLight l = light_at(50, 30, 10);
    brdf::Material m;
    m.specular = brdf::Model::kLambert;
    m.albedo = {0.8, 0.5, 0.2};
    // Midpoint rule on a 200 x 800 polar grid: O(h^2) with h = alpha / 200 = 8.7e-4 rad, i.e.
    // ~7.6e-7 of the flux (cells cut by n's horizon are as small, the cut being a smooth curve
    // in (t, phi)); measured worst 2.1e-7.
    constexpr double kQuadratureRel = 1e-6;
    int straddling = 0;
    for (const auto& n : envmap::validation_normals(60)) {
        const Eigen::Vector3d model = shade_lights({l}, n, m, nullptr);
        const Eigen::Vector3d ref = brute_force_cap(l, n, m, nullptr, 200, 800);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(model[c], ref[c], kQuadratureRel * l.flux[c] * m.albedo[c] * kInvPi)
                << "n " << n.transpose() << " channel " << c;
        straddling += std::abs(n.dot(l.direction)) < std::sin(l.angular_radius);
    }
    EXPECT_GT(straddling, 3);
}

TEST(ShadeLights, SpecularIsTheBruteForceLobeOverASmallCap) {
    // GGX, a sun-sized cap (0.5 deg): the model evaluates f_s at the cap's centre. Over the cap
    // f_s varies by its second derivative: relative error ~ (cap radius / lobe width)^2 / 4 =
    // (0.0087 / (2 x 0.2))^2 / 4 = 1.2e-4 at the lobe's peak, a few times more on its flanks
    // (measured worst 4.2e-4 over these normals); 1e-3 bounds it.
    constexpr double kLobeCurvatureRel = 1e-3;
    envmap::DirectionalLight l = light_at(35, -40, 0.5);
    brdf::Material m;
    m.specular = brdf::Model::kGgx;
    m.alpha = 0.2;
    m.f0 = {0.9, 0.6, 0.3};
    m.albedo = {0.3, 0.3, 0.3};
    const Eigen::Vector3d view = Eigen::Vector3d(0.2, 0.1, 1).normalized();
    const Eigen::Vector3d mirror = (l.direction + view).normalized();
    int near_peak = 0;
    for (const auto& n : envmap::validation_normals(800)) {
        if (n.dot(mirror) < std::cos(0.35) || n.dot(view) <= 0) continue;  // inside the lobe
        ++near_peak;
        const Eigen::Vector3d model = shade_lights({l}, n, m, &view);
        const Eigen::Vector3d ref = brute_force_cap(l, n, m, &view, 60, 240);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(model[c], ref[c], kLobeCurvatureRel * ref[c]) << n.transpose();
    }
    EXPECT_GT(near_peak, 10);
    // A 5-degree cap: the centre's lobe value no longer stands for the cap (the error grows
    // as the radius squared, ~100x): what a light's radius costs the specular term.
    l.angular_radius = 5 * kPi / 180;
    const Eigen::Vector3d n = mirror;
    const Eigen::Vector3d model = shade_lights({l}, n, m, &view);
    const Eigen::Vector3d ref = brute_force_cap(l, n, m, &view, 200, 800);
    EXPECT_GT(std::abs(model[1] - ref[1]), 10 * kLobeCurvatureRel * ref[1]);
    // No view: no specular term, only the diffuse part.
    EXPECT_LT(
        (shade_lights({l}, n, m, nullptr) - brute_force_cap(l, n, m, nullptr, 200, 800)).norm(),
        1e-4 * l.flux.norm());
}

using testscenes::patch_scene;

TEST(RenderRealtime, AddsTheLightsToEveryFragment) {
    SurfaceMaterial m;
    m.name = "ggx";
    m.brdf.specular = brdf::Model::kGgx;
    m.brdf.alpha = 0.3;
    m.brdf.albedo = {0.5, 0.4, 0.3};
    SceneDesc d = patch_scene(m, 4);
    d.environment.radiance = {0.5, 0.5, 0.5};
    const Scene scene(d);
    RealtimeLighting lighting = testscenes::one_material_lighting(scene, 3, "octa:5", 256);
    RealtimeOptions ro;
    ro.supersample = 1;
    const image::Image without = render_realtime(scene, lighting, ro);
    lighting.lights = {light_at(20, 10, 0.5), light_at(60, 200, 3)};
    const image::Image with = render_realtime(scene, lighting, ro);
    // The patch faces the camera: every fragment has n = +z and the table's view.
    const Eigen::Vector3d add =
        shade_lights(lighting.lights, {0, 0, 1}, m.brdf, &lighting.tables[0].view);
    // Float images of O(1) values: a few roundings of 6e-8.
    constexpr double kFloatRel = 1e-6;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(with.at(x, y, c) - without.at(x, y, c), add[c],
                            kFloatRel * with.at(x, y, c));
    EXPECT_GT(add.minCoeff(), 0.1);
    // The seed (report) mode has no light term: asking for one is a usage error.
    ro.mode = RealtimeMode::kSeed;
    EXPECT_THROW(render_realtime(scene, lighting, ro), UsageError);
}

TEST(LightingFile, ReadsWhatEnvmapProjectWritesAndNamesBadLights) {
    const std::string dir = testing::temp_dir("lighting_file");
    sh::CoefficientSet set;
    set.sh_bands = 2;
    set.coeffs = Eigen::MatrixXd::Random(4, 3);
    nlohmann::json doc = sh::to_json(set);
    fs::write_text_atomic(dir + "/pure.json", doc.dump());
    const LightingFile pure = read_lighting_file(dir + "/pure.json");
    EXPECT_TRUE(pure.lights.empty());
    EXPECT_LT((pure.sh.coeffs - set.coeffs).norm(), 1e-12);

    const envmap::DirectionalLight l = light_at(30, 60, 0.7);
    doc["lights"] = {envmap::to_json(l)};
    fs::write_text_atomic(dir + "/lit.json", doc.dump());
    const LightingFile lit = read_lighting_file(dir + "/lit.json");
    ASSERT_EQ(lit.lights.size(), 1u);
    EXPECT_LT((lit.lights[0].direction - l.direction).norm(), 1e-12);
    EXPECT_LT((lit.lights[0].flux - l.flux).norm(), 1e-12);
    EXPECT_NEAR(lit.lights[0].angular_radius, l.angular_radius, 1e-12);

    doc["lights"][0]["flux"] = {1, -1, 1};
    fs::write_text_atomic(dir + "/bad.json", doc.dump());
    EXPECT_EQ(inlight::testing::error_of([&] { read_lighting_file(dir + "/bad.json"); }),
              dir + "/bad.json: lights[0]: light flux must be >= 0");
    doc["lights"] = 3;
    fs::write_text_atomic(dir + "/bad2.json", doc.dump());
    EXPECT_EQ(inlight::testing::error_of([&] { read_lighting_file(dir + "/bad2.json"); }),
              dir + "/bad2.json: \"lights\" must be an array");
}

}  // namespace
}  // namespace inlight::render
