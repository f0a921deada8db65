#include "render/btf_capture.h"

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "btf/dataset.h"
#include "core/conventions.h"
#include "core/parallel.h"
#include "testing/testing.h"

namespace inlight::render {
namespace {

/// Embree intersects in float: a hit normal's direction is good to ~1e-6, so a cosine is too;
/// images are stored as float.
constexpr double kFloatTol = 1e-5;

std::shared_ptr<const weave::Weave> make_weave(const std::string& toml) {
    return std::make_shared<weave::Weave>(weave::build(weave::parse_weave(toml, "test.toml")));
}

/// A matte (Lambertian) fabric: radiance = albedo E cos / pi, so with E = pi the image reads
/// albedo * cos(theta_l) where a yarn's top (normal +z) is lit.
const char* kMatteSingle = R"(
pattern = "matrix"
matrix = "1"
spacing_mm = 1.0
yarn_radius_mm = 0.3
warp_albedo = [0.8, 0.4, 0.2]
weft_albedo = [0.2, 0.6, 0.9]
backing_albedo = [1, 1, 1]
[material]
specular = "lambert"
)";

const char* kMattePlainGaps = R"(
pattern = "plain"
spacing_mm = 1.0
yarn_radius_mm = 0.2
crimp_mm = 0.2
warp_albedo = 0.5
weft_albedo = 0.5
backing_albedo = 1
[material]
specular = "lambert"
)";

CaptureOptions direct_only(int size) {
    CaptureOptions o;
    o.width_px = o.height_px = size;
    o.spp = 1;
    o.max_depth = 1;  // direct light only: deterministic with no jitter
    o.jitter = false;
    return o;
}

TEST(BtfCapture, TopOfAStraightYarnReadsAlbedoTimesCosine) {
    // The single-thread weave: one straight warp at x = 0.5 mm over one straight weft. Its top
    // line (normal +z, above everything) is lit unshadowed from any direction above the plane.
    // 15 px over 1 mm: column 7's centre is x = 0.5 exactly.
    const CaptureScene cs(make_weave(kMatteSingle), direct_only(15), 75);
    const Eigen::Vector3d warp(0.8, 0.4, 0.2);
    for (const btf::Direction l : {btf::Direction{0, 0}, btf::Direction{60, 0},
                                   btf::Direction{60, 90}, btf::Direction{75, 200}}) {
        const ViewCapture vc = capture_view(cs, {0, 0}, 0, {l});
        const double cos_l = std::cos(l.theta_deg * kPi / 180);
        for (int row = 0; row < 15; ++row) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(vc.radiance[0].at(7, row, c), warp[c] * cos_l, kFloatTol)
                    << "light " << l.theta_deg << "/" << l.phi_deg << " row " << row;
            }
        }
        EXPECT_EQ(vc.primary_misses, 0);
    }
}

TEST(BtfCapture, GapsShowTheBackingAndGrazingLightShadowsThem) {
    // A plain weave with 0.6 mm gaps between 0.4 mm yarns (2 x 2 threads, 2 mm repeat). With the
    // window shifted by 1/8 mm, pixel (3, 4) of 8 x 8 looks straight down at the gap centre
    // (1, 1) mm and sees the white backing plate: lit from the normal it reads 1. From theta 75
    // over +x the shadow ray rises 0.27 mm per mm and meets the warp at x = 1.5 (whose tube
    // spans z = -0.2..0.2 between crossings), so the plate is in shadow: exactly 0.
    CaptureOptions o = direct_only(8);
    o.origin_mm = {0.125, 0.125};
    const CaptureScene cs(make_weave(kMattePlainGaps), o, 75);
    const ViewCapture vc = capture_view(cs, {0, 0}, 0, {{0, 0}, {75, 0}});
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(vc.radiance[0].at(3, 4, c), 1.0, kFloatTol);
        EXPECT_EQ(vc.radiance[1].at(3, 4, c), 0.0f);
    }
    EXPECT_GT(vc.primary_backing, 0);
}

TEST(BtfCapture, LightBehindTheSampleGivesBlackNotNoise) {
    CaptureOptions o;
    o.width_px = o.height_px = 8;
    o.spp = 4;
    const CaptureScene cs(make_weave(kMattePlainGaps), o, 75);
    const ViewCapture vc = capture_view(cs, {30, 0}, 0, {{90, 0}, {120, 45}, {30, 180}});
    for (int k = 0; k < 2; ++k) {
        for (float v : vc.radiance[static_cast<size_t>(k)].pixels) EXPECT_EQ(v, 0.0f) << k;
        EXPECT_TRUE(std::isnan(vc.rel_error[static_cast<size_t>(k)]));
    }
    double sum = 0;
    for (float v : vc.radiance[2].pixels) sum += v;
    EXPECT_GT(sum, 0);
}

