// hard_disks: throughput and equation of state of hard disks (2-D) and hard spheres (3-D) in a walled
// box, for every space kind. Compares against the issue-2 speed targets and against Henderson's
// (disks) and Carnahan-Starling's (spheres) compressibility factor.
//
// Units: diameter 1 m, mass 1 kg, kT = 1 J (so speeds are O(1) m/s).
//
// Pressure is measured in the bulk, away from the walls, because a walled box has a density layer
// at each wall that the nominal N/V does not see. An interior region (the box shrunk by w on every
// side) gives
//   P = n_in kT + (1 / (D V_in T)) sum_{collisions with contact point in V_in} r_ij . dp_i
// with n_in the time-averaged number density of centres in V_in, r_ij = r_i - r_j at contact and
// dp_i the impulse on i (r_ij . dp_i = sigma |dp| > 0 for a repulsive contact). Hence
//   Z = P / (n_in kT) = 1 + sum r_ij . dp_i / (D kT T N_in),   N_in = n_in V_in,
// compared with the reference at phi_in = N_in v_1 / V_in (v_1 the volume of one ball).
// A second estimate, Z_wall, takes P from the impulse on the central part of each wall (contacts
// whose tangential coordinates lie within the interior range): in mechanical equilibrium the normal
// pressure on a flat wall equals the bulk pressure.
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <stcore/simulator.hpp>

namespace {

using st::Vec;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Cells kind's default fat-box margin (fraction of the radius) in 2-D and 3-D, measured best with
// cells of 1.2 diameters at phi 0.1-0.7 (stcore/README.md): a Boundary event re-checks only the
// cells entered, so thin margins (more boundary events, fewer neighbours) pay, more so in 3-D.
constexpr double kCellsMargin[2] = {0.2, 0.02};
// Cells kind's default cell edge (diameters) in 2-D and 3-D. Neighbour lists (--shell) are off by
// default: with Smallenburg's shell (--shell 0.5 --cell-size 1.5) spheres ran faster at N 4000,
// even at 32 000 and slower at 256 000, and disks slower at 10^4 (bench/RESULTS.md, issue 53).
constexpr double kCellsSize[2] = {1.2, 1.2};

struct Options {
  std::vector<int> dims{2, 3};
  std::vector<long> ns{1000, 10000, 100000, 1000000};
  std::vector<double> phis{0.1, 0.3, 0.5, 0.7};
  std::vector<st::SpaceKind> kinds{st::SpaceKind::None, st::SpaceKind::Single, st::SpaceKind::Tree,
                                   st::SpaceKind::Cells};
  std::uint64_t collisions = 0;  // 0: default per point
  std::optional<std::uint64_t> warmup;
  std::uint64_t seed = 1;
  double cellSize = 0.0;      // cells kind: cell edge in diameters (0: kCellsSize)
  double margin = 0.0;        // SimulatorConfig::marginFactor when given, else kCellsMargin / simulator's
  bool marginGiven = false;
  double shell = 0.0;         // SimulatorConfig::neighborShell (cells, none, single)
  double calendar = 0.0;      // SimulatorConfig::eventsPerBlock (0: one heap)
  int decomposition = 5;      // tree kind: decomposition factor
  double interior = -1.0;     // interior margin w in diameters; <0: automatic
  bool json = false;
  bool single = false;        // exactly one point requested: run in-process
  std::optional<double> maxDz;  // --max-dz: the largest |Z / Z_ref - 1| (%) that passes
};

struct Point {
  int dim;
  long n;
  double phi;
  st::SpaceKind kind;
};

struct Result {
  bool ok = false;
  std::string why;
  std::uint64_t collisions = 0, ballBall = 0, events = 0, stale = 0, pairChecks = 0, warmup = 0;
  double seconds = 0.0, wallSeconds = 0.0, setupSeconds = 0.0, simTime = 0.0;
  double peakMiB = 0.0;
  double phiIn = 0.0, z = 0.0, zWall = 0.0, zRef = 0.0, zRefNominal = 0.0;
  double energyDrift = 0.0;
};

// ---- memory --------------------------------------------------------------------------------------

// A field of /proc/self/status in KiB (VmRSS, VmHWM), or 0.
double procStatusKiB(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.compare(0, key.size(), key) == 0) return std::atof(line.c_str() + key.size());
  return 0.0;
}

