// Tests for core/json_in.h: the bounded JSON reader.
#include "core/json_in.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"

using namespace inlight;

namespace {

std::string nested_arrays(size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

std::string error_of(const std::string& text, size_t max_depth = json_in::kMaxDepth,
                     size_t max_bytes = json_in::kMaxBytes) {
    try {
        json_in::parse(text, "in.json", max_depth, max_bytes);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(JsonIn, DepthCountsBracketsOutsideStringsOnly) {
    EXPECT_EQ(json_in::nesting_depth("1"), 0u);
    EXPECT_EQ(json_in::nesting_depth(R"({"a": [1, {"b": []}]})"), 4u);
    // Brackets and escaped quotes inside strings do not count.
    EXPECT_EQ(json_in::nesting_depth(R"({"a": "[[[{\"[[["})"), 1u);
    EXPECT_EQ(json_in::nesting_depth(nested_arrays(30000), 100), 101u);  // stops past the bound
}

TEST(JsonIn, AcceptsUpToTheBoundRefusesOneMore) {
    EXPECT_EQ(error_of(nested_arrays(json_in::kMaxDepth)), "");
    EXPECT_EQ(json_in::parse(nested_arrays(3), "x").dump(), "[[[]]]");
    const std::string e = error_of(nested_arrays(json_in::kMaxDepth + 1));
    EXPECT_NE(e.find("in.json: arrays/objects nested deeper than 64 levels"), std::string::npos) << e;
}

TEST(JsonIn, The30000LevelDocumentIsRefusedNotCrashed) {
    const std::string e = error_of(R"({"properties": )" + nested_arrays(30000) + "}");
    EXPECT_NE(e.find("nested deeper"), std::string::npos) << e;
}

TEST(JsonIn, SizeAndSyntaxErrorsNameTheSource) {
    const std::string big = error_of("[1, 2, 3]", json_in::kMaxDepth, 8);  // 9 bytes > 8
    EXPECT_NE(big.find("in.json: 9 bytes, more than the 8"), std::string::npos) << big;
    EXPECT_NE(error_of(R"({"a": )").find("in.json: not valid JSON"), std::string::npos);
    EXPECT_NE(error_of("1e999").find("in.json: not valid JSON"), std::string::npos);
}
