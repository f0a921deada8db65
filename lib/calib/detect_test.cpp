#include "calib/detect.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "calib/corner_file.h"
#include "core/error.h"
#include "image/image.h"
#include "core/fs.h"
#include "testing/testing.h"

namespace inlight::calib {
namespace {

CameraModel camera() {
    CameraModel m = CameraModel::make(ModelType::kFisheye, 640, 480, 160.0, 160.0, 319.5, 239.5);
    m.distortion = {0.02, -0.01, 0.003, -0.0007};
    return m;
}

Eigen::Isometry3d facing(double dist, const BoardSpec& b) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    t.translation() = Eigen::Vector3d(0, 0, dist) -
                      t.linear() * Eigen::Vector3d(4 * b.square_size_m, 2.5 * b.square_size_m, 0);
    return t;
}

TEST(Detect, FindsRenderedBoardToSubPixel) {
    // Sub-pixel: a fifth of a pixel RMS, no corner off by more than 0.3 px. (Measured on this
    // render, 18 px squares without blur: classic 0.12 px RMS / 0.21 max, sb 0.04 / 0.10; the
    // bias of both is what fronto-parallel refinement removes, see refine.h.)
    // The board is found either way round (a 180-degree relabelling is a rigid motion).
    constexpr double kRmsPx = 0.2;
    constexpr double kMaxPx = 0.3;
    const BoardSpec board{9, 6, 1.0};
    const CameraModel m = camera();
    const auto pose = facing(9.0, board);
    const GrayImage img = render_board(m, board, pose);
    for (Detector d : {Detector::kAuto, Detector::kClassic, Detector::kSectorBased}) {
        DetectOptions opt;
        opt.board = board;
        opt.detector = d;
        const Detection det = detect_board(img, "x.png", opt);
        ASSERT_TRUE(det.found) << to_string(d) << ": " << det.reason;
        ASSERT_EQ(det.view.image_points.size(), 54u);
        double sum[2] = {0, 0}, max[2] = {0, 0};
        for (size_t i = 0; i < 54; ++i) {
            for (int flip = 0; flip < 2; ++flip) {
                const auto truth = m.project(pose * det.view.object_points[flip ? 53 - i : i]);
                const double e = (det.view.image_points[i] - *truth).norm();
                sum[flip] += e * e;
                max[flip] = std::max(max[flip], e);
            }
        }
        const int best = sum[0] < sum[1] ? 0 : 1;
        EXPECT_LT(std::sqrt(sum[best] / 54), kRmsPx) << to_string(d);
        EXPECT_LT(max[best], kMaxPx) << to_string(d);
        RecordProperty(to_string(d) + "_rms_px", std::to_string(std::sqrt(sum[best] / 54)));
    }
}

TEST(Detect, ReportsWhyNot) {
    const BoardSpec board{9, 6, 1.0};
    DetectOptions opt;
    opt.board = board;
    GrayImage blank;
    blank.width = 320;
    blank.height = 240;
    blank.pixels.assign(320 * 240, 120);
    EXPECT_EQ(detect_board(blank, "b.png", opt).reason, "board of 9x6 inner corners not found");
    // A board with corners near the frame is rejected, not used (here "near" is made 200 px so
    // a board in the middle of a 640 x 480 frame trips it).
    const Detection ok =
        detect_board(render_board(camera(), board, facing(9.0, board)), "c.png", opt);
    ASSERT_TRUE(ok.found);
    opt.border_px = 200;
    const Detection d =
        detect_board(render_board(camera(), board, facing(9.0, board)), "c.png", opt);
    EXPECT_FALSE(d.found);
    EXPECT_NE(d.reason.find("within 200 px of the image edge"), std::string::npos) << d.reason;
}

TEST(Detect, LoadsSixteenBitAndScalesToMaximum) {
    const std::string dir = testing::temp_dir("detect_16bit");
    image::Image img(8, 4, 1, image::ColorSpace::kData);
    for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = 0.25f * (i % 4) / 3.0f;
    image::WriteOptions wo;
    wo.bits = 16;
    wo.encode_srgb = false;
    image::write_image(dir + "/a.png", img, wo);
    const GrayImage g = load_gray(dir + "/a.png");
    ASSERT_EQ(g.width, 8);
    EXPECT_EQ(g.at(3, 0), 255);  // the maximum maps to 255
    EXPECT_EQ(g.at(0, 0), 0);
    EXPECT_EQ(image_size(dir + "/a.png"), Eigen::Vector2i(8, 4));
}

TEST(Detect, InputsAndBoardSpecs) {
    EXPECT_THROW(expand_image_inputs({"/nonexistent/x.png"}), Error);
    const std::string dir = testing::temp_dir("detect_empty");
    EXPECT_THROW(expand_image_inputs({dir}), Error);
    EXPECT_THROW(parse_board("8", 1.0), UsageError);
    EXPECT_THROW(parse_board("8x1", 1.0), UsageError);
    EXPECT_THROW(parse_board("8x6", 0.0), UsageError);
    EXPECT_EQ(parse_board("8x6", 0.1).cols, 8);
    // A board too large to allocate is a usage error naming the side, not std::bad_alloc.
    EXPECT_NE(testing::error_of([] { parse_board("100000x100000", 1.0); })
                  .find("--board '100000x100000': columns: 100000 is outside [2, 1000]"),
              std::string::npos);
    EXPECT_THROW(parse_board("8x6", std::nan("")), UsageError);
    EXPECT_EQ(detector_from_string("ros"), Detector::kRos);
    EXPECT_THROW(detector_from_string("harris"), UsageError);
}

TEST(CornerFile, RoundTrip) {
    const BoardSpec board{4, 3, 0.05};
    View v;
    v.name = "a.png";
    v.object_points = board_object_points(board);
    for (size_t i = 0; i < v.object_points.size(); ++i) {
        v.image_points.emplace_back(10.125 + i, 20.0625 - 0.5 * i);
    }
    const std::string dir = testing::temp_dir("corner_file");
    write_corner_files(dir + "/i.yml", dir + "/o.yml", {v, v}, 640, 480);
    const CornerSet back = read_corner_files(dir + "/i.yml", dir + "/o.yml", BoardSpec{});
    ASSERT_EQ(back.views.size(), 2u);
    EXPECT_EQ(back.width, 640);
    EXPECT_EQ(back.height, 480);
    EXPECT_EQ(back.views[1].name, "a.png");
    EXPECT_EQ(back.views[0].image_points, v.image_points);
    EXPECT_EQ(back.views[0].object_points, v.object_points);
    // Without object points, --board supplies them; a count mismatch is an error naming it.
    EXPECT_EQ(read_corner_files(dir + "/i.yml", "", board).views[0].object_points, v.object_points);
    EXPECT_THROW(read_corner_files(dir + "/i.yml", "", BoardSpec{5, 3, 0.05}), Error);
    EXPECT_THROW(read_corner_files(dir + "/missing.yml", "", board), Error);
}

TEST(CornerFile, NonFiniteCoordinatesAreErrorsNamingThePoint) {
    const std::string dir = testing::temp_dir("corner_nan");
    for (const char* bad : {".nan", ".inf", "-.inf"}) {
        fs::write_text_atomic(dir + "/i.yml", str("%YAML:1.0\n---\nimage_width: 64\nimage_height: 48\n"
                                                  "image_0: [ 1., 2., 3., ", bad, ", 5., 6., 7., 8. ]\n"));
        const std::string msg = testing::error_of(
            [&] { read_corner_files(dir + "/i.yml", "", BoardSpec{2, 2, 0.05}); });
        EXPECT_NE(msg.find("i.yml: node image_0, point 1: "), std::string::npos) << msg;
        EXPECT_NE(msg.find("is not a finite number"), std::string::npos) << msg;
    }
    fs::write_text_atomic(dir + "/i.yml", "%YAML:1.0\n---\nimage_width: -5\nimage_0: [ 1., 2. ]\n");
    EXPECT_NE(testing::error_of([&] { read_corner_files(dir + "/i.yml", "", BoardSpec{2, 2, 1}); })
                  .find("image_width must be an integer in [1, 65536]"),
              std::string::npos);
}

}  // namespace
}  // namespace inlight::calib
