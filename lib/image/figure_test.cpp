#include "image/figure.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "image/color.h"
#include "image/metrics.h"
#include "testing/testing.h"

namespace inlight::image {
namespace {

TEST(Figure, ScaleIsTheSmallestIntegerReaching256Px) {
    EXPECT_EQ(figure_scale(16), 16);
    EXPECT_EQ(figure_scale(100), 3);  // 300 px: 2x would be 200
    EXPECT_EQ(figure_scale(128), 2);
    EXPECT_EQ(figure_scale(256), 1);
    EXPECT_EQ(figure_scale(1000), 1);
    EXPECT_THROW(figure_scale(0), Error);
}

// matplotlib's viridis at t = i/8, the anchors heat_map documents, sRGB-encoded 8-bit: the bar's
// expected codes are interpolated from these here, independently of heat_map's code.
constexpr int kViridis[9][3] = {{0x44, 0x01, 0x54}, {0x47, 0x2d, 0x7b}, {0x3b, 0x52, 0x8b},
                                {0x2c, 0x72, 0x8e}, {0x21, 0x91, 0x8c}, {0x28, 0xae, 0x80},
                                {0x5e, 0xc9, 0x62}, {0xad, 0xdc, 0x30}, {0xfd, 0xe7, 0x25}};

double viridis_code(double t, int c) {
    const double x = std::clamp(t, 0.0, 1.0) * 8;
    const int i = std::min(int(x), 7);
    return (1 - (x - i)) * kViridis[i][c] + (x - i) * kViridis[i + 1][c];
}

// The figure as a user opens it: written to PNG and read back as 8-bit codes (0..255).
struct Png {
    Image codes;
    int code(int x, int y, int c) const { return int(std::lround(codes.at(x, y, c) * 255)); }
};

Png written(const Image& fig, const std::string& name) {
    const std::string path = testing::temp_dir("figure") + "/" + name + ".png";
    write_image(path, fig);
    return {read_image(path, {false})};
}

TEST(Figure, PanelsAreEnlargedCaptionedAndTheBarFollowsTheHeatMapsRamp) {
    // A 16 x 16 grey panel and a heat map of a left-to-right ramp of relative error.
    Image grey(16, 16, 3, ColorSpace::kLinearSrgb), err(16, 16, 1, ColorSpace::kData);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            for (int c = 0; c < 3; ++c) grey.at(x, y, c) = 0.18f;
            err.at(x, y, 0) = 0.5f * x / 15;
        }
    const Image heat = heat_map(err, 0.5);
    const ColorBar bar{0.5, "rel. error"};
    FigureLayout L;
    const Image fig = figure("relative error, model vs path-traced truth",
                             {{&grey, "path-traced truth"}, {&heat, "relative error"}}, &bar, &L);
    const Png png = written(fig, "two_panels");
    ASSERT_EQ(png.codes.width, fig.width);
    ASSERT_EQ(png.codes.height, fig.height);

    // Size: 16 px panels enlarged 16x to 256 px, below the title and caption bands.
    EXPECT_EQ(L.scale, 16);
    EXPECT_EQ(L.panel_height_px, 256);
    EXPECT_EQ(png.codes.height, L.panels_top_px + 256 + 10);
    EXPECT_GT(png.codes.width, 2 * 256 + L.bar_width_px);

    // Nearest-neighbour: each source pixel is a 16 x 16 block of its own code.
    const int left = L.panel_left_px[1], top = L.panels_top_px;
    for (int x : {0, 7, 15})
        for (int y : {0, 15})
            for (int c = 0; c < 3; ++c) {
                const int want = int(std::lround(srgb_encode(heat.at(x, y, c)) * 255));
                EXPECT_EQ(png.code(left + 16 * x, top + 16 * y, c), want) << x << "," << y;
                EXPECT_EQ(png.code(left + 16 * x + 15, top + 16 * y + 15, c), want);
            }

    // The bar: row y shows t = 1 - (y + 0.5) / 256 of the scale, in viridis, across its width;
    // 1 code of tolerance for the float sRGB decode/encode round trip to 8 bits.
    int worst = 0;
    for (int y = 0; y < L.panel_height_px; ++y) {
        const double t = 1 - (y + 0.5) / L.panel_height_px;
        for (int x = L.bar_left_px; x < L.bar_left_px + L.bar_width_px; ++x)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(png.code(x, top + y, c) -
                                                 int(std::lround(viridis_code(t, c)))));
    }
    EXPECT_LE(worst, 1);
    // Its ends are the map's ends (top = the heat map's 0.5, bottom = 0).
    EXPECT_NEAR(png.code(L.bar_left_px, top, 0), 0xfd, 2);
    EXPECT_NEAR(png.code(L.bar_left_px, top + 255, 2), 0x54, 2);

    // Text is drawn: light pixels in the title band, above each panel, and beside the bar
    // (the max and 0 labels). The background is code 32, the text 235 anti-aliased.
    auto light = [&](int x0, int x1, int y0, int y1) {
        int n = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) n += png.code(x, y, 1) > 128 ? 1 : 0;
        return n;
    };
    EXPECT_GT(light(0, png.codes.width, 0, L.title_height_px), 100);
    for (int p : L.panel_left_px) EXPECT_GT(light(p, p + 256, L.title_height_px, top), 30);
    const int ticks = L.bar_left_px + L.bar_width_px;
    EXPECT_GT(light(ticks, png.codes.width, top, top + 20), 5);         // ">= 0.5"
    EXPECT_GT(light(ticks, png.codes.width, top + 236, top + 256), 5);  // "0"
    // ... and nowhere inside the panels' and the bar's rows left of the tick labels but panels.
    EXPECT_EQ(light(0, L.panel_left_px[0], top, top + 256), 0);
}

TEST(Figure, LargePanelsAreNotEnlargedAndMismatchedPanelsAreRefused) {
    Image a(300, 260, 3, ColorSpace::kLinearSrgb), b(300, 250, 3, ColorSpace::kLinearSrgb);
    FigureLayout L;
    const Image fig = figure("t", {{&a, "a"}}, nullptr, &L);
    EXPECT_EQ(L.scale, 1);
    EXPECT_EQ(L.bar_left_px, -1);
    EXPECT_EQ(fig.height, L.panels_top_px + 260 + 10);
    EXPECT_THROW(figure("t", {{&a, "a"}, {&b, "b"}}, nullptr), Error);
    Image one(8, 8, 1, ColorSpace::kData);
    EXPECT_THROW(figure("t", {{&one, "one channel"}}, nullptr), Error);
}

}  // namespace
}  // namespace inlight::image
