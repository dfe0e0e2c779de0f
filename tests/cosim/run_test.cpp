// cosim::runScenario, the run loop the stsim front end drives: it stops when asked, writes the files
// it lists, reports progress, and rejects contradicting options before touching SUMO.
#include <stcosim/run.hpp>
#include <sthighway/report.hpp>

#include <gtest/gtest.h>

#include "test_util.hpp"

namespace st::cosim {
namespace {

using namespace st::cosim::test;

TEST(CosimRun, StopsWhenAskedAndWritesWhatItLists) {
  Scenario s = loadScenario(sourceDir() / "networks/ring/scenario.yaml");
  s.end = 60.0;
  RunSetup setup;
  setup.out = freshDir("run_stop");
  setup.map = false;
  int polls = 0, reports = 0;
  RunObserver obs;
  obs.stopRequested = [&] { return ++polls > 20; };  // 20 steps, then stop
  obs.progress = [&](const RunProgress& p) {
    ++reports;
    EXPECT_EQ(p.endTime, 60.0);
    EXPECT_GT(p.time, 0.0);
  };
  obs.progressInterval = std::chrono::milliseconds(0);
  const st::cosim::RunResult r = runScenario(s, setup, obs);
  EXPECT_EQ(r.stopReason, "interrupted");
  EXPECT_EQ(r.plugin.steps, 20u);
  EXPECT_EQ(reports, 20);
  EXPECT_EQ(r.backend.rfind("libsumo", 0), 0u) << r.backend;
  ASSERT_EQ(r.written.size(), 6u);  // with conflicts.csv; the map is off (setup.map): drawing is tested with the CLI
  for (const auto& f : r.written) EXPECT_TRUE(std::filesystem::is_regular_file(f)) << f;
  const std::string summary = slurp(setup.out / "summary.json");
  EXPECT_EQ(jsonString(summary, "stop_reason"), "interrupted");
  EXPECT_EQ(jsonNumber(summary, "steps"), 20.0);
  // the warnings it counted are the rows it wrote
  std::uint64_t total = 0;
  for (auto n : r.monitor.warningsByKind) total += n;
  EXPECT_EQ(lines(slurp(setup.out / "warnings.csv")).size(), total + 1);
  // and the conflicts it counted are the rows of conflicts.csv, one per pair and encounter
  EXPECT_EQ(lines(slurp(setup.out / "conflicts.csv")).size(), st::highway::conflictCount(r.monitor) + 1);
}

TEST(CosimRun, ContradictingOptionsAreRejectedBeforeAnythingIsWritten) {
  const Scenario s = loadScenario(sourceDir() / "networks/ring/scenario.yaml");
  RunSetup setup;
  setup.out = freshDir("run_setup") / "out";
  setup.attach = TraciEndpoint{"127.0.0.1", 1, 1};
  setup.gui = true;
  EXPECT_THROW(runScenario(s, setup), RunSetupError);
  EXPECT_FALSE(std::filesystem::exists(setup.out));
}

}  // namespace
}  // namespace st::cosim
