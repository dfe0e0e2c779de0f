// stsim batch end to end, on short SUMO runs of the shipped motorway: the same experiment gives the
// same runs.csv (timing columns aside) with 1 job, 2 jobs, 2 shards merged and MPI; a batch killed
// mid-way resumes without redoing finished runs or duplicating rows.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "files.hpp"
#include "process.hpp"
#include "svg_markers.hpp"

namespace st::batch {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) { return st::test::freshDir("batch_e2e", name); }
using st::test::slurp;

// A child process in its own process group (so the whole batch, runs included, can be killed),
// output to files in `dir`.
using st::test::Process;
const Process::Options kOwnGroup{{}, true};

int runStsim(const std::vector<std::string>& args, const fs::path& logDir, std::string* err = nullptr) {
  std::vector<std::string> argv{STSIM_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  Process p(argv, logDir, kOwnGroup);
  const int code = p.wait();
  if (err) *err = p.err();
  return code;
}

// A CSV file as rows of cells (a trailing comma is an empty last cell).
std::vector<std::vector<std::string>> csvRows(const fs::path& csv) {
  std::vector<std::vector<std::string>> t;
  std::istringstream in(slurp(csv));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    t.push_back(cells);
  }
  return t;
}

// The cell of column `name` in row `row` (a failure, and "", when there is no such column).
std::string csvCell(const std::vector<std::vector<std::string>>& t, const std::string& name, std::size_t row = 1) {
  const auto at = std::find(t[0].begin(), t[0].end(), name);
  EXPECT_NE(at, t[0].end()) << name;
  return at == t[0].end() ? std::string() : t[row][static_cast<std::size_t>(at - t[0].begin())];
}

// runs.csv as rows of cells, without the columns that time the run (they differ between runs).
std::vector<std::vector<std::string>> tableWithoutTimings(const fs::path& csv) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(csv));
  std::string line;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    if (keep.empty())
      for (const auto& name : cells)
        keep.push_back(name.find("wall") == std::string::npos && name.find("seconds") == std::string::npos);
    std::vector<std::string> kept;
    for (std::size_t i = 0; i < cells.size() && i < keep.size(); ++i)
      if (keep[i]) kept.push_back(cells[i]);
    rows.push_back(kept);
  }
  return rows;
}

// 2 detectors x 2 demand scales x 2 seeds of 30 s on the motorway: 8 short runs.
fs::path writeExperiment(const fs::path& dir, double end = 30) {
  const fs::path file = dir / "experiment.yaml";
  std::ofstream(file) << "name: e2e\ncommand: highway\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/motorway/scenario.yaml\n"
                         "sweep:\n  detector: [five, box]\n  demand_scale: [0.5, 1.0]\n"
                         "fixed:\n  end: "
                      << end << "\n  action: none\nseeds: 2\n";
  return file;
}

TEST(BatchEndToEnd, JobsShardsAndMpiGiveTheSameRuns) {
  const auto dir = freshDir("same");
  const auto exp = writeExperiment(dir).string();
  std::string err;
  ASSERT_EQ(runStsim({"batch", exp, "--out", (dir / "j1").string(), "--jobs", "1", "--no-plots"}, dir, &err), 0) << err;
  const auto reference = tableWithoutTimings(dir / "j1/runs.csv");
  ASSERT_EQ(reference.size(), 9u);  // header + 8 runs
  ASSERT_GT(reference[0].size(), 20u);
  for (std::size_t i = 1; i < reference.size(); ++i) EXPECT_EQ(reference[i][2], "done") << i;

  ASSERT_EQ(runStsim({"batch", exp, "--out", (dir / "j2").string(), "--jobs", "2", "--no-plots"}, dir, &err), 0) << err;
  EXPECT_EQ(tableWithoutTimings(dir / "j2/runs.csv"), reference);
  EXPECT_EQ(slurp(dir / "j2/summary.csv").empty(), false);

  for (const char* shard : {"1/2", "2/2"}) {
    const std::string out = (dir / (std::string("shard") + shard[0])).string();
    ASSERT_EQ(runStsim({"batch", exp, "--out", out, "--shard", shard, "--jobs", "2", "--no-plots"}, dir, &err), 0)
        << err;
  }
  // a shard alone holds half the runs
  EXPECT_LT(tableWithoutTimings(dir / "shard1/runs.csv").size(), reference.size());
  ASSERT_EQ(runStsim({"batch", "merge", (dir / "shard1").string(), (dir / "shard2").string(), "--out",
                      (dir / "merged").string(), "--no-plots"},
                     dir, &err),
            0)
      << err;
  EXPECT_EQ(tableWithoutTimings(dir / "merged/runs.csv"), reference);

  // summary.csv holds no timing columns' means only where runs agree; compare its deterministic part
  const auto summaryRef = tableWithoutTimings(dir / "j1/summary.csv");
  EXPECT_EQ(tableWithoutTimings(dir / "merged/summary.csv"), summaryRef);
  // paired comparisons: box vs five at each scale, 1.0 vs 0.5 for each detector
  const auto pairedRef = tableWithoutTimings(dir / "j1/paired.csv");
  ASSERT_EQ(pairedRef.size(), 5u);
  EXPECT_EQ(pairedRef[1][4], "2");  // both seeds paired
  EXPECT_EQ(tableWithoutTimings(dir / "merged/paired.csv"), pairedRef);

  // Under AddressSanitizer (CI): OpenMPI's own allocations held at MPI_Finalize are suppressed
  // by library name (.ci/lsan.supp), which needs the full unwinder (OpenMPI has no frame
  // pointers: the fast one stops in it, unnamed) and its plugins kept loaded to the end.
  std::vector<std::string> mpiEnv{"OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1", "OMPI_MCA_plm_rsh_agent=",
                                  "OMPI_MCA_mca_base_component_disable_dlclose=1",
                                  "PMIX_MCA_mca_base_component_disable_dlclose=1"};
  if (const char* asan = std::getenv("ASAN_OPTIONS"))
    mpiEnv.push_back(std::string("ASAN_OPTIONS=") + asan + ":fast_unwind_on_malloc=0");
  Process mpi({"mpirun", "-np", "2", STSIM_BINARY, "batch", exp, "--mpi", "--out", (dir / "mpi").string(), "--no-plots"},
              dir, {mpiEnv, true});
  ASSERT_EQ(mpi.wait(), 0) << mpi.err();
  EXPECT_EQ(tableWithoutTimings(dir / "mpi/runs.csv"), reference);
  EXPECT_EQ(tableWithoutTimings(dir / "mpi/summary.csv"), summaryRef);
  EXPECT_EQ(tableWithoutTimings(dir / "mpi/paired.csv"), pairedRef);
}

