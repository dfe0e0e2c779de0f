// runs.csv / summary.csv / paired.csv from hand-made run results: the paired differences against
// values computed by hand.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stbatch/conflicts.hpp>
#include <stbatch/rates.hpp>
#include <stbatch/run_result.hpp>
#include <stbatch/tables.hpp>

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
  e.command = "pool";  // the metrics' tables alone: a highway experiment reads each run's conflicts.csv too
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
  e.command = "pool";  // the metrics' tables alone
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

// A run's summary.json and validation.json as the batch reads them (nlohmann::json): numeric
// leaves in the document's order under dotted keys, true/false as 1/0, a number written as a
// string (the arm's infinite times, "inf") as that number, other strings and unnamed array
// elements left out, a named array element (validation.json's detectors) reached by its name.
// A summary.json that is not JSON fails the run with an error naming the file.
TEST(BatchTables, RunResultReadsTheSummaryLeavesInDocumentOrder) {
  const fs::path dir = fs::temp_directory_path() / ("stsim_tables_leaves_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  RunSpec spec;
  spec.id = "r1";
  const fs::path run = dir / "runs" / spec.id;
  fs::create_directories(run);
  std::ofstream(run / "result.yaml") << "status: done\nerror: \"\"\nwall_seconds: 1\n";
  std::ofstream(run / "summary.json")
      << "{\"zeta\": 2, \"name\": \"x\", \"alpha\": {\"ok\": true, \"t\": \"inf\", \"v\": [1, 2], \"big\": 1e300},"
         " \"flag\": false, \"none\": null}\n";
  std::ofstream(run / "validation.json")
      << "{\"detectors\": [{\"detector\": \"five\", \"f1\": 0.5}, {\"name\": \"box\", \"f1\": 0.25}, {\"f1\": 9}]}";
  const RunResult r = loadRunResult(dir, spec);
  ASSERT_EQ(r.status, RunStatus::Done) << r.error;
  std::vector<std::string> keys;
  for (const auto& m : r.metrics) keys.push_back(m.first);
  EXPECT_EQ(keys, (std::vector<std::string>{"zeta", "alpha.ok", "alpha.t", "alpha.big", "flag", "none",
                                            "ssm.detectors.five.f1", "ssm.detectors.box.f1"}));
  ASSERT_EQ(r.metrics.size(), 8u);
  EXPECT_EQ(r.metrics[0].second, 2.0);
  EXPECT_EQ(r.metrics[1].second, 1.0);
  EXPECT_EQ(r.metrics[2].second, std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.metrics[3].second, 1e300);
  EXPECT_EQ(r.metrics[4].second, 0.0);
  EXPECT_TRUE(std::isnan(r.metrics[5].second));
  EXPECT_EQ(r.metrics[6].second, 0.5);
  EXPECT_EQ(r.metrics[7].second, 0.25);

  std::ofstream(run / "summary.json") << "{\"zeta\": 2,\n \"cut";
  const RunResult bad = loadRunResult(dir, spec);
  EXPECT_EQ(bad.status, RunStatus::Failed);
  EXPECT_NE(bad.error.find((run / "summary.json").string() + ": "), std::string::npos) << bad.error;
  fs::remove_all(dir);
}

// Hindsight figures with nothing to count: a run's summary.json gives them as null; the tables
// keep the column with an empty cell (not 0, not 1), and hindsight.csv pools each combination's
// counts, by hand: detector five, seeds 1 and 2: vehicle 3/4 and 1/6 confirmed -> 4/10, curb 0
// judged in both -> empty; near misses 2 of 2 and none -> 2/2 = 1, lead medians 0.8 and none ->
// 0.8; crossings 3 of 4 (lead median 0.6) and 0 of 2 (null) -> 3/6 = 0.5, 0.6; SUMO collisions
// 2 of 3 warned ahead (lead median 1.2) and 1 of 1 (2.0) -> 3/4 = 0.75, 1.6. Detector box, seed 1
// done and seed 2 failed: vehicle 0 of 0, no near miss, no crossing, no collision figures -> all empty.
// The kinds hindsight judged, as both hindsight tables and the warm-up's counts find them in
// summary.json's keys: only hindsight.by_kind.<kind>.judged names one, a kind with dots included.
TEST(BatchTables, JudgedKindIsReadOnlyFromAJudgedKey) {
  EXPECT_EQ(judgedKind("hindsight.by_kind.rear_end.judged"), "rear_end");
  EXPECT_EQ(judgedKind("hindsight.by_kind.lane.left.judged"), "lane.left");
  EXPECT_EQ(judgedKind("hindsight.by_kind.rear_end.confirmed"), "");
  EXPECT_EQ(judgedKind("hindsight.by_kind..judged"), "");
  EXPECT_EQ(judgedKind("hindsight.by_kind.judged"), "");
  EXPECT_EQ(judgedKind("after_warmup.hindsight.by_kind.rear_end.judged"), "");
  EXPECT_EQ(judgedKind("warnings.by_kind.rear_end"), "");
  EXPECT_EQ(judgedKind(""), "");
}

TEST(BatchTables, HindsightNullsStayEmptyAndSharesArePooledOverSeeds) {
  const fs::path dir = fs::temp_directory_path() / ("stsim_tables_hindsight_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  Experiment e;
  e.sweep = {{"detector", {"five", "box"}}};
  e.seeds = {1, 2};
  const auto specs = expandRuns(e);
  ASSERT_EQ(specs.size(), 4u);
  struct Fig {
    int vJudged, vConfirmed, events, warned;
    const char* lead;  // the median, or "null"
    double km;
    int vehicleWarnings, curbWarnings;
  };
  const Fig figs[] = {{4, 3, 2, 2, "0.8", 10.0, 4, 5}, {6, 1, 0, 0, "null", 30.0, 6, 3}, {0, 0, 0, 0, "null", 5.0, 0, 0}};
  std::vector<RunResult> results;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const fs::path run = dir / "runs" / specs[i].id;
    fs::create_directories(run);
    const bool failed = i == 3;
    std::ofstream(run / "result.yaml") << "status: " << (failed ? "failed" : "done") << "\nerror: \"\"\nwall_seconds: 1\n";
    if (!failed) {
      std::ofstream(run / "conflicts.csv") << "first,second,type,begin,min_ttc\n";  // a done highway run writes one
      const Fig& f = figs[i];
      auto share = [](int part, int whole) { return whole ? std::to_string(static_cast<double>(part) / whole) : std::string("null"); };
      const std::string lead = std::string(f.lead) == "null" ? "null"
                                                             : std::string("{\"min\": 0.6, \"median\": ") + f.lead + ", \"p90\": 1.0}";
      std::ofstream(run / "summary.json")
          << "{\"vehicle_km\": " << f.km
          << (i == 0 ? ", \"collisions\": {\"events\": 3, \"warned\": 2, \"recall\": 0.667, "
                       "\"lead_s\": {\"min\": 0.9, \"median\": 1.2, \"p90\": 1.5}}"
              : i == 1 ? ", \"collisions\": {\"events\": 1, \"warned\": 1, \"recall\": 1, "
                         "\"lead_s\": {\"min\": 2, \"median\": 2, \"p90\": 2}}"
                       : "")
          << ", \"warnings\": {\"by_kind\": {\"vehicle\": " << f.vehicleWarnings
          << ", \"curb\": " << f.curbWarnings << "}},\n \"hindsight\": {\"clearance_m\": 0.5, \"by_kind\": {"
          << "\"vehicle\": {\"judged\": " << f.vJudged << ", \"confirmed\": " << f.vConfirmed
          << ", \"precision\": " << share(f.vConfirmed, f.vJudged) << "}, "
          << "\"curb\": {\"judged\": 0, \"confirmed\": 0, \"precision\": null}},\n"
          << " \"near_misses\": {\"events\": " << f.events << ", \"warned\": " << f.warned
          << ", \"recall\": " << share(f.warned, f.events) << ", \"lead_s\": " << lead << "},\n"
          << " \"crossings\": "
          << (i == 0   ? "{\"events\": 4, \"warned\": 3, \"recall\": 0.75, \"lead_s\": {\"min\": 0.5, \"median\": 0.6, \"p90\": 0.9}}"
              : i == 1 ? "{\"events\": 2, \"warned\": 0, \"recall\": 0, \"lead_s\": null}"
                       : "{\"events\": 0, \"warned\": 0, \"recall\": null, \"lead_s\": null}")
          << "}}\n";
    }
    results.push_back(loadRunResult(dir, specs[i]));
    ASSERT_EQ(results.back().status, failed ? RunStatus::Failed : RunStatus::Done) << results.back().error;
  }
  writeTables(e, results, dir);

  auto column = [](const std::vector<std::vector<std::string>>& rows, const std::string& name) {
    for (std::size_t c = 0; c < rows[0].size(); ++c)
      if (rows[0][c] == name) return c;
    ADD_FAILURE() << "no column " << name;
    return std::size_t{0};
  };
  // runs.csv: the null figures are empty cells of columns that exist (the curb precision is null
  // in every run, a lead time in two of three)
  const auto runs = readCsv(dir / "runs.csv");
  ASSERT_EQ(runs.size(), 5u);
  const auto curbPrecision = column(runs, "hindsight.by_kind.curb.precision");
  const auto recall = column(runs, "hindsight.near_misses.recall");
  const auto leadMedian = column(runs, "hindsight.near_misses.lead_s.median");
  EXPECT_EQ(runs[1][curbPrecision], "");
  EXPECT_EQ(runs[1][recall], "1");
  EXPECT_EQ(runs[1][leadMedian], "0.8");
  EXPECT_EQ(runs[2][recall], "");
  EXPECT_EQ(runs[2][leadMedian], "");
  EXPECT_EQ(runs[3][column(runs, "hindsight.by_kind.vehicle.precision")], "");
  for (const auto& row : runs)
    for (const auto& cell : row) EXPECT_NE(cell, "nan");

  // summary.csv: a mean over the runs that have the figure; none has: empty
  const auto summary = readCsv(dir / "summary.csv");
  ASSERT_EQ(summary.size(), 3u);
  EXPECT_EQ(summary[1][column(summary, "hindsight.near_misses.recall.mean")], "1");
  EXPECT_EQ(summary[1][column(summary, "hindsight.by_kind.curb.precision.mean")], "");
  EXPECT_EQ(summary[2][column(summary, "hindsight.near_misses.recall.mean")], "");

  // hindsight.csv: pooled
  const auto h = readCsv(dir / "hindsight.csv");
  ASSERT_EQ(h.size(), 3u);
  EXPECT_EQ(h[0][0], "detector");
  EXPECT_EQ(h[1][0], "five");
  EXPECT_EQ(h[1][column(h, "runs")], "2");
  EXPECT_DOUBLE_EQ(std::stod(h[1][column(h, "vehicle_km")]), 40.0);
  // a rate's one definition, as summary.csv's: the mean of the runs' rates (4/10 and 6/30; 5/10 and 3/30)
  EXPECT_DOUBLE_EQ(std::stod(h[1][column(h, "vehicle.per_vehicle_km")]), (4.0 / 10.0 + 6.0 / 30.0) / 2.0);
  EXPECT_DOUBLE_EQ(std::stod(h[1][column(h, "curb.per_vehicle_km")]), (5.0 / 10.0 + 3.0 / 30.0) / 2.0);
  EXPECT_EQ(h[1][column(h, "vehicle.judged")], "10");
  EXPECT_EQ(h[1][column(h, "vehicle.confirmed")], "4");
  EXPECT_DOUBLE_EQ(std::stod(h[1][column(h, "vehicle.confirmed_share")]), 0.4);
  EXPECT_EQ(h[1][column(h, "curb.judged")], "0");
  EXPECT_EQ(h[1][column(h, "curb.confirmed_share")], "");
  EXPECT_EQ(h[1][column(h, "near_misses")], "2");
  EXPECT_EQ(h[1][column(h, "near_miss_recall")], "1");
  EXPECT_EQ(h[1][column(h, "near_miss_lead_median_s")], "0.8");
  EXPECT_EQ(h[1][column(h, "crossings")], "6");
  EXPECT_EQ(h[1][column(h, "crossings_warned")], "3");
  EXPECT_EQ(h[1][column(h, "crossing_recall")], "0.5");
  EXPECT_EQ(h[1][column(h, "crossing_lead_median_s")], "0.6");
  EXPECT_EQ(h[1][column(h, "collisions")], "4");
  EXPECT_EQ(h[1][column(h, "collisions_warned")], "3");
  EXPECT_EQ(h[1][column(h, "collision_recall")], "0.75");
  EXPECT_EQ(h[1][column(h, "collision_lead_median_s")], "1.6");
  EXPECT_EQ(h[2][0], "box");
  EXPECT_EQ(h[2][column(h, "runs")], "1");
  EXPECT_EQ(h[2][column(h, "vehicle.confirmed_share")], "");
  EXPECT_EQ(h[2][column(h, "near_misses")], "0");
  EXPECT_EQ(h[2][column(h, "near_miss_recall")], "");
  EXPECT_EQ(h[2][column(h, "near_miss_lead_median_s")], "");
  EXPECT_EQ(h[2][column(h, "crossings")], "0");
  EXPECT_EQ(h[2][column(h, "crossing_recall")], "");
  EXPECT_EQ(h[2][column(h, "crossing_lead_median_s")], "");
  // no collision figures (an attached run counts none): empty, not 0
  EXPECT_EQ(h[2][column(h, "collisions")], "");
  EXPECT_EQ(h[2][column(h, "collision_recall")], "");
  fs::remove_all(dir);
}

// Two designs' conflicts from hand-made conflicts.csv files (the warnings.csv beside them, per ego,
// is not what is counted): only SSAM's types are pooled, over the
// seeds; the comparison is Welch's interval worked by hand (equal n and sd: 2(n - 1) = 4 degrees
// of freedom, t = 2.776445).
TEST(BatchTables, ConflictTablesPoolSsamTypesAndCompareDesignsByWelch) {
  Experiment e;
  e.sweep = {{"design", {"base", "x"}}};
  e.seeds = {1, 2};
  const std::vector<RunSpec> specs = expandRuns(e);
  ASSERT_EQ(specs.size(), 4u);
  const fs::path dir = fs::temp_directory_path() / ("stsim_conflicts_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string header = "first,second,type,min_ttc,drac,max_delta_v\n";
  // per (design, seed): the rows; a quoted id with a comma, a proximity and a road row that are no conflicts
  auto rows = [](const RunSpec& s) -> std::string {
    const bool x = s.params[0].second == "x";
    if (s.seed == 1)
      return x ? "\"a,1\",b,rear_end,1,2,5\na,b,proximity,0,,1\na,curb,road,0.5,,\n"
               : "a,b,rear_end,2,inf,4\n";
    return x ? "a,b,lane_change,2,4,7\nc,d,rear_end,3,,9\n"
             : "a,b,crossing,3,1,6\nc,d,rear_end,4,3,8\n";
  };
  std::vector<RunResult> results;
  for (const RunSpec& s : specs) {
    fs::create_directories(dir / "runs" / s.id);
    std::ofstream(dir / "runs" / s.id / "conflicts.csv") << header << rows(s);
    // each conflict twice, once per ego: not counted
    std::ofstream(dir / "runs" / s.id / "warnings.csv") << "ego,foe,kind,min_ttc,type\na,b,vehicle,0.1,rear_end\nb,a,vehicle,0.1,rear_end\n";
    RunResult r;
    r.spec = s;
    r.status = RunStatus::Done;
    results.push_back(r);
  }
  writeConflictTables(e, results, dir);
  const auto c = readCsv(dir / "conflicts.csv");
  ASSERT_EQ(c.size(), 3u);
  auto at = [&](const std::vector<std::vector<std::string>>& t, int row, const std::string& name) {
    for (std::size_t i = 0; i < t[0].size(); ++i)
      if (t[0][i] == name) return t[row][i];
    ADD_FAILURE() << "no column " << name;
    return std::string();
  };
  EXPECT_EQ(at(c, 1, "design"), "base");
  EXPECT_EQ(at(c, 1, "runs"), "2");
  EXPECT_EQ(at(c, 1, "conflicts"), "3");
  EXPECT_EQ(at(c, 1, "crossing"), "1");
  EXPECT_EQ(at(c, 1, "min_ttc.mean"), "3");
  EXPECT_EQ(at(c, 1, "drac.n"), "2");  // inf (touching) is no value to average
  EXPECT_EQ(at(c, 1, "drac.mean"), "2");
  EXPECT_EQ(at(c, 2, "conflicts"), "3");  // the proximity and the road rows are none
  EXPECT_EQ(at(c, 2, "rear_end"), "2");
  EXPECT_EQ(at(c, 2, "lane_change"), "1");
  EXPECT_EQ(at(c, 2, "min_ttc.mean"), "2");
  EXPECT_EQ(at(c, 2, "min_ttc.sd"), "1");
  EXPECT_EQ(at(c, 2, "max_delta_v.mean"), "7");
  // no pet column in these files: the measure is left out
  EXPECT_EQ(std::count(c[0].begin(), c[0].end(), std::string("pet.n")), 0);
  const auto d = readCsv(dir / "conflicts_compared.csv");
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(at(d, 1, "compared"), "design");
  EXPECT_EQ(at(d, 1, "baseline"), "base");
  EXPECT_EQ(at(d, 1, "design"), "x");
  const double se = std::sqrt(1.0 / 3.0 + 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(std::stod(at(d, 1, "min_ttc.diff_mean")), -1.0);
  EXPECT_NEAR(std::stod(at(d, 1, "min_ttc.diff_ci95")), 2.776445 * se, 1e-5);
  EXPECT_NEAR(std::stod(at(d, 1, "min_ttc.t")), -1.0 / se, 1e-9);
  EXPECT_DOUBLE_EQ(std::stod(at(d, 1, "max_delta_v.diff_mean")), 7.0 - 6.0);
  fs::remove_all(dir);
}


// A highway study on a hand-made fixture: 2 designs x 3 seeds, a 100 s warm-up. Each run's
// exposure after the warm-up is summary.json's total less exposure.csv's row at 100 s; the
// conflicts are those of conflicts.csv that began at or after 100 s. Every figure below is worked
// out by hand from the fixture (no call into stats.cpp):
//   rear-end conflicts after the warm-up  base: 2, 4, 3   x: 1, 2, 4   (one more at 99.9 s each: left out)
//   vehicle-km after the warm-up          base: 10 - 2 = 8   x: 12 - 3 = 9
//   rear-end per vehicle-km               base: 1/4, 1/2, 3/8   x: 1/9, 2/9, 4/9
//   paired differences x - base           -5/36, -5/18, 5/72: mean -25/216, sd sqrt(2850/216^2/2),
//                                         95 % half-width t(0.975, 2) = 4.302653 x sd / sqrt(3)
//   Welch on min_ttc (all types)          x (n 7): sum 5.3, squares about the mean 58/35
//                                         base (n 10): sum 11, squares about the mean 0.96
//                                         dof 9.23 -> 9, t(0.975, 9) = 2.262157
TEST(BatchTables, StudyRatesHonourTheWarmupAndMatchHandWorkedIntervals) {
  Experiment e;
  e.command = "highway";
  e.warmup = 100.0;
  e.sweep = {{"design", {"base", "x"}}};
  e.seeds = {1, 2, 3};
  const std::vector<RunSpec> specs = expandRuns(e);
  ASSERT_EQ(specs.size(), 6u);
  const fs::path dir = fs::temp_directory_path() / ("stsim_study_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  // rear-end min_ttc values after the warm-up, per (design, seed); base seed 2 has a lane change too
  const std::map<std::pair<std::string, std::int64_t>, std::vector<double>> rearEnds = {
      {{"base", 1}, {1.0, 1.2}}, {{"base", 2}, {0.5, 0.7, 0.9, 1.1}}, {{"base", 3}, {1.3, 1.4, 1.5}},
      {{"x", 1}, {0.6}},         {{"x", 2}, {0.4, 1.4}},               {{"x", 3}, {0.2, 0.3, 1.5, 0.9}}};
  std::vector<RunResult> results;
  for (const RunSpec& s : specs) {
    const bool x = s.params[0].second == "x";
    const fs::path run = dir / "runs" / s.id;
    fs::create_directories(run);
    std::ofstream(run / "result.yaml") << "status: done\nerror: \"\"\nwall_seconds: 1\n";
    std::ofstream(run / "summary.json") << "{\"vehicle_km\": " << (x ? 12 : 10) << ", \"vehicles\": " << (x ? 52 : 50)
                                        << ", \"simulated_s\": 400}\n";
    std::ofstream(run / "exposure.csv") << "time,vehicle_km,vehicles\n0,0,0\n50,1,6\n100," << (x ? 3 : 2) << ","
                                        << (x ? 12 : 10) << "\n100.1,5,20\n400," << (x ? 12 : 10) << "," << (x ? 52 : 50) << "\n";
    std::ofstream c(run / "conflicts.csv");
    c << "first,second,type,begin,min_ttc\n";
    c << "w,v,rear_end,99.9,0.05\n";  // the warm-up's: counted nowhere
    double begin = 100.0;              // the first at the warm-up's end: counted
    for (double ttc : rearEnds.at({s.params[0].second, s.seed})) c << "a,b,rear_end," << begin << "," << ttc << "\n", begin += 10.0;
    if (!x && s.seed == 2) c << "c,d,lane_change,300,1.4\n";
    c << "e,f,proximity,200,0.3\n";  // not a conflict type
    c.close();
    results.push_back(loadRunResult(dir, s));
    ASSERT_EQ(results.back().status, RunStatus::Done) << results.back().error;
  }
  writeTables(e, results, dir);
  auto column = [](const std::vector<std::vector<std::string>>& t, const std::string& name) {
    for (std::size_t i = 0; i < t[0].size(); ++i)
      if (t[0][i] == name) return i;
    ADD_FAILURE() << "no column " << name;
    return std::size_t{0};
  };
  const auto runs = readCsv(dir / "runs.csv");
  ASSERT_EQ(runs.size(), 7u);
  // base seed 1: 2 rear-ends after the warm-up over 8 vehicle-km, 300 s, 40 entering vehicles
  EXPECT_DOUBLE_EQ(std::stod(runs[1][column(runs, "exposure.vehicle_km")]), 8.0);
  EXPECT_NEAR(std::stod(runs[1][column(runs, "exposure.hours")]), 300.0 / 3600.0, 1e-12);  // the tables write 12 digits
  EXPECT_DOUBLE_EQ(std::stod(runs[1][column(runs, "exposure.entering_vehicles")]), 40.0);
  EXPECT_EQ(runs[1][column(runs, "counted.rear_end")], "2");
  EXPECT_EQ(runs[1][column(runs, "counted.all")], "2");
  EXPECT_DOUBLE_EQ(std::stod(runs[1][column(runs, "rate.per_vehicle_km.rear_end")]), 0.25);
  EXPECT_DOUBLE_EQ(std::stod(runs[1][column(runs, "rate.per_hour.rear_end")]), 24.0);
  EXPECT_DOUBLE_EQ(std::stod(runs[1][column(runs, "rate.per_entering_vehicle.rear_end")]), 0.05);
  EXPECT_EQ(runs[2][column(runs, "counted.all")], "5");  // base seed 2: 4 rear-ends and the lane change
  EXPECT_EQ(runs[2][column(runs, "counted.lane_change")], "1");
  EXPECT_DOUBLE_EQ(std::stod(runs[4][column(runs, "exposure.vehicle_km")]), 9.0);

  // summary.csv: the mean of the runs' rates, (1/4 + 1/2 + 3/8) / 3
  const auto summary = readCsv(dir / "summary.csv");
  EXPECT_NEAR(std::stod(summary[1][column(summary, "rate.per_vehicle_km.rear_end.mean")]), 1.125 / 3.0, 1e-12);

  // paired.csv: x - base on the same seeds
  const auto paired = readCsv(dir / "paired.csv");
  ASSERT_EQ(paired.size(), 2u);
  EXPECT_EQ(paired[1][column(paired, "pairs")], "3");
  const double sd = std::sqrt(2850.0 / (216.0 * 216.0) / 2.0);
  EXPECT_NEAR(std::stod(paired[1][column(paired, "rate.per_vehicle_km.rear_end.diff_mean")]), -25.0 / 216.0, 1e-12);
  EXPECT_NEAR(std::stod(paired[1][column(paired, "rate.per_vehicle_km.rear_end.diff_sd")]), sd, 1e-12);
  EXPECT_NEAR(std::stod(paired[1][column(paired, "rate.per_vehicle_km.rear_end.diff_ci95")]), 4.302653 * sd / std::sqrt(3.0), 1e-6);

  // conflicts.csv and conflicts_compared.csv: the pooled conflicts after the warm-up, Welch by hand
  const auto pooled = readCsv(dir / "conflicts.csv");
  EXPECT_EQ(pooled[1][column(pooled, "conflicts")], "10");
  EXPECT_EQ(pooled[2][column(pooled, "conflicts")], "7");
  EXPECT_NEAR(std::stod(pooled[1][column(pooled, "min_ttc.mean")]), 1.1, 1e-12);
  const auto welch = readCsv(dir / "conflicts_compared.csv");
  ASSERT_EQ(welch.size(), 2u);
  const double vx = 58.0 / 35.0 / 6.0 / 7.0, vb = 0.96 / 9.0 / 10.0, se = std::sqrt(vx + vb);
  const double diff = 5.3 / 7.0 - 1.1;
  EXPECT_NEAR(std::stod(welch[1][column(welch, "min_ttc.diff_mean")]), diff, 1e-12);
  EXPECT_NEAR(std::stod(welch[1][column(welch, "min_ttc.t")]), diff / se, 1e-9);
  EXPECT_NEAR(std::stod(welch[1][column(welch, "min_ttc.diff_ci95")]), 2.262157 * se, 1e-6);
  EXPECT_NEAR(std::stod(welch[1][column(welch, "min_ttc.t")]), -1.5314296826704683, 1e-9);
  fs::remove_all(dir);
}

// The conflicts with a bicycle, counted apart (counted.with_bicycle.<type>, its rates) from the
// class columns of conflicts.csv after the warm-up, beside the unchanged counts of every type. Worked
// out by hand: after the 100 s warm-up, 4 conflicts of the SSAM types, 3 with a bicycle (2 rear-end,
// 1 crossing; one of them between two bicycles); 10 - 2 = 8 vehicle-km. A file without the class
// columns cannot tell: its with_bicycle cells are empty, its other counts as before.
TEST(BatchTables, BicycleConflictsAreCountedApartAfterTheWarmup) {
  Experiment e;
  e.command = "highway";
  e.warmup = 100.0;
  e.sweep = {{"design", {"base"}}};
  e.seeds = {1, 2};
  const std::vector<RunSpec> specs = expandRuns(e);
  ASSERT_EQ(specs.size(), 2u);
  const fs::path dir = fs::temp_directory_path() / ("stsim_bicycle_rates_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  std::vector<RunResult> results;
  for (const RunSpec& s : specs) {
    const fs::path run = dir / "runs" / s.id;
    fs::create_directories(run);
    std::ofstream(run / "result.yaml") << "status: done\nerror: \"\"\nwall_seconds: 1\n";
    std::ofstream(run / "summary.json") << "{\"vehicle_km\": 10, \"vehicles\": 50, \"simulated_s\": 400}\n";
    std::ofstream(run / "exposure.csv") << "time,vehicle_km,vehicles\n0,0,0\n100,2,10\n400,10,50\n";
    std::ofstream c(run / "conflicts.csv");
    if (s.seed == 1) {
      c << "first,second,type,begin,min_ttc,first_class,second_class\n";
      c << "a,b1,rear_end,99.9,0.5,passenger,bicycle\n";  // the warm-up's: counted nowhere
      c << "b2,b3,rear_end,150,0.9,bicycle,bicycle\n";
      c << "c,b4,crossing,160,1.1,passenger,bicycle\n";
      c << "t,d,crossing,170,1.2,truck,passenger\n";  // no bicycle
      c << "b5,e,rear_end,180,1.3,bicycle,truck\n";
      c << "b6,f,proximity,200,0.3,bicycle,passenger\n";  // not a conflict type
    } else {
      c << "first,second,type,begin,min_ttc\n";  // no class columns
      c << "a,b,rear_end,150,0.9\n";
    }
    c.close();
    results.push_back(loadRunResult(dir, s));
    ASSERT_EQ(results.back().status, RunStatus::Done) << results.back().error;
  }
  writeTables(e, results, dir);
  const auto runs = readCsv(dir / "runs.csv");
  ASSERT_EQ(runs.size(), 3u);
  auto at = [&](std::size_t row, const std::string& name) {
    for (std::size_t i = 0; i < runs[0].size(); ++i)
      if (runs[0][i] == name) return runs[row][i];
    ADD_FAILURE() << "no column " << name;
    return std::string("?");
  };
  // every type as before
  EXPECT_EQ(at(1, "counted.all"), "4");
  EXPECT_EQ(at(1, "counted.rear_end"), "2");
  EXPECT_EQ(at(1, "counted.crossing"), "2");
  // with a bicycle, apart
  EXPECT_EQ(at(1, "counted.with_bicycle.all"), "3");
  EXPECT_EQ(at(1, "counted.with_bicycle.rear_end"), "2");
  EXPECT_EQ(at(1, "counted.with_bicycle.crossing"), "1");
  EXPECT_EQ(at(1, "counted.with_bicycle.lane_change"), "0");
  EXPECT_EQ(at(1, "counted.with_bicycle.pedestrian"), "0");
  EXPECT_DOUBLE_EQ(std::stod(at(1, "rate.per_vehicle_km.with_bicycle.all")), 3.0 / 8.0);
  EXPECT_DOUBLE_EQ(std::stod(at(1, "rate.per_vehicle_km.with_bicycle.rear_end")), 2.0 / 8.0);
  EXPECT_NEAR(std::stod(at(1, "rate.per_hour.with_bicycle.crossing")), 1.0 / (300.0 / 3600.0), 1e-9);
  EXPECT_DOUBLE_EQ(std::stod(at(1, "rate.per_entering_vehicle.with_bicycle.all")), 3.0 / 40.0);
  // no classes: unknown, not 0
  EXPECT_EQ(at(2, "counted.all"), "1");
  EXPECT_EQ(at(2, "counted.with_bicycle.all"), "");
  EXPECT_EQ(at(2, "rate.per_vehicle_km.with_bicycle.all"), "");
  fs::remove_all(dir);
}

// A done highway run's folder as the batch leaves it: result.yaml, summary.json and conflicts.csv.
fs::path doneRun(const fs::path& dir, const RunSpec& spec, const std::string& conflicts) {
  const fs::path run = dir / "runs" / spec.id;
  fs::create_directories(run);
  std::ofstream(run / "result.yaml") << "status: done\nerror: \"\"\nwall_seconds: 1\n";
  std::ofstream(run / "summary.json") << "{\"vehicle_km\": 3, \"vehicles\": 9, \"simulated_s\": 400}\n";
  std::ofstream(run / "conflicts.csv") << conflicts;
  return run;
}

// writeTables' error, or "(written)"
std::string tablesError(const Experiment& e, const std::vector<RunResult>& results, const fs::path& dir) {
  try {
    writeTables(e, results, dir);
  } catch (const std::runtime_error& ex) {
    return ex.what();
  }
  return "(written)";
}

// A done run's conflicts.csv and exposure.csv are read whole or not at all: a file missing, cut
// short, with a row of the wrong width or a cell that is not a number is an error of one line
// naming the file and the line, never rows skipped or zeros.
TEST(BatchTables, BrokenRunFilesAreErrorsNamingFileAndLine) {
  const fs::path dir = fs::temp_directory_path() / ("stsim_tables_broken_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path f = dir / "conflicts.csv";
  const std::string head = "first,second,type,begin,min_ttc\n";
  // the error reading f (after writing `text` to it, unless none)
  auto error = [&](const std::optional<std::string>& text, double warmup) {
    if (text) std::ofstream(f, std::ios::binary) << *text;
    try {
      readRunConflicts(f, warmup);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("(read)");
  };
  // whole files read as they were
  EXPECT_EQ(error(head + "a,b,rear_end,60,1\na,c,proximity,61,\n", 0.0), "(read)");
  const RunConflicts ok = readRunConflicts(f, 0.0);
  ASSERT_EQ(ok.rows.size(), 1u);  // proximity is not a conflict type
  EXPECT_EQ(ok.rows[0].values, (std::vector<double>{1.0}));
  EXPECT_EQ(error(head, 0.0), "(read)");  // no conflicts

  EXPECT_EQ(error(head + "a,b,rear_end,60,1\na,b,rear_end,6", 0.0),
            f.string() + ":3: the last line is cut short (no line end)");
  EXPECT_EQ(error(head + "a,b,rear_end,60,1\na,b,rear_end,60\n", 0.0), f.string() + ":3: 4 fields, the header has 5");
  EXPECT_EQ(error(head + "\na,b,rear_end,60,1\n", 0.0), f.string() + ":2: 1 fields, the header has 5");
  EXPECT_EQ(error(head + "a,b,rear_end,60,1\na,b,lane_change,61,fast\n", 0.0),
            f.string() + ":3: min_ttc: \"fast\" is not a number");
  EXPECT_EQ(error(head + "a,b,crossing,sixty,1\n", 10.0), f.string() + ":2: begin: \"sixty\" is not a number");
  EXPECT_EQ(error("first,second,begin\n", 0.0), f.string() + ": no type column (not a highway conflicts.csv)");
  fs::remove(f);
  fs::create_directories(f);  // not a file
  EXPECT_EQ(error(std::nullopt, 0.0).rfind(f.string() + ": is a directory", 0), 0u) << error(std::nullopt, 0.0);
  fs::remove(f);
  EXPECT_EQ(error(std::nullopt, 0.0), f.string() + ": no such file");
  EXPECT_EQ(error("", 0.0), f.string() + ":1: empty, no header line");

  // exposure.csv: every cell a number (through a warm-up's writeTables)
  Experiment e;
  e.warmup = 50.0;
  e.seeds = {1};
  const std::vector<RunSpec> specs = expandRuns(e);
  const fs::path run = doneRun(dir, specs[0], head + "a,b,rear_end,60,1\n");
  std::ofstream(run / "exposure.csv") << "time,vehicle_km,vehicles\n0,0,0\n10,,1\n";
  const std::vector<RunResult> results{loadRunResult(dir, specs[0])};
  EXPECT_EQ(tablesError(e, results, dir), (run / "exposure.csv").string() + ":3: vehicle_km: empty");
  fs::remove(run / "conflicts.csv");
  e.warmup = 0.0;
  EXPECT_EQ(tablesError(e, results, dir), (run / "conflicts.csv").string() + ": no such file");
  fs::remove_all(dir);
}

// A warm-up the run cannot honour is said, naming the file: no exposure.csv, or a run no longer
// than the warm-up.
TEST(BatchTables, WarmupWithoutExposureNamesTheFile) {
  Experiment e;
  e.command = "highway";
  e.warmup = 50.0;
  e.seeds = {1};
  const std::vector<RunSpec> specs = expandRuns(e);
  const fs::path dir = fs::temp_directory_path() / ("stsim_warmup_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path run = doneRun(dir, specs[0], "first,second,type,begin,min_ttc\na,b,rear_end,60,1\n");
  const std::vector<RunResult> results{loadRunResult(dir, specs[0])};
  EXPECT_EQ(tablesError(e, results, dir), (run / "exposure.csv").string() + ": no such file");
  e.warmup = 400.0;
  const std::string late = tablesError(e, results, dir);
  EXPECT_NE(late.find("not longer than the experiment's warmup"), std::string::npos) << late;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace st::batch
