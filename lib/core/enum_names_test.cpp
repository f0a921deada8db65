// Tests of core/enum_names.h: both directions over one table, the error type and its wording.
#include <gtest/gtest.h>

#include "core/enum_names.h"

namespace inlight {
namespace {

enum class Fruit { kApple, kPear, kPlum };
constexpr EnumName<Fruit> kFruitNames[] = {
    {Fruit::kApple, "apple"}, {Fruit::kPear, "pear"}, {Fruit::kPlum, "plum"}};

TEST(EnumNames, RoundTripsEveryEnumerator) {
    for (const auto& e : kFruitNames) {
        EXPECT_EQ(enum_to_string(kFruitNames, e.value), e.name);
        EXPECT_EQ(enum_from_string(kFruitNames, e.name, "fruit"), e.value);
    }
}

TEST(EnumNames, ListsTheNamesInTableOrder) {
    EXPECT_EQ(enum_name_list(kFruitNames), "apple, pear or plum");
    constexpr EnumName<Fruit> kOne[] = {{Fruit::kApple, "apple"}};
    EXPECT_EQ(enum_name_list(kOne), "apple");
    constexpr EnumName<Fruit> kTwo[] = {{Fruit::kApple, "apple"}, {Fruit::kPear, "pear"}};
    EXPECT_EQ(enum_name_list(kTwo), "apple or pear");
}

TEST(EnumNames, UnknownNameIsAUsageErrorNamingWhatAndTheChoices) {
    try {
        enum_from_string(kFruitNames, "Apple", "fruit");  // names are case-sensitive
        FAIL() << "no exception";
    } catch (const UsageError& e) {
        EXPECT_STREQ(e.what(), "unknown fruit 'Apple' (expected apple, pear or plum)");
    }
}

TEST(EnumNames, DataFileNamesThrowARuntimeError) {
    EXPECT_THROW(enum_from_string<Error>(kFruitNames, "", "fruit"), Error);
    try {
        enum_from_string<Error>(kFruitNames, "fig", "fruit");
    } catch (const UsageError&) {
        FAIL() << "a name read from a file is not a usage error";
    } catch (const Error&) {
    }
}

TEST(EnumNamesDeathTest, EnumeratorMissingFromTheTableIsABug) {
    constexpr EnumName<Fruit> kPartial[] = {{Fruit::kApple, "apple"}};
    EXPECT_DEATH(enum_to_string(kPartial, Fruit::kPlum), "has no name");
}

}  // namespace
}  // namespace inlight
