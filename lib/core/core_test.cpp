// Tests of lib/core: hashing, atomic files, conventions, deterministic reductions, reports.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "core/app.h"
#include "core/conventions.h"
#include "core/error.h"
#include "core/fs.h"
#include "core/number.h"
#include "core/parallel.h"
#include "core/report.h"
#include "core/sha256.h"
#include "core/validators.h"
#include "testing/testing.h"

namespace inlight {
namespace {

constexpr double kExact = 1e-12;  // closed-form angles: only rounding of a few operations

TEST(Sha256, NistVectors) {
    // FIPS 180-4 example messages.
    EXPECT_EQ(sha256_hex("abc", 3),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256_hex("", 0),
              "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    const std::string two_blocks = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    EXPECT_EQ(sha256_hex(two_blocks.data(), two_blocks.size()),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Fs, WriteAtomicLeavesNothingOnFailure) {
    const std::string dir = testing::temp_dir("fs");
    const std::string path = dir + "/out.json";
    EXPECT_THROW(fs::write_atomic(path,
                                  [](const std::string& tmp) {
                                      fs::write_text_atomic(tmp, "partial");
                                      throw Error("simulated failure");
                                  }),
                 Error);
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_TRUE(std::filesystem::is_empty(dir));
    fs::write_text_atomic(path, "whole");
    EXPECT_EQ(fs::read_file(path), "whole");
    EXPECT_EQ(fs::extension("a/B.EXR"), "exr");
    EXPECT_EQ(std::filesystem::path(fs::temp_sibling("a/b.exr")).extension(), ".exr");
}

TEST(Conventions, LatLongMatchesCycles) {
    // Image centre faces +x, u = 0.25 faces +y, top row is +z, edges face -x.
    EXPECT_NEAR((latlong_direction(0.5, 0.5) - Eigen::Vector3d(1, 0, 0)).norm(), 0, kExact);
    EXPECT_NEAR((latlong_direction(0.25, 0.5) - Eigen::Vector3d(0, 1, 0)).norm(), 0, kExact);
    EXPECT_NEAR((latlong_direction(0.75, 0.5) - Eigen::Vector3d(0, -1, 0)).norm(), 0, kExact);
    EXPECT_NEAR((latlong_direction(0.0, 0.5) - Eigen::Vector3d(-1, 0, 0)).norm(), 0, kExact);
    EXPECT_NEAR(latlong_direction(0.3, 0.0).z(), 1.0, kExact);
    EXPECT_NEAR(latlong_direction(0.3, 1.0).z(), -1.0, kExact);
}

TEST(Conventions, LatLongRoundTripAcrossSeamAndPoles) {
    for (double u : {0.0, 1e-9, 0.25, 0.5, 0.999999999}) {
        for (double v : {1e-7, 0.3, 0.5, 0.9, 1 - 1e-7}) {
            const Eigen::Vector2d uv = latlong_uv(latlong_direction(u, v));
            EXPECT_NEAR(uv.y(), v, 1e-9);
            // u wraps at the seam: compare on the circle.
            const double du = std::remainder(uv.x() - u, 1.0);
            EXPECT_NEAR(du, 0.0, 1e-7) << "u=" << u << " v=" << v;
            EXPECT_GE(uv.x(), 0.0);
            EXPECT_LT(uv.x(), 1.0);
        }
    }
}

TEST(Conventions, RowSolidAnglesSumToSphere) {
    for (int h : {1, 2, 7, 512}) {
        double total = 0;
        for (int row = 0; row < h; ++row) total += 2 * h * latlong_pixel_solid_angle(row, 2 * h, h);
        EXPECT_NEAR(total, 4 * kPi, 1e-11) << "height " << h;
    }
}

TEST(Conventions, AtanTwoKeepsQuadrant) {
    double theta, phi;
    spherical_from_direction({-1, -1, 0}, theta, phi);
    EXPECT_NEAR(phi, -3 * kPi / 4, kExact);
    spherical_from_direction({-1, 1, 0}, theta, phi);
    EXPECT_NEAR(phi, 3 * kPi / 4, kExact);
    EXPECT_NEAR(theta, kPi / 2, kExact);
}

TEST(Conventions, ParseRotation) {
    const Eigen::Matrix3d yup = parse_rotation("y-up");
    EXPECT_NEAR((yup * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), 0, kExact);
    const Eigen::Matrix3d rz = parse_rotation("z=90");
    EXPECT_NEAR((rz * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0, kExact);
    // Applied left to right: first z=90 (x -> y), then x=90 (y -> z).
    const Eigen::Matrix3d both = parse_rotation("z=90,x=90");
    EXPECT_NEAR((both * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitZ()).norm(), 0, kExact);
    EXPECT_THROW(parse_rotation("q=3"), UsageError);
    EXPECT_THROW(parse_rotation("z=abc"), UsageError);
    // Angles that are not finite numbers are usage errors naming the rotation, never an abort.
    for (const char* bad : {"z=nan", "x=inf", "y=-inf", "z=1e999", "z=", "z=90,x=nan", "z=400"}) {
        const std::string msg = testing::error_of([&] { parse_rotation(bad); });
        EXPECT_NE(msg.find(str("rotation '", bad, "'")), std::string::npos) << msg;
    }
}

TEST(Number, ParseFiniteAcceptsDecimalsOnly) {
    EXPECT_EQ(parse_finite("1.5", "x"), 1.5);
    EXPECT_EQ(parse_finite(" +2e-3 ", "x"), 2e-3);
    EXPECT_EQ(parse_finite("-7", "x"), -7.0);
    for (const char* bad : {"nan", "NaN", "-nan", "inf", "-inf", "infinity", "1e999", "", " ",
                            "1.5x", "0x10", "1,5", "--1"}) {
        const std::string msg = testing::error_of([&] { parse_finite(bad, "--opt"); });
        EXPECT_EQ(msg, str("--opt: '", bad, "' is not a finite number")) << bad;
    }
    EXPECT_EQ(parse_integer("42", "n", 0, 100), 42);
    EXPECT_NE(testing::error_of([] { parse_integer("100000", "n", 0, 16384); })
                  .find("100000 is outside [0, 16384]"),
              std::string::npos);
    EXPECT_NE(testing::error_of([] { parse_integer("1.5", "n", 0, 9); }).find("not an integer"),
              std::string::npos);
    EXPECT_EQ(split("a,,b", ','), (std::vector<std::string>{"a", "", "b"}));
}

/// Parses argv with `cli`; returns the exit code (or -1 to continue) and the captured stderr.
std::pair<int, std::string> parse_args(CLI::App& cli, std::vector<std::string> args) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    ::testing::internal::CaptureStderr();
    ::testing::internal::CaptureStdout();
    const std::optional<int> code = app::parse(cli, static_cast<int>(argv.size()), argv.data());
    ::testing::internal::GetCapturedStdout();
    return {code.value_or(-1), ::testing::internal::GetCapturedStderr()};
}

TEST(Validators, RejectNanInfAndOutOfRange) {
    struct Case {
        CLI::Validator check;
        const char* value;
        bool ok;
    };
    const Case cases[] = {
        {app::finite(), "1e300", true},          {app::finite(), "nan", false},
        {app::finite(), "-inf", false},          {app::finite_range(0, 1), "1", true},
        {app::finite_range(0, 1), "nan", false}, {app::finite_range(0, 1), "1.0001", false},
        {app::finite_positive(), "1e-300", true}, {app::finite_positive(), "0", false},
        {app::finite_positive(), "nan", false},  {app::finite_positive(), "inf", false},
        {app::finite_non_negative(), "0", true}, {app::finite_non_negative(), "-0.5", false},
        {app::finite_non_negative(), "nan", false},
        {app::finite_range_or(0, 1e6, -1), "-1", true},
        {app::finite_range_or(0, 1e6, -1), "-0.5", false},
        {app::finite_range_or(0, 1e6, -1), "nan", false},
    };
    for (const Case& c : cases) {
        std::string v = c.value;
        EXPECT_EQ(c.check(v).empty(), c.ok) << c.value << ": " << c.check(v);
    }
}

TEST(Validators, ParseAddsFiniteToEveryFloatOption) {
    // A tool that forgot the check (or used CLI11's NaN-blind PositiveNumber) still rejects NaN,
    // on the command line and in --config.
    CLI::App cli{"t"};
    app::CommonArgs common;
    double intensity = 1;
    std::vector<double> exposures;
    cli.add_option("--intensity", intensity)->check(CLI::PositiveNumber);
    cli.add_option("--exposure-s", exposures);
    app::setup(cli, common, "t");
    for (const char* v : {"nan", "inf", "-inf"}) {
        EXPECT_EQ(parse_args(cli, {"t", "--intensity", v}).first, app::kExitUsage) << v;
    }
    const std::string err = parse_args(cli, {"t", "--intensity", "nan"}).second;
    EXPECT_NE(err.find("--intensity: 'nan' is not a finite number"), std::string::npos) << err;
    EXPECT_EQ(parse_args(cli, {"t", "--exposure-s", "1", "nan"}).first, app::kExitUsage);
    const std::string dir = testing::temp_dir("validators");
    fs::write_text_atomic(dir + "/nan.toml", "intensity = nan\n");
    EXPECT_EQ(parse_args(cli, {"t", "--config", dir + "/nan.toml"}).first, app::kExitUsage);
}

TEST(Parallel, ReduceIsIdenticalForAnyThreadCount) {
    const int64_t n = 1000003;
    auto sum = [&]() {
        return parallel::reduce(
            n, 4096, 0.0,
            [](int64_t b, int64_t e) {
                double s = 0;
                for (int64_t i = b; i < e; ++i) s += 1.0 / (1.0 + static_cast<double>(i) * 1e-3);
                return s;
            },
            [](double a, double b) { return a + b; });
    };
    parallel::set_thread_count(1);
    const double one = sum();
    parallel::set_thread_count(2);
    const double two = sum();
    parallel::set_thread_count(0);
    EXPECT_EQ(one, two);  // bit-identical, not merely close
}

TEST(Report, HasRequiredFields) {
    Report r("tool-x");
    const std::string dir = testing::temp_dir("report");
    fs::write_text_atomic(dir + "/in.txt", "abc");
    r.add_input(dir + "/in.txt");
    r.add_output(dir + "/o.exr", "image", "linear_srgb");
    r.add_stage_time("load", 0.5);
    r.add_stage_time("load", 0.25);
    r.metrics()["err_rel"] = 0.1;
    const auto j = r.to_json("ok", 0, {"w1"});
    for (const char* key : {"tool", "version", "status", "exit_code", "argv", "config", "seed",
                            "threads", "started_utc", "wall_time_s", "inputs", "outputs",
                            "metrics", "warnings", "stage_time_s"}) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["inputs"][0]["sha256"],
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_DOUBLE_EQ(j["stage_time_s"]["load"].get<double>(), 0.75);
    EXPECT_EQ(j["outputs"][0]["color_space"], "linear_srgb");
}

TEST(App, ExitCodesAndConfig) {
    CLI::App cli{"t"};
    app::CommonArgs common;
    int bands = 3;
    cli.add_option("--sh-bands", bands)->capture_default_str();
    app::setup(cli, common, "t --sh-bands 3");
    const std::string dir = testing::temp_dir("app");
    fs::write_text_atomic(dir + "/good.toml", "sh-bands = 5\n");
    fs::write_text_atomic(dir + "/bad.toml", "no-such-key = 1\n");
    {
        std::string cfg = dir + "/good.toml";
        const char* argv[] = {"t", "--config", cfg.c_str()};
        EXPECT_FALSE(app::parse(cli, 3, const_cast<char**>(argv)).has_value());
        EXPECT_EQ(bands, 5);
        EXPECT_EQ(app::resolved_config(cli)["sh_bands"], 5);
    }
    {
        std::string cfg = dir + "/bad.toml";
        const char* argv[] = {"t", "--config", cfg.c_str()};
        ::testing::internal::CaptureStderr();
        ::testing::internal::CaptureStdout();
        EXPECT_EQ(app::parse(cli, 3, const_cast<char**>(argv)), app::kExitUsage);
        ::testing::internal::GetCapturedStdout();
        ::testing::internal::GetCapturedStderr();
    }
    const char* argv[] = {"t"};
    auto code = [&](auto body) {
        ::testing::internal::CaptureStderr();
        const int c = app::run("t", cli, common, 1, const_cast<char**>(argv), body);
        ::testing::internal::GetCapturedStderr();
        return c;
    };
    EXPECT_EQ(code([](Report&) {}), app::kExitOk);
    EXPECT_EQ(code([](Report&) { throw Error("x"); }), app::kExitRuntime);
    EXPECT_EQ(code([](Report&) { throw UsageError("x"); }), app::kExitUsage);
    EXPECT_EQ(code([](Report&) { throw app::QualityGateFailed("x"); }), app::kExitQualityGate);
}

}  // namespace
}  // namespace inlight