// CPU time of this process (s). Rates use it rather than wall time: the machines this runs on are
// shared, and a descheduled process would otherwise look slow. Both are reported.
double cpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// ---- physics references ----------------------------------------------------------------------------

double ballVolume(int dim) { return dim == 2 ? std::numbers::pi / 4.0 : std::numbers::pi / 6.0; }

// Henderson (1975) for disks, Carnahan-Starling (1969) for spheres.
double zReference(int dim, double phi) {
  if (dim == 2) return (1.0 + phi * phi / 8.0) / ((1.0 - phi) * (1.0 - phi));
  return (1.0 + phi + phi * phi - phi * phi * phi) / std::pow(1.0 - phi, 3);
}

// ---- initial state -------------------------------------------------------------------------------

// Lattice sites for n unit-diameter balls in [0, L]^D, centres in [0.5, L - 0.5]: a simple
// square/cubic lattice when it fits, else (3-D) face-centred cubic; a random subset of the sites
// when the lattice has more. Empty if no lattice fits.
template <int D>
std::vector<Vec<D>> latticeSites(long n, double L, std::mt19937_64& rng) {
  std::vector<Vec<D>> sites;
  const double span = L - 1.0;
  auto m = static_cast<long>(std::ceil(std::pow(static_cast<double>(n), 1.0 / D) - 1e-9));
  while (std::pow(static_cast<double>(m), D) < static_cast<double>(n)) ++m;
  const double h = m > 1 ? span / static_cast<double>(m - 1) : 0.0;
  if (m == 1 || h >= 1.0 + 1e-9) {
    long total = 1;
    for (int i = 0; i < D; ++i) total *= m;
    for (long k = 0; k < total; ++k) {
      Vec<D> p;
      long rest = k;
      for (int i = 0; i < D; ++i) {
        p[i] = 0.5 + h * static_cast<double>(rest % m);
        rest /= m;
      }
      sites.push_back(m == 1 ? Vec<D>::Constant(0.5 * L) : p);
    }
  } else if (D == 3) {
    // fcc: 2k planes per axis, spacing g, sites where the index sum is even; nearest distance g*sqrt2
    auto k = static_cast<long>(std::ceil(std::cbrt(static_cast<double>(n) / 4.0)));
    while (4 * k * k * k < n) ++k;
    const double g = span / static_cast<double>(2 * k - 1);
    if (g * std::sqrt(2.0) < 1.0 + 1e-9) return {};
    for (long a = 0; a < 2 * k; ++a)
      for (long b = 0; b < 2 * k; ++b)
        for (long c = 0; c < 2 * k; ++c) {
          if ((a + b + c) % 2 != 0) continue;
          Vec<D> p;
          p[0] = 0.5 + g * static_cast<double>(a);
          p[1] = 0.5 + g * static_cast<double>(b);
          p[D - 1] = 0.5 + g * static_cast<double>(c);
          sites.push_back(p);
        }
  } else {
    return {};
  }
  std::shuffle(sites.begin(), sites.end(), rng);
  sites.resize(static_cast<std::size_t>(n));
  return sites;
}

// ---- one point -----------------------------------------------------------------------------------

std::uint64_t defaultCollisions(const Point& p) {
  const bool quadratic = p.kind == st::SpaceKind::None || p.kind == st::SpaceKind::Single;
  // at least 2e5: with 10 per ball a small 3-D system has not melted (N = 4000: Z 12 % high)
  const double perBall = 10.0 * static_cast<double>(p.n);
  return static_cast<std::uint64_t>(quadratic ? std::min(perBall, 5e4) : std::clamp(perBall, 2e5, 1e6));
}