TEST(BatchEndToEnd, KilledBatchResumesWithoutRedoingRuns) {
  const auto dir = freshDir("resume");
  const auto exp = writeExperiment(dir, 60).string();
  const fs::path out = dir / "out";
  std::map<std::string, fs::file_time_type> finished;
  {
    Process batch({STSIM_BINARY, "batch", exp, "--out", out.string(), "--jobs", "1", "--no-plots"}, dir, kOwnGroup);
    // kill the whole process group (batch and its current run) once two runs have finished
    for (int i = 0; i < 600; ++i) {
      int done = 0;
      if (fs::exists(out / "runs"))
        for (const auto& d : fs::directory_iterator(out / "runs")) done += fs::exists(d.path() / "result.yaml");
      if (done >= 2) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    batch.killGroup();
    batch.wait();
  }
  for (const auto& d : fs::directory_iterator(out / "runs"))
    if (fs::exists(d.path() / "result.yaml")) finished[d.path().filename().string()] = fs::last_write_time(d.path() / "summary.json");
  ASSERT_GE(finished.size(), 2u);
  ASSERT_LT(finished.size(), 8u) << "the batch ended before it was killed; make the runs longer";

  std::string err;
  ASSERT_EQ(runStsim({"batch", exp, "--out", out.string(), "--jobs", "2", "--no-plots"}, dir, &err), 0) << err;
  // finished runs were not run again
  for (const auto& [id, time] : finished) EXPECT_EQ(fs::last_write_time(out / "runs" / id / "summary.json"), time) << id;
  // one row per run, each once, nothing half-written left behind
  const auto table = tableWithoutTimings(out / "runs.csv");
  ASSERT_EQ(table.size(), 9u);
  std::set<std::string> ids;
  for (std::size_t i = 1; i < table.size(); ++i) {
    EXPECT_EQ(table[i][2], "done");
    ids.insert(table[i][1]);
  }
  EXPECT_EQ(ids.size(), 8u);
  for (const auto& d : fs::directory_iterator(out / "runs"))
    EXPECT_FALSE(d.path().filename().string().ends_with(".tmp")) << "left over: " << d.path();
  // and the result equals an uninterrupted batch
  ASSERT_EQ(runStsim({"batch", exp, "--out", (dir / "whole").string(), "--jobs", "2", "--no-plots"}, dir, &err), 0)
      << err;
  EXPECT_EQ(table, tableWithoutTimings(dir / "whole/runs.csv"));
}

// The report's conflict maps: one per parameter combination, all its seeds' conflicts in it (one
// SVG marker per conflicts.csv row of those runs, none for their warnings); the runs themselves
// draw none.
TEST(BatchEndToEnd, OneConflictMapPerCombination) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3-matplotlib not installed";
  const auto dir = freshDir("maps");
  const fs::path file = dir / "experiment.yaml";
  std::ofstream(file) << "name: maps\ncommand: highway\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/motorway/scenario.yaml\nsweep:\n  detector: [five, box]\n"
                         "fixed:\n  end: 200\n  action: none\nseeds: 2\n";  // 3-6 conflicts a run (none by 60 s)
  std::string err;
  ASSERT_EQ(runStsim({"batch", file.string(), "--out", (dir / "out").string(), "--jobs", "2"}, dir, &err), 0) << err;
  const auto table = tableWithoutTimings(dir / "out/runs.csv");
  ASSERT_EQ(table.size(), 5u);
  std::size_t detectorCol = 0;
  for (std::size_t i = 0; i < table[0].size(); ++i)
    if (table[0][i] == "detector") detectorCol = i;
  ASSERT_GT(detectorCol, 0u);
  std::map<std::string, long> rows;
  for (std::size_t r = 1; r < table.size(); ++r) {
    const fs::path run = dir / "out/runs" / table[r][1];
    EXPECT_FALSE(fs::exists(run / "conflict_map.png")) << run;
    const std::string csv = slurp(run / "conflicts.csv");
    rows[table[r][detectorCol]] += static_cast<long>(std::count(csv.begin(), csv.end(), '\n')) - 1;
  }
  ASSERT_EQ(rows.size(), 2u);
  long total = 0;
  for (const auto& [detector, n] : rows) {
    const fs::path map = dir / "out" / ("conflict_map_" + detector);
    ASSERT_TRUE(fs::exists(map.string() + ".png")) << map;
    EXPECT_EQ(slurp(map.string() + ".png").substr(0, 4), "\x89PNG");
    EXPECT_EQ(st::test::svgMarkers(slurp(map.string() + ".svg")), n) << detector;
    total += n;
  }
  EXPECT_GT(total, 0);
  const std::string report = slurp(dir / "out/report.md");
  EXPECT_NE(report.find("conflict_map_five.png"), std::string::npos);
  EXPECT_NE(report.find("conflict_map_box.svg"), std::string::npos);
}

