// Tests of core/json_out.h: the pointer to the first non-finite number follows RFC 6901, so
// nlohmann::json's own pointer lookup finds the same value, and dump_finite refuses NaN and Inf.
#include "core/json_out.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

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

// json_float: the shortest decimal that reads back as the same float, for every float of a
// sweep over 80 binary orders of magnitude (both signs, subnormals, extremes), through nlohmann.
TEST(JsonOut, JsonFloatIsTheShortestDecimalThatReadsBackExactly) {
    EXPECT_EQ(nlohmann::json(json_float(0.1f)).dump(), "0.1");
    EXPECT_EQ(nlohmann::json(json_float(0.00047978584f)).dump(), "0.00047978584");
    EXPECT_EQ(nlohmann::json(json_float(2.0f / 255)).dump(), "0.007843138");
    EXPECT_EQ(nlohmann::json(json_float(-1.0f)).dump(), "-1.0");
    uint32_t bits = 0x00000001u;  // the least subnormal, then a stride over every exponent
    for (int i = 0; i < 50000; ++i, bits += 0x13c6du) {
        float x;
        std::memcpy(&x, &bits, sizeof x);
        for (float f : {x, -x}) {
            if (!std::isfinite(f)) continue;
            const nlohmann::json j = nlohmann::json::parse(nlohmann::json(json_float(f)).dump());
            ASSERT_EQ(j.get<float>(), f) << bits;
            // The double is a decimal of at most 9 significant digits.
            const double d = json_float(f);
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.9g", d);
            ASSERT_EQ(std::strtod(buf, nullptr), d) << buf;
        }
    }
    EXPECT_TRUE(std::isnan(json_float(kNan)));
}

}  // namespace
}  // namespace inlight