template <int D>
Result runPoint(const Point& pt, const Options& opt) {
  Result r;
  const double rssStart = procStatusKiB("VmRSS");
  const auto n = pt.n;
  const double L = std::pow(static_cast<double>(n) * ballVolume(D) / pt.phi, 1.0 / D);
  std::mt19937_64 rng(opt.seed);
  const std::vector<Vec<D>> sites = latticeSites<D>(n, L, rng);
  if (sites.empty()) {
    r.why = "no lattice fits this phi with walls at this N";
    return r;
  }
  // Maxwell velocities, zero total momentum, scaled to kT = 1 exactly (unit mass)
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Vec<D>> vel(static_cast<std::size_t>(n));
  Vec<D> mean = Vec<D>::Zero();
  for (auto& v : vel) {
    for (int i = 0; i < D; ++i) v[i] = gauss(rng);
    mean += v;
  }
  mean /= static_cast<double>(n);
  double sumSq = 0.0;
  for (auto& v : vel) {
    v -= mean;
    sumSq += v.squaredNorm();
  }
  const double scale = std::sqrt(D * static_cast<double>(n) / sumSq);
  for (auto& v : vel) v *= scale;

  const auto t0 = std::chrono::steady_clock::now();
  st::SimulatorConfig cfg;
  cfg.spaceKind = pt.kind;
  cfg.rule.cellSize = opt.cellSize > 0.0 ? opt.cellSize : kCellsSize[D - 2];
  cfg.rule.decompositionFactor = opt.decomposition;
  cfg.rule.minChildSizeRatio = 1.0;  // dense clusters would otherwise split down to maxDepth
  if (opt.marginGiven) cfg.marginFactor = opt.margin;
  else if (pt.kind == st::SpaceKind::Cells) cfg.marginFactor = kCellsMargin[D - 2];
  if (pt.kind != st::SpaceKind::Tree) cfg.neighborShell = opt.shell;
  cfg.eventsPerBlock = opt.calendar;
  st::Aabb<D> box{Vec<D>::Zero(), Vec<D>::Constant(L)};
  st::Simulator<D> sim(box, cfg);
  for (int a = 0; a < D; ++a) {
    const Vec<D> e = Vec<D>::Unit(a);
    sim.addWall({e, 0.0});  // wall 2a:   x_a = 0
    sim.addWall({e, L});    // wall 2a+1: x_a = L
  }
  for (long i = 0; i < n; ++i) sim.addBall(sites[i], vel[i], 0.5, 1.0);
  const double energy0 = sim.kineticEnergy();
  const auto t1 = std::chrono::steady_clock::now();
  r.setupSeconds = std::chrono::duration<double>(t1 - t0).count();

  const std::uint64_t measured = opt.collisions ? opt.collisions : defaultCollisions(pt);
  const std::uint64_t warmup = opt.warmup ? *opt.warmup : measured / 2;

  // runs until `target` more collisions (ball-ball and ball-wall) or simulated time `until`
  std::uint64_t coll = 0, events = 0;
  auto runCollisions = [&](std::uint64_t target, double until, auto&& onEvent) {
    const std::uint64_t stop = coll + target;
    while (coll < stop) {
      const auto why = sim.run(until, [&](const st::EventRecord& e) {
        ++events;
        if (e.kind == st::EventKind::BallBall || e.kind == st::EventKind::BallWall) ++coll;
        onEvent(e);
      }, stop - coll);
      if (why != st::StopReason::EventLimit) return why;
    }
    return st::StopReason::EventLimit;
  };
  auto ignore = [](const st::EventRecord&) {};

  // warm-up: melt the lattice, discard the transient
  runCollisions(warmup, kInf, ignore);
  r.warmup = coll;
  const double tStart = sim.now();

  // interior region [w, L - w]^D
  double w = opt.interior >= 0.0 ? opt.interior : std::min(0.25 * L, std::max(5.0, 0.1 * L));
  w = std::min(w, 0.49 * L);
  const double lo = w, hi = L - w, side = hi - lo;
  auto inside = [&](const Vec<D>& p) { return (p.array() >= lo).all() && (p.array() <= hi).all(); };
  double virial = 0.0, wallImpulse = 0.0;
  auto onEvent = [&](const st::EventRecord& e) {
    if (e.kind == st::EventKind::BallBall) {
      // after the event both balls sit at the contact point with their new velocities:
      // r_ab . dp_a = 2 mu (v_a' - v_b') . (p_a - p_b)
      const auto& a = sim.ball(e.a);
      const auto& b = sim.ball(e.b);
      if (inside(0.5 * (a.p + b.p))) {
        const double mu = a.mass * b.mass / (a.mass + b.mass);
        virial += 2.0 * mu * (a.v - b.v).dot(a.p - b.p);
      }
    } else if (e.kind == st::EventKind::BallWall) {
      const auto& a = sim.ball(e.a);
      const int axis = e.b / 2;
      bool central = true;
      for (int i = 0; i < D; ++i)
        if (i != axis && (a.p[i] < lo || a.p[i] > hi)) central = false;
      if (central) wallImpulse += 2.0 * a.mass * std::abs(a.v[axis]);
    }
  };
  auto countInside = [&]() {
    long c = 0;
    const double t = sim.now();
    for (const auto& b : sim.balls()) c += inside(b.positionAt(t)) ? 1 : 0;
    return static_cast<double>(c);
  };

  // sample the interior count at equal simulated-time steps, ~every N/4 collisions
  const auto counters0 = sim.counters();
  const auto t2 = std::chrono::steady_clock::now();
  const double cpu2 = cpuSeconds();
  const std::uint64_t coll0 = coll, events0 = events;
  double dt = 0.0;
  if (warmup > 0 && tStart > 0.0) {
    dt = tStart / static_cast<double>(r.warmup) * static_cast<double>(std::max<long>(n / 4, 1));
  } else {
    runCollisions(std::min<std::uint64_t>(measured, std::max<long>(n / 4, 1)), kInf, onEvent);
    dt = std::max(sim.now() - tStart, 1e-12);
  }
  double insideSum = countInside();
  std::uint64_t samples = 1;
  while (coll - coll0 < measured) {
    const double until = sim.now() + dt;
    const auto why = runCollisions(measured - (coll - coll0), until, onEvent);
    if (why == st::StopReason::NothingLeft) break;
    if (why == st::StopReason::TimeLimit) {
      insideSum += countInside();
      ++samples;
    }
  }
  const double cpu3 = cpuSeconds();
  const auto t3 = std::chrono::steady_clock::now();
  const double T = sim.now() - tStart;

  r.seconds = cpu3 - cpu2;
  r.wallSeconds = std::chrono::duration<double>(t3 - t2).count();
  r.collisions = coll - coll0;
  r.events = events - events0;
  r.ballBall = sim.counters().events[0] - counters0.events[0];
  r.stale = sim.counters().staleEvents - counters0.staleEvents;
  r.pairChecks = sim.counters().pairChecks - counters0.pairChecks;
  r.simTime = T;
  const double energy1 = sim.kineticEnergy();
  r.energyDrift = (energy1 - energy0) / energy0;
  const double kT = 2.0 * energy1 / (D * static_cast<double>(n));
  const double nIn = insideSum / static_cast<double>(samples);
  const double vIn = std::pow(side, D);
  r.phiIn = nIn * ballVolume(D) / vIn;
  r.z = 1.0 + virial / (D * kT * T * nIn);
  const double wallArea = 2.0 * D * std::pow(side, D - 1);
  r.zWall = (wallImpulse / (T * wallArea)) / (nIn / vIn * kT);
  r.zRef = zReference(D, r.phiIn);
  r.zRefNominal = zReference(D, pt.phi);
  r.peakMiB = (procStatusKiB("VmHWM") - rssStart) / 1024.0;
  r.ok = T > 0.0;
  if (!r.ok) r.why = "nothing happened";
  return r;
}

