// Detection beside SUMO's step (DetectionStage, `stsim highway --threads 2`): the monitor's work
// for tick t on a worker while SUMO steps to t+1. The truth is the serial run (--threads 1): every
// shipped scenario must give its files byte for byte, summary.json apart from its timings.
#include <stcosim/detection.hpp>
#include <stcosim/run.hpp>
#include <sthighway/report.hpp>

#include <gtest/gtest.h>

#include <map>
#include <regex>

#include "test_util.hpp"

namespace st::cosim {
namespace {

namespace fs = std::filesystem;
using namespace st::cosim::test;

// summary.json without the lines that time the run (each key is on its own line)
std::string withoutTimings(const std::string& summary) {
  static const std::regex timing(R"re(\n *"(wall_s|sumo_seconds|stsim_seconds|validation_seconds)": [^\n]*)re");
  return std::regex_replace(summary, timing, "");
}

st::cosim::RunResult runWith(const fs::path& scenario, int threads, const fs::path& out, double end) {
  Scenario s = loadScenario(scenario);
  s.end = end;
  s.plugin.actions.action = Action::None;  // the action that lets detection overlap
  RunSetup setup;
  setup.out = out;
  setup.map = false;
  setup.threads = threads;
  return runScenario(s, setup);
}

void expectSameFiles(const fs::path& serial, const fs::path& threaded) {
  for (const char* f : {"warnings.csv", "events.csv", "collisions.csv", "collision_warnings.csv"}) {
    const std::string a = slurp(serial / f), b = slurp(threaded / f);
    EXPECT_GT(a.size(), 0u) << serial / f;
    EXPECT_TRUE(a == b) << f << " differs: " << serial / f << " vs " << threaded / f;
  }
  const std::string a = withoutTimings(slurp(serial / "summary.json"));
  const std::string b = withoutTimings(slurp(threaded / "summary.json"));
  EXPECT_EQ(a.find("wall_s"), std::string::npos);  // the timings are out, nothing else
  EXPECT_EQ(a, b);
}

// 150 s of each: past the motorway incidents' first (120 s), warnings in every one
TEST(DetectionOverlap, EveryShippedScenarioGivesTheSerialRunsFilesByteForByte) {
  for (const char* name : {"motorway/scenario", "motorway/incident", "ring/scenario", "sublane/scenario"}) {
    SCOPED_TRACE(name);
    const fs::path scenario = sourceDir() / "networks" / (std::string(name) + ".yaml");
    const fs::path dir = freshDir(std::string("detection_") + std::regex_replace(name, std::regex("/"), "_"));
    const st::cosim::RunResult serial = runWith(scenario, 1, dir / "serial", 150.0);
    const st::cosim::RunResult threaded = runWith(scenario, 2, dir / "threaded", 150.0);
    EXPECT_EQ(serial.threads, 1);
    EXPECT_EQ(threaded.threads, 2);  // the worker ran
    EXPECT_EQ(serial.plugin.steps, 1500u);
    EXPECT_EQ(threaded.plugin.steps, serial.plugin.steps);
    std::uint64_t warnings = 0;
    for (auto n : serial.monitor.warningsByKind) warnings += n;
    EXPECT_GT(warnings, 0u);
    expectSameFiles(dir / "serial", dir / "threaded");
  }
}

// Ctrl-C between steps: both paths stop at the same step with the same files
TEST(DetectionOverlap, StopRequestEndsBothPathsAtTheSameStepWithTheSameFiles) {
  const fs::path dir = freshDir("detection_stop");
  auto run = [&](int threads) {
    Scenario s = loadScenario(motorway());
    s.plugin.actions.action = Action::None;
    RunSetup setup;
    setup.out = dir / std::to_string(threads);
    setup.map = false;
    setup.threads = threads;
    int polls = 0;
    RunObserver obs;
    obs.stopRequested = [&] { return ++polls > 700; };
    return runScenario(s, setup, obs);
  };
  const st::cosim::RunResult serial = run(1), threaded = run(2);
  EXPECT_EQ(serial.stopReason, "interrupted");
  EXPECT_EQ(threaded.stopReason, "interrupted");
  EXPECT_EQ(threaded.threads, 2);
  EXPECT_EQ(threaded.plugin.steps, 700u);
  expectSameFiles(dir / "1", dir / "2");
}

// An error on the worker reaches the caller's thread, the same error the in-line path throws: a
// tick detected twice (no SUMO step between) breaks the monitor's strictly increasing time.
TEST(DetectionOverlap, AnErrorOnTheWorkerIsRethrownOnTheCallersThread) {
  Scenario s = loadScenario(sourceDir() / "networks/ring/scenario.yaml");
  s.plugin.actions.action = Action::None;
  auto errorOf = [&](bool overlap) {
    auto sumo = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});
    HighwayPlugin plugin(*sumo, s.plugin);
    int collected = 0;
    std::string what;
    {
      DetectionStage detection(plugin, overlap, [&] { ++collected; });
      EXPECT_EQ(detection.overlapped(), overlap);
      sumo->step();
      detection.afterStep();
      try {
        detection.afterStep();  // the same tick again: in line it throws here
        detection.drain();      // overlapped: the worker's error comes back here
      } catch (const std::invalid_argument& e) {
        what = e.what();
      }
      detection.drain();  // nothing left running: no second throw
    }
    EXPECT_EQ(collected, 1);  // the failed tick is not collected
    sumo->close();
    return what;
  };
  const std::string serial = errorOf(false);
  EXPECT_NE(serial.find("strictly"), std::string::npos) << serial;
  EXPECT_EQ(errorOf(true), serial);
}

