// Tests of core/json_out.h: the pointer to the first non-finite number follows RFC 6901, so
// nlohmann::json's own pointer lookup finds the same value, and dump_finite refuses NaN and Inf.
#include "core/json_out.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.h"

namespace inlight {
namespace {

const double kNan = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

TEST(JsonOut, FiniteDocumentsHaveNoPointer) {
    EXPECT_EQ(first_non_finite(nlohmann::json::parse(R"({"a": [1, 2.5, -1e308], "b": {"c": null}})")), "");
    EXPECT_EQ(first_non_finite(nlohmann::json(3.0)), "");
}

TEST(JsonOut, PointerNamesTheValueNlohmannFinds) {
    nlohmann::json j;
    j["coefficients"] = {{0.0, 1.0}, {2.0, kNan}};
    EXPECT_EQ(first_non_finite(j), "/coefficients/1/1");
    // Keys with "~" and "/" escape as "~0" and "~1" (RFC 6901 section 3); without the escape
    // "a/b" would read as two levels and "~1" as "/".
    for (const char* key : {"a/b", "x~1y", "~", "/", "~/~0"}) {
        nlohmann::json k;
        k["ok"] = 1.0;
        k[key] = {{"m", {0.5, kInf}}};
        const std::string p = first_non_finite(k);
        ASSERT_FALSE(p.empty()) << key;
        const nlohmann::json& found = k.at(nlohmann::json::json_pointer(p));
        EXPECT_TRUE(std::isinf(found.get<double>())) << key << " -> " << p;
    }
    EXPECT_EQ(first_non_finite(nlohmann::json(kNan)), "/");
}

TEST(JsonOut, DumpFiniteRefusesAndNamesTheOutput) {
    nlohmann::json j = {{"gain", -kInf}};
    try {
        dump_finite(j, 2, "out/report.json");
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("out/report.json"), std::string::npos) << m;
        EXPECT_NE(m.find("/gain"), std::string::npos) << m;
    }
    j["gain"] = 2.0;
    EXPECT_EQ(dump_finite(j, -1, "x"), "{\"gain\":2.0}\n");
}

}  // namespace
}  // namespace inlight
