// The pool's settings table (stpool/settings.hpp) holds its front ends to one definition: every
// key is accepted and refused alike by the scenario YAML, by the command line's overrides (the
// library's parseScenario(text, source, overrides), which stsim pool's --set, --space and --df
// give) and by the stsim binary itself, with the same words; docs/pool_settings.md is the table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <stio/format.hpp>
#include <stpool/scenario.hpp>
#include <stpool/scenario_writer.hpp>
#include <stpool/settings.hpp>

#include "pool_test_util.hpp"

namespace st::pool {
namespace {

namespace fs = std::filesystem;
using test::Ran;
using test::runStsim;

bool isCellsKey(const std::string& key) { return key == "space.cell_size" || key == "space.margin"; }

// A scenario (a rack on a 9-ft table) with the space kind the key is for; with a value, the key's
// line is the last one.
std::string scenarioText(const std::string& key, const std::string* value) {
  const auto dot = key.find('.');
  const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
  const std::string name = key.substr(dot == std::string::npos ? 0 : dot + 1);
  std::string out = "rack: standard\n";
  if (section == "table") {
    out += "table:\n";
    if (!value || name != "width") out += "  width: 2.54\n";
    if (!value || name != "height") out += "  height: 1.27\n";
  } else {
    out += "table: {width: 2.54, height: 1.27}\n";
  }
  if (section == "space" && (value || name != "kind")) out += "space:\n";
  if (section == "space" && name != "kind") out += std::string("  kind: ") + (isCellsKey(key) ? "cells" : "quadtree") + "\n";
  if (!value) return out;
  return out + (section.empty() ? "" : "  ") + name + ": " + *value + "\n";
}

std::size_t lines(const std::string& text) { return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')); }

std::string defaultText(const Setting& s) { return settingText(s.get(Scenario{})); }

// A value inside the range, other than the default and plausible for a rack on a 9-ft table (a
// quarter more than the default, or one more for a whole number); the other boolean, another word.
std::string validText(const Setting& s) {
  const SettingValue d = s.get(Scenario{});
  switch (s.type) {
    case SettingType::Number: {
      const double* x = std::get_if<double>(&d);
      return settingText(x && *x != 0.0 ? *x * 1.25 : s.min + (s.max - s.min) / 400.0);
    }
    case SettingType::Integer: return settingText(std::get<double>(d) + 1.0);
    case SettingType::Boolean: return std::get<bool>(d) ? "false" : "true";
    case SettingType::Choice:
      for (std::string_view w : io::split(s.words, '|'))
        if (w != std::get<std::string>(d)) return std::string(w);
  }
  return "";
}

// Values each key must refuse: beyond the range, below it, not whole, of the wrong type.
std::vector<std::string> badTexts(const Setting& s) {
  switch (s.type) {
    case SettingType::Number: return {settingText(s.max * 2 + 1), settingText(s.min - 1), "fast", "[1, 2]", "nan"};
    case SettingType::Integer: return {settingText(s.max * 2 + 1), settingText(s.min - 1), "2.5", "often", "[1, 2]"};
    case SettingType::Boolean: return {"maybe", "1", "[true]"};
    case SettingType::Choice: return {"nonsense", "1", "{a: b}"};
  }
  return {};
}

std::vector<SettingOverride> set(const Setting& s, const std::string& text) {
  return {{s.key, text, std::string("--set ") + s.key}};
}

TEST(PoolSettings, EveryKeyIsAcceptedAlikeByTheYamlAndTheCommandLine) {
  for (const Setting& s : poolSettings()) {
    const std::string v = validText(s);
    ASSERT_NE(v, defaultText(s)) << s.key << ": the test would not see the value stored";
    Scenario fromYaml, fromCli;
    ASSERT_NO_THROW(fromYaml = parseScenario(scenarioText(s.key, &v), "s.yaml")) << s.key << " = " << v;
    ASSERT_NO_THROW(fromCli = parseScenario(scenarioText(s.key, nullptr), "s.yaml", set(s, v))) << s.key << " = " << v;
    EXPECT_EQ(settingText(s.get(fromYaml)), v) << s.key;
    EXPECT_EQ(settingText(s.get(fromCli)), v) << s.key;
  }
}

TEST(PoolSettings, EveryKeyRefusesABadValueAlikeInTheYamlAndOnTheCommandLine) {
  for (const Setting& s : poolSettings()) {
    for (const std::string& bad : badTexts(s)) {
      const std::string text = scenarioText(s.key, &bad);
      std::string yamlError;
      try {
        parseScenario(text, "s.yaml");
      } catch (const ScenarioError& e) {
        yamlError = e.what();
      }
      ASSERT_FALSE(yamlError.empty()) << s.key << ": " << bad << " accepted in the YAML";
      const std::string at = "s.yaml:" + std::to_string(lines(text)) + ":";
      EXPECT_EQ(yamlError.rfind(at, 0), 0u) << yamlError;
      // a scalar the command line can give: the same problem in the same words
      if (bad.front() == '[' || bad.front() == '{') {
        EXPECT_NE(yamlError.find(std::string(s.key) + ": must be " + expected(s)), std::string::npos) << yamlError;
        continue;
      }
      std::string key, problem;
      try {
        parseScenario(scenarioText(s.key, nullptr), "s.yaml", set(s, bad));
      } catch (const SettingError& e) {
        key = e.key();
        problem = e.problem();
      }
      ASSERT_FALSE(problem.empty()) << s.key << ": " << bad << " accepted on the command line";
      EXPECT_EQ(key, s.key);
      const std::string tail = ": " + std::string(s.key) + ": " + problem;
      EXPECT_EQ(yamlError.substr(yamlError.size() - std::min(yamlError.size(), tail.size())), tail) << yamlError;
    }
  }
}

// The recorded game's writer (writeScenarioYaml) writes every key from the table: read back, the
// same value, whatever its kind's keys.
TEST(PoolSettings, EveryKeyIsWrittenAndReadBackAlike) {
  for (const Setting& s : poolSettings()) {
    const std::string v = validText(s);
    const Scenario sc = parseScenario(scenarioText(s.key, &v), "s.yaml");
    std::ostringstream os;
    writeScenarioYaml(os, sc);
    Scenario back;
    ASSERT_NO_THROW(back = parseScenario(os.str(), "written.yaml")) << os.str();
    EXPECT_EQ(settingText(s.get(back)), v) << s.key << "\n" << os.str();
  }
}

// The binary: --set refuses what the YAML refuses, in its words, naming the option, exit 2; the
// options that stand for a key (--space, --df) likewise.
TEST(PoolSettings, TheCommandLineSpeaksTheTablesWords) {
  const fs::path dir = test::tempDir("settings");
  fs::create_directories(dir);
  for (const Setting& s : poolSettings()) {
    const fs::path file = dir / "base.yaml";
    std::ofstream(file) << scenarioText(s.key, nullptr);
    const std::string bad = badTexts(s).front();
    std::string problem;
    try {
      parseScenario(scenarioText(s.key, nullptr), "s.yaml", set(s, bad));
    } catch (const SettingError& e) {
      problem = e.problem();
    }
    const Ran r = runStsim("pool " + file.string() + " --set " + s.key + "=" + bad);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(r.out, "stsim pool: option --set " + std::string(s.key) + ": " + problem + "\n");
  }
  const std::string base = (dir / "base.yaml").string();
  std::ofstream(base) << scenarioText("seed", nullptr);
  EXPECT_EQ(runStsim("pool " + base + " --space cells --df 7").out,
            "stsim pool: option --df: only for kind quadtree (this space is cells)\n");
  EXPECT_EQ(runStsim("pool " + base + " --set space.cell_size=0.2").out,
            "stsim pool: option --set space.cell_size: only for kind cells (this space is quadtree)\n");
  EXPECT_EQ(runStsim("pool " + base + " --set nonsense=1").out,
            "stsim pool: option --set nonsense: unknown setting 'nonsense' (stsim pool --settings lists them)\n");
  EXPECT_EQ(runStsim("pool " + base + " --df 6 --set space.decomposition_factor=7").out,
            "stsim pool: option --set space.decomposition_factor: space.decomposition_factor given twice\n");
  EXPECT_EQ(runStsim("pool " + base + " --set until").out, "stsim pool: option --set needs KEY=VALUE, got 'until'\n");
  fs::remove_all(dir);
}

// A check past one key's range (the cells a table holds) names the option that gave the key, or
// the key's line; the file's keys of another kind are set aside by --space.
TEST(PoolSettings, CrossChecksNameTheOptionOrTheLine) {
  const std::string cells = scenarioText("space.cell_size", nullptr);
  try {
    parseScenario(cells, "s.yaml", {{"space.cell_size", "0.0001", "--set space.cell_size"}});
    ADD_FAILURE() << "accepted";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.key(), "space.cell_size");
    EXPECT_EQ(e.problem().rfind("too small for the table", 0), 0u) << e.problem();
  }
  const std::string v = "0.0001";
  try {
    parseScenario(scenarioText("space.cell_size", &v), "s.yaml");
    ADD_FAILURE() << "accepted";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.yaml:5:14: space.cell_size: too small for the table", 0), 0u) << e.what();
  }
  const std::string margin = "0.3";
  const Scenario s = parseScenario(scenarioText("space.margin", &margin), "s.yaml", {{"space.kind", "quadtree", "--space"}});
  EXPECT_EQ(s.space.kind, SpaceKind::Tree);
}

TEST(PoolSettings, DefaultsAreTheStructs) {
  const Scenario sc;
  EXPECT_EQ(std::get<double>(findSetting("table.width")->get(sc)), TableSpec{}.width);
  EXPECT_EQ(std::get<double>(findSetting("space.cell_size")->get(sc)), SpaceSpec{}.cellSize);
  EXPECT_EQ(std::get<double>(findSetting("until")->get(sc)), Scenario{}.until);
  // a scenario built in code is held to the table as a file is
  Scenario bad = test::oneTable(true);
  bad.balls.push_back(test::ball(0, Vec2(0.5, 0.5)));
  bad.friction = 200.0;
  EXPECT_THROW(validateScenario(bad, "code"), ScenarioError);
}

TEST(PoolSettings, TheDocsAreTheTable) {
  const std::string doc = test::slurp(std::string(STSIM_SOURCE_DIR) + "/docs/pool_settings.md");
  ASSERT_FALSE(doc.empty()) << "docs/pool_settings.md";
  EXPECT_NE(doc.find(settingsReferenceMarkdown()), std::string::npos)
      << "docs/pool_settings.md differs from the table: regenerate it with build/stsim pool --settings\n"
      << settingsReferenceMarkdown();
}

}  // namespace
}  // namespace st::pool
