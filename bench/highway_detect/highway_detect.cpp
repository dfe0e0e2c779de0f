// highway_detect: microseconds per tick and vehicle-updates per second of the smart-car monitor
// for each detector, with the cell broad phase and with all pairs, on synthetic traffic.
// Compares against: all pairs (same warnings, checked here at 1e3 and 1e4) and the issue-4 targets.
//
// Traffic: a divided motorway, two carriageways of three 3.2 m lanes (eastbound lane centres
// y = 0, 3.2, 6.4; westbound 20.8, 17.6, 14.4; a 4.8 m median), 25 vehicles per km per lane (time headways ~1.2-1.8 s at
// 25-35 m/s), 10% trucks, drivers weaving within their lane (lateral speed ~0.15 m/s) and a few
// lane changes with signals, 0.1 s ticks. Road length grows with N.
//
// All pairs (the reference of the speedup column): every equipped ego against every other car,
// n(n-1) ordered pair tests, with the cells' narrow phase (cheap bound, exact prune, detector).
// Its time moves by a few per cent with code layout between builds; compare builds side by side.
//
// Times are CPU seconds of the monitor's step() (thread CPU clock), not wall time: the build
// machine is shared.
//
// usage: highway_detect [--n 1000,10000,100000] [--ticks K] [--seed S] [--all-pairs yes|no]
//                       [--detector concentric|five|box]  (default: all three) [--hindsight yes|no]
//                       [--prediction road|straight|both]  (both: the road prediction's cost, side by side)
//                       [--hindsight both]  (hindsight's cost: rounds without and with it, side by side)
//                       [--repeat R]  (R rounds of cells then all pairs: median times, and the
//                                      speedup as the median of the rounds' own ratios)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <stcore/cpu_clock.hpp>
#include <sthighway/monitor.hpp>

namespace {

using namespace st::highway;

using st::Vec2;

struct Traffic {
  RoadGeometry road;
  std::vector<VehicleState> cars;
  std::vector<double> laneY;   // target lateral position of each car
  std::mt19937_64 rng;
  double length = 0.0;
};

Traffic makeTraffic(long n, std::uint64_t seed) {
  Traffic t;
  t.rng.seed(seed);
  const double perKm = 2 * 3 * 25.0;
  t.length = 1000.0 * static_cast<double>(n) / perKm;
  for (int dir = 0; dir < 2; ++dir)
    for (int i = 0; i < 3; ++i) {
      Lane l;
      l.edge = dir == 0 ? "east" : "west";
      l.id = l.edge;
      l.id += '_';
      l.id += std::to_string(i);
      l.index = i;
      const double y = dir == 0 ? 3.2 * i : 20.8 - 3.2 * i;  // lane 0 is the rightmost
      l.shape = dir == 0 ? std::vector<Vec2>{Vec2(0, y), Vec2(t.length, y)} : std::vector<Vec2>{Vec2(t.length, y), Vec2(0, y)};
      t.road.lanes.push_back(l);
    }
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::normal_distribution<double> N(0.0, 1.0);
  long id = 0;
  for (int dir = 0; dir < 2 && id < n; ++dir)
    for (int lane = 0; lane < 3; ++lane) {
      double x = 10.0 * U(t.rng);
      while (x < t.length && id < n) {
        VehicleState v;
        v.id = "v";
        v.id += std::to_string(id++);
        const double y = dir == 0 ? 3.2 * lane : 20.8 - 3.2 * lane;
        v.heading = dir == 0 ? 0.0 : 3.14159265358979323846;
        v.speed = 25.0 + 5.0 * lane + 3.0 * N(t.rng);
        v.position = Vec2(dir == 0 ? x : t.length - x, y + 0.3 * N(t.rng));
        v.lateralSpeed = 0.15 * N(t.rng);
        v.acceleration = 0.5 * N(t.rng);
        if (U(t.rng) < 0.1) {
          v.vehicleClass = VehicleClass::Truck;
          v.length = 12.0;
          v.width = 2.55;
          v.mass = 15000.0;
          v.speed = std::min(v.speed, 25.0);
        }
        t.cars.push_back(v);
        t.laneY.push_back(y);
        x += 1000.0 / 25.0 * (0.6 + 0.8 * U(t.rng));
      }
    }
  return t;
}

// Moves every car by one tick: straight on, weaving within the lane, a rare signalled lane change.
void advance(Traffic& t, double dt) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (std::size_t i = 0; i < t.cars.size(); ++i) {
    VehicleState& v = t.cars[i];
    const Vec2 d = v.direction();
    v.position += dt * v.velocity();
    v.speed = std::max(0.0, v.speed + v.acceleration * dt);
    if (U(t.rng) < 0.02) v.acceleration = -v.acceleration;
    const double left = d.x() > 0 ? 1.0 : -1.0;  // +y is left when eastbound
    const double off = (v.position.y() - t.laneY[i]) * left;
    if (v.signals == kSignalNone && U(t.rng) < 0.0005) {
      // start a lane change to a neighbouring lane of the same carriageway
      const bool west = d.x() < 0;
      const double lo = west ? 14.4 : 0.0, hi = west ? 20.8 : 6.4;
      const double target = t.laneY[i] + (U(t.rng) < 0.5 ? -3.2 : 3.2);
      if (target >= lo - 1e-9 && target <= hi + 1e-9) {
        v.signals = (target - t.laneY[i]) * left > 0 ? kSignalLeft : kSignalRight;
        t.laneY[i] = target;
        v.lateralSpeed = (v.signals == kSignalLeft ? 1.0 : -1.0);
      }
    } else if (v.signals != kSignalNone && std::abs(off) < 0.3) {
      v.signals = kSignalNone;
      v.lateralSpeed = 0.0;
    } else if (v.signals == kSignalNone && std::abs(off) > 0.5) {
      v.lateralSpeed = off > 0 ? -0.15 : 0.15;
    }
  }
}