// ---- output --------------------------------------------------------------------------------------

void printHeader() {
  std::printf("%-3s %8s %5s %-6s %9s %8s %8s %8s %7s %6s %8s %6s %7s %7s %7s %7s\n", "dim", "N", "phi",
              "space", "coll", "cpu_s", "Mcoll/s", "Mev/s", "ns/ev", "stale%", "peakMiB", "phi_in", "Z",
              "Z_wall", "Z_ref", "dZ%");
  std::fflush(stdout);
}

// Prints a point's row; returns its deviation from the reference Z (%), NaN if it was skipped.
double printRow(const Point& p, const Result& r, bool json) {
  if (!r.ok) {
    std::printf("%-3d %8ld %5.2f %-6s  skipped: %s\n", p.dim, p.n, p.phi, st::toString(p.kind), r.why.c_str());
    if (json)
      std::printf("{\"dim\":%d,\"n\":%ld,\"phi\":%g,\"space\":\"%s\",\"skipped\":\"%s\"}\n", p.dim, p.n, p.phi,
                  st::toString(p.kind), r.why.c_str());
    std::fflush(stdout);
    return std::numeric_limits<double>::quiet_NaN();
  }
  const double cps = static_cast<double>(r.collisions) / r.seconds;
  const double eps = static_cast<double>(r.events) / r.seconds;
  const double nsPerEvent = 1e9 * r.seconds / static_cast<double>(r.events);
  const double stalePct = 100.0 * static_cast<double>(r.stale) / static_cast<double>(r.events + r.stale);
  const double dz = 100.0 * (r.z / r.zRef - 1.0);
  std::printf("%-3d %8ld %5.2f %-6s %9llu %8.3f %8.3f %8.3f %7.1f %6.1f %8.1f %6.4f %7.4f %7.4f %7.4f %+7.2f\n",
              p.dim, p.n, p.phi, st::toString(p.kind), static_cast<unsigned long long>(r.collisions), r.seconds,
              cps / 1e6, eps / 1e6, nsPerEvent, stalePct, r.peakMiB, r.phiIn, r.z, r.zWall, r.zRef, dz);
  if (json) {
    std::printf(
        "{\"dim\":%d,\"n\":%ld,\"phi\":%g,\"space\":\"%s\",\"collisions\":%llu,\"ball_ball\":%llu,"
        "\"events\":%llu,\"stale_pops\":%llu,\"pair_checks\":%llu,\"warmup_collisions\":%llu,"
        "\"cpu_seconds\":%.6g,\"wall_seconds\":%.6g,\"setup_seconds\":%.6g,\"collisions_per_s\":%.6g,\"events_per_s\":%.6g,"
        "\"ns_per_event\":%.6g,\"peak_mib\":%.6g,\"sim_time\":%.6g,\"phi_interior\":%.6g,\"z\":%.6g,"
        "\"z_wall\":%.6g,\"z_ref\":%.6g,\"z_ref_nominal\":%.6g,\"z_ref_name\":\"%s\",\"z_dev_percent\":%.4g,"
        "\"energy_drift\":%.3g}\n",
        p.dim, p.n, p.phi, st::toString(p.kind), static_cast<unsigned long long>(r.collisions),
        static_cast<unsigned long long>(r.ballBall), static_cast<unsigned long long>(r.events),
        static_cast<unsigned long long>(r.stale), static_cast<unsigned long long>(r.pairChecks),
        static_cast<unsigned long long>(r.warmup), r.seconds, r.wallSeconds, r.setupSeconds, cps, eps, nsPerEvent, r.peakMiB,
        r.simTime, r.phiIn, r.z, r.zWall, r.zRef, r.zRefNominal, p.dim == 2 ? "henderson" : "carnahan-starling",
        dz, r.energyDrift);
  }
  std::fflush(stdout);
  return dz;
}

