#include "btf/sh_lighting.h"

#include <cmath>

#include <gtest/gtest.h>

#include "btf/compressed.h"
#include "btf/pca_run.h"
#include "btf/synthetic.h"
#include "core/conventions.h"
#include "core/error.h"
#include "sh/sh.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

constexpr double kDeg = kPi / 180;

/// sum_k A(k, j) w_k for light weights w.
double weighted_column(const Eigen::MatrixXd& a, int j, const std::vector<double>& w) {
    double s = 0;
    for (Eigen::Index k = 0; k < a.rows(); ++k) s += a(k, j) * w[static_cast<size_t>(k)];
    return s;
}

TEST(ShLightWeights, CosineRuleGivesTheIrradianceAtTheNormal) {
    // Under the cosine rules a Lambertian BTF (btf_k = albedo / pi cos(theta_k)) reflects
    // sum_k W_k cos(theta_k) = integral over the hemisphere of L cos = E(+z): so
    // sum_k A(k, j) cos(theta_k) = A_l Y_j(+z) (Ramamoorthi and Hanrahan's A_l), in closed form;
    // for the cells (cosine) and the triangles (cosine-barycentric), on the dome and with its
    // horizon rings.
    for (const CellRule rule : {CellRule::kCosine, CellRule::kCosineBarycentric}) {
        for (const auto* set : {&ubo2003_dome(), &ubo2003_horizon_dome()}) {
            const std::vector<Direction>& dome = *set;
            DomeLightingOptions opt;
            opt.rule = rule;
            std::vector<double> cos_k;
            for (const Direction& d : dome) cos_k.push_back(std::cos(d.theta_deg * kDeg));
            for (const auto& [bands, height, tol] : {std::tuple{3, 256, 2e-4}, {9, 128, 2e-3}}) {
                // Tolerances: the map path's midpoint rule per pixel, error ~ (pi / h)^2 / 24 |Y''| with
                // |Y''| ~ l^2 (2e-4 at l = 2, h = 256; 2e-3 at l = 8, h = 128), of |A_0 Y_0| = 0.886.
                const Eigen::MatrixXd a = sh_light_weight_matrix(dome, bands, opt, height);
                ASSERT_EQ(a.rows(), static_cast<Eigen::Index>(dome.size()));
                ASSERT_EQ(a.cols(), sh::count(bands));
                const std::vector<double> y = sh::eval(bands, Eigen::Vector3d(0, 0, 1));
                for (int l = 0; l < bands; ++l) {
                    for (int m = -l; m <= l; ++m) {
                        const int j = sh::index(l, m);
                        EXPECT_NEAR(weighted_column(a, j, cos_k), sh::cosine_zonal(l) * y[static_cast<size_t>(j)], tol)
                            << to_string(rule) << " " << dome.size() << " lights, bands " << bands << " l " << l << " m " << m;
                    }
                }
            }
        }
    }
}

TEST(ShLightWeights, ConstantRuleIntegratesTheBasisOverTheHemisphere) {
    // Cells partition the hemisphere: sum_k A(k, j) = integral of Y_j over z > 0, i.e.
    // sqrt(pi) for Y_00, pi sqrt(3 / (4 pi)) for Y_10, and 0 for every m != 0 (odd in phi).
    DomeLightingOptions constant;
    constant.rule = CellRule::kConstant;
    const Eigen::MatrixXd a = sh_light_weight_matrix(ubo2003_dome(), 3, constant, 256);
    const std::vector<double> ones(81, 1.0);
    // The equator is a row boundary of the even-height maps and Y_00 is constant: exact to
    // float rounding (the basis maps are float32, 6e-8 relative).
    EXPECT_NEAR(weighted_column(a, 0, ones), std::sqrt(kPi), 1e-6);
    // Y_10 = sqrt(3 / 4 pi) cos: each pixel holds cos at its centre where its band's mean is
    // (cos theta0 + cos theta1) / 2, (pi / h)^2 / 8 = 1.9e-5 of it at h = 256: 2.9e-5 of the
    // integral 1.535; 4e-5.
    EXPECT_NEAR(weighted_column(a, sh::index(1, 0), ones), kPi * std::sqrt(3 / (4 * kPi)), 4e-5);
    for (int j : {sh::index(1, -1), sh::index(1, 1), sh::index(2, -2), sh::index(2, 1)}) {
        // Odd in phi, pixel columns symmetric: cancels to float rounding of the basis.
        EXPECT_NEAR(weighted_column(a, j, ones), 0.0, 1e-5) << "j " << j;
    }
}

