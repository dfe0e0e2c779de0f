#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <map>
#include <set>
#include <stbatch/experiment.hpp>
#include <stbatch/record.hpp>
#include <yaml-cpp/yaml.h>

namespace st::batch {
namespace {

namespace fs = std::filesystem;

fs::path writeExperiment(const std::string& name, const std::string& text) {
  // per process: ctest runs the tests in parallel, and other checkouts may run theirs at once
  const fs::path dir = fs::temp_directory_path() / ("stsim_batch_tests_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(fs::path(STSIM_SOURCE_DIR) / "tests/batch/data/base.yaml", dir / "base.yaml",
                fs::copy_options::overwrite_existing);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

std::string errorOf(const std::string& text) {
  try {
    loadExperiment(writeExperiment("bad.yaml", text));
  } catch (const ExperimentError& e) {
    return e.what();
  }
  return "";
}

TEST(BatchExperiment, CrossProductAndStableIds) {
  const auto e = loadExperiment(writeExperiment("a.yaml",
      "base: base.yaml\nseeds: 3\nsweep:\n  detector: [concentric, five, box]\n  penetration: [0.5, 1.0]\n"));
  const auto runs = expandRuns(e);
  ASSERT_EQ(runs.size(), 3u * 2u * 3u);
  std::set<std::string> ids;
  for (const auto& r : runs) ids.insert(r.id);
  EXPECT_EQ(ids.size(), runs.size());
  // the same parameters in another sweep order give the same ids
  const auto e2 = loadExperiment(writeExperiment("b.yaml",
      "base: base.yaml\nseeds: 3\nsweep:\n  penetration: [1.0, 0.5]\n  detector: [box, five, concentric]\n"));
  std::set<std::string> ids2;
  for (const auto& r : expandRuns(e2)) ids2.insert(r.id);
  EXPECT_EQ(ids, ids2);
}

TEST(BatchExperiment, RunScenarioAppliesOverridesAndAbsolutizesPaths) {
  const auto e = loadExperiment(writeExperiment("c.yaml",
      "base: base.yaml\nseeds: [7]\nsweep:\n  safe_time.reaction: [0.5]\nfixed:\n  detector: five\n"));
  const auto runs = expandRuns(e);
  ASSERT_EQ(runs.size(), 1u);
  const YAML::Node n = YAML::Load(runScenarioYaml(e, runs[0]));
  EXPECT_EQ(n["detector"].as<std::string>(), "five");
  EXPECT_DOUBLE_EQ(n["safe_time"]["reaction"].as<double>(), 0.5);
  EXPECT_EQ(n["seed"].as<int>(), 7);
  EXPECT_TRUE(fs::path(n["sumocfg"].as<std::string>()).is_absolute());
}

// base: as a map, one base scenario per name (networks with their own settings): the names are
// the first sweep axis, each run starts from its own base, and a key must be in every base.
TEST(BatchExperiment, SeveralNamedBasesAreTheFirstAxis) {
  const fs::path dir = writeExperiment("base.yaml", "").parent_path();
  fs::copy_file(fs::path(STSIM_SOURCE_DIR) / "tests/batch/data/base.yaml", dir / "base.yaml",
                fs::copy_options::overwrite_existing);
  fs::create_directories(dir / "other");
  std::ofstream(dir / "other/two.yaml") << "detector: box\npenetration: 0.5\nseed: 3\nsafe_time: {reaction: 2.0}\n"
                                           "sumocfg: two.yaml\nend: 60\n";
  const auto e = loadExperiment(writeExperiment("bases.yaml",
      "base:\n  one: base.yaml\n  two: {scenario: other/two.yaml, fixed: {end: 90}}\nseeds: [4, 5]\n"
      "sweep:\n  detector: [five, box]\n"
      "fixed:\n  safe_time.reaction: 1.5\n"));
  ASSERT_EQ(e.bases.size(), 2u);
  EXPECT_EQ(e.bases[1].name, "two");
  EXPECT_EQ(e.bases[1].file, fs::weakly_canonical(dir / "other/two.yaml"));
  EXPECT_EQ(e.bases[1].fixed, (std::map<std::string, std::string>{{"end", "90"}}));
  ASSERT_EQ(e.sweep.size(), 2u);
  EXPECT_EQ(e.sweep[0].key, "base");
  EXPECT_EQ(e.sweep[0].values, (std::vector<std::string>{"one", "two"}));
  const auto runs = expandRuns(e);
  ASSERT_EQ(runs.size(), 2u * 2u * 2u);
  std::set<std::string> ids;
  for (const auto& r : runs) ids.insert(r.id);
  EXPECT_EQ(ids.size(), runs.size());
  // the last run: base two, detector box, seed 5, from two.yaml with the overrides applied
  const RunSpec& last = runs.back();
  EXPECT_EQ(last.params[0], (std::pair<std::string, std::string>{"base", "two"}));
  EXPECT_EQ(baseOf(e, last), e.bases[1].file);
  const YAML::Node n = YAML::Load(runScenarioYaml(e, last));
  EXPECT_FALSE(n["base"]) << "the base's name is not a scenario key";
  EXPECT_EQ(n["detector"].as<std::string>(), "box");
  EXPECT_DOUBLE_EQ(n["penetration"].as<double>(), 0.5);  // two.yaml's own
  EXPECT_DOUBLE_EQ(n["safe_time"]["reaction"].as<double>(), 1.5);
  EXPECT_EQ(n["seed"].as<int>(), 5);
  EXPECT_EQ(n["end"].as<int>(), 90);  // two's own override (two.yaml says 60)
  EXPECT_EQ(fs::path(n["sumocfg"].as<std::string>()), fs::weakly_canonical(dir / "other/two.yaml"));
  const YAML::Node first = YAML::Load(runScenarioYaml(e, runs.front()));
  EXPECT_DOUBLE_EQ(first["penetration"].as<double>(), 1.0);  // base.yaml's
  EXPECT_FALSE(first["end"]);
  // the record a batch keeps for resuming and merging shards gives the same runs back
  const fs::path out = dir / "record";
  fs::remove_all(out);
  writeExperimentRecord(e, out);
  const Experiment back = readExperimentRecord(out);
  EXPECT_EQ(back.bases, e.bases);
  std::vector<std::string> backIds;
  for (const auto& r : expandRuns(back)) backIds.push_back(r.id);
  std::vector<std::string> runIds;
  for (const auto& r : runs) runIds.push_back(r.id);
  EXPECT_EQ(backIds, runIds);
  EXPECT_NO_THROW(checkResumable(e, out));
  // a key only one base has would fail the other's runs; the bases are not swept twice
  // (errorOf writes bad.yaml beside base.yaml and other/two.yaml)
  EXPECT_NE(errorOf("base: {one: base.yaml, two: other/two.yaml}\nfixed: {end: 30}\n")
                .find("end: unknown key: not in the base scenario base.yaml"),
            std::string::npos);
  EXPECT_NE(errorOf("base: {one: base.yaml}\nsweep: {base: [a]}\n").find("sweep.base: the bases are swept by base:"),
            std::string::npos);
  EXPECT_NE(errorOf("base: {one: base.yaml, two: nowhere.yaml}\n").find("base.two: no such file"), std::string::npos);
  EXPECT_NE(errorOf("base: {}\n").find("base: empty map"), std::string::npos);
  EXPECT_NE(errorOf("base: [base.yaml]\n").find("base: must be a scenario file, or a map"), std::string::npos);
  // a base's own overrides: keys of that base, not swept
  EXPECT_NE(errorOf("base: {one: {scenario: base.yaml, fixed: {end: 5}}}\n").find("base.one.fixed.end: unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf("base: {one: {scenario: base.yaml, fixed: {detector: box}}}\nsweep: {detector: [five]}\n")
                .find("base.one.fixed.detector: is swept"),
            std::string::npos);
  EXPECT_NE(errorOf("base: {one: {fixed: {detector: box}}}\n").find("base.one.scenario: missing"), std::string::npos);
  EXPECT_NE(errorOf("base: {one: {scenario: base.yaml, fixd: {}}}\n").find("base.one.fixd: unknown key"), std::string::npos);
}

TEST(BatchExperiment, RunCountIsLimitedBeforeAnyRunIsMade) {
  // 1000 x 1000 values x 100 seeds: 1e8 runs, refused at once (it was 8 GB of --list in 20 s)
  std::string a, b;
  for (int k = 0; k < 1000; ++k) {
    a += (k ? ", d" : "d") + std::to_string(k);
    b += (k ? ", " : "") + std::to_string(k);
  }
  const auto big = loadExperiment(writeExperiment("big.yaml", "base: base.yaml\nseeds: 100\nsweep:\n  detector: [" + a +
                                                                  "]\n  penetration: [" + b + "]\n"));
  EXPECT_EQ(runCount(big), 100000000u);
  try {
    expandRuns(big);
    FAIL() << "1e8 runs were made";
  } catch (const ExperimentError& e) {
    EXPECT_NE(std::string(e.what()).find("big.yaml: the experiment makes 100000000 runs (1000 detector x 1000 penetration x "
                                         "100 seeds), more than the limit of 100000 (raise it with --max-runs N)"),
              std::string::npos)
        << e.what();
  }
  // the limit is the caller's: 3 x 2 x 1 = 6 runs pass 6 and not 5
  const auto small = loadExperiment(writeExperiment("small.yaml",
      "base: base.yaml\nseeds: 1\nsweep:\n  detector: [concentric, five, box]\n  penetration: [0.5, 1.0]\n"));
  EXPECT_EQ(expandRuns(small, 6).size(), 6u);
  EXPECT_THROW(expandRuns(small, 5), ExperimentError);
}

TEST(BatchExperiment, ShardsPartitionTheRuns) {
  const auto e = loadExperiment(writeExperiment("d.yaml", "base: base.yaml\nseeds: 5\nsweep:\n  detector: [five, box]\n"));
  const auto runs = expandRuns(e);
  std::multiset<int> seen;
  for (int s = 1; s <= 3; ++s)
    for (const auto& r : shardRuns(runs, s, 3)) seen.insert(r.index);
  EXPECT_EQ(seen.size(), runs.size());
  EXPECT_EQ(std::set<int>(seen.begin(), seen.end()).size(), runs.size());
}

TEST(BatchExperiment, RepeatedKeysAreErrors) {
  EXPECT_NE(errorOf("base: base.yaml\nseeds: 2\nseeds: 3\n").find(":3: seeds: repeated key (first given at line 2)"),
            std::string::npos) << errorOf("base: base.yaml\nseeds: 2\nseeds: 3\n");
}

TEST(BatchExperiment, RepeatsEmptySweepsBadNamesAndSeedKeysAreErrors) {
  // two equal seeds or sweep values would be one run id twice
  EXPECT_NE(errorOf("base: base.yaml\nseeds: [1, 1]\n").find(":2: seeds: seed 1 is given twice"), std::string::npos)
      << errorOf("base: base.yaml\nseeds: [1, 1]\n");
  EXPECT_NE(errorOf("base: base.yaml\nsweep:\n  detector: [five, box, five]\n").find("sweep.detector: value five is given twice"),
            std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nsweep:\n  detector: [five]\n  detector: [box]\n").find("sweep.detector: repeated key"),
            std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nsweep: {}\n").find("sweep: empty"), std::string::npos);
  // the name is the default folder out/<name>
  EXPECT_NE(errorOf("name: ../../escape\nbase: base.yaml\n").find(":1: name: must be a plain folder name"), std::string::npos);
  EXPECT_NE(errorOf("name: ..\nbase: base.yaml\n").find("name: must be a plain folder name"), std::string::npos);
  // a seed key the scenarios lack would fail every run: named once, up front
  EXPECT_NE(errorOf("base: base.yaml\nseed_key: random.seed\n").find(":2: seed_key: 'random.seed' is not a key of the base"),
            std::string::npos);
  EXPECT_EQ(errorOf("name: ok-1.2_x\nbase: base.yaml\nseeds: [1, 2]\nsweep:\n  detector: [five, box]\n"), "");
}

TEST(BatchExperiment, MalformedExperimentsNameTheKey) {
  EXPECT_NE(errorOf("base: base.yaml\nsweep:\n  detectr: [five]\n").find("detectr: unknown key"), std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nsweep:\n  detector: []\n").find("sweep.detector: empty sweep"), std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nseeds: many\n").find("bad.yaml:2: seeds: must be a count or a list of integers"),
            std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nsweeps:\n  detector: [five]\n").find("sweeps: unknown key"), std::string::npos);
  EXPECT_NE(errorOf("sweep:\n  detector: [five]\n").find("base: missing"), std::string::npos);
  EXPECT_NE(errorOf("base: nowhere.yaml\n").find("no such file"), std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nsweep:\n  detector: {a: 1}\n").find("sweep.detector"), std::string::npos);
  // the line is named
  EXPECT_NE(errorOf("base: base.yaml\nseeds: 2\nsweep:\n  detectr: [five]\n").find("bad.yaml:4:"), std::string::npos);
}


// warmup: and report: {headline}: the analysis keys, checked with the key and line named; a
// resumed batch may change them (its runs stay), and the record keeps them for merges.
TEST(BatchExperiment, WarmupAndHeadlineAreCheckedAndRecorded) {
  const auto e = loadExperiment(writeExperiment("w.yaml",
      "base: base.yaml\nseeds: 2\nwarmup: 120\nreport: {headline: conflicts_per_hour}\n"));
  EXPECT_DOUBLE_EQ(e.warmup, 120.0);
  EXPECT_EQ(e.headline, "conflicts_per_hour");
  const auto d = loadExperiment(writeExperiment("d.yaml", "base: base.yaml\n"));
  EXPECT_DOUBLE_EQ(d.warmup, 0.0);
  EXPECT_EQ(d.headline, "conflicts_per_vehicle_km");
  EXPECT_NE(errorOf("base: base.yaml\nwarmup: -5\n").find("bad.yaml:2:"), std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nwarmup: -5\n").find("warmup: must be seconds >= 0"), std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nwarmup: soon\n").find("warmup: must be seconds"), std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nreport: {headline: crashes}\n").find("report.headline: unknown headline 'crashes'"),
            std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nreport: {headlin: conflicts_per_hour}\n").find("headlin"), std::string::npos);
  EXPECT_NE(errorOf("base: base.yaml\nreport: conflicts_per_hour\n")
                .find("bad.yaml:2: report: must be a mapping (report: {headline: conflicts_per_vehicle_km})"),
            std::string::npos);
  EXPECT_NE(errorOf("command: pool\nbase: base.yaml\nwarmup: 10\n").find("warmup: applies to highway"), std::string::npos);
  const fs::path out = writeExperiment("d2.yaml", "").parent_path() / "analysis_record";
  fs::remove_all(out);
  writeExperimentRecord(d, out);
  Experiment again = d;
  again.warmup = 60.0;
  again.headline = "conflicts_per_entering_vehicle";
  EXPECT_NO_THROW(checkResumable(again, out));  // the same runs, analysed anew
  writeExperimentRecord(again, out);
  const Experiment back = readExperimentRecord(out);
  EXPECT_DOUBLE_EQ(back.warmup, 60.0);
  EXPECT_EQ(back.headline, "conflicts_per_entering_vehicle");
  Experiment other = d;
  other.seeds = {9};
  EXPECT_THROW(checkResumable(other, out), ExperimentError);
  fs::remove_all(out);
}

}  // namespace
}  // namespace st::batch