// Colour beside the step: SUMO's own colour of every vehicle, read after each step, is the serial
// run's of the step before (for the vehicles on the road at both); the warnings are the same.
TEST(DetectionOverlap, OverlappedColoursAreTheSerialRunsOneStepLater) {
  Scenario s = loadScenario(motorway());
  s.end = 150.0;
  ASSERT_EQ(s.plugin.actions.action, Action::Color);
  struct Run {
    std::vector<std::map<std::string, std::uint32_t>> colours;  // per step: id -> RGBA
    std::vector<std::string> warnings;
    std::uint64_t changes = 0;
  };
  auto run = [&](bool overlap) {
    Run r;
    auto sumo = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});
    HighwayPlugin plugin(*sumo, s.plugin);
    {
      DetectionStage detection(plugin, overlap, [&] {
        for (const auto& w : plugin.takeFinished()) r.warnings.push_back(highway::warningCsvRow(w));
      });
      EXPECT_EQ(detection.overlapped(), overlap);
      while (sumo->running() && sumo->time() < *s.end - 0.05) {
        sumo->step();
        detection.afterStep();
        auto& now = r.colours.emplace_back();
        for (const auto& v : sumo->vehicles()) {
          const Rgba c = sumo->color(v.id);
          now[v.id] = std::uint32_t(c.r) << 24 | std::uint32_t(c.g) << 16 | std::uint32_t(c.b) << 8 | c.a;
        }
      }
      detection.drain();
    }
    plugin.finish();
    for (const auto& w : plugin.takeFinished()) r.warnings.push_back(highway::warningCsvRow(w));
    r.changes = plugin.counters().colorChanges;
    sumo->close();
    return r;
  };
  const Run serial = run(false), overlapped = run(true);
  ASSERT_EQ(serial.colours.size(), 1500u);
  ASSERT_EQ(overlapped.colours.size(), serial.colours.size());
  EXPECT_GT(serial.warnings.size(), 50u);
  EXPECT_EQ(overlapped.warnings, serial.warnings);
  std::size_t compared = 0;
  for (std::size_t k = 1; k < serial.colours.size(); ++k)
    for (const auto& [id, colour] : overlapped.colours[k]) {
      const auto before = serial.colours[k - 1].find(id);
      if (before == serial.colours[k - 1].end()) continue;  // appeared at k: not yet judged
      ++compared;
      ASSERT_EQ(colour, before->second) << id << " at step " << k;
    }
  EXPECT_GT(compared, 100000u);
  // the colour changes are the serial run's, but for vehicles that left before theirs reached SUMO
  EXPECT_GT(serial.changes, 100u);
  EXPECT_LE(overlapped.changes, serial.changes);
  EXPECT_GE(overlapped.changes + 10, serial.changes);
}

// brake acts in SUMO on a tick's alerts before its next step: it keeps the serial order
TEST(DetectionOverlap, ActionsThatMustReachSumoFirstKeepTheSerialOrder) {
  PluginConfig c;
  c.actions.action = Action::None;
  EXPECT_TRUE(detectionCanOverlap(c));
  c.actions.action = Action::Color;
  EXPECT_TRUE(detectionCanOverlap(c));  // a colour one step late changes nothing SUMO does
  c.actions.action = Action::Brake;
  EXPECT_FALSE(detectionCanOverlap(c));
  Scenario s = loadScenario(sourceDir() / "networks/ring/scenario.yaml");
  s.plugin.actions.action = Action::Brake;
  RunSetup setup;
  setup.out = freshDir("detection_brake") / "out";
  setup.threads = 2;
  EXPECT_THROW(runScenario(s, setup), RunSetupError);
  EXPECT_FALSE(fs::exists(setup.out));
  setup.threads = 0;  // the default picks the serial path for it
  EXPECT_EQ(resolveThreads(s, setup), 1);
  s.plugin.actions.action = Action::None;
  EXPECT_EQ(resolveThreads(s, setup), std::thread::hardware_concurrency() >= 2 ? 2 : 1);
}

}  // namespace
}  // namespace st::cosim