TEST(ShLightWeights, MatrixIsLinearInTheCoefficientsAsTheMapPath) {
    // W = A c equals integrating the SH map of c by the map path, to float rounding of the map.
    const std::vector<Direction>& dome = ubo2003_dome();
    DomeLightingOptions opt;
    opt.rule = CellRule::kBarycentric;
    const int h = 64;
    const Eigen::MatrixXd a = sh_light_weight_matrix(dome, 2, opt, h);
    const double c[4] = {1.0, 0.3, 0.7, -0.2};
    image::Image map(2 * h, h, 3);
    for (int row = 0; row < h; ++row) {
        for (int col = 0; col < 2 * h; ++col) {
            const std::vector<double> y = sh::eval(2, latlong_direction((col + 0.5) / (2 * h), (row + 0.5) / h));
            double v = 0;
            for (int j = 0; j < 4; ++j) v += c[j] * y[static_cast<size_t>(j)];
            for (int ch = 0; ch < 3; ++ch) map.at(col, row, ch) = static_cast<float>(v);
        }
    }
    const DomeLighting ref = integrate_dome_cells(map, dome, opt);
    for (size_t k = 0; k < dome.size(); ++k) {
        double w = 0;
        for (int j = 0; j < 4; ++j) w += a(static_cast<Eigen::Index>(k), j) * c[j];
        // float32 map values: relative 1e-7 of the cell's |integral| <= 2 pi x 1.7.
        EXPECT_NEAR(w, ref.weight[k].x(), 2e-6) << "light " << k;
    }
}

TEST(ShLightWeights, DirectionalLightOnBetweenAndBelowTheLightDirections) {
    const std::vector<Direction>& dome = ubo2003_dome();
    const Eigen::Vector3d e(3.0, 2.0, 1.0);
    // Exactly on light direction 10: the cosine ratio is 1, the whole irradiance is its own.
    const DomeLighting on = directional_light_weights(dome, dome[10].vector(), e);
    for (size_t k = 0; k < dome.size(); ++k) {
        EXPECT_LT((on.weight[k] - (k == 10 ? e : Eigen::Vector3d::Zero())).norm(), 1e-12) << k;
    }
    // Between three (the centroid of lights 1, 2 and 8's directions): barycentric weights
    // split E over the triangle's vertices and sum to it.
    DomeLightingOptions bary;
    bary.rule = CellRule::kBarycentric;
    const Eigen::Vector3d mid = (dome[0].vector() + dome[1].vector() + dome[2].vector()).normalized();
    const DomeLighting between = directional_light_weights(dome, mid, e, bary);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int touched = 0;
    for (const auto& w : between.weight) {
        sum += w;
        touched += w.norm() > 0;
    }
    EXPECT_LT((sum - e).norm(), 1e-12);
    EXPECT_LE(touched, 3);
    EXPECT_GE(touched, 2);
    // Grazing, 85-90 deg: the outer ring's cell takes E cos(theta) / cos(75 deg), which fades to
    // 0 at the horizon as on the real sample; never NaN.
    for (double theta : {85.0, 89.0, 89.99}) {
        const Eigen::Vector3d d(std::sin(theta * kDeg), 0, std::cos(theta * kDeg));
        const DomeLighting g = directional_light_weights(dome, d, e);
        Eigen::Vector3d total = Eigen::Vector3d::Zero();
        for (const auto& w : g.weight) total += w;
        EXPECT_NEAR(total.x(), 3.0 * std::cos(theta * kDeg) / std::cos(75 * kDeg), 1e-9) << theta;
    }
    // At and below the plane: nothing lit, all reported below the horizon.
    for (double z : {0.0, -0.3}) {
        const DomeLighting b = directional_light_weights(dome, Eigen::Vector3d(std::sqrt(1 - z * z), 0, z), e);
        for (const auto& w : b.weight) EXPECT_EQ(w.norm(), 0.0);
        EXPECT_EQ(b.below_horizon, e);
    }
}

TEST(ShLightWeights, SmallCapOfTheMapPathEqualsTheDirectionalLight) {
    // An independent route: a 1-degree cap of radiance L drawn into a map and integrated by the
    // map path gives W ~ L Omega cos(theta_d) / cos(theta_k) in the cell holding its centre.
    const std::vector<Direction>& dome = ubo2003_dome();
    // 2 deg from a light direction of the 30 deg ring: the cap lies inside that light's cell.
    const Direction* ring30 = nullptr;
    for (const Direction& l : dome) {
        if (std::abs(l.theta_deg - 30) < 1e-9) ring30 = &l;
    }
    ASSERT_NE(ring30, nullptr);
    const Eigen::Vector3d d = Direction{ring30->theta_deg + 1.5, ring30->phi_deg + 2.0}.vector();
    const int h = 1024;
    const double radius = 1.0 * kDeg, cos_r = std::cos(radius);
    image::Image map(2 * h, h, 3);
    double omega = 0;  // the cap as drawn (pixel centres inside it)
    for (int row = 0; row < h; ++row) {
        for (int col = 0; col < 2 * h; ++col) {
            if (latlong_direction((col + 0.5) / (2 * h), (row + 0.5) / h).dot(d) < cos_r) continue;
            for (int c = 0; c < 3; ++c) map.at(col, row, c) = 1.0f;
            omega += latlong_pixel_solid_angle(row, 2 * h, h);
        }
    }
    const DomeLighting cap = integrate_dome_cells(map, dome, {});
    const DomeLighting point = directional_light_weights(dome, d, Eigen::Vector3d::Constant(omega));
    for (size_t k = 0; k < dome.size(); ++k) {
        // The cap's cosine varies by +-sin(1 deg) tan(37 deg) ~ 1.3% across it, to first order
        // symmetric: the residual is second order, (1 deg)^2 / 2 ~ 1.5e-4 of the weight; 1e-3.
        EXPECT_NEAR(cap.weight[k].x(), point.weight[k].x(), 1e-3 * omega + 1e-12) << k;
    }
}

