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