struct Row {
  long n;
  DetectorKind kind;
  Broadphase bp;
  int ticks;
  double usPerTick;
  double updatesPerSecond;
  double pairsPerVehicle;
  double toiPerVehicle;
  std::uint64_t warnings;
  double speedup = 0.0;  // all-pairs rows: the median over the rounds of all-pairs time / cells time
};

// The row of median time of a round's measurements (rounds odd or even: the upper median).
Row medianRow(std::vector<Row> rounds) {
  std::sort(rounds.begin(), rounds.end(), [](const Row& a, const Row& b) { return a.usPerTick < b.usPerTick; });
  return rounds[rounds.size() / 2];
}

// --hindsight no: the monitor without judging its warnings (hindsight.cpp), for its cost
bool gHindsight = true;
// --prediction road|straight (default road, the monitor's); both: rounds of each side by side
Prediction gPrediction = Prediction::Road;

Row measure(long n, DetectorKind kind, Broadphase bp, int ticks, std::uint64_t seed) {
  Traffic t = makeTraffic(n, seed);
  MonitorConfig cfg;
  cfg.detector.kind = kind;
  cfg.hindsight.enabled = gHindsight;
  cfg.prediction = gPrediction;
  cfg.broadphase = bp;
  HighwayMonitor m(t.road, cfg);
  const double dt = 0.1;
  // one warm-up tick attaches every car to its cell
  m.step(0.0, t.cars);
  advance(t, dt);
  const MonitorCounters before = m.counters();
  double sec = 0.0;
  std::vector<Warning> ended;  // as the front end does: one buffer for every tick
  for (int k = 1; k <= ticks; ++k) {
    const double c0 = st::threadCpuSeconds();
    m.step(k * dt, t.cars);
    m.takeFinished(ended);
    sec += st::threadCpuSeconds() - c0;
    advance(t, dt);  // the traffic generator is not timed
  }
  sec = std::max(sec, 1e-9);
  const MonitorCounters& c = m.counters();
  const double updates = static_cast<double>(c.vehicleUpdates - before.vehicleUpdates);
  std::uint64_t warnings = 0;
  for (auto w : c.warningsByKind) warnings += w;
  return {n, kind, bp, ticks, 1e6 * sec / ticks, updates / sec,
          static_cast<double>(c.candidatePairs - before.candidatePairs) / updates,
          static_cast<double>(c.toiChecks - before.toiChecks) / updates, warnings};
}

// Same ticks through both broad phases: the warnings must be identical.
bool sameWarnings(long n, DetectorKind kind, int ticks, std::uint64_t seed) {
  std::vector<std::vector<Warning>> out(2);
  for (int b = 0; b < 2; ++b) {
    Traffic t = makeTraffic(n, seed);
    MonitorConfig cfg;
    cfg.detector.kind = kind;
    cfg.broadphase = b == 0 ? Broadphase::Cells : Broadphase::AllPairs;
    HighwayMonitor m(t.road, cfg);
    for (int k = 0; k < ticks; ++k) {
      m.step(0.1 * k, t.cars);
      for (auto& w : m.takeFinished()) out[b].push_back(w);
      advance(t, 0.1);
    }
    m.finish(0.1 * (ticks - 1));
    for (auto& w : m.takeFinished()) out[b].push_back(w);
  }
  if (out[0].size() != out[1].size()) return false;
  for (std::size_t i = 0; i < out[0].size(); ++i) {
    const Warning& a = out[0][i];
    const Warning& b = out[1][i];
    if (a.ego != b.ego || a.foe != b.foe || a.kind != b.kind || a.zone != b.zone || a.begin != b.begin ||
        a.end != b.end || a.minTtc != b.minTtc)
      return false;
  }
  return true;
}