// The number after `key` at or after `from` in a summary.json (read here by hand, not by the batch).
double numberAfter(const std::string& json, const std::string& key, std::size_t from = 0) {
  const auto at = json.find("\"" + key + "\": ", from);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no " << key << " in " << json.substr(0, 200);
    return 0.0;
  }
  return std::stod(json.substr(at + key.size() + 4));
}

// Hindsight in the batch: hindsight.csv pools each combination's seeds, so its counts are the sums
// of the runs' own summary.json counts and its shares their ratios; report.md shows them.
TEST(BatchEndToEnd, HindsightIsPooledPerCombinationAndReported) {
  const auto dir = freshDir("hindsight");
  const fs::path file = dir / "experiment.yaml";
  std::ofstream(file) << "name: hindsight\ncommand: highway\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/sublane/scenario.yaml\nsweep:\n  detector: [five, box]\n"
                         "fixed:\n  end: 60\n  action: none\nseeds: 2\n";
  std::string err;
  ASSERT_EQ(runStsim({"batch", file.string(), "--out", (dir / "out").string(), "--jobs", "2", "--no-plots"}, dir, &err), 0)
      << err;
  const auto runs = tableWithoutTimings(dir / "out/runs.csv");
  const auto h = tableWithoutTimings(dir / "out/hindsight.csv");
  ASSERT_EQ(runs.size(), 5u);
  ASSERT_EQ(h.size(), 3u);
  auto col = [](const std::vector<std::string>& header, const std::string& name) {
    const auto at = std::find(header.begin(), header.end(), name);
    EXPECT_NE(at, header.end()) << name;
    return static_cast<std::size_t>(at - header.begin());
  };
  double missed = 0;  // events not warned the lead time ahead, over all runs
  for (std::size_t row = 1; row < h.size(); ++row) {
    const std::string detector = h[row][0];
    double judged = 0, confirmed = 0, markerJudged = 0, markerConfirmed = 0, events = 0, warned = 0, markerRates = 0, rated = 0,
           collisions = 0;
    for (std::size_t r = 1; r < runs.size(); ++r) {
      if (runs[r][col(runs[0], "detector")] != detector) continue;
      const std::string json = slurp(dir / "out/runs" / runs[r][1] / "summary.json");
      const auto hs = json.find("\"hindsight\"");
      ASSERT_NE(hs, std::string::npos);
      judged += numberAfter(json, "judged", json.find("\"vehicle\"", hs));
      confirmed += numberAfter(json, "confirmed", json.find("\"vehicle\"", hs));
      markerJudged += numberAfter(json, "judged", json.find("\"lane_marker\"", hs));
      markerConfirmed += numberAfter(json, "confirmed", json.find("\"lane_marker\"", hs));
      events += numberAfter(json, "events", hs);
      warned += numberAfter(json, "warned", hs);
      // events.csv lists those near misses and the crossings, one a row, with the same verdicts
      double listed[2] = {0, 0}, listedWarned[2] = {0, 0};
      std::istringstream ev(slurp(dir / "out/runs" / runs[r][1] / "events.csv"));
      std::string line;
      std::getline(ev, line);
      EXPECT_EQ(line, "time,kind,ego,foe,x,y,lane,speed,gap,lateral_speed,warned,lead");
      while (std::getline(ev, line)) {
        std::vector<std::string> cells;
        std::istringstream ls(line);
        for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
        ASSERT_GE(cells.size(), 11u) << line;
        const int k = cells[1] == "near_miss" ? 0 : 1;
        EXPECT_TRUE(cells[1] == "near_miss" || cells[1] == "crossing") << line;
        listed[k] += 1;
        listedWarned[k] += cells[10] == "1";
        missed += cells[10] == "1" ? 0 : 1;
      }
      EXPECT_EQ(listed[0], numberAfter(json, "events", hs));
      EXPECT_EQ(listedWarned[0], numberAfter(json, "warned", hs));
      EXPECT_EQ(listed[1], numberAfter(json, "events", json.find("\"crossings\"", hs)));
      EXPECT_EQ(listedWarned[1], numberAfter(json, "warned", json.find("\"crossings\"", hs)));
      collisions += numberAfter(json, "events", json.find("\"collisions\": {"));
      EXPECT_EQ(numberAfter(json, "events", json.find("\"collisions\": {")), numberAfter(json, "sumo_collisions"));
      // a rate's one definition: each run's warnings over its vehicle-km, averaged over the runs
      markerRates += numberAfter(json, "lane_marker", json.find("\"by_kind\"")) / numberAfter(json, "vehicle_km");
      ++rated;
    }
    EXPECT_GT(judged, 0.0) << detector;       // there is something to pool
    EXPECT_GT(events, 0.0) << detector;
    EXPECT_EQ(std::stod(h[row][col(h[0], "vehicle.judged")]), judged) << detector;
    EXPECT_EQ(std::stod(h[row][col(h[0], "vehicle.confirmed")]), confirmed) << detector;
    EXPECT_NEAR(std::stod(h[row][col(h[0], "vehicle.confirmed_share")]), confirmed / judged, 1e-11) << detector;
    EXPECT_NEAR(std::stod(h[row][col(h[0], "lane_marker.confirmed_share")]), markerConfirmed / markerJudged, 1e-11);
    EXPECT_NEAR(std::stod(h[row][col(h[0], "lane_marker.per_vehicle_km")]), markerRates / rated, 1e-9) << detector;
    EXPECT_EQ(std::stod(h[row][col(h[0], "near_misses")]), events) << detector;
    EXPECT_NEAR(std::stod(h[row][col(h[0], "near_miss_recall")]), warned / events, 1e-11) << detector;
    EXPECT_EQ(std::stod(h[row][col(h[0], "collisions")]), collisions) << detector;
    // no hazards on this network: nothing judged, so no share (an empty cell, not 0 or 1)
    EXPECT_EQ(h[row][col(h[0], "hazard.judged")], "0");
    EXPECT_EQ(h[row][col(h[0], "hazard.confirmed_share")], "") << detector;
  }
  if (std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") != 0) return;
  ASSERT_EQ(runStsim({"batch", file.string(), "--out", (dir / "out").string()}, dir, &err), 0) << err;
  const std::string report = slurp(dir / "out/report.md");
  EXPECT_NE(report.find("## Hindsight"), std::string::npos) << report;
  EXPECT_NE(report.find("![confirmed share by warning kind and near-miss recall](hindsight.png)"), std::string::npos);
  EXPECT_NE(report.find("| five | "), std::string::npos);
  // the sublane network's first minute has crossings warned too late: listed to look at
  EXPECT_GT(missed, 0.0);
  const auto misses = report.find("## Missed events");
  ASSERT_NE(misses, std::string::npos) << report;
  EXPECT_NE(report.find("| crossing | ", misses), std::string::npos) << report.substr(misses);
  EXPECT_EQ(slurp(dir / "out/hindsight.png").substr(0, 4), "\x89PNG");
}

// warmup: hindsight.csv counts the warnings begun and the events at or after it, over the distance
// driven after it: against a recount of the run's own files, and less than the whole run's. The
// collisions from a collision_warnings.csv written here (the run had none): at 10 s (in the
// warm-up), 30 s warned 1.0 s ahead, 40 s warned 0.2 s ahead (less than hindsight's 0.5 s lead),
// 50 s not warned: 3 collisions, 1 warned, median lead 1.0 s.
TEST(BatchEndToEnd, WarmupLeavesWarningsAndEventsOutOfHindsight) {
  const auto dir = freshDir("warmup_hindsight");
  const fs::path file = dir / "experiment.yaml";
  const double warmup = 20.0;
  std::ofstream(file) << "name: warm\ncommand: highway\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/sublane/scenario.yaml\nfixed:\n  end: 60\n  action: none\n  detector: box\n"
                         "warmup: 20\nseeds: 1\n";
  std::string err;
  ASSERT_EQ(runStsim({"batch", file.string(), "--out", (dir / "out").string(), "--no-plots"}, dir, &err), 0) << err;
  fs::path run;
  for (const auto& d : fs::directory_iterator(dir / "out/runs")) run = d.path();
  std::ofstream(run / "collision_warnings.csv") << "time,collider,victim,collider_warned,lead_time_s\n"
                                                   "10,a,b,1,2\n30,c,d,1,1\n40,e,f,1,0.2\n50,g,h,0,\n";
  ASSERT_EQ(runStsim({"batch", "merge", (dir / "out").string(), "--out", (dir / "m").string(), "--no-plots"}, dir, &err), 0)
      << err;
  // the recount: warnings.csv by begin, events.csv by time
  const auto warnings = csvRows(run / "warnings.csv"), events = csvRows(run / "events.csv");
  std::map<std::string, double> count, judged, confirmed, whole;
  for (std::size_t i = 1; i < warnings.size(); ++i) {
    const std::string kind = csvCell(warnings, "kind", i);
    whole[kind] += 1;
    if (std::stod(csvCell(warnings, "begin", i)) < warmup) continue;
    count[kind] += 1;
    judged[kind] += csvCell(warnings, "verdict", i).empty() ? 0 : 1;
    confirmed[kind] += csvCell(warnings, "verdict", i) == "confirmed";
  }
  double crossings = 0, crossingsWarned = 0, allCrossings = 0;
  for (std::size_t i = 1; i < events.size(); ++i) {
    if (csvCell(events, "kind", i) != "crossing") continue;
    allCrossings += 1;
    if (std::stod(csvCell(events, "time", i)) < warmup) continue;
    crossings += 1;
    crossingsWarned += csvCell(events, "warned", i) == "1";
  }
  const auto h = csvRows(dir / "m/hindsight.csv"), runsCsv = csvRows(dir / "m/runs.csv");
  ASSERT_EQ(h.size(), 2u);
  const double km = std::stod(csvCell(runsCsv, "exposure.vehicle_km"));
  EXPECT_LT(km, std::stod(csvCell(runsCsv, "vehicle_km")));
  EXPECT_EQ(std::stod(csvCell(h, "vehicle_km")), km);
  EXPECT_LT(count["lane_marker"], whole["lane_marker"]);  // the warm-up leaves something out
  EXPECT_GT(count["lane_marker"], 0.0);
  for (const char* kind : {"vehicle", "curb", "lane_marker"}) {
    EXPECT_EQ(std::stod(csvCell(h, std::string(kind) + ".judged")), judged[kind]) << kind;
    EXPECT_EQ(std::stod(csvCell(h, std::string(kind) + ".confirmed")), confirmed[kind]) << kind;
    EXPECT_NEAR(std::stod(csvCell(h, std::string(kind) + ".per_vehicle_km")), count[kind] / km, 1e-9) << kind;
  }
  EXPECT_LT(crossings, allCrossings);
  EXPECT_EQ(std::stod(csvCell(h, "crossings")), crossings);
  EXPECT_EQ(std::stod(csvCell(h, "crossings_warned")), crossingsWarned);
  EXPECT_EQ(csvCell(h, "collisions"), "3");
  EXPECT_EQ(csvCell(h, "collisions_warned"), "1");
  EXPECT_EQ(csvCell(h, "collision_lead_median_s"), "1");
  // runs.csv keeps the whole run's figures beside them
  EXPECT_EQ(std::stod(csvCell(runsCsv, "hindsight.crossings.events")), allCrossings);
  EXPECT_EQ(std::stod(csvCell(runsCsv, "after_warmup.hindsight.crossings.events")), crossings);
}

// networks/bicycles in a batch with a warm-up: each run's counted.with_bicycle.<type> equals a recount
// of its conflicts.csv (the rows of a conflict type begun at or after the warm-up with a bicycle
// either side), its rate is that over the exposure, and summary.json's whole-run
// conflicts.with_bicycle reaches runs.csv flattened, equal to the recount without the warm-up.
TEST(BatchEndToEnd, BicycleConflictsAreCountedApartInTheTables) {
  const auto dir = freshDir("bicycles");
  const fs::path file = dir / "experiment.yaml";
  // bicycle conflicts begin at 238, 314 and 411 s (seed 1) and 222, 530-535 and 586 s (seed 2)
  const double warmup = 300.0;
  std::ofstream(file) << "name: bikes\ncommand: highway\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/bicycles/scenario.yaml\nfixed:\n  end: 600\nwarmup: 300\nseeds: 2\n";
  std::string err;
  ASSERT_EQ(runStsim({"batch", file.string(), "--out", (dir / "out").string(), "--no-plots"}, dir, &err), 0) << err;
  const auto runsCsv = csvRows(dir / "out/runs.csv");
  ASSERT_EQ(runsCsv.size(), 3u);
  const std::vector<std::string> types{"rear_end", "lane_change", "crossing", "pedestrian"};
  double bikesAfter = 0, bikesWhole = 0, all = 0;
  for (std::size_t r = 1; r < runsCsv.size(); ++r) {
    const auto conflicts = csvRows(dir / "out/runs" / csvCell(runsCsv, "run_id", r) / "conflicts.csv");
    std::map<std::string, double> after, whole;
    for (std::size_t i = 1; i < conflicts.size(); ++i) {
      const std::string type = csvCell(conflicts, "type", i);
      if (std::find(types.begin(), types.end(), type) == types.end()) continue;
      if (csvCell(conflicts, "first_class", i) != "bicycle" && csvCell(conflicts, "second_class", i) != "bicycle") continue;
      whole[type] += 1, whole["all"] += 1;
      if (std::stod(csvCell(conflicts, "begin", i)) >= warmup) after[type] += 1, after["all"] += 1;
    }
    const double km = std::stod(csvCell(runsCsv, "exposure.vehicle_km", r));
    for (const std::string& t : {std::string("all"), types[0], types[1], types[2], types[3]}) {
      EXPECT_EQ(std::stod(csvCell(runsCsv, "counted.with_bicycle." + t, r)), after[t]) << "run " << r << " " << t;
      EXPECT_NEAR(std::stod(csvCell(runsCsv, "rate.per_vehicle_km.with_bicycle." + t, r)), after[t] / km, 1e-9) << t;
    }
    EXPECT_EQ(std::stod(csvCell(runsCsv, "conflicts.with_bicycle.count", r)), whole["all"]) << "run " << r;
    for (const std::string& t : types)
      EXPECT_EQ(std::stod(csvCell(runsCsv, "conflicts.with_bicycle.by_type." + t, r)), whole[t]) << "run " << r << " " << t;
    EXPECT_LE(after["all"], std::stod(csvCell(runsCsv, "counted.all", r)));
    bikesAfter += after["all"], bikesWhole += whole["all"], all += std::stod(csvCell(runsCsv, "counted.all", r));
  }
  EXPECT_GT(bikesAfter, 0.0);        // not vacuous: bicycle conflicts after the warm-up
  EXPECT_LT(bikesAfter, bikesWhole);  // and the warm-up leaves some out
  // summary.csv: the mean over the two seeds
  const auto summary = csvRows(dir / "out/summary.csv");
  EXPECT_NEAR(std::stod(csvCell(summary, "counted.with_bicycle.all.mean")), bikesAfter / 2.0, 1e-9);
}

// validate_ssm: the runs' agreement with SUMO's SSM device reaches runs.csv as ssm.* columns, the
// same numbers as each run's validation.json.
TEST(BatchEndToEnd, ResumingIntoAnotherExperimentsFolderIsRefused) {
  const auto dir = freshDir("resume_other");
  const fs::path out = dir / "out";
  std::string err;
  const fs::path small = dir / "small.yaml";
  std::ofstream(small) << "name: a\nbase: " << STSIM_SOURCE_DIR
                       << "/networks/motorway/scenario.yaml\nsweep:\n  detector: [five]\nfixed:\n  end: 5\nseeds: 1\n";
  ASSERT_EQ(runStsim({"batch", small.string(), "--out", out.string(), "--no-plots"}, dir, &err), 0) << err;
  const std::string runs = slurp(out / "runs.csv"), record = slurp(out / "experiment.yaml");
  // the same sweep and seeds with another fixed end: the run ids match, the runs do not
  const fs::path longer = dir / "longer.yaml";
  std::ofstream(longer) << "name: a\nbase: " << STSIM_SOURCE_DIR
                        << "/networks/motorway/scenario.yaml\nsweep:\n  detector: [five]\nfixed:\n  end: 10\nseeds: 1\n";
  EXPECT_EQ(runStsim({"batch", longer.string(), "--out", out.string(), "--no-plots"}, dir, &err), 1);
  EXPECT_NE(err.find("holds the runs of another experiment"), std::string::npos) << err;
  EXPECT_EQ(slurp(out / "runs.csv"), runs);
  EXPECT_EQ(slurp(out / "experiment.yaml"), record);
  // a run's error names its files where they are after the run, not the vanished .tmp folder
  const fs::path broken = dir / "broken.yaml";
  std::ofstream(broken) << "name: b\nbase: " << STSIM_SOURCE_DIR
                        << "/networks/motorway/scenario.yaml\nsweep:\n  detector: [five]\nfixed:\n  end: 5\n"
                           "  sumocfg: nowhere.sumocfg\nseeds: 1\n";
  EXPECT_EQ(runStsim({"batch", broken.string(), "--out", (dir / "b").string(), "--no-plots"}, dir, &err), 1);
  const std::string table = slurp(dir / "b/runs.csv");
  EXPECT_EQ(table.find(".tmp"), std::string::npos) << table;
  EXPECT_NE(table.find((dir / "b/runs").string()), std::string::npos) << table;
}

TEST(BatchEndToEnd, AnEditedBaseScenarioIsRunAgainNotReused) {
  // a pool break (no SUMO, a second a run): the run ids name the parameters, not the base's
  // content; a base struck at 8 m/s edited to 4 m/s must not leave the 8 m/s runs "done"
  const auto dir = freshDir("stale");
  const fs::path base = dir / "break.yaml", out = dir / "out", exp = dir / "exp.yaml";
  std::string text = slurp(fs::path(STSIM_SOURCE_DIR) / "models/pool/scenarios/break.yaml");
  const auto at = text.find("speed: 8.0");
  ASSERT_NE(at, std::string::npos);
  std::ofstream(base) << text;
  std::ofstream(exp) << "name: stale\ncommand: pool\nbase: " << base.string() << "\nsweep:\n  until: [1.0]\nseeds: 2\n";
  std::string err;
  ASSERT_EQ(runStsim({"batch", exp.string(), "--out", out.string(), "--no-plots"}, dir, &err), 0) << err;
  std::vector<fs::path> runs;
  for (const auto& d : fs::directory_iterator(out / "runs")) runs.push_back(d.path());
  ASSERT_EQ(runs.size(), 2u);
  for (const auto& r : runs) EXPECT_NE(slurp(r / "scenario.yaml").find("speed: 8"), std::string::npos);
  // unchanged: both reused
  ASSERT_EQ(runStsim({"batch", exp.string(), "--out", out.string(), "--no-plots"}, dir, &err), 0) << err;
  EXPECT_EQ(err.find("stale"), std::string::npos) << err;
  // edited: both run again, on the new base
  text.replace(at, 10, "speed: 4.0");
  std::ofstream(base) << text;
  ASSERT_EQ(runStsim({"batch", exp.string(), "--out", out.string(), "--no-plots"}, dir, &err), 0) << err;
  EXPECT_NE(err.find("stale (its scenario changed since it ran): run again"), std::string::npos) << err;
  for (const auto& r : runs) {
    const std::string scenario = slurp(r / "scenario.yaml");
    EXPECT_NE(scenario.find("speed: 4"), std::string::npos) << r << " still holds the old scenario:\n" << scenario;
  }
}

TEST(BatchEndToEnd, ARunawaySweepIsRefusedListToo) {
  const auto dir = freshDir("runaway");
  const fs::path exp = dir / "exp.yaml";
  std::ofstream(exp) << "name: runaway\ncommand: pool\nbase: " << STSIM_SOURCE_DIR
                     << "/models/pool/scenarios/break.yaml\nsweep:\n  until: [1.0, 2.0, 3.0]\nseeds: 2\n";
  std::string err;
  EXPECT_EQ(runStsim({"batch", exp.string(), "--list", "--max-runs", "5"}, dir, &err), 1);
  EXPECT_NE(err.find("the experiment makes 6 runs (3 until x 2 seeds), more than the limit of 5 (raise it with --max-runs N)"),
            std::string::npos)
      << err;
  EXPECT_EQ(slurp(dir / "stdout.txt"), "") << "runs were listed";
  EXPECT_EQ(runStsim({"batch", exp.string(), "--list", "--max-runs", "6"}, dir, &err), 0) << err;
  const std::string listed = slurp(dir / "stdout.txt");
  EXPECT_EQ(std::count(listed.begin(), listed.end(), '\n'), 6) << listed;
  EXPECT_EQ(runStsim({"batch", exp.string(), "--list", "--max-runs", "0"}, dir, &err), 2);
  EXPECT_NE(err.find("--max-runs: expected a count >= 1, got 0"), std::string::npos) << err;
}

TEST(BatchEndToEnd, ListChecksJobsAndShardAsARunWould) {
  const auto dir = freshDir("list_options");
  const fs::path exp = dir / "exp.yaml";
  std::ofstream(exp) << "name: listopts\ncommand: pool\nbase: " << STSIM_SOURCE_DIR
                     << "/models/pool/scenarios/break.yaml\nsweep:\n  until: [1.0, 2.0]\nseeds: 2\n";
  std::string err;
  for (const char* jobs : {"0", "-3"}) {
    EXPECT_EQ(runStsim({"batch", exp.string(), "--list", "--jobs", jobs}, dir, &err), 2) << jobs;
    EXPECT_NE(err.find("--jobs must be between 1 and 1024"), std::string::npos) << err;
  }
  for (const char* shard : {"5/4", "0/0"}) {
    EXPECT_EQ(runStsim({"batch", exp.string(), "--list", "--shard", shard}, dir, &err), 2) << shard;
    EXPECT_NE(err.find("--shard wants I/N with 1 <= I <= N, got '" + std::string(shard) + "'"), std::string::npos) << err;
  }
  // a shard lists its own runs
  EXPECT_EQ(runStsim({"batch", exp.string(), "--list", "--shard", "1/2"}, dir, &err), 0) << err;
  const std::string listed = slurp(dir / "stdout.txt");
  EXPECT_EQ(std::count(listed.begin(), listed.end(), '\n'), 2) << listed;
}

TEST(BatchEndToEnd, AFolderInUseIsRefusedNamingItsBatch) {
  const auto dir = freshDir("folder_lock");
  const fs::path exp = dir / "exp.yaml", out = dir / "out";
  std::ofstream(exp) << "name: lock\ncommand: pool\nbase: " << STSIM_SOURCE_DIR
                     << "/models/pool/scenarios/break.yaml\nsweep:\n  until: [1.0]\nseeds: 1\n";
  // this test holds the folder as a running batch does
  fs::create_directories(out);
  const int fd = ::open((out / ".batch.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const std::string pid = std::to_string(::getpid()) + "\n";
  ASSERT_EQ(::write(fd, pid.data(), pid.size()), static_cast<ssize_t>(pid.size()));
  std::string err;
  EXPECT_EQ(runStsim({"batch", exp.string(), "--out", out.string(), "--no-plots"}, dir, &err), 1);
  EXPECT_NE(err.find(out.string() + ": folder in use by pid " + std::to_string(::getpid())), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out / "experiment.yaml")) << "the second batch wrote into the folder";
  EXPECT_FALSE(fs::exists(out / "runs")) << "the second batch wrote into the folder";
  ::close(fd);
  EXPECT_EQ(runStsim({"batch", exp.string(), "--out", out.string(), "--no-plots"}, dir, &err), 0) << err;
}

TEST(BatchEndToEnd, SigtermToTheBatchAloneStopsItsRuns) {
  const auto dir = freshDir("sigterm");
  const fs::path file = dir / "long.yaml";
  // one run of the ring for 10 simulated hours: minutes of work, far longer than the test waits
  std::ofstream(file) << "name: long\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/ring/scenario.yaml\nsweep:\n  detector: [five]\nfixed:\n  end: 36000\nseeds: 1\n";
  const fs::path out = dir / "out";
  Process batch({STSIM_BINARY, "batch", file.string(), "--out", out.string(), "--jobs", "1", "--no-plots"}, dir, kOwnGroup);
  // wait until the run has started writing (its .tmp folder has a warnings.csv)
  const auto giveUp = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  bool started = false;
  while (!started && std::chrono::steady_clock::now() < giveUp) {
    if (fs::exists(out / "runs"))
      for (const auto& d : fs::directory_iterator(out / "runs"))
        started = started || fs::exists(d.path() / "warnings.csv");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(started) << batch.err();
  const auto t0 = std::chrono::steady_clock::now();
  batch.signal(SIGTERM);
  EXPECT_EQ(batch.wait(), 143) << batch.err();
  // the run was told to stop, not waited for (it would take minutes)
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0);
  EXPECT_TRUE(fs::exists(out / "runs.csv"));
}

// A done run's files broken after the batch (cut short, a row of the wrong width, a cell that is
// not a number, deleted): building the tables again (stsim batch merge) stops with exit 1 and one
// line naming the file and the line, and writes no tables from the half it could read.
TEST(BatchEndToEnd, BrokenRunFilesStopTheTablesNamingFileAndLine) {
  const auto dir = freshDir("broken_files");
  const fs::path file = dir / "experiment.yaml";
  std::ofstream(file) << "name: broken\ncommand: highway\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/motorway/scenario.yaml\nfixed:\n  end: 30\n  action: none\nwarmup: 5\nseeds: 1\n";
  std::string err;
  ASSERT_EQ(runStsim({"batch", file.string(), "--out", (dir / "out").string(), "--no-plots"}, dir, &err), 0) << err;
  fs::path run;
  for (const auto& d : fs::directory_iterator(dir / "out/runs")) run = d.path();
  const std::string conflicts = slurp(run / "conflicts.csv"), exposure = slurp(run / "exposure.csv");
  const auto lines = [](const std::string& text) { return std::count(text.begin(), text.end(), '\n'); };
  ASSERT_GE(lines(exposure), 3) << exposure;
  struct Case {
    const char* file;
    std::string text;   // the file's new content
    std::string error;  // after "<the file>"
  };
  const std::string exposureHead = exposure.substr(0, exposure.find('\n') + 1);
  const std::vector<Case> cases{
      {"conflicts.csv", conflicts.substr(0, conflicts.size() - 1),
       std::string(":") += std::to_string(lines(conflicts)) + ": the last line is cut short (no line end)"},
      {"exposure.csv", exposureHead + "0,0\n", ":2: 2 fields, the header has 3"},
      {"exposure.csv", exposureHead + "0,0,0\n1,x,2\n", ":3: vehicle_km: \"x\" is not a number"},
      {"conflicts.csv", "", ":1: empty, no header line"},
  };
  int k = 0;
  for (const Case& c : cases) {
    const std::string merged = (dir / "m").string() += std::to_string(k++);
    fs::remove_all(merged);
    const std::string keep = slurp(run / c.file);
    std::ofstream(run / c.file, std::ios::binary) << c.text;
    EXPECT_EQ(runStsim({"batch", "merge", (dir / "out").string(), "--out", merged, "--no-plots"}, dir, &err), 1) << c.error;
    const std::string named = (fs::path(merged) / "runs" / run.filename() / c.file).string();
    EXPECT_EQ(err, "stsim batch: error: " + named + c.error + "\n");
    EXPECT_FALSE(fs::exists(fs::path(merged) / "runs.csv")) << c.error;
    std::ofstream(run / c.file, std::ios::binary) << keep;
  }
  fs::remove(run / "conflicts.csv");
  EXPECT_EQ(runStsim({"batch", "merge", (dir / "out").string(), "--out", (dir / "gone").string(), "--no-plots"}, dir, &err), 1);
  EXPECT_EQ(err, "stsim batch: error: " + (dir / "gone/runs" / run.filename() / "conflicts.csv").string() + ": no such file\n");
}

TEST(BatchEndToEnd, MergeWithoutFoldersSaysWhatItNeeds) {
  const auto dir = freshDir("merge_none");
  std::string err;
  EXPECT_EQ(runStsim({"batch", "merge", "--out", (dir / "m").string()}, dir, &err), 2);
  EXPECT_NE(err.find("merge needs the batch output folders to merge"), std::string::npos) << err;
  EXPECT_EQ(err.find("--missing-dirs"), std::string::npos) << err;
}

TEST(BatchEndToEnd, SsmAgreementReachesRunsCsv) {
  const auto dir = freshDir("ssm");
  const fs::path file = dir / "experiment.yaml";
  std::ofstream(file) << "name: ssm\nbase: " << STSIM_SOURCE_DIR
                      << "/networks/motorway/scenario.yaml\nsweep:\n  detector: [five]\n"
                         "fixed:\n  end: 40\n  validate_ssm: true\nseeds: 1\n";
  std::string err;
  ASSERT_EQ(runStsim({"batch", file.string(), "--out", (dir / "out").string(), "--no-plots"}, dir, &err), 0) << err;
  const auto table = tableWithoutTimings(dir / "out/runs.csv");
  ASSERT_EQ(table.size(), 2u);
  std::map<std::string, std::string> row;
  for (std::size_t i = 0; i < table[0].size(); ++i) row[table[0][i]] = table[1][i];
  ASSERT_TRUE(row.count("ssm.following.matched_samples"));
  ASSERT_TRUE(row.count("ssm.detectors.box.recall"));
  const std::string json = slurp(dir / "out/runs" / table[1][1] / "validation.json");
  const auto at = json.find("\"matched_samples\": ");
  ASSERT_NE(at, std::string::npos) << json;
  EXPECT_EQ(std::stod(row["ssm.following.matched_samples"]), std::stod(json.substr(at + 19)));
  EXPECT_GT(std::stod(row["ssm.following.matched_samples"]), 100.0);
}

}  // namespace
}  // namespace st::batch
