// The settings core the models' tables share: a value read from text is checked by its key's
// type and range, in one wording; --set's list splits into its assignments.
#include <stio/settings_table.hpp>

#include <gtest/gtest.h>

namespace {

using namespace st::io;

const SettingSpec kTime{"run.until", SettingType::Number, "s", 0.0, 10.0, true, "", "", "doc"};
const SettingSpec kFactor{"space.factor", SettingType::Integer, "", 1.0, 100.0, false, "auto", "", "doc"};
const SettingSpec kKind{"space.kind", SettingType::Choice, "", 0, 0, false, "a|b", "", "doc"};
const SettingSpec kFlag{"table.pockets", SettingType::Boolean, "", 0, 0, false, "", "", "doc"};

std::string problem(const SettingSpec& s, const std::string& text) {
  try {
    settingValue(s, text);
  } catch (const SettingError& e) {
    EXPECT_EQ(e.key(), s.key);
    return e.problem();
  }
  return "(accepted)";
}

TEST(SettingsTable, TextIsReadAsTheKeysTypeAndChecked) {
  EXPECT_EQ(std::get<double>(settingValue(kTime, "2.5")), 2.5);
  EXPECT_EQ(std::get<std::string>(settingValue(kFactor, "auto")), "auto");
  EXPECT_EQ(std::get<bool>(settingValue(kFlag, "false")), false);
  EXPECT_EQ(problem(kTime, "0"), "must be positive, got 0");
  EXPECT_EQ(problem(kTime, "11"), "must be in (0, 10] s, got 11");
  EXPECT_EQ(problem(kTime, " 1"), "must be a number, got ' 1'");
  EXPECT_EQ(problem(kTime, "inf"), "must be a finite number, got inf");
  EXPECT_EQ(problem(kFactor, "2.5"), "must be a whole number, got 2.5");
  EXPECT_EQ(problem(kFactor, "0"), "must be in [1, 100], got 0");
  EXPECT_EQ(problem(kFactor, "never"), "must be a whole number or auto, got 'never'");
  EXPECT_EQ(problem(kKind, "c"), "must be one of a, b, got 'c'");
  EXPECT_EQ(problem(kFlag, "yes"), "must be true or false, got 'yes'");
  EXPECT_EQ(valuesText(kTime), "number in (0, 10] s");
  EXPECT_EQ(referenceRow(kFactor, 5.0, "doc"), "| `space.factor` | whole number in [1, 100], or auto | 5 | doc |\n");
}

// a table that words every value outside its range alike (the highway's, the cosim scenario's)
TEST(SettingsTable, RangeWordsNameTheRangeEitherSide) {
  const SettingSpec kReaction{"safe_time.vehicle_reaction", SettingType::Number, "s", 0.0, 60.0, false, "", "", "doc", true};
  EXPECT_EQ(problem(kReaction, "-1"), "must be in [0, 60] s, got -1");
  EXPECT_EQ(problem(kReaction, "61"), "must be in [0, 60] s, got 61");
  EXPECT_EQ(problem(kReaction, "nan"), "must be in [0, 60] s, got nan");
  EXPECT_EQ(problem(kReaction, "x"), "must be a number, got 'x'");
  const SettingSpec kEnd{"end", SettingType::Number, "s", 0.0, 1e9, true, "", "", "doc", true};
  EXPECT_EQ(problem(kEnd, "0"), "must be in (0, 1000000000] s, got 0");
  EXPECT_EQ(std::get<double>(settingValue(kEnd, "1e9")), 1e9);
}

TEST(SettingsTable, KeysSplitIntoSectionAndName) {
  EXPECT_EQ(keySection("space.cell_size"), "space");
  EXPECT_EQ(keyName("space.cell_size"), "cell_size");
  EXPECT_EQ(keySection("until"), "");
  EXPECT_EQ(keyName("until"), "until");
  // the text a file is written with reads back to the same double; the reference's is shorter
  EXPECT_EQ(exactSettingText(0.1 / 3.0), "0.03333333333333333");
  EXPECT_EQ(settingText(0.1 / 3.0), "0.0333333333333333");
}

TEST(SettingsTable, SetSplitsIntoAssignments) {
  const auto a = splitAssignments("a.b=1,c=x=y");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].key, "a.b");
  EXPECT_EQ(a[0].text, "1");
  EXPECT_EQ(a[1].key, "c");
  EXPECT_EQ(a[1].text, "x=y");
  for (const char* bad : {"", "a", "a=1,", "a=1,,b=2"}) EXPECT_THROW(splitAssignments(bad), std::invalid_argument) << bad;
}

}  // namespace
