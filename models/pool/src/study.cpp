#include <stpool/study.hpp>

#include <cmath>
#include <iomanip>
#include <numbers>
#include <span>
#include <string>

#include <stcore/cpu_clock.hpp>
#include <stpool/game.hpp>
#include <stpool/rack.hpp>

namespace st::pool {

namespace {

StudyRun measure(const Scenario& s, double duration, bool reportCounting = false) {
  Game game(s, simulatorConfig(s));
  StudyRun r;
  if (reportCounting) {
    // a run of its own: the recount after every event would dominate the timing
    Game counted(s, simulatorConfig(s));
    counted.coast(duration, [&](const PoolEvent&) {
      r.reportChecks += reportChecksNow(counted.simulator());
      r.reportBoundaryChecks += reportBoundaryChecksNow(counted.simulator());
    });
  }
  const double cpu0 = threadCpuSeconds();
  r.wallSeconds = wallSeconds([&] { game.coast(duration, [](const PoolEvent&) {}); });
  r.cpuSeconds = threadCpuSeconds() - cpu0;
  const SimulatorCounters& c = game.simulator().counters();
  r.checks = c.pairChecks;
  r.events = c.totalEvents();
  r.collisions = c.collisions();
  return r;
}

std::string label(const SpaceSpec& s) {
  switch (s.kind) {
    case SpaceKind::None: return "NS";
    case SpaceKind::Single: return "one space";
    case SpaceKind::Tree: return "df " + std::to_string(s.decompositionFactor);
    case SpaceKind::Cells: return "cells";
  }
  return "?";
}

SpaceSpec spaceOf(SpaceKind kind, int df = 5) {
  SpaceSpec s;
  s.kind = kind;
  s.decompositionFactor = df;
  return s;
}

Scenario fig13Scenario(int mobile, const SpaceSpec& space, std::uint64_t seed, double speed) {
  Scenario s;
  s.name = "fig13";
  s.table.pockets = false;
  s.space = space;
  Rng rng(seed);
  s.balls = randomBalls(makeTable(s.table), 15, 0.0, kBallRadius, kBallMass, 0.0, rng);
  for (int i = 0; i < mobile; ++i) {
    const double phi = 2.0 * std::numbers::pi * rng.uniform();
    s.balls[i].velocity = speed * Vec2(std::cos(phi), std::sin(phi));
  }
  return s;
}

}  // namespace

std::uint64_t reportChecksNow(const Simulator<2>& sim) {
  const auto& balls = sim.balls();
  const double t = sim.now();
  auto moving = [&](int b) { return balls[b].active && (balls[b].velocityAt(t).array() != 0.0).any(); };
  // n objects in a region, m of them moving: the pairs with a mover
  auto pairs = [](std::uint64_t n, std::uint64_t m) { return m * (n - 1) - m * (m - 1) / 2; };
  // (no space, the brute force: one notional leaf holding every active ball)
  const Space<2>* space = sim.space();
  std::uint64_t sum = 0;
  for (int leaf : space->leaves()) {
    std::uint64_t n = 0, m = 0;
    for (int b : space->objectsIn(leaf)) {
      ++n;
      m += moving(b) ? 1 : 0;
    }
    if (m > 0) sum += pairs(n, m);
  }
  return sum;
}

std::uint64_t reportBoundaryChecksNow(const Simulator<2>& sim) {
  const Space<2>* space = sim.space();
  if (space->kind() == SpaceKind::None) return 0;  // the report's NS has no regions to check against
  const auto& balls = sim.balls();
  const double t = sim.now();
  std::uint64_t sum = 0;
  for (int leaf : space->leaves())
    for (int b : space->objectsIn(leaf)) sum += (balls[b].velocityAt(t).array() != 0.0).any() ? 1 : 0;
  return sum;
}

StudyRun runFig13Case(int mobile, const SpaceSpec& space, std::uint64_t seed, double duration, double speed) {
  return measure(fig13Scenario(mobile, space, seed, speed), duration);
}

StudyRun runFig13CaseCounted(int mobile, const SpaceSpec& space, std::uint64_t seed, double duration) {
  return measure(fig13Scenario(mobile, space, seed, 1.0), duration, true);
}

StudyRun runBoxCase(int n, const SpaceSpec& space, std::uint64_t seed, double duration) {
  Scenario s;
  s.name = "box";
  s.table.pockets = false;
  // 10 % of the area covered by balls
  const double side = std::sqrt(n * std::numbers::pi * kBallRadius * kBallRadius / 0.10);
  s.table.width = s.table.height = side;
  s.space = space;
  Rng rng(seed);
  s.balls = randomBalls(makeTable(s.table), n, 1.0, kBallRadius, kBallMass, 0.0, rng);
  return measure(s, duration);
}

namespace {

// One Fig. 13 case summed over seeds 1..seeds.
StudyRun sumOverSeeds(int mobile, const SpaceSpec& sp, bool report, int seeds, double duration) {
  StudyRun sum;
  for (int seed = 1; seed <= seeds; ++seed) {
    const StudyRun r = report ? runFig13CaseCounted(mobile, sp, static_cast<std::uint64_t>(seed), duration)
                              : runFig13Case(mobile, sp, static_cast<std::uint64_t>(seed), duration);
    sum.checks += r.checks;
    sum.reportChecks += r.reportChecks;
    sum.reportBoundaryChecks += r.reportBoundaryChecks;
    sum.events += r.events;
    sum.collisions += r.collisions;
    sum.wallSeconds += r.wallSeconds;
    sum.cpuSeconds += r.cpuSeconds;
  }
  return sum;
}

// The Fig. 13 runs' times: CPU per case, wall and events at 15 mobile, the report's figures.
void printFig13Times(std::ostream& os, std::span<const SpaceSpec> spaces, const std::vector<std::vector<StudyRun>>& all) {
  os << "\nCPU time (ms, this thread: the wall time on an idle core) for the same runs:\n" << std::left << std::setw(8)
     << "mobile";
  for (const auto& sp : spaces) os << std::right << std::setw(11) << label(sp);
  os << "\n";
  const int mobiles[] = {2, 3, 5, 10, 15};
  for (std::size_t i = 0; i < all.size(); ++i) {
    os << std::left << std::setw(8) << mobiles[i] << std::right << std::fixed << std::setprecision(2);
    for (const auto& r : all[i]) os << std::setw(11) << 1e3 * r.cpuSeconds;
    os << std::defaultfloat << "\n";
  }
  os << "wall clock (ms, with any preemption) at 15 mobile:" << std::fixed << std::setprecision(2);
  for (std::size_t j = 0; j < all.back().size(); ++j) os << " " << label(spaces[j]) << " " << 1e3 * all.back()[j].wallSeconds;
  os << std::defaultfloat << "\n";
  os << "events (collisions + region crossings) at 15 mobile:";
  for (std::size_t j = 0; j < all.back().size(); ++j) os << " " << label(spaces[j]) << " " << all.back()[j].events;
  os << "\nreport (Fig. 13) at 15 mobile: NS 16756, one space 17078, df 10 12081, df 5 10742, df 2 11210\n";
}

// Past the report: many balls in a box, every space kind and a range of decomposition factors.
void printBoxStudy(std::ostream& os) {
  os << "\nBeyond the report: n balls at 1 m/s in a square box with 10 % of its area covered, 1 s "
        "simulated (about 4 collisions per ball), seed 1.\n";
  const int dfs[] = {1, 2, 3, 5, 8, 12, 20, 40, 80};
  for (int n : {100, 1000, 10000}) {
    os << "\nn = " << n << "\n"
       << std::left << std::setw(12) << "space" << std::right << std::setw(14) << "checks" << std::setw(10)
       << "events" << std::setw(14) << "checks/event" << std::setw(12) << "wall ms" << std::setw(12) << "cpu ms"
       << "\n";
    std::vector<SpaceSpec> row = {spaceOf(SpaceKind::None), spaceOf(SpaceKind::Single)};
    for (int df : dfs) row.push_back(spaceOf(SpaceKind::Tree, df));
    SpaceSpec cells = spaceOf(SpaceKind::Cells);
    cells.cellSize = 4.0 * kBallRadius;
    row.push_back(cells);
    double bestCpu = 1e300;
    int bestDf = 0;
    for (const auto& sp : row) {
      const StudyRun r = runBoxCase(n, sp, 1, 1.0);
      if (sp.kind == SpaceKind::Tree && r.cpuSeconds < bestCpu) {
        bestCpu = r.cpuSeconds;
        bestDf = sp.decompositionFactor;
      }
      os << std::left << std::setw(12) << (sp.kind == SpaceKind::Cells ? "cells 4r" : label(sp)) << std::right
         << std::setw(14) << r.checks << std::setw(10) << r.events << std::setw(14) << std::fixed
         << std::setprecision(2) << static_cast<double>(r.checks) / static_cast<double>(std::max<std::uint64_t>(r.events, 1))
         << std::setw(12) << 1e3 * r.wallSeconds << std::setw(12) << 1e3 * r.cpuSeconds << std::defaultfloat << "\n";
    }
    os << "df minimising CPU time: " << bestDf << "\n";
  }
}

}  // namespace

void printFig13Study(std::ostream& os, Counting counting) {
  constexpr int kSeeds = 5;
  constexpr double kDuration = 10.0;
  const bool report = counting == Counting::Report;
  os << "Fig. 13 redone: collision checks in " << kDuration
     << " s, 15 balls on a closed 2.54 x 1.27 m table,\n"
        "k of them moving at 1 m/s in random directions, the rest at rest; sums over "
     << kSeeds << " seeded layouts.\n"
        "event-driven: ball-ball predictions, each ball re-predicted at its own events (a region event\n"
        "checks only the balls of the leaves it enters).\n";
  if (report)
    os << "report: the report's counting, a global minimum step from one event (a collision or a region\n"
          "crossing) to the next, and after each every pair within a space with a ball moving in it (§2);\n"
          "+ walls: the same plus one check per moving ball and space it is in, against that space's\n"
          "boundary (§5.1: \"collision checks ... between objects and space boundaries\").\n";
  os << "\n";
  const SpaceSpec spaces[] = {spaceOf(SpaceKind::None), spaceOf(SpaceKind::Single), spaceOf(SpaceKind::Tree, 10),
                              spaceOf(SpaceKind::Tree, 5), spaceOf(SpaceKind::Tree, 2)};
  os << std::left << std::setw(8) << "mobile";
  for (const auto& sp : spaces) os << std::right << std::setw(11) << label(sp);
  if (report) {
    os << "   | report:";
    for (const auto& sp : spaces)
      if (sp.kind != SpaceKind::Single) os << std::right << std::setw(10) << label(sp);
    os << "   | + walls:";
    for (const auto& sp : spaces)
      if (sp.kind != SpaceKind::Single) os << std::right << std::setw(10) << label(sp);
  }
  os << "   | checks/event\n";
  std::vector<std::vector<StudyRun>> all;
  for (int mobile : {2, 3, 5, 10, 15}) {
    std::vector<StudyRun> row;
    for (const auto& sp : spaces) row.push_back(sumOverSeeds(mobile, sp, report, kSeeds, kDuration));
    os << std::left << std::setw(8) << mobile << std::right;
    for (const auto& r : row) os << std::setw(11) << r.checks;
    if (report) {
      os << "   |        ";
      for (std::size_t j = 0; j < row.size(); ++j)
        if (spaces[j].kind != SpaceKind::Single) os << std::setw(10) << row[j].reportChecks;
      os << "   |         ";
      for (std::size_t j = 0; j < row.size(); ++j)
        if (spaces[j].kind != SpaceKind::Single) os << std::setw(10) << row[j].reportChecks + row[j].reportBoundaryChecks;
    }
    os << "   |";
    for (const auto& r : row)
      os << std::setw(6) << std::fixed << std::setprecision(2)
         << static_cast<double>(r.checks) / static_cast<double>(std::max<std::uint64_t>(r.events, 1));
    os << std::defaultfloat << "\n";
    all.push_back(row);
  }
  printFig13Times(os, spaces, all);
  printBoxStudy(os);
}

}  // namespace st::pool
