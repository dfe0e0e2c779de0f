// The shared YAML error reporting: places, the common problems, loading.
#include <stio/yaml.hpp>

#include <gtest/gtest.h>

#include "errors.hpp"

#include <fstream>
#include <set>
#include <stdexcept>

#include "files.hpp"

namespace {

namespace fs = std::filesystem;
using namespace st::io;

struct TestError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string errorOf(const std::function<void()>& f) { return st::test::errorOf<TestError>(f); }

fs::path freshDir(const std::string& name) { return st::test::freshDir("io_test", name); }

TEST(IoYaml, PlacesNameLineAndColumn) {
  const YAML::Node root = YAML::Load("a: 1\nb:\n  c: [1, 2]\n");
  EXPECT_EQ(place("f.yaml", root["a"]), "f.yaml:1");
  EXPECT_EQ(place("f.yaml", root["b"]["c"]), "f.yaml:3");
  EXPECT_EQ(place("f.yaml", root["b"]["c"], true), "f.yaml:3:6");
  EXPECT_EQ(place("f.yaml", root["nothere"]), "f.yaml");
  EXPECT_EQ(place("f.yaml", YAML::Mark::null_mark()), "f.yaml");
  const Yaml<TestError> y("f.yaml");
  EXPECT_EQ(errorOf([&] { y.missingKey(root["b"], "b.d", "the d"); }), "f.yaml:3: b.d: missing key (the d)");  // a block map starts at its first key
  EXPECT_EQ(errorOf([&] { y.wrongType(root["a"], "a", "a string"); }), "f.yaml:1: a: must be a string");
  EXPECT_EQ(wrongTypeText("a number", "lots"), "must be a number, got 'lots'");
  EXPECT_EQ(wrongTypeText("a number", ""), "must be a number, got ''");  // text given, even empty, is quoted
  EXPECT_EQ(errorOf([&] { y.unknownKey(root["a"], "a"); }), "f.yaml:1: a: unknown key");
}

TEST(IoYaml, UnknownAndRepeatedKeysAreFound) {
  const std::set<std::string> allowed{"seed", "end", "brake"};
  auto ok = [&](const std::string& k) { return allowed.count(k) > 0; };
  const Yaml<TestError> y("s.yaml");
  // yaml-cpp itself accepts a repeated key and answers with the first value
  const YAML::Node twice = YAML::Load("seed: 42\nend: 10\nseed: 43\n");
  ASSERT_EQ(twice["seed"].as<int>(), 42);
  EXPECT_EQ(errorOf([&] { y.onlyKeys(twice, "", ok); }), "s.yaml:3: seed: repeated key (first given at line 1)");
  const YAML::Node nested = YAML::Load("brake: {end: 1, end: 2}\n");
  EXPECT_EQ(errorOf([&] { y.onlyKeys(nested["brake"], "brake", ok); }),
            "s.yaml:1: brake.end: repeated key (first given at line 1)");
  EXPECT_EQ(errorOf([&] { y.onlyKeys(YAML::Load("seed: 1\nsed: 2\n"), "", ok, "did you mean seed?"); }),
            "s.yaml:2: sed: unknown key (did you mean seed?)");
  EXPECT_EQ(errorOf([&] { y.onlyKeys(YAML::Load("[1, 2]"), "", ok); }), "s.yaml:1: (top level): must be a mapping");
  EXPECT_EQ(errorOf([&] { y.onlyKeys(YAML::Load("seed: 1\nend: 2\n"), "", ok); }), "(no error)");
}

TEST(IoYaml, LoadingNamesTheFileAndWhatIsWrong) {
  const fs::path d = freshDir("load");
  const Yaml<TestError> y("unused");
  EXPECT_EQ(errorOf([&] { y.load(d / "none.yaml"); }), (d / "none.yaml").string() + ": no such file");
  EXPECT_EQ(errorOf([&] { y.load(d); }), d.string() + ": is a directory, not a YAML file");
  std::ofstream(d / "bad.yaml") << "a: 1\nb: [1, 2\n";
  const std::string e = errorOf([&] { y.load(d / "bad.yaml"); });
  EXPECT_EQ(e.rfind((d / "bad.yaml").string() + ":", 0), 0u) << e;
  EXPECT_NE(e.find(": malformed YAML: "), std::string::npos) << e;
  std::ofstream(d / "good.yaml") << "a: 1\n";
  EXPECT_EQ(y.load(d / "good.yaml")["a"].as<int>(), 1);
  std::string error;
  loadText("x: [", "t.yaml", error);
  EXPECT_EQ(error.rfind("t.yaml:", 0), 0u) << error;
}

}  // namespace
