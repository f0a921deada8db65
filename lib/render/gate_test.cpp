// Tests of render/gate.h: the grading rule of idiff (-warn / -fail: above a threshold, never at
// it), the worst item deciding, NaN failing, the thresholds' checks, and which entries of a
// compare's metrics are graded.
#include "render/gate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"

namespace inlight::render {
namespace {

GateThresholds de2000_only(double warn, double fail) {
    GateThresholds t;
    t.warn_de2000 = warn;
    t.fail_de2000 = fail;
    return t;
}

TEST(Gate, AtAThresholdPassesItAboveItDoesNot) {
    const GateThresholds t = de2000_only(1.0, 2.0);
    EXPECT_EQ(grade(t, {{"a", 5.0, 1.0}}).overall, Verdict::kPass);  // mean_rel has no threshold
    EXPECT_EQ(grade(t, {{"a", 0, std::nextafter(1.0, 2.0)}}).overall, Verdict::kWarning);
    EXPECT_EQ(grade(t, {{"a", 0, 2.0}}).overall, Verdict::kWarning);
    EXPECT_EQ(grade(t, {{"a", 0, std::nextafter(2.0, 3.0)}}).overall, Verdict::kFailure);
}

TEST(Gate, TheWorstItemAndMetricDecide) {
    GateThresholds t = de2000_only(1.0, 4.0);
    t.warn_mean_rel = 0.1;
    t.fail_mean_rel = 0.2;
    // b fails on mean_rel at 1.5 x its threshold, c on dE2000 at 2 x: c decides; a warns.
    const GateResult r = grade(t, {{"a", 0.15, 0.5}, {"b", 0.3, 0.5}, {"c", 0.05, 8.0}});
    ASSERT_EQ(r.items.size(), 3u);
    EXPECT_EQ(r.items[0].verdict, Verdict::kWarning);
    EXPECT_EQ(r.items[1].verdict, Verdict::kFailure);
    EXPECT_EQ(r.items[2].verdict, Verdict::kFailure);
    EXPECT_EQ(r.overall, Verdict::kFailure);
    EXPECT_EQ(r.decided_by, "mean Delta E 2000 8 of c > fail 4");
    // On a PASS the figure nearest its (lowest) threshold is named.
    const GateResult p = grade(t, {{"a", 0.09, 0.5}, {"b", 0.02, 0.95}});
    EXPECT_EQ(p.overall, Verdict::kPass);
    EXPECT_EQ(p.decided_by, "mean Delta E 2000 0.95 of b <= warn 1");
}

TEST(Gate, OnlyAWarnThresholdNeverFailsAFiniteValue) {
    GateThresholds t;
    t.warn_mean_rel = 0.1;
    EXPECT_EQ(grade(t, {{"a", 100.0, 0}}).overall, Verdict::kWarning);
    t = GateThresholds();
    t.fail_mean_rel = 0.0;  // zero tolerance: any error fails, none passes
    EXPECT_EQ(grade(t, {{"a", 0.0, 0}}).overall, Verdict::kPass);
    EXPECT_EQ(grade(t, {{"a", 1e-12, 0}}).overall, Verdict::kFailure);
}

TEST(Gate, ANonFiniteMetricFailsAnyThresholdOnIt) {
    GateThresholds t;
    t.warn_mean_rel = 0.1;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const GateResult r = grade(t, {{"a", nan, 0}});
    EXPECT_EQ(r.overall, Verdict::kFailure);
    EXPECT_NE(r.decided_by.find("of a > warn 0.1"), std::string::npos) << r.decided_by;
    // A metric without thresholds is not graded, finite or not.
    EXPECT_EQ(grade(t, {{"a", 0.05, nan}}).overall, Verdict::kPass);
}

TEST(Gate, ThresholdsAreCheckedNamingTheOption) {
    const double inf = std::numeric_limits<double>::infinity();
    auto message = [](const GateThresholds& t) {
        try {
            check_gate_thresholds(t);
        } catch (const UsageError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(message(de2000_only(1, 2)), "");
    EXPECT_EQ(message(de2000_only(2, 2)), "");
    EXPECT_NE(message(de2000_only(3, 2)).find("--warn-de2000 3 exceeds --fail-de2000 2"),
              std::string::npos);
    EXPECT_NE(message(de2000_only(-1, 2)).find("--warn-de2000"), std::string::npos);
    EXPECT_NE(message(de2000_only(1, inf)).find("--fail-de2000"), std::string::npos);
    GateThresholds t;
    t.fail_mean_rel = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(message(t).find("--fail-mean-rel"), std::string::npos);
}

TEST(Gate, ItemsAreWhatTheAppCanShowInTheChosenModes) {
    const nlohmann::json rt = {
        {"modes", {{"consistent", {{"mean_rel", 0.1}, {"mean_de2000", 1.0}}},
                   {"seed", {{"mean_rel", 0.2}, {"mean_de2000", 2.0}}}}},
        {"consistent_by_sh_bands",
         {{{"sh_bands", 1}, {"mean_rel", 0.9}, {"mean_de2000", 9.0}},
          {{"sh_bands", 3}, {"mean_rel", 0.1}, {"mean_de2000", 1.0}},
          {{"sh_bands", 4}, {"mean_rel", 0.05}, {"mean_de2000", 0.5}}}},
        {"lighting_file", {{"sh_bands", 2}, {"with_lights", {{"mean_rel", 0.07}, {"mean_de2000", nullptr}}}}},
        {"gles", {{"variants", {{{"variant", "es300-seed-b3-highp"}, {"mode", "seed"},
                                 {"mean_rel", 0.3}, {"mean_de2000", 3.0}}}}}}};
    const std::vector<GateItem> all = gate_items(rt, {"consistent", "seed"});
    std::vector<std::string> names;
    for (const GateItem& i : all) names.push_back(i.name);
    EXPECT_EQ(names, (std::vector<std::string>{"cpu consistent b3", "cpu seed b3", "cpu consistent b4",
                                               "cpu consistent b2 + lights (--rt-lighting)",
                                               "gles es300-seed-b3-highp"}));
    EXPECT_DOUBLE_EQ(all[2].mean_rel, 0.05);
    EXPECT_TRUE(std::isnan(all[3].mean_de2000));  // null in the report: not finite
    EXPECT_EQ(gate_items(rt, {"consistent"}).size(), 3u);
    EXPECT_EQ(gate_items(rt, {"seed"}).size(), 2u);
}

}  // namespace
}  // namespace inlight::render
