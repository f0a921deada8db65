// Tests of core/toml.h: toml++'s tree flattened into tables and arrays of tables (values, arrays,
// dotted keys, inline tables), syntax errors with file:line:column, the constructs inlight
// rejects, and the typed Reader (types, ranges, unknown keys), every error naming the key.
#include "core/toml.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "testing/testing.h"

namespace inlight {
namespace {

TEST(Toml, ValuesAndArrays) {
    const toml::Document doc = toml::parse(
        "[a]\ns = \"x\\\"y\" # comment\nl = 'C:\\path'\ni = -3\nf = 1e-3\nb = true\n"
        "v = [1, 2.5,\n  3]  # multi-line\n[[arr]]\nk = 1\n[[arr]]\nk = 2\n",
        "t.toml");
    const toml::Table& a = doc.tables.at("a");
    EXPECT_EQ(std::get<std::string>(a.values.at("s").data), "x\"y");
    EXPECT_EQ(std::get<std::string>(a.values.at("l").data), "C:\\path");
    EXPECT_TRUE(a.values.at("i").is_integer);
    EXPECT_DOUBLE_EQ(std::get<double>(a.values.at("f").data), 1e-3);
    EXPECT_TRUE(std::get<bool>(a.values.at("b").data));
    EXPECT_EQ(std::get<toml::Array>(a.values.at("v").data).size(), 3u);
    EXPECT_EQ(doc.table_arrays.at("arr").size(), 2u);
    EXPECT_EQ(doc.table_arrays.at("arr")[1].line, 11);
}

TEST(Toml, MalformedInputsThrowWithLineNumbers) {
    const char* const bad[] = {"[",
                               "[[a]",
                               "[a.]",
                               "a = [",
                               "a = \"x",
                               "a =",
                               "a = 'x",
                               "a = [1,,2]",
                               "a = 1.2.3",
                               "= 1",
                               "a = 1\na = 2",
                               "[a]\n[[a]]",
                               "a = \"\\q\"",
                               "a = [1 2]",
                               "a = 1 # ok\nb = tru"};
    for (const char* text : bad) {
        try {
            toml::parse(text, "f.toml");
            ADD_FAILURE() << "no error for: " << text;
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("f.toml:", 0), 0u) << e.what();
        }
    }
}

using inlight::testing::error_of;

TEST(Toml, SyntaxErrorsGiveLineAndColumn) {
    // toml++ words the description; the position is what this layer promises.
    auto prefix = [](const std::string& text) {
        const std::string e = error_of([&] { toml::parse(text, "s.toml"); });
        return e.substr(0, e.find(" error: ") + 7);
    };
    EXPECT_EQ(prefix("a = 1\nb = [1,\n 2,,3]\n"), "s.toml:3:4: TOML syntax error:");
    EXPECT_EQ(prefix("a = 1\na = 2\n"), "s.toml:2:5: TOML syntax error:");  // the second 'a ='
    EXPECT_EQ(prefix("f0 = abc\n"), "s.toml:1:6: TOML syntax error:");
    // A binary file is an error that says so, not a crash or an empty table: NUL bytes are
    // found before parsing; invalid UTF-8 is toml++'s error (placed at the last good position).
    EXPECT_EQ(error_of([] { toml::parse(std::string("a = 1\nb\x00\x01", 9), "s.bin"); }),
              "s.bin:2: binary data (a NUL byte): not a TOML text file");
    const std::string utf8 = error_of([] { toml::parse("a = 1\n\xff\xfe\x01", "s.bin"); });
    EXPECT_EQ(utf8.rfind("s.bin:1:6: TOML syntax error:", 0), 0u) << utf8;
    EXPECT_NE(utf8.find("(a binary file, not TOML text?)"), std::string::npos) << utf8;
}

TEST(Toml, DottedKeysAndInlineTablesAreTables) {
    const toml::Document doc = toml::parse(
        "camera.fov_deg = 40\n[material.denim]\nalbedo = {r = 1}\ns = \"\"\"two\nlines\"\"\"\n",
        "t.toml");
    EXPECT_EQ(std::get<double>(doc.tables.at("camera").values.at("fov_deg").data), 40.0);
    EXPECT_EQ(std::get<double>(doc.tables.at("material.denim.albedo").values.at("r").data), 1.0);
    EXPECT_EQ(std::get<std::string>(doc.tables.at("material.denim").values.at("s").data),
              "two\nlines");
    // [material] exists only implicitly (it holds tables alone), so it is not listed.
    EXPECT_EQ(doc.tables.count("material"), 0u);
    const toml::Value& s = doc.tables.at("material.denim").values.at("s");
    EXPECT_EQ(s.line, 4);
    EXPECT_EQ(s.column, 5);
}

TEST(Toml, ConstructsInlightDoesNotTakeAreErrors) {
    EXPECT_EQ(error_of([] { toml::parse("[[object]]\nname = 'a'\n[object.t]\nx = 1\n", "s.toml"); }),
              "s.toml:3:1: [object] t: a table inside [[object]] is not supported");
    EXPECT_EQ(error_of([] { toml::parse("[cam]\nwhen = 2026-11-23\n", "s.toml"); }),
              "s.toml:2:8: [cam] when: dates and times are not used by inlight");
}

TEST(TomlReader, TypesRangesAndUnknownKeys) {
    const toml::Document doc = toml::parse(
        "[t]\nc = 0.5\nv = [0.1, 0.2, 0.3]\nshort = [1, 2]\nn = 7\nx = 6.5\ns = \"str\"\n"
        "big = inf\nflag = false\ntypo = 1\n",
        "r.toml");
    const toml::Reader r(doc, doc.tables.at("t"));
    const Eigen::VectorXd zero3 = Eigen::VectorXd::Zero(3);
    EXPECT_EQ(r.get_vector("c", 3, zero3, true), Eigen::VectorXd::Constant(3, 0.5));
    EXPECT_EQ(r.get_vector("v", 3, zero3), Eigen::Vector3d(0.1, 0.2, 0.3));
    EXPECT_EQ(r.get_vector("absent", 3, Eigen::VectorXd::Ones(3)), Eigen::VectorXd::Ones(3));
    EXPECT_EQ(r.get_int("n", 0), 7);
    EXPECT_EQ(r.get_double("n", 0), 7.0);
    EXPECT_EQ(r.get_string("s", ""), "str");
    EXPECT_FALSE(r.get_bool("flag", true));
    EXPECT_EQ(error_of([&] { r.get_vector("c", 3, zero3); }),
              "r.toml:2: [t] c: expected an array of 3 numbers, got a number");
    EXPECT_EQ(error_of([&] { r.get_vector("short", 3, zero3, true); }),
              "r.toml:4: [t] short: expected an array of 3 numbers (or one number), got 2 values");
    EXPECT_EQ(error_of([&] { r.get_int("x", 0); }),
              "r.toml:6: [t] x: expected an integer, got 6.5");
    EXPECT_EQ(error_of([&] { r.get_double("s", 0); }),
              "r.toml:7: [t] s: expected a number, got a string");
    EXPECT_EQ(error_of([&] { r.get_double("big", 0); }),
              "r.toml:8: [t] big: expected a finite number");
    EXPECT_EQ(error_of([&] { r.check_range("n", 7, 0, 1); }),
              "r.toml:5: [t] n: 7 is outside [0, 1]");
    EXPECT_NO_THROW(r.check_range("n", 1, 0, 1));
    EXPECT_EQ(error_of([&] { r.require_string("name"); }),
              "r.toml:1: [t] name: required key is missing");
    EXPECT_EQ(error_of([&] { r.finish(); }),
              "r.toml:10: [t] unknown key 'typo' (known: absent, big, c, flag, n, s, short, v, x)");
}

TEST(TomlReader, RootKeysHaveNoTablePrefix) {
    const toml::Document doc = toml::parse("alpha = 2\nbeta = 1\n", "m.toml");
    const toml::Reader r(doc, doc.root);
    EXPECT_EQ(error_of([&] { r.check_range("alpha", r.get_double("alpha", 0), 0, 1); }),
              "m.toml:1: alpha: 2 is outside [0, 1]");
    EXPECT_EQ(error_of([&] { r.finish(); }), "m.toml:2: unknown key 'beta' (known: alpha)");
}

}  // namespace
}  // namespace inlight