constexpr int kOffReference = 3;  // a grid point's exit status when its Z failed --max-dz

// --max-dz: a point whose Z is further than that from its reference fails the run (exit 1)
bool withinReference(const Point& p, double dz, const Options& o) {
  if (!o.maxDz || !(std::abs(dz) > *o.maxDz)) return true;
  std::fprintf(stderr, "hard_disks: dim %d N %ld phi %g %s: Z is %+.2f %% off its reference (limit %g %%)\n", p.dim,
               p.n, p.phi, st::toString(p.kind), dz, *o.maxDz);
  return false;
}

Result runAny(const Point& p, const Options& o) {
  return p.dim == 2 ? runPoint<2>(p, o) : runPoint<3>(p, o);
}

// ---- command line --------------------------------------------------------------------------------

const char* kUsage =
    "usage: hard_disks [--dim 2|3] [--n N] [--phi PHI] [--space none|single|tree|cells]\n"
    "                  [--collisions K] [--warmup W] [--seed S] [--cell-size C] [--margin M]\n"
    "                  [--df F] [--shell S] [--calendar K] [--interior W] [--max-dz PCT] [--json]\n"
    "Hard disks (2-D) / spheres (3-D), diameter 1, mass 1, kT 1, in a walled box, from a lattice.\n"
    "Axes not given run over the grid: dim {2,3}, N {1e3,1e4,1e5,1e6}, phi {0.1,0.3,0.5,0.7},\n"
    "space {none,single,tree,cells} (none and single only up to N=1e4); each grid point runs in its\n"
    "own process so peak memory is per point.\n"
    "  --collisions K  measured collisions (ball-ball + ball-wall); default 10*N within [2e5, 1e6]\n"
    "                  (at 5e4 for none/single, which cost O(N) per prediction)\n"
    "  --warmup W      collisions discarded first (lattice melting); default K/2\n"
    "  --cell-size C   cells kind: cell edge in diameters (default 1.2)\n"
    "  --margin M      fat-box margin as a fraction of the radius (default: cells 0.2 in 2-D,\n"
    "                  0.02 in 3-D; other kinds the simulator's 0.5)\n"
    "  --df F          tree kind: decomposition factor (default 5)\n"
    "  --shell S       neighbour lists with a shell of S radii (0.5: Smallenburg's 1.5 diameters;\n"
    "                  default 0, none; not for the tree kind)\n"
    "  --calendar K    event calendar sized for about K updates per time block (default 0: one\n"
    "                  heap of every ball's event; the same history either way)\n"
    "  --interior W    pressure measured in the box shrunk by W diameters (default max(5, L/10))\n"
    "  --max-dz PCT    exit 1 if a point's Z is more than PCT % off its reference (Henderson in\n"
    "                  2-D, Carnahan-Starling in 3-D; fluids only: below phi 0.7 / 0.49)\n"
    "  --json          also print one JSON object per point\n";