TEST(BtfCapture, InterReflectionAddsLight) {
    // Paths past the first vertex only add (radiance >= 0): the full image must be brighter than
    // direct light alone, by far more than its noise (white yarns inter-reflect strongly).
    const auto w = make_weave(R"(
pattern = "plain"
spacing_mm = 0.5
yarn_radius_mm = 0.25
warp_albedo = 0.95
weft_albedo = 0.95
[material]
specular = "lambert"
)");
    CaptureOptions full;
    full.width_px = full.height_px = 8;
    full.spp = 16;
    CaptureOptions direct = full;
    direct.max_depth = 1;
    const ViewCapture a = capture_view(CaptureScene(w, full, 75), {45, 0}, 0, {{45, 180}});
    const ViewCapture b = capture_view(CaptureScene(w, direct, 75), {45, 0}, 0, {{45, 180}});
    double sa = 0, sb = 0;
    for (size_t i = 0; i < a.radiance[0].pixels.size(); ++i) {
        sa += a.radiance[0].pixels[i];
        sb += b.radiance[0].pixels[i];
    }
    // The same camera paths (same seeds): full = direct + indirect, indirect >= 0, per pixel.
    for (size_t i = 0; i < a.radiance[0].pixels.size(); ++i)
        EXPECT_GE(a.radiance[0].pixels[i], b.radiance[0].pixels[i] - kFloatTol);
    // a.rel_error is the per-pixel relative noise; pixels are independent, so the image sum's
    // standard error is rel_error * sum / sqrt(pixels): demand a gain of 5 of those.
    ASSERT_TRUE(std::isfinite(a.rel_error[0]));
    const double pixels = a.radiance[0].pixel_count();
    EXPECT_GT(sa - sb, 5 * a.rel_error[0] * sa / std::sqrt(pixels));
    EXPECT_GT(a.shadow_rays, b.shadow_rays);
}

TEST(BtfCapture, ImagesTileWithoutASeam) {
    // The window shifted by half a repeat must show the same image rolled by half its size:
    // geometry and rays are periodic. Direct light, pixel centres: no sampling noise; the only
    // difference is float rounding of the shifted coordinates, which can flip a ray that grazes
    // a silhouette within ~1e-6 mm (probability ~1e-5 per pixel): allow 1% of pixels to differ.
    const auto w = make_weave(R"(
pattern = "twill"
twill = [2, 1]
spacing_mm = 0.5
yarn_radius_mm = 0.2
warp_albedo = [0.7, 0.3, 0.2]
weft_albedo = [0.2, 0.3, 0.7]
[material]
specular = "ggx"
alpha = 0.3
)");
    const int n = 24;  // 3 threads per repeat: 8 px per thread
    CaptureOptions a = direct_only(n), b = direct_only(n);
    b.origin_mm = {0.5 * w->period_x_mm, 0.5 * w->period_y_mm};
    const btf::Direction view{45, 30}, light{60, 200};
    const ViewCapture ia = capture_view(CaptureScene(w, a, 60), view, 0, {light});
    const ViewCapture ib = capture_view(CaptureScene(w, b, 60), view, 0, {light});
    int differ = 0;
    double mean = 0;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            // b's pixel (x, y) is a's pixel (x + n/2, y - n/2): +x right, image y down = -y.
            const int xa = (x + n / 2) % n, ya = (y + n / 2) % n;
            for (int c = 0; c < 3; ++c) {
                const double va = ia.radiance[0].at(xa, ya, c), vb = ib.radiance[0].at(x, y, c);
                mean += va;
                if (std::abs(va - vb) > 1e-4) ++differ;
            }
        }
    }
    EXPECT_GT(mean, 0);
    EXPECT_LE(differ, n * n * 3 / 100);
}

