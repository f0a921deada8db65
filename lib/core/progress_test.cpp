#include "core/progress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace inlight {
namespace {

TEST(FormatDuration, MinutesSecondsAndHours) {
    EXPECT_EQ(format_duration(0), "0:00");
    EXPECT_EQ(format_duration(59.99), "0:59");  // rounded down, never shows time not yet spent
    EXPECT_EQ(format_duration(61), "1:01");
    EXPECT_EQ(format_duration(3599), "59:59");
    EXPECT_EQ(format_duration(3600), "1:00:00");
    EXPECT_EQ(format_duration(3 * 3600 + 25 * 60 + 7), "3:25:07");
}

TEST(FormatDuration, UnknownForBadValues) {
    EXPECT_EQ(format_duration(-1), "--:--");
    EXPECT_EQ(format_duration(std::nan("")), "--:--");
    EXPECT_EQ(format_duration(std::numeric_limits<double>::infinity()), "--:--");
}

TEST(FormatProgress, EtaIsRemainingItemsAtTheAverageRate) {
    // 25 of 100 items in 10 s: 75 left at 0.4 s each = 30 s.
    EXPECT_EQ(format_progress("render", 25, 100, 10.0),
              "render [##########                              ]  25%  0:10 elapsed, ETA 0:30");
    // 2 of 3 in 100 s: 50 s left; percent rounds down (66).
    EXPECT_EQ(format_progress("x", 2, 3, 100.0),
              "x [##########################              ]  66%  1:40 elapsed, ETA 0:50");
}

TEST(FormatProgress, StartAndEnd) {
    EXPECT_EQ(format_progress("a", 0, 10, 5.0),
              "a [                                        ]   0%  0:05 elapsed, ETA --:--");
    EXPECT_EQ(format_progress("a", 10, 10, 7200.0),
              "a [########################################] 100%  2:00:00 elapsed, ETA 0:00");
    // More done than the total (a caller's overshoot) is shown as complete, not > 100 %.
    EXPECT_EQ(format_progress("a", 12, 10, 1.0),
              "a [########################################] 100%  0:01 elapsed, ETA 0:00");
}

}  // namespace
}  // namespace inlight

#include "core/log.h"

namespace inlight {
namespace {

TEST(LogCount, SingularOnlyForOne) {
    EXPECT_EQ(log::count(1, "light"), "1 light");
    EXPECT_EQ(log::count(0, "light"), "0 lights");
    EXPECT_EQ(log::count(2, "bundle"), "2 bundles");
    EXPECT_EQ(log::count(1, "view"), "1 view");
    EXPECT_EQ(log::count(3, "entry", "entries"), "3 entries");
    EXPECT_EQ(log::count(1, "entry", "entries"), "1 entry");
}

TEST(LogSummary, LabelledLineOnStderrSilentWhenQuiet) {
    const log::Level before = log::level();
    log::set_level(log::Level::kNormal);
    testing::internal::CaptureStderr();
    log::summary("calibrate", "RMS reprojection error", "0.21 px");
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "calibrate: RMS reprojection error: 0.21 px\n");
    log::set_level(log::Level::kQuiet);
    testing::internal::CaptureStderr();
    log::summary("calibrate", "RMS reprojection error", "0.21 px");
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    log::set_level(before);
}

}  // namespace
}  // namespace inlight

namespace inlight {
namespace {

TEST(LogNum, SignificantDigits) {
    EXPECT_EQ(log::num(0.213471, 4), "0.2135");
    EXPECT_EQ(log::num(253.71301, 6), "253.713");
    EXPECT_EQ(log::num(1.0, 4), "1");
}

}  // namespace
}  // namespace inlight