std::vector<long> parseList(const char* s) {
  std::vector<long> v;
  for (const char* p = s; *p;) {
    v.push_back(std::strtol(p, const_cast<char**>(&p), 10));
    if (*p == ',') ++p;
  }
  return v;
}

// Rounds of side 0 then side 1 (setSide switches the monitor between them), cells, each round's
// own ratio: per size and detector the median us per tick of each side, the median ratio 1 / 0
// with its range, and each side's warnings.
void compareSides(const std::vector<long>& ns, const std::vector<DetectorKind>& kinds, int ticksOverride, int repeat,
                  std::uint64_t seed, void (*setSide)(int)) {
  for (long n : ns)
    for (DetectorKind kind : kinds) {
      const int ticks = ticksOverride ? ticksOverride : n <= 1000 ? 200 : n <= 10000 ? 40 : 8;
      std::vector<double> ratios, us[2];
      std::uint64_t warnings[2] = {0, 0};
      for (int r = 0; r < repeat; ++r) {
        for (int side = 0; side < 2; ++side) {
          setSide(side);
          const Row row = measure(n, kind, Broadphase::Cells, ticks, seed);
          us[side].push_back(row.usPerTick);
          warnings[side] = row.warnings;
        }
        ratios.push_back(us[1].back() / us[0].back());
      }
      for (auto* v : {&ratios, &us[0], &us[1]}) std::sort(v->begin(), v->end());
      std::printf("%8ld %-10s %14.1f %14.1f %12.3f %5.2f-%.2f   warnings %llu / %llu\n", n, toString(kind), us[0][repeat / 2],
                  us[1][repeat / 2], ratios[repeat / 2], ratios.front(), ratios.back(),
                  static_cast<unsigned long long>(warnings[0]), static_cast<unsigned long long>(warnings[1]));
      std::fflush(stdout);
    }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long> ns{1000, 10000, 100000};
  int ticksOverride = 0;
  int repeat = 1;
  std::uint64_t seed = 1;
  bool allPairs = true;
  std::vector<DetectorKind> kinds{DetectorKind::Concentric, DetectorKind::FiveCircle, DetectorKind::Box};
  bool comparePredictions = false, compareHindsight = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--n")) ns = parseList(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--all-pairs")) allPairs = std::strcmp(argv[i + 1], "no") != 0;
    else if (!std::strcmp(argv[i], "--ticks")) ticksOverride = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--hindsight") && !std::strcmp(argv[i + 1], "both")) compareHindsight = true;
    else if (!std::strcmp(argv[i], "--hindsight")) gHindsight = std::strcmp(argv[i + 1], "no") != 0;
    else if (!std::strcmp(argv[i], "--prediction") && !std::strcmp(argv[i + 1], "both")) comparePredictions = true;
    else if (Prediction p; !std::strcmp(argv[i], "--prediction") && parsePrediction(argv[i + 1], p)) gPrediction = p;
    else if (!std::strcmp(argv[i], "--seed")) seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--repeat") && std::atoi(argv[i + 1]) >= 1) repeat = std::atoi(argv[i + 1]);
    else if (DetectorKind k; !std::strcmp(argv[i], "--detector") && parseDetectorKind(argv[i + 1], k)) kinds = {k};
    else {
      std::fprintf(stderr, "usage: highway_detect [--n 1000,10000,100000] [--ticks K] [--seed S] [--all-pairs yes|no] [--hindsight yes|no|both] "
                           "[--detector concentric|five|box] [--repeat R] [--prediction road|straight|both]\n");
      return 2;
    }
  }
  if (compareHindsight) {
    // hindsight's cost: rounds without then with it, cells, each round's own ratio
    std::printf("highway_detect: hindsight's cost, cells, %s prediction, seed %llu\n", toString(gPrediction),
                static_cast<unsigned long long>(seed));
    std::printf("%8s %-10s %14s %14s %12s %12s\n", "vehicles", "detector", "without us/t", "with us/t", "with/without", "rounds");
    compareSides(ns, kinds, ticksOverride, repeat, seed, [](int side) { gHindsight = side == 1; });
    return 0;
  }
  if (comparePredictions) {
    // the road prediction's cost: rounds of straight then road, cells, each round's own ratio
    std::printf("highway_detect: road vs straight prediction, cells, seed %llu\n", static_cast<unsigned long long>(seed));
    std::printf("%8s %-10s %14s %14s %12s %12s\n", "vehicles", "detector", "straight us/t", "road us/t", "road/straight", "rounds");
    compareSides(ns, kinds, ticksOverride, repeat, seed,
                 [](int side) { gPrediction = side == 0 ? Prediction::Straight : Prediction::Road; });
    return 0;
  }
  std::printf("highway_detect: divided motorway, 2x3 lanes, 25 veh/km/lane, 0.1 s ticks, seed %llu\n",
              static_cast<unsigned long long>(seed));
  std::printf("%8s %-10s %-9s %5s %12s %14s %10s %9s %9s %9s\n", "vehicles", "detector", "broad", "ticks", "cpu us/tick",
              "veh-updates/s", "pairs/veh", "toi/veh", "warnings", "speedup");
  std::vector<Row> rows;
  for (long n : ns) {
    for (DetectorKind kind : kinds) {
      const int cellTicks = ticksOverride ? ticksOverride : n <= 1000 ? 200 : n <= 10000 ? 40 : 8;
      const bool withAllPairs = n <= 10000 && allPairs;
      const int apTicks = n <= 1000 ? 20 : 2;
      // rounds of cells then all pairs, back to back: each round's ratio sees one spell of the
      // host's speed, which drifts between rounds
      std::vector<Row> cellRounds, apRounds;
      std::vector<double> ratios;
      for (int r = 0; r < repeat; ++r) {
        cellRounds.push_back(measure(n, kind, Broadphase::Cells, cellTicks, seed));
        if (!withAllPairs) continue;
        apRounds.push_back(measure(n, kind, Broadphase::AllPairs, apTicks, seed));
        ratios.push_back(apRounds.back().usPerTick / cellRounds.back().usPerTick);
      }
      const Row cells = medianRow(cellRounds);
      rows.push_back(cells);
      std::printf("%8ld %-10s %-9s %5d %12.1f %14.3e %10.2f %9.2f %9llu %9s\n", n, toString(kind), "cells", cells.ticks,
                  cells.usPerTick, cells.updatesPerSecond, cells.pairsPerVehicle, cells.toiPerVehicle,
                  static_cast<unsigned long long>(cells.warnings), "");
      if (withAllPairs) {
        Row ap = medianRow(apRounds);
        std::sort(ratios.begin(), ratios.end());
        ap.speedup = ratios[ratios.size() / 2];
        rows.push_back(ap);
        std::printf("%8ld %-10s %-9s %5d %12.1f %14.3e %10.2f %9.2f %9llu %8.0fx", n, toString(kind), "all-pairs",
                    ap.ticks, ap.usPerTick, ap.updatesPerSecond, ap.pairsPerVehicle, ap.toiPerVehicle,
                    static_cast<unsigned long long>(ap.warnings), ap.speedup);
        if (repeat > 1) std::printf("  (rounds %.0f-%.0fx)", ratios.front(), ratios.back());
        std::printf("\n");
      } else if (allPairs) {
        std::printf("%8ld %-10s %-9s %5s %12s (all pairs at 1e5: ~1e10 pair tests per tick, not run)\n", n,
                    toString(kind), "all-pairs", "-", "-");
      }
      std::fflush(stdout);
    }
  }
  // exactness of the cells against all pairs on the same ticks
  for (long n : ns)
    if (n <= 10000 && allPairs)
      for (DetectorKind kind : kinds)
        std::printf("same warnings cells vs all-pairs, %ld vehicles, %s, %d ticks: %s\n", n, toString(kind),
                    n <= 1000 ? 30 : 4, sameWarnings(n, kind, n <= 1000 ? 30 : 4, seed) ? "yes" : "NO");
  // the issue-4 targets at 1e4
  for (const Row& r : rows) {
    if (r.n != 10000 || r.bp != Broadphase::Cells) continue;
    if (r.kind == DetectorKind::Concentric)
      std::printf("target concentric >= 2e6 veh-updates/s at 1e4: %.3e %s\n", r.updatesPerSecond,
                  r.updatesPerSecond >= 2e6 ? "met" : "NOT MET");
    if (r.kind == DetectorKind::FiveCircle)
      std::printf("target five-circle >= 1e6 veh-updates/s at 1e4: %.3e %s\n", r.updatesPerSecond,
                  r.updatesPerSecond >= 1e6 ? "met" : "NOT MET");
    for (const Row& a : rows)
      if (a.n == 10000 && a.kind == r.kind && a.bp == Broadphase::AllPairs)
        std::printf("target cells >= 100x all pairs at 1e4 (%s): %.0fx %s\n", toString(r.kind), a.speedup,
                    a.speedup >= 100 ? "met" : "NOT MET");
  }
  return 0;
}