TEST(BtfCapture, GrazingLightAndViewAndTouchingYarns) {
    // theta 75 for both, yarns touching (radius = spacing / 2): every camera ray finds the
    // fabric within the margin, images are finite and non-negative, and the noise is measured.
    const auto w = make_weave(R"(
pattern = "satin"
satin = [5, 2]
spacing_mm = 0.4
yarn_radius_mm = 0.2
[material]
specular = "charlie"
alpha = 0.5
)");
    CaptureOptions o;
    o.width_px = o.height_px = 10;
    o.spp = 8;
    const CaptureScene cs(w, o, 75);
    const ViewCapture vc = capture_view(cs, {75, 0}, 3, {{75, 0}, {75, 180}, {75, 90}});
    EXPECT_EQ(vc.primary_misses, 0);
    for (size_t k = 0; k < 3; ++k) {
        double sum = 0;
        for (float v : vc.radiance[k].pixels) {
            ASSERT_TRUE(std::isfinite(v));
            ASSERT_GE(v, 0.0f);
            sum += v;
        }
        EXPECT_GT(sum, 0) << k;
        EXPECT_TRUE(std::isfinite(vc.rel_error[k])) << k;
    }
}

TEST(BtfCapture, SameImagesForAnyThreadCount) {
    const auto w = make_weave(kMattePlainGaps);
    CaptureOptions o;
    o.width_px = o.height_px = 12;
    o.spp = 3;
    o.tile_px = 4;
    const CaptureScene cs(w, o, 60);
    parallel::set_thread_count(1);
    const ViewCapture one = capture_view(cs, {30, 60}, 2, {{15, 0}, {45, 100}});
    parallel::set_thread_count(2);
    const ViewCapture two = capture_view(cs, {30, 60}, 2, {{15, 0}, {45, 100}});
    parallel::set_thread_count(0);
    for (size_t k = 0; k < 2; ++k) EXPECT_EQ(one.radiance[k].pixels, two.radiance[k].pixels);
}

TEST(BtfCapture, WritesUbo2003FoldersTheBtfReaderOpens) {
    const auto w = make_weave(kMattePlainGaps);
    CaptureOptions o;
    o.width_px = o.height_px = 6;
    o.spp = 2;
    const CaptureScene cs(w, o, 45);
    const std::vector<btf::Direction> lights = {{0, 0}, {30, 90}, {45, 200}};
    const std::vector<btf::Direction> views = {{0, 0}, {15, 60}};
    const std::string dir = testing::temp_dir("btf_capture") + "/out";
    const CaptureResult r = capture_btf(cs, full_jobs(views, lights), dir, {});
    EXPECT_EQ(r.images, 6);
    EXPECT_GT(r.images_per_s, 0);
    const std::string base = testing::temp_dir("btf_capture_dirs");
    std::ofstream(base + "/l.txt") << "0 0\n30 90\n45 200\n";
    std::ofstream(base + "/v.txt") << "0 0\n15 60\n";
    btf::OpenOptions oo;
    oo.light_directions = base + "/l.txt";
    oo.view_directions = base + "/v.txt";
    const auto btf = btf::FolderBtf::open(dir, oo);
    ASSERT_EQ(btf->shape().n_lights(), 3);
    ASSERT_EQ(btf->shape().width, 6);
    EXPECT_NE(btf->index().files[0].find("tv000_pv000/tl000 pl000 tv000 pv000.png"),
              std::string::npos)
        << btf->index().files[0];
    // 8-bit sRGB round trip of one image: within half a code step of the encoded value.
    const ViewCapture vc = capture_view(cs, views[1], 1, lights);
    const image::Image back = btf->read_image(2, 1);
    for (size_t i = 0; i < back.pixels.size(); ++i) {
        const double v = std::min(1.0f, vc.radiance[2].pixels[i]);
        // d(linear)/d(code) <= 1/255 * 2.4 * ... the sRGB slope is at most ~3.3 / 255 near 1.
        EXPECT_NEAR(back.pixels[i], v, 0.5 * 3.3 / 255) << i;
    }
}

TEST(BtfCapture, PairsGroupByView) {
    const std::vector<btf::DirectionPair> pairs = {
        {{0, 0}, {15, 0}}, {{30, 0}, {45, 10}}, {{12.5, 3}, {15, 0}}};
    const auto jobs = pair_jobs(pairs);
    ASSERT_EQ(jobs.size(), 2u);
    EXPECT_EQ(jobs[0].lights.size(), 2u);
    EXPECT_EQ(jobs[0].lights[1].theta_deg, 12.5);
    EXPECT_EQ(jobs[1].view.phi_deg, 10);
}

}  // namespace
}  // namespace inlight::render
