// Tests of core/toml.h: the TOML subset (values, arrays, tables, arrays of tables), syntax errors
// with file:line, and the typed Reader (types, ranges, unknown keys), every error naming the key.
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
                               "a = {b=1}",
                               "a = 1.2.3",
                               "= 1",
                               "a.b = 1",
                               "a = 1\na = 2",
                               "[a]\n[[a]]",
                               "a = \"\"\"x\"\"\"",
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

TEST(Toml, ValueErrorsNameTheKey) {
    EXPECT_EQ(error_of([] { toml::parse("f0 = abc\n", "m.toml"); }),
              "m.toml:1: f0: 'abc' is not a number, boolean or quoted string");
    EXPECT_EQ(error_of([] { toml::parse("[cam]\nfov = 1\nv = [1,\n 2,,3]\n", "s.toml"); }),
              "s.toml:4: [cam] v: expected a value, got ','");
    // Errors after the value or about the key itself carry no key prefix.
    EXPECT_EQ(error_of([] { toml::parse("a = 1 2\n", "s.toml"); }),
              "s.toml:1: unexpected '2' after the value");
    EXPECT_EQ(error_of([] { toml::parse("a = 1\na = 2\n", "s.toml"); }),
              "s.toml:2: duplicate key 'a'");
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
