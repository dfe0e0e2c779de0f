#include <stpool/study.hpp>

#include <cmath>
#include <iomanip>
#include <numbers>
#include <string>

#include <time.h>

#include <stpool/game.hpp>
#include <stpool/rack.hpp>

namespace st::pool {

namespace {

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

StudyRun measure(const Scenario& s, double duration) {
  Game game(s, simulatorConfig(s));
  StudyRun r;
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

}  // namespace

StudyRun runFig13Case(int mobile, const SpaceSpec& space, std::uint64_t seed, double duration, double speed) {
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
  return measure(s, duration);
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

void printFig13Study(std::ostream& os) {
  constexpr int kSeeds = 5;
  constexpr double kDuration = 10.0;
  os << "Fig. 13 redone: collision checks (ball-ball predictions) in " << kDuration
     << " s, 15 balls on a closed 2.54 x 1.27 m table,\n"
        "k of them moving at 1 m/s in random directions, the rest at rest; sums over "
     << kSeeds << " seeded layouts.\n\n";
  const SpaceSpec spaces[] = {spaceOf(SpaceKind::None), spaceOf(SpaceKind::Single), spaceOf(SpaceKind::Tree, 10),
                              spaceOf(SpaceKind::Tree, 5), spaceOf(SpaceKind::Tree, 2)};
  os << std::left << std::setw(8) << "mobile";
  for (const auto& sp : spaces) os << std::right << std::setw(12) << label(sp);
  os << "   | checks/event for the same columns\n";
  std::vector<std::vector<StudyRun>> all;
  for (int mobile : {2, 3, 5, 10, 15}) {
    std::vector<StudyRun> row;
    for (const auto& sp : spaces) {
      StudyRun sum;
      for (int seed = 1; seed <= kSeeds; ++seed) {
        const StudyRun r = runFig13Case(mobile, sp, static_cast<std::uint64_t>(seed), kDuration);
        sum.checks += r.checks;
        sum.events += r.events;
        sum.collisions += r.collisions;
        sum.wallSeconds += r.wallSeconds;
        sum.cpuSeconds += r.cpuSeconds;
      }
      row.push_back(sum);
    }
    os << std::left << std::setw(8) << mobile << std::right;
    for (const auto& r : row) os << std::setw(12) << r.checks;
    os << "   |";
    for (const auto& r : row)
      os << std::setw(7) << std::fixed << std::setprecision(2)
         << static_cast<double>(r.checks) / static_cast<double>(std::max<std::uint64_t>(r.events, 1));
    os << std::defaultfloat << "\n";
    all.push_back(row);
  }
  os << "\nCPU time (ms, this thread: the wall time on an idle core) for the same runs:\n" << std::left << std::setw(8)
     << "mobile";
  for (const auto& sp : spaces) os << std::right << std::setw(12) << label(sp);
  os << "\n";
  const int mobiles[] = {2, 3, 5, 10, 15};
  for (std::size_t i = 0; i < all.size(); ++i) {
    os << std::left << std::setw(8) << mobiles[i] << std::right << std::fixed << std::setprecision(2);
    for (const auto& r : all[i]) os << std::setw(12) << 1e3 * r.cpuSeconds;
    os << std::defaultfloat << "\n";
  }
  os << "wall clock (ms, with any preemption) at 15 mobile:" << std::fixed << std::setprecision(2);
  for (std::size_t j = 0; j < all.back().size(); ++j) os << " " << label(spaces[j]) << " " << 1e3 * all.back()[j].wallSeconds;
  os << std::defaultfloat << "\n";
  os << "events (collisions + space crossings) at 15 mobile:";
  for (std::size_t j = 0; j < all.back().size(); ++j) os << " " << label(spaces[j]) << " " << all.back()[j].events;
  os << "\nreport (Fig. 13) at 15 mobile: NS 16756, one space 17078, df 10 12081, df 5 10742, df 2 11210\n";

  // the lever on the boundary events: a wider fat box means fewer re-filings, more neighbours
  os << "\nThe fat-box margin (space.margin, fraction of the radius) at 15 mobile, same layouts:\n"
     << std::left << std::setw(8) << "margin" << std::right;
  const int marginDfs[] = {10, 5, 2};
  for (int df : marginDfs) os << std::setw(14) << ("df " + std::to_string(df) + " checks");
  os << std::setw(10) << "events" << std::setw(14) << "df 5 cpu ms" << "\n";
  for (double margin : {0.5, 1.0, 2.0, 4.0, 8.0}) {
    os << std::left << std::setw(8) << margin << std::right;
    std::uint64_t events = 0;
    double cpu5 = 0.0;
    for (int df : marginDfs) {
      SpaceSpec sp = spaceOf(SpaceKind::Tree, df);
      sp.margin = margin;
      StudyRun sum;
      for (int seed = 1; seed <= kSeeds; ++seed) {
        const StudyRun r = runFig13Case(15, sp, static_cast<std::uint64_t>(seed), kDuration);
        sum.checks += r.checks;
        sum.events += r.events;
        sum.cpuSeconds += r.cpuSeconds;
      }
      os << std::setw(14) << sum.checks;
      events = sum.events;
      if (df == 5) cpu5 = sum.cpuSeconds;
    }
    os << std::setw(10) << events << std::setw(14) << std::fixed << std::setprecision(2) << 1e3 * cpu5
       << std::defaultfloat << "\n";
  }

  // past the report: many balls
  os << "\nBeyond the report: n balls at 1 m/s in a square box with 10 % of its area covered, 1 s "
        "simulated (about 4 collisions per ball), seed 1.\n";
  const int dfs[] = {1, 2, 3, 5, 8, 12, 20};
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

}  // namespace st::pool
