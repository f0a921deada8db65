#include "render/btf_shade.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "testing/testing.h"

namespace inlight::render {
namespace {

/// A BTF whose image of light l and view v is constant: value(l, v) per channel c is
/// (l + 1) * (c + 1) + 100 v.
class ConstantBtf : public btf::BtfSource {
  public:
    ConstantBtf(std::vector<btf::Direction> lights, std::vector<btf::Direction> views) {
        m_shape.lights = std::move(lights);
        m_shape.views = std::move(views);
        m_shape.width = 3;
        m_shape.height = 2;
    }
    const btf::BtfShape& shape() const override { return m_shape; }
    image::Image read_image(int light, int view) const override {
        image::Image img(3, 2, 3);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 3; ++x)
                for (int c = 0; c < 3; ++c)
                    img.at(x, y, c) = static_cast<float>((light + 1) * (c + 1) + 100 * view);
        return img;
    }

  private:
    btf::BtfShape m_shape;
};

TEST(BtfShade, SumsEachLightsImageTimesItsCellWeight) {
    const ConstantBtf b({{0, 0}, {45, 0}, {45, 180}}, {{0, 0}, {60, 90}});
    btf::DomeLighting lighting;
    lighting.weight = {{1, 2, 3}, {0.5, 0, 1}, {0, 0, 4}};
    const double e = 2.0;
    const image::Image img = shade_btf(b, lighting, select_views(b.shape().views, {60, 90}, 1), e);
    for (int c = 0; c < 3; ++c) {
        double want = 0;
        for (int l = 0; l < 3; ++l) want += ((l + 1) * (c + 1) + 100) * lighting.weight[size_t(l)][c] / e;
        // Float images, double sums: float rounding of values ~1e2.
        EXPECT_NEAR(img.at(2, 1, c), want, 1e-4 * want) << c;
    }
}

TEST(BtfShade, ViewSelection) {
    const std::vector<btf::Direction> views = {{0, 0}, {15, 0}, {15, 90}, {30, 0}};
    const ViewBlend exact = select_views(views, {15, 90}, 3);
    ASSERT_EQ(exact.views.size(), 1u);  // an exact match takes it alone
    EXPECT_EQ(exact.views[0], 2);
    const ViewBlend near = select_views(views, {14, 2}, 1);
    EXPECT_EQ(near.views, std::vector<int>{1});
    const ViewBlend three = select_views(views, {7.5, 0}, 3);
    ASSERT_EQ(three.views.size(), 3u);
    // 7.5 deg from both (0, 0) and (15, 0): equal weights for those two.
    EXPECT_NEAR(three.weights[0], three.weights[1], 1e-12);
    double sum = 0;
    for (double w : three.weights) sum += w;
    EXPECT_NEAR(sum, 1.0, 1e-12);
}

TEST(BtfShade, InterpolatedViewsAreTheDelaunayWeights) {
    const auto& dome = btf::ubo2003_dome();
    const btf::DelaunayInterpolator di(dome);
    const ViewBlend on = interpolate_views(di, dome[30]);  // a measured view: itself alone
    ASSERT_EQ(on.views.size(), 1u);
    EXPECT_EQ(on.views[0], 30);
    const btf::Direction off{37, 21};
    const ViewBlend b = interpolate_views(di, off);
    ASSERT_EQ(b.views.size(), 3u);
    // The blend of the three view vectors points along the query (exact barycentrics), to
    // the rounding of 3x3 determinants (1e-12).
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    double sum = 0;
    for (size_t i = 0; i < 3; ++i) {
        p += b.weights[i] * dome[size_t(b.views[i])].vector();
        sum += b.weights[i];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_LT(p.normalized().cross(off.vector()).norm(), 1e-12);
}

}  // namespace
}  // namespace inlight::render
