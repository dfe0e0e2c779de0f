// pool_break: the 10 s break of models/pool/scenarios/break.yaml (or the scenario given as the
// first argument) on every space kind, printed side by side: wall time (median of repeats),
// events/s, collision checks. Every kind plays the same shot (tests/models/pool/versions_test.cpp),
// so the columns compare only the cost of finding it. Reference: version I, the report's one space.
#include <algorithm>
#include <cstdio>
#include <functional>
#include <iterator>
#include <cstdlib>
#include <string>
#include <vector>

#include <stcore/cpu_clock.hpp>
#include <stpool/game.hpp>
#include <stpool/report.hpp>
#include <stpool/scenario.hpp>
#include <stpool/study.hpp>

namespace {

struct Column {
  const char* label;
  st::SpaceKind kind;
  int df;
  int maxDepth = -1;  // space.max_depth (-1: the pool's automatic depth)
  bool autoFactor = false;
};

// decomposition_factor: auto against every fixed factor on one workload: the least CPU time of
// `repeats` runs each, the fixed ones and auto interleaved round by round.
struct Sweep {
  std::string name;
  std::function<st::pool::StudyRun(const st::pool::SpaceSpec&)> run;
  int repeats;
};

void printSweeps(const std::vector<Sweep>& sweeps) {
  using namespace st::pool;
  const int dfs[] = {2, 5, 10, 20, 40, 80};
  std::printf("\ndecomposition_factor: auto against the fixed factors (least CPU ms of the rounds; df 2-80 swept)\n\n");
  std::printf("%-22s %9s %9s %11s %9s %10s %9s %9s %9s\n", "workload", "single", "best df", "best ms",
              "worst df", "worst ms", "auto ms", "auto/best", "auto/I");
  for (const Sweep& w : sweeps) {
    std::vector<double> fixed(std::size(dfs), 1e300);
    double single = 1e300, automatic = 1e300;
    for (int k = 0; k < w.repeats; ++k) {
      SpaceSpec sp;
      sp.kind = st::SpaceKind::Single;
      single = std::min(single, w.run(sp).cpuSeconds);
      sp.kind = st::SpaceKind::Tree;
      for (std::size_t j = 0; j < std::size(dfs); ++j) {
        sp.decompositionFactor = dfs[j];
        fixed[j] = std::min(fixed[j], w.run(sp).cpuSeconds);
      }
      sp.autoFactor = true;
      automatic = std::min(automatic, w.run(sp).cpuSeconds);
    }
    const auto best = std::min_element(fixed.begin(), fixed.end()) - fixed.begin();
    const auto worst = std::max_element(fixed.begin(), fixed.end()) - fixed.begin();
    std::printf("%-22s %9.3f %9d %11.3f %9d %10.3f %9.3f %8.2fx %8.2fx\n", w.name.c_str(), 1e3 * single, dfs[best],
                1e3 * fixed[best], dfs[worst], 1e3 * fixed[worst], 1e3 * automatic, automatic / fixed[best],
                automatic / single);
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace st::pool;
  const std::string path =
      argc > 1 ? argv[1] : std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/break.yaml";
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 101;
  Scenario base;
  try {
    base = loadScenario(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pool_break: %s\n", e.what());
    return 1;
  }
  const Column columns[] = {{"none (NS)", st::SpaceKind::None, 0}, {"single (I)", st::SpaceKind::Single, 0},
                            {"tree df 2", st::SpaceKind::Tree, 2},  {"tree df 5", st::SpaceKind::Tree, 5},
                            {"tree df 10", st::SpaceKind::Tree, 10}, {"df 5 depth 1", st::SpaceKind::Tree, 5, 1},
                            {"tree df auto", st::SpaceKind::Tree, 0, -1, true},
                            {"cells 0.15m", st::SpaceKind::Cells, 0}};
  std::printf("pool_break: %s, %zu balls, %d repeats (median wall time)\n\n", path.c_str(), base.balls.size(),
              repeats);
  std::printf("%-12s %10s %9s %11s %11s %12s %9s %10s\n", "space", "wall ms", "events", "events/s", "collisions",
              "collisions/s", "checks", "vs single");
  struct Row {
    double wall;
    std::uint64_t events, collisions, checks;
  };
  std::vector<Row> rows;
  for (const Column& c : columns) {
    Scenario s = base;
    s.space.kind = c.kind;
    if (c.df > 0) s.space.decompositionFactor = c.df;
    s.space.autoFactor = c.autoFactor;
    s.space.cellSize = 0.15;
    if (c.maxDepth > 0) s.space.maxDepth = c.maxDepth;
    std::vector<double> walls;
    std::uint64_t events = 0, collisions = 0, checks = 0;
    for (int k = 0; k < repeats; ++k) {
      Game game(s, simulatorConfig(s));
      const RunRecord run = playScenario(game, s);
      walls.push_back(run.wallSeconds);
      events = game.simulator().counters().totalEvents();
      collisions = game.simulator().counters().collisions();
      checks = game.simulator().counters().pairChecks;
    }
    std::nth_element(walls.begin(), walls.begin() + walls.size() / 2, walls.end());
    rows.push_back(Row{walls[walls.size() / 2], events, collisions, checks});
  }
  const double singleWall = rows[1].wall;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    std::printf("%-12s %10.3f %9llu %11.3g %11llu %12.3g %9llu %9.2fx\n", columns[i].label, 1e3 * r.wall,
                static_cast<unsigned long long>(r.events), static_cast<double>(r.events) / r.wall,
                static_cast<unsigned long long>(r.collisions), static_cast<double>(r.collisions) / r.wall,
                static_cast<unsigned long long>(r.checks), r.wall / singleWall);
  }
  std::printf("\nevents include region events (tree: a ball's box starts or stops touching a leaf; cells: it\n"
              "reaches a cell outside its block); collisions are ball-ball, cushion, jaw and pocket events, the\n"
              "same in every column; \"vs single\" is wall time relative to version I (above 1: slower).\n"
              "\"df 5 depth 1\" is the least a subdivided space can do (one division into quadrants): its\n"
              "region events are the balls' crossings of the table's two middle lines, the floor of every tree.\n");
  if (argc > 3 && std::string(argv[3]) == "no-sweep") return 0;
  // the workloads for the automatic factor, each a CPU time (this thread's)
  auto scenarioRun = [](Scenario sc) {
    return [sc](const SpaceSpec& sp) {
      Scenario s = sc;
      s.space.kind = sp.kind;
      s.space.decompositionFactor = sp.decompositionFactor;
      s.space.autoFactor = sp.autoFactor;
      Game game(s, simulatorConfig(s));
      const double t0 = st::threadCpuSeconds();
      playScenario(game, s);
      StudyRun r;
      r.cpuSeconds = st::threadCpuSeconds() - t0;
      return r;
    };
  };
  std::vector<Sweep> sweeps;
  const int sweepRepeats = std::max(3, repeats / 5);
  sweeps.push_back({"this scenario", scenarioRun(base), sweepRepeats});
  try {
    sweeps.push_back({"practice.yaml", scenarioRun(loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/practice.yaml")),
                      sweepRepeats});
  } catch (const std::exception&) {
  }
  sweeps.push_back({"Fig. 13, 15 mobile", [](const SpaceSpec& sp) { return runFig13Case(15, sp, 1); }, 5});
  for (int n : {100, 1000, 10000})
    sweeps.push_back({"box " + std::to_string(n) + " balls, 1 s",
                      [n](const SpaceSpec& sp) { return runBoxCase(n, sp, 1, 1.0); }, n >= 10000 ? 2 : 3});
  printSweeps(sweeps);
  std::printf("\nauto/best: auto's CPU time over the best fixed factor's; auto/I: over version I's (one space).\n");
  return 0;
}