[[noreturn]] void usageError(const std::string& msg) {
  std::fprintf(stderr, "hard_disks: %s (try --help)\n", msg.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  int given = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usageError("missing value for " + a);
      return argv[++i];
    };
    auto number = [&](const std::string& s) {
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (end == s.c_str() || *end != '\0' || !std::isfinite(v)) usageError("bad number '" + s + "' for " + a);
      return v;
    };
    if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (a == "--json") {
      o.json = true;
    } else if (a == "--dim") {
      const double d = number(value());
      if (d != 2.0 && d != 3.0) usageError("--dim must be 2 or 3");
      o.dims = {static_cast<int>(d)};
      ++given;
    } else if (a == "--n") {
      const double n = number(value());
      if (n < 1 || n > 1e8) usageError("--n out of range");
      o.ns = {static_cast<long>(n)};
      ++given;
    } else if (a == "--phi") {
      const double p = number(value());
      if (!(p > 0.0 && p < 0.75)) usageError("--phi must be in (0, 0.75)");
      o.phis = {p};
      ++given;
    } else if (a == "--space") {
      st::SpaceKind k;
      if (!st::parseSpaceKind(value(), k)) usageError("unknown space kind");
      o.kinds = {k};
      ++given;
    } else if (a == "--collisions") {
      o.collisions = static_cast<std::uint64_t>(number(value()));
    } else if (a == "--warmup") {
      o.warmup = static_cast<std::uint64_t>(number(value()));
    } else if (a == "--seed") {
      o.seed = static_cast<std::uint64_t>(number(value()));
    } else if (a == "--cell-size") {
      o.cellSize = number(value());
      if (!(o.cellSize >= 1.0)) usageError("--cell-size must be at least one diameter");
    } else if (a == "--margin") {
      o.margin = number(value());
      o.marginGiven = true;
    } else if (a == "--shell") {
      o.shell = number(value());
      if (!(o.shell >= 0.0 && o.shell <= 10.0)) usageError("--shell must be in [0, 10]");
    } else if (a == "--calendar") {
      o.calendar = number(value());
      if (!(o.calendar >= 0.0 && o.calendar <= 1e6)) usageError("--calendar must be in [0, 1e6]");
    } else if (a == "--df") {
      o.decomposition = static_cast<int>(number(value()));
    } else if (a == "--interior") {
      o.interior = number(value());
    } else if (a == "--max-dz") {
      o.maxDz = number(value());
    } else {
      usageError("unknown option " + a);
    }
  }
  o.single = given == 4;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  std::vector<Point> points;
  for (int d : opt.dims)
    for (long n : opt.ns)
      for (double phi : opt.phis)
        for (st::SpaceKind k : opt.kinds) {
          const bool quadratic = k == st::SpaceKind::None || k == st::SpaceKind::Single;
          if (quadratic && n > 10000 && !opt.single) continue;
          points.push_back({d, n, phi, k});
        }
  printHeader();
  if (opt.single) {
    const double dz = printRow(points[0], runAny(points[0], opt), opt.json);
    return withinReference(points[0], dz, opt) ? 0 : 1;
  }
  bool allWithin = true;
  // one child process per point: peak memory and allocator state do not leak between points
  for (const Point& p : points) {
    const pid_t pid = fork();
    if (pid < 0) {
      std::perror("fork");
      return 1;
    }
    if (pid == 0) {
      const double dz = printRow(p, runAny(p, opt), opt.json);
      std::fflush(stdout);
      _exit(withinReference(p, dz, opt) ? 0 : kOffReference);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFEXITED(status) && WEXITSTATUS(status) == kOffReference) allWithin = false;
    else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
      std::printf("%-3d %8ld %5.2f %-6s  failed (status %d)\n", p.dim, p.n, p.phi, st::toString(p.kind), status);
  }
  return allWithin ? 0 : 1;
}
