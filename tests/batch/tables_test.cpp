// runs.csv / summary.csv / paired.csv from hand-made run results: the paired differences against
// values computed by hand.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stbatch/runner.hpp>

namespace st::batch {
namespace {

namespace fs = std::filesystem;

std::vector<std::vector<std::string>> readCsv(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> row(1);
    for (char c : line) {
      if (c == ',') row.emplace_back();
      else row.back() += c;
    }
    rows.push_back(row);
  }
  return rows;
}

TEST(BatchTables, PairedDifferencesMatchSeedBySeedArithmetic) {
  Experiment e;
  e.sweep = {{"action", {"none", "brake"}}, {"penetration", {"0.5", "1.0"}}};
  e.seeds = {1, 2, 3};
  std::vector<RunSpec> specs = expandRuns(e);
  ASSERT_EQ(specs.size(), 12u);
  // collisions = seed-specific level + an action effect; one brake run fails (seed 3, 1.0)
  auto collisions = [](const RunSpec& s) {
    const double level = s.seed == 1 ? 4.0 : s.seed == 2 ? 0.0 : 9.0;  // what the seed shares
    const bool brake = s.params[0].second == "brake", full = s.params[1].second == "1.0";
    return level + (brake ? (full ? -2.0 : -1.0) : 0.0) + (full ? 0.5 : 0.0) + 0.25 * static_cast<double>(s.seed);
  };
  std::vector<RunResult> results;
  for (const RunSpec& s : specs) {
    RunResult r;
    r.spec = s;
    const bool broken = s.seed == 3 && s.params[0].second == "brake" && s.params[1].second == "1.0";
    r.status = broken ? RunStatus::Failed : RunStatus::Done;
    if (!broken) r.metrics = {{"collisions", collisions(s)}};
    results.push_back(r);
  }
  const fs::path dir = fs::temp_directory_path() / ("stsim_tables_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  writeTables(e, results, dir);
  const auto rows = readCsv(dir / "paired.csv");
  ASSERT_EQ(rows.size(), 5u);  // header; brake vs none at 0.5 and 1.0; 1.0 vs 0.5 for none and brake
  EXPECT_EQ(rows[0], (std::vector<std::string>{"compared", "baseline", "action", "penetration", "pairs",
                                               "collisions.diff_mean", "collisions.diff_sd", "collisions.diff_ci95"}));
  auto num = [](const std::string& s) { return std::stod(s); };
  // brake vs none at 0.5: -1 on every seed, no spread
  EXPECT_EQ(rows[1][0], "action");
  EXPECT_EQ(rows[1][1], "none");
  EXPECT_EQ(rows[1][2], "brake");
  EXPECT_EQ(rows[1][3], "0.5");
  EXPECT_EQ(rows[1][4], "3");
  EXPECT_DOUBLE_EQ(num(rows[1][5]), -1.0);
  EXPECT_DOUBLE_EQ(num(rows[1][6]), 0.0);
  // brake vs none at 1.0: seed 3's brake run failed, 2 pairs of -2
  EXPECT_EQ(rows[2][3], "1.0");
  EXPECT_EQ(rows[2][4], "2");
  EXPECT_DOUBLE_EQ(num(rows[2][5]), -2.0);
  // penetration 1.0 vs 0.5, action none: +0.5 each
  EXPECT_EQ(rows[3][0], "penetration");
  EXPECT_EQ(rows[3][1], "0.5");
  EXPECT_EQ(rows[3][2], "none");
  EXPECT_EQ(rows[3][3], "1.0");
  EXPECT_DOUBLE_EQ(num(rows[3][5]), 0.5);
  // action brake: +0.5 - 1 = -0.5 on the 2 complete seeds
  EXPECT_EQ(rows[4][2], "brake");
  EXPECT_EQ(rows[4][4], "2");
  EXPECT_DOUBLE_EQ(num(rows[4][5]), -0.5);
  // the unpaired summary sees the seeds' spread (levels 4.25, 0.5, 9.75): its CI is wide
  const auto summary = readCsv(dir / "summary.csv");
  ASSERT_EQ(summary.size(), 5u);
  EXPECT_GT(num(summary[1][6]), 5.0) << "collisions.ci95 of action none, penetration 0.5";
  fs::remove_all(dir);
}

// a difference that varies by seed: the sd and the t-based CI of the differences, by hand
TEST(BatchTables, PairedSpreadIsTheDifferencesSpread) {
  Experiment e;
  e.sweep = {{"action", {"none", "brake"}}};
  e.seeds = {1, 2, 3, 4};
  const double diffs[] = {-1.0, 0.0, -3.0, 0.0};  // mean -1, sd sqrt(2), ci95 = 3.182 * sqrt(2) / 2
  std::vector<RunResult> results;
  for (const RunSpec& s : expandRuns(e)) {
    RunResult r;
    r.spec = s;
    r.status = RunStatus::Done;
    const double base = 10.0 * static_cast<double>(s.seed);
    r.metrics = {{"m", base + (s.params[0].second == "brake" ? diffs[s.seed - 1] : 0.0)}};
    results.push_back(r);
  }
  const fs::path dir = fs::temp_directory_path() / ("stsim_tables_spread_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  writeTables(e, results, dir);
  const auto rows = readCsv(dir / "paired.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][3], "4");
  EXPECT_NEAR(std::stod(rows[1][4]), -1.0, 1e-9);
  EXPECT_NEAR(std::stod(rows[1][5]), std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(std::stod(rows[1][6]), 3.182446 * std::sqrt(2.0) / 2.0, 1e-4);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace st::batch