TEST(ShLightWeights, PerFrameComponentWeightsEqualTheCompressedShading) {
    // The per-frame path (M c per colour and view, then mean x m_0 + basis x m) against
    // CompressedBtf::combine of the light weights W = A c: the same sums in another order.
    AnalyticBtfOptions ao;
    ao.width = 10;
    ao.height = 8;
    ao.rank = 4;
    ao.views = {{0, 0}, {30, 0}, {45, 180}, {75, 90}};
    const AnalyticBtf raw(ao);
    PcaRunOptions po;
    po.output = testing::temp_dir("sh_lighting_matrix");
    po.pca.view_group_size = 2;
    po.pca.components = 3;
    po.encoding = ComponentEncoding::kExrFloat;
    compress_to_folder(raw, po, 0);
    const auto btf = CompressedBtf::open(po.output);
    const int bands = 3, count = sh::count(bands);
    const Eigen::MatrixXd a = sh_light_weight_matrix(raw.shape().lights, bands, {}, 64);
    // A lighting of 3 colours: a sky, a warm key from the side, a little from below.
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(count, 3);
    c.row(0) << 2.0, 1.8, 1.5;
    c.row(sh::index(1, 0)) << 0.9, 0.8, 0.6;
    c.row(sh::index(1, 1)) << 0.5, 0.3, 0.1;
    c.row(sh::index(2, 0)) << -0.2, -0.1, 0.0;
    c.row(sh::index(2, -2)) << 0.05, 0.1, 0.15;
    const double irradiance = kPi;
    DomeLighting w;
    for (Eigen::Index k = 0; k < a.rows(); ++k) {
        w.weight.push_back(Eigen::Vector3d(a.row(k).dot(c.col(0)), a.row(k).dot(c.col(1)), a.row(k).dot(c.col(2))));
    }
    double worst = 0, largest = 0;
    for (int v = 0; v < raw.shape().n_views(); ++v) {
        const image::Image ref = btf->combine(shading_terms(w, {v}, {1.0}, irradiance));
        const int g = btf->group_of_view(v);
        for (int ch = 0; ch < 3; ++ch) {
            const Eigen::MatrixXd m = btf->lighting_matrix(v, ch, a, irradiance);
            ASSERT_EQ(m.rows(), 1 + btf->components(g));
            ASSERT_EQ(m.cols(), count);
            const Eigen::VectorXd coeff = m * c.col(ch);
            const Eigen::VectorXd img = btf->group_mean(g).cast<double>() * coeff(0) +
                                        btf->group_basis(g).cast<double>() * coeff.tail(coeff.size() - 1);
            for (Eigen::Index p = 0; p < img.size(); ++p) {
                worst = std::max(worst, std::abs(img(p) - ref.pixels[static_cast<size_t>(p * 3 + ch)]));
                largest = std::max(largest, std::abs(img(p)));
            }
        }
    }
    ASSERT_GT(largest, 0.1);  // a lit image, not zeros on both sides
    // The reference is stored as float32: half an ulp of values <= `largest`, plus double sums.
    EXPECT_LE(worst, 1e-6 * largest) << "largest " << largest;
    // The sRGB model does not fold: refused, not silently wrong.
    PcaRunOptions ps = po;
    ps.output = testing::temp_dir("sh_lighting_matrix_srgb");
    ps.fit_space = FitSpace::kSrgb;
    compress_to_folder(raw, ps, 0);
    EXPECT_THROW(CompressedBtf::open(ps.output)->lighting_matrix(0, 0, a, irradiance), Error);
}

TEST(ShLightWeights, RefusesBadArguments) {
    EXPECT_THROW(sh_light_weight_matrix(ubo2003_dome(), 10), Error);
    EXPECT_THROW(sh_light_weight_matrix(ubo2003_dome(), 3, {}, 8), Error);
    EXPECT_THROW(directional_light_weights(ubo2003_dome(), Eigen::Vector3d(0, 0, 2), Eigen::Vector3d::Ones()), Error);
    EXPECT_THROW(directional_light_weights(ubo2003_dome(), Eigen::Vector3d(0, 0, 1),
                                           Eigen::Vector3d(NAN, 0, 0)),
                 Error);
}

}  // namespace
}  // namespace inlight::btf
