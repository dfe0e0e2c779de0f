// The arm's settings table (starm/settings.hpp) holds its front ends to one definition: every key
// is accepted and refused alike by the scenario YAML and by the command line's overrides (the
// library's loadScenario(path, overrides), which stsim arm --set calls; cli_test.cpp runs the
// binary), with the same words; docs/arm_settings.md is the table; the defaults are the structs'.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <starm/scenario.hpp>
#include <starm/settings.hpp>

namespace st::arm {
namespace {

namespace fs = std::filesystem;

// one arm (lines 1-2); a settings key nested below it: "SECTION:\n  NAME: VALUE\n" is line 4
const std::string kArm =
    "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}, {t: 0.1, q: [0, 0, 0, -1, 0, 1, 0]}]}\n";

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("stsim_arm_settings_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

std::string nested(const Setting& s, const std::string& value) {
  const std::string key = s.key;
  const auto dot = key.find('.');
  return kArm + key.substr(0, dot) + ":\n  " + key.substr(dot + 1) + ": " + value + "\n";
}

// A value inside the range (a quarter of the way up; whole for an Integer), the other boolean,
// the last word of a choice.
std::string validText(const Setting& s) {
  switch (s.type) {
    case SettingType::Number: return settingText(s.min + (s.max - s.min) / 4.0);
    case SettingType::Integer: return settingText(std::floor(s.min + (s.max - s.min) / 4.0));
    case SettingType::Boolean: return std::get<bool>(s.get(Scenario{})) ? "false" : "true";
    case SettingType::Choice: {
      const std::string w = s.words;
      return w.substr(w.rfind('|') + 1);
    }
  }
  return "";
}

// Values each key must refuse: beyond the range, below it, not whole, of the wrong type.
std::vector<std::string> badTexts(const Setting& s) {
  switch (s.type) {
    case SettingType::Number:
      return {settingText(s.max * 2 + 1), settingText(s.min - 1), "fast", "[1, 2]", "nan"};
    case SettingType::Integer:
      return {settingText(s.max * 2 + 1), settingText(s.min - 1), "2.5", "often", "[1, 2]"};
    case SettingType::Boolean: return {"maybe", "1", "[true]"};
    case SettingType::Choice: return {"nonsense", "1", "{a: b}"};
  }
  return {};
}

TEST(ArmSettings, EveryKeyIsAcceptedAlikeByTheYamlAndTheCommandLine) {
  const fs::path base = write("base.yaml", kArm);
  for (const Setting& s : armSettings()) {
    const std::string v = validText(s);
    const fs::path p = write("valid.yaml", nested(s, v));
    Scenario fromYaml, fromCli;
    ASSERT_NO_THROW(fromYaml = loadScenario(p.string())) << s.key << " = " << v;
    ASSERT_NO_THROW(fromCli = loadScenario(base.string(), {{s.key, v, std::string("--set ") + s.key}})) << s.key << " = " << v;
    EXPECT_EQ(settingText(s.get(fromYaml)), v) << s.key;
    EXPECT_EQ(settingText(s.get(fromCli)), v) << s.key;
    // and the value differs from the default, so the test sees it stored
    Scenario defaults;
    followDefaults(defaults);
    EXPECT_NE(settingText(s.get(defaults)), v) << s.key;
    fs::remove(p);
  }
  fs::remove(base);
}

TEST(ArmSettings, EveryKeyRefusesABadValueAlikeInTheYamlAndOnTheCommandLine) {
  const fs::path base = write("base.yaml", kArm);
  for (const Setting& s : armSettings()) {
    for (const std::string& bad : badTexts(s)) {
      const fs::path p = write("bad.yaml", nested(s, bad));
      std::string yamlError;
      try {
        loadScenario(p.string());
      } catch (const InputError& e) {
        yamlError = e.what();
      }
      ASSERT_FALSE(yamlError.empty()) << s.key << ": " << bad << " accepted in the YAML";
      EXPECT_NE(yamlError.find(p.string() + ":4: " + s.key + ": "), std::string::npos) << yamlError;
      // a scalar the command line can give: the same problem in the same words
      if (bad.front() == '[' || bad.front() == '{') {
        EXPECT_NE(yamlError.find("must be " + expected(s)), std::string::npos) << yamlError;
        fs::remove(p);
        continue;
      }
      std::string key, problem;
      try {
        loadScenario(base.string(), {{s.key, bad, std::string("--set ") + s.key}});
      } catch (const SettingError& e) {
        key = e.key();
        problem = e.problem();
      }
      ASSERT_FALSE(problem.empty()) << s.key << ": " << bad << " accepted on the command line";
      EXPECT_EQ(key, s.key);
      EXPECT_EQ(yamlError, p.string() + ":4: " + s.key + ": " + problem);
      fs::remove(p);
    }
  }
  fs::remove(base);
}

TEST(ArmSettings, RangesAreInclusiveOrOpenAsTheTableSays) {
  Scenario sc;
  for (const Setting& s : armSettings()) {
    if (s.type != SettingType::Number && s.type != SettingType::Integer) continue;
    EXPECT_NO_THROW(applySettingText(sc, s, settingText(s.max))) << s.key;
    if (s.aboveMin) EXPECT_THROW(applySettingText(sc, s, settingText(s.min)), SettingError) << s.key;
    else EXPECT_NO_THROW(applySettingText(sc, s, settingText(s.min))) << s.key;
  }
}

TEST(ArmSettings, DefaultsAreTheStructsAndBrakingFollowsTheSafetyTerms) {
  Scenario sc;
  followDefaults(sc);
  EXPECT_EQ(std::get<double>(findSetting("safety.stopping_time")->get(sc)), SafetyConfig{}.stoppingTime);
  EXPECT_EQ(std::get<double>(findSetting("ssm.body_speed")->get(sc)), SsmConfig{}.bodySpeed);
  EXPECT_EQ(std::get<double>(findSetting("octree.margin")->get(sc)), BroadphaseConfig{}.margin);
  // a scenario that gives the safety terms and no braking: braking follows them
  const fs::path p = write("follow.yaml", kArm + "safety: {reaction_time: 0.02, stopping_time: 0.3}\n");
  Scenario s = loadScenario(p.string());
  EXPECT_EQ(s.braking.stoppingTime, 0.3);
  EXPECT_EQ(s.braking.delay, 0.02);
  // the command line's safety term is followed alike; a braking key given is not overridden
  s = loadScenario(p.string(), {{"safety.stopping_time", "0.4", "--set safety.stopping_time"},
                                {"braking.delay", "0.05", "--set braking.delay"}});
  EXPECT_EQ(s.braking.stoppingTime, 0.4);
  EXPECT_EQ(s.braking.delay, 0.05);
  fs::remove(p);
}

TEST(ArmSettings, CrossChecksNameTheOptionOrTheLine) {
  const fs::path p = write("cross.yaml", kArm + "safety: {horizon: 0.3}\n");
  // the command line makes the safe time longer than the file's horizon: the horizon's line
  try {
    loadScenario(p.string(), {{"safety.stopping_time", "0.5", "--set safety.stopping_time"}});
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + ":3: safety.horizon: must be at least the safe time (cycle + reaction + stopping)");
  }
  // the command line's horizon: the option
  try {
    loadScenario(p.string(), {{"safety.horizon", "0.1", "--set safety.horizon"}});
    ADD_FAILURE() << "accepted";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.key(), "safety.horizon");
  }
  // both braking times: refused whichever front end gave them
  try {
    loadScenario(p.string(), {{"braking.stopping_time", "0.1", "--set braking.stopping_time"},
                              {"braking.deceleration", "3", "--set braking.deceleration"}});
    ADD_FAILURE() << "accepted";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.key(), "braking.deceleration");
    EXPECT_EQ(e.problem(), "give either stopping_time or deceleration, not both");
  }
  fs::remove(p);
}

TEST(ArmSettings, TheDocsAreTheTable) {
  std::ifstream in(std::string(STSIM_SOURCE_DIR) + "/docs/arm_settings.md");
  ASSERT_TRUE(in) << "docs/arm_settings.md";
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find(settingsReferenceMarkdown()), std::string::npos)
      << "docs/arm_settings.md differs from the table: regenerate it with build/stsim arm --settings\n"
      << settingsReferenceMarkdown();
}

}  // namespace
}  // namespace st::arm
