#include "btf/dome.h"

#include <cmath>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"
#include "testing/testing.h"

namespace inlight::btf {
namespace {

/// Angles are printed and parsed as decimal text with at most 3 decimals: exact to 1e-12 deg.
constexpr double kAngleTolDeg = 1e-12;

std::string write_file(const std::string& name, const std::string& text) {
    const std::string path = testing::temp_dir("btf_dome") + "/" + name;
    std::ofstream(path) << text;
    return path;
}

TEST(Ubo2003Dome, RingsAndAzimuthsOfTheBonnGrid) {
    const auto& dome = ubo2003_dome();
    ASSERT_EQ(dome.size(), 81u);
    const int counts[] = {1, 6, 12, 18, 20, 24};
    size_t i = 0;
    for (int ring = 0; ring < 6; ++ring) {
        for (int k = 0; k < counts[ring]; ++k, ++i) {
            EXPECT_EQ(dome[i].theta_deg, 15.0 * ring);
            EXPECT_NEAR(dome[i].phi_deg, 360.0 * k / counts[ring], kAngleTolDeg);
        }
    }
    // Neighbours on the 45 deg ring (18 azimuths, 20 deg apart) are the closest pair of the
    // dome: 2 asin(sin 45 sin 10) = 14.11 deg (the 75 deg ring's are 14.49). None coincide.
    double min_sep = 180;
    for (size_t a = 0; a < dome.size(); ++a)
        for (size_t b = a + 1; b < dome.size(); ++b)
            min_sep = std::min(min_sep, angle_between_deg(dome[a], dome[b]));
    const double expected = 2 * std::asin(std::sin(45 * kPi / 180) * std::sin(10 * kPi / 180));
    EXPECT_NEAR(min_sep, expected * 180 / kPi, 1e-9);
}

/// format_directions writes what read_directions reads back bit for bit (the file a capture
/// folder records its set in).
void ExpectRoundTripsThroughItsFile(const std::vector<Direction>& set, const std::string& name) {
    const std::string path = testing::temp_dir(name) + "/lights.txt";
    fs::write_text_atomic(path, format_directions(set, "test"));
    const std::vector<Direction> back = read_directions(path);
    ASSERT_EQ(back.size(), set.size());
    for (size_t i = 0; i < set.size(); ++i) {
        EXPECT_EQ(back[i].theta_deg, set[i].theta_deg);
        EXPECT_EQ(back[i].phi_deg, set[i].phi_deg);
    }
}

TEST(Ubo2003Dome, HorizonSetIsTheDomeThenRingsToTheHorizonAndRoundTripsThroughItsFile) {
    const auto& set = ubo2003_horizon_dome();
    const auto& dome = ubo2003_dome();
    ASSERT_EQ(set.size(), dome.size() + 24 * std::size(kHorizonRingThetasDeg));
    for (size_t i = 0; i < dome.size(); ++i) {  // the dome first, unchanged: its indices hold
        EXPECT_EQ(set[i].theta_deg, dome[i].theta_deg);
        EXPECT_EQ(set[i].phi_deg, dome[i].phi_deg);
    }
    for (size_t i = dome.size(); i < set.size(); ++i) {
        EXPECT_GT(set[i].theta_deg, 75.0);
        EXPECT_LT(set[i].theta_deg, 89.5);  // within 0.5 deg a direction owns no cell (lighting.h)
    }
    EXPECT_EQ(named_direction_set("ubo2003").size(), dome.size());
    EXPECT_EQ(named_direction_set("ubo2003-horizon").size(), set.size());
    EXPECT_THROW(named_direction_set("bonn"), Error);
    ExpectRoundTripsThroughItsFile(set, "dome_horizon_set");
}

TEST(FibonacciHemisphere, DirectionsHaveEqualSolidAngleDownTo89DegAndNoneRepeats) {
    const int n = 250;
    const std::vector<Direction> set = named_direction_set("fibonacci-250");
    ASSERT_EQ(set.size(), static_cast<size_t>(n));
    // The lattice's defining property: cos(theta) steps evenly from the pole to cos(89 deg), so
    // each direction stands for the same solid angle; 1e-12 is a few ulps of acos/cos.
    const double z_span = 1 - std::cos(kFibonacciMaxThetaDeg * kPi / 180);
    for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(std::cos(set[i].theta_deg * kPi / 180), 1 - double(i) / (n - 1) * z_span, 1e-12);
        EXPECT_GE(set[i].phi_deg, 0.0);
        EXPECT_LT(set[i].phi_deg, 360.0);
    }
    // The ends exactly: the frontal light (tl000 pl000, the albedo's image) and 89 deg.
    EXPECT_EQ(set.front().theta_deg, 0.0);
    EXPECT_EQ(set.front().phi_deg, 0.0);
    EXPECT_EQ(set.back().theta_deg, kFibonacciMaxThetaDeg);
    // Even spread: every direction's nearest neighbour lies between 0.5 and 1.5 times the
    // spacing of equal cells, sqrt(2 pi z_span / n) (a lattice with no clumps or holes).
    const double spacing_deg = std::sqrt(2 * kPi * z_span / n) * 180 / kPi;
    for (size_t a = 0; a < set.size(); ++a) {
        double nearest = 180;
        for (size_t b = 0; b < set.size(); ++b)
            if (a != b) nearest = std::min(nearest, angle_between_deg(set[a], set[b]));
        EXPECT_GT(nearest, 0.5 * spacing_deg) << a;
        EXPECT_LT(nearest, 1.5 * spacing_deg) << a;
    }
    ExpectRoundTripsThroughItsFile(set, "dome_fibonacci_set");
    for (const char* bad : {"fibonacci-15", "fibonacci-4097", "fibonacci-", "fibonacci-2e2",
                            "fibonacci--20", "fibonacci-00250x"})
        EXPECT_THROW(named_direction_set(bad), Error) << bad;
}

TEST(Direction, VectorFollowsTheSampleFrame) {
    // phi = 0 points along +x (image right), phi = 90 along +y (image up).
    const Eigen::Vector3d x = Direction{90, 0}.vector(), y = Direction{90, 90}.vector();
    EXPECT_NEAR((x - Eigen::Vector3d::UnitX()).norm(), 0, 1e-15);
    EXPECT_NEAR((y - Eigen::Vector3d::UnitY()).norm(), 0, 1e-15);
    const Direction d = Direction::from_vector(Direction{60, 300}.vector());
    EXPECT_NEAR(d.theta_deg, 60, 1e-12);
    EXPECT_NEAR(d.phi_deg, 300, 1e-12);
    EXPECT_EQ(Direction::from_vector(Eigen::Vector3d::UnitZ()).phi_deg, 0);
}

TEST(Ubo2003Name, WritesThreeDigitWholeDegreesAndParsesByPattern) {
    const Direction l{15, 60}, v{30, 90};
    EXPECT_EQ(ubo2003_stem(l, v), "tl015 pl060 tv030 pv090");
    EXPECT_EQ(ubo2003_view_folder(v), "tv030_pv090");
    EXPECT_EQ(ubo2003_stem({12.5, 0}, {0, 0}), "tl012.500 pl000 tv000 pv000");
    for (const std::string name :
         {"tl015 pl060 tv030 pv090.png", "00123 tl015 pl060 tv030 pv090.jpg",
          "tv030_pv090/tl015_pl060_tv030_pv090.png", "wool/TL015-PL060-TV030-PV090.exr"}) {
        const auto p = parse_ubo2003_name(name);
        ASSERT_TRUE(p) << name;
        EXPECT_EQ(p->light.theta_deg, 15) << name;
        EXPECT_EQ(p->light.phi_deg, 60) << name;
        EXPECT_EQ(p->view.theta_deg, 30) << name;
        EXPECT_EQ(p->view.phi_deg, 90) << name;
    }
    const auto off = parse_ubo2003_name("tl012.500 pl007.250 tv000 pv000.png");
    ASSERT_TRUE(off);
    EXPECT_EQ(off->light.theta_deg, 12.5);
    EXPECT_EQ(off->light.phi_deg, 7.25);
    // The folder name alone, or a name missing a part, is not an image name.
    EXPECT_FALSE(parse_ubo2003_name("tv030_pv090"));
    EXPECT_FALSE(parse_ubo2003_name("tl015 pl060 tv030.png"));
    EXPECT_FALSE(parse_ubo2003_name("tv030_pv090/readme.txt"));
}

TEST(ReadDirections, AnglesAndVectorsWithComments) {
    const auto path = write_file("dirs.txt",
                                 "# light set\n"
                                 "0 0\n"
                                 "45 370   # wraps to 10\n"
                                 "\n"
                                 "0.6 0 0.8\n");
    const auto d = read_directions(path);
    ASSERT_EQ(d.size(), 3u);
    EXPECT_NEAR(d[1].phi_deg, 10, kAngleTolDeg);
    EXPECT_NEAR(d[2].theta_deg, std::acos(0.8) * 180 / kPi, 1e-12);
    EXPECT_EQ(find_direction(d, Direction{45, 10}), 1);
    EXPECT_FALSE(find_direction(d, Direction{45, 11}));
}

TEST(ReadDirections, BadListsNameTheLine) {
    auto message = [](const std::string& text) {
        const auto path = write_file("bad.txt", text);
        return testing::error_of([&] { read_directions(path); });
    };
    {
        const auto m = message("0 0\n15 0\n15 0\n");
        EXPECT_NE(m.find("bad.txt:3"), std::string::npos) << m;
        EXPECT_NE(m.find("duplicates"), std::string::npos) << m;
        EXPECT_NE(m.find("bad.txt:2"), std::string::npos) << m;
    }
    // Every azimuth at the pole is the same direction.
    EXPECT_NE(message("0 0\n0 90\n").find("duplicates"), std::string::npos);
    EXPECT_NE(message("0 0 1.01\n").find("not unit length"), std::string::npos);
    EXPECT_NE(message("0.6 0 -0.8\n").find("below"), std::string::npos);
    EXPECT_NE(message("nan 0\n").find("NaN"), std::string::npos);
    EXPECT_NE(message("15 inf\n").find("NaN or Inf"), std::string::npos);
    EXPECT_NE(message("95 0\n").find("outside [0, 90]"), std::string::npos);
    EXPECT_NE(message("15 zero\n").find("bad.txt:1: not a list of numbers"), std::string::npos);
    EXPECT_NE(message("1 2 3 4\n").find("got 4 numbers"), std::string::npos);
    EXPECT_NE(message("# nothing\n").find("no directions"), std::string::npos);
    EXPECT_NE(testing::error_of([] { read_directions("/nonexistent/dirs.txt"); }).find("cannot open"),
              std::string::npos);
}

TEST(ReadDirectionPairs, PairsAndDuplicatePairs) {
    const auto p = read_direction_pairs(write_file("pairs.txt", "15 0 0 0\n15 0 30 90\n"));
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p[1].view.theta_deg, 30);
    const auto vec = read_direction_pairs(write_file("pairs_vec.txt", "0 0 1 0.6 0 0.8\n"));
    EXPECT_NEAR(vec[0].view.theta_deg, std::acos(0.8) * 180 / kPi, 1e-12);
    const auto path = write_file("pairs_dup.txt", "15 0 0 0\n15 360 0 45\n");
    const auto m = testing::error_of([&] { read_direction_pairs(path); });
    EXPECT_NE(m.find("pairs_dup.txt:2: light/view pair duplicates"), std::string::npos) << m;
}

}  // namespace
}  // namespace inlight::btf
