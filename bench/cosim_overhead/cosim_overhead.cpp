// bench/cosim_overhead: what stsim's smart-car warnings cost on top of SUMO, measured side by side
// in one run on the motorway scenario scaled to >= 1000 vehicles on the road at once (0.1 s steps,
// every vehicle equipped):
//   sumo                plain `sumo` process (the reference)
//   libsumo only        SUMO embedded, stepping, no state read (libsumo vs the binary)
//   libsumo reads       the libsumo backend: stepping + event lists + every vehicle's state, with
//                       every variable, and with those the five-circle run needs (VehicleReads)
//   stsim <detector>    libsumo + plugin, for concentric, five, box (actions off: detection cost)
//   stsim via libtraci  launched sumo + TraCI subscriptions + plugin (five)
//   ..., 2 threads      five with its detection beside SUMO's next step (DetectionStage), against
//                       the same run in line: wall is the figure (CPU adds both threads)
//   sumo + SSM          `sumo` with the SSM device on every vehicle (SUMO's own conflict detection)
// Wall and CPU seconds (CPU: this process's user+sys for in-process runs, the child's for sumo
// processes; the machine may be shared, CPU time is the fairer figure) and the ratio to plain sumo.
// Targets (issue 5): five-circle <= 1.3x plain sumo; >= 4x faster than sumo + SSM.
//
// The scaled scenario: motorway's sources with the downstream section 20 km long, plus 1000 vehicles
// inserted at t = 0 spread over it (departPos random_free), then the normal demand; 120 s simulated.
//   usage: bench_cosim_overhead [SIMULATED_SECONDS=120] [WORK_DIR=/tmp/stsim_cosim_overhead]
//
// --scale: stsim's cost per vehicle-step at 1 000 and at 10 000 vehicles on the road at once, the
// same motorway with the downstream section 20 km per 1 000 preloaded vehicles (the same density:
// 200 km for 10 000). Each run is a child process (its own peak RSS): libsumo with the five-circle
// run's reads (the floor) and stsim five (libsumo, road prediction, hindsight). stsim's time is the
// CPU inside the plugin's update (conversions, the monitor, hindsight; SUMO's step and the reads
// excluded), per vehicle-step; its memory the peak RSS of the second run less the first's, per
// vehicle at once. Target (issue 36): stsim's time per vehicle-step at 10 000 within
// 1.5x of its time at 1 000.
//   usage: bench_cosim_overhead --scale [SIMULATED_SECONDS=60] [WORK_DIR=/tmp/stsim_cosim_scale]
//
// --junction: what reading the traffic lights and the persons costs where there are some
// (networks/crosswalk: a fixed-time light, crosswalks, persons on foot) and where there are none
// (the motorway main job), against stsim's own time there: the CPU inside the plugin's update
// (conversions, the monitor, hindsight) beside the backend's reads by part (Backend::readCost),
// each the least of 3 runs, alternated. Box detector, every vehicle equipped, actions off.
// Target (issue 51): reading the lights and the persons <= 10 % of stsim's time.
//   usage: bench_cosim_overhead --junction [SIMULATED_SECONDS=600]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <libsumo/libsumo.h>

#include <stcore/cpu_clock.hpp>
#include <stcosim/backend.hpp>
#include <stcosim/detection.hpp>
#include <stcosim/plugin.hpp>
#include <stcosim/scenario.hpp>
#include <stcosim/sumo_home.hpp>

namespace fs = std::filesystem;
using namespace st::cosim;
using Clock = std::chrono::steady_clock;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void run(const std::string& cmd) {
  if (std::system(cmd.c_str()) != 0) {
    std::fprintf(stderr, "bench_cosim_overhead: command failed: %s\n", cmd.c_str());
    std::exit(1);
  }
}

// The motorway scaled up, written to `dir`; returns the sumocfg.
fs::path makeScenario(const fs::path& dir, double seconds, int preload = 1000, double downstreamKm = 20.0) {
  const fs::path src = fs::path(STSIM_SOURCE_DIR) / "networks/motorway";
  fs::create_directories(dir);
  std::string nodes = slurp(src / "motorway.nod.xml");
  // mergeEnd is at x = 1450 m
  const std::string east = std::to_string(1450.0 + 1000.0 * downstreamKm);
  nodes = std::regex_replace(nodes, std::regex("id=\"east\"       x=\"3000.0\""), "id=\"east\"       x=\"" + east + "\"");
  std::ofstream(dir / "m.nod.xml") << nodes;
  fs::copy_file(src / "motorway.edg.xml", dir / "m.edg.xml", fs::copy_options::overwrite_existing);
  fs::copy_file(src / "motorway.con.xml", dir / "m.con.xml", fs::copy_options::overwrite_existing);
  run("netconvert --node-files " + (dir / "m.nod.xml").string() + " --edge-files " + (dir / "m.edg.xml").string() +
      " --connection-files " + (dir / "m.con.xml").string() +
      " --no-turnarounds true --offset.disable-normalization true --no-warnings true -o " +
      (dir / "m.net.xml").string() + " > /dev/null");
  std::string routes = slurp(src / "motorway.rou.xml");
  routes = std::regex_replace(
      routes, std::regex("</routes>"),
      "    <route id=\"long\" edges=\"downstream\"/>\n"
      "    <flow id=\"preload\" type=\"mix\" route=\"long\" begin=\"0\" end=\"0.1\" number=\"1000\" "
      "departPos=\"random_free\" departLane=\"random\" departSpeed=\"desired\"/>\n</routes>");
  routes = std::regex_replace(routes, std::regex("number=\"1000\""), "number=\"" + std::to_string(preload) + "\"");
  std::ofstream(dir / "m.rou.xml") << routes;
  std::string cfg = slurp(src / "motorway.sumocfg");
  cfg = std::regex_replace(cfg, std::regex("motorway\\.net\\.xml"), "m.net.xml");
  cfg = std::regex_replace(cfg, std::regex("motorway\\.rou\\.xml"), "m.rou.xml");
  cfg = std::regex_replace(cfg, std::regex("<end value=\"[0-9.]+\"/>"), "<end value=\"" + std::to_string(seconds) + "\"/>");
  std::ofstream(dir / "m.sumocfg") << cfg;
  return dir / "m.sumocfg";
}

struct Row {
  std::string name;
  double wall = 0.0, cpu = 0.0;
  double childCpu = 0.0;  // CPU of the sumo children the run waited for (a libtraci run's SUMO)
  double stepWall = 0.0;  // wall inside SUMO's step and its reads (backend.step()), stsim runs
  double maxVehicles = 0.0;
  long peakRssKb = -1;
  std::string note;
};

double cpuOf(int who) {
  rusage u{};
  getrusage(who, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
double cpuSelf() { return cpuOf(RUSAGE_SELF); }

// A sumo process to completion: wall, child CPU, peak RSS.
Row sumoProcess(const std::string& name, const std::vector<std::string>& args) {
  std::string cmd = "sumo";
  for (const auto& a : args) cmd += " '" + a + "'";
  cmd += " > /dev/null 2>&1";
  rusage before{}, after{};
  getrusage(RUSAGE_CHILDREN, &before);
  const auto t0 = Clock::now();
  run(cmd);
  Row r;
  r.name = name;
  r.wall = std::chrono::duration<double>(Clock::now() - t0).count();
  getrusage(RUSAGE_CHILDREN, &after);
  auto sec = [](const rusage& u) {
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  };
  r.cpu = sec(after) - sec(before);
  r.peakRssKb = after.ru_maxrss;  // max over all children so far
  return r;
}

double lastStepWall = 0.0;  // set by the stsim runs' bodies

Row inProcess(const std::string& name, const std::function<double()>& body) {
  lastStepWall = 0.0;
  const double c0 = cpuSelf();
  const double k0 = cpuOf(RUSAGE_CHILDREN);
  const auto t0 = Clock::now();
  Row r;
  r.name = name;
  r.maxVehicles = body();
  r.wall = std::chrono::duration<double>(Clock::now() - t0).count();
  r.cpu = cpuSelf() - c0;
  r.childCpu = cpuOf(RUSAGE_CHILDREN) - k0;
  r.stepWall = lastStepWall;
  return r;
}

// What a child run sends back to the bench.
struct ChildResult {
  double wall = 0.0, cpu = 0.0;
  double vehicleSteps = 0.0, maxVehicles = 0.0;
  double updateCpu = 0.0;  // CPU seconds inside the plugin's update (stsim's own work)
  long peakRssKb = 0;
};

// `body` in a child process (so that its peak RSS is its own); exits the bench if the child fails.
ChildResult inChild(const std::function<ChildResult()>& body) {
  int fds[2];
  if (pipe(fds) != 0) {
    std::perror("bench_cosim_overhead: pipe");
    std::exit(1);
  }
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const auto t0 = Clock::now();
    ChildResult r = body();
    r.wall = std::chrono::duration<double>(Clock::now() - t0).count();
    r.cpu = cpuSelf();
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    r.peakRssKb = u.ru_maxrss;
    const bool ok = write(fds[1], &r, sizeof r) == static_cast<ssize_t>(sizeof r);
    _exit(ok ? 0 : 1);
  }
  close(fds[1]);
  ChildResult r;
  const bool got = read(fds[0], &r, sizeof r) == static_cast<ssize_t>(sizeof r);
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!got || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "bench_cosim_overhead: a child run failed\n");
    std::exit(1);
  }
  return r;
}

int scaleMain(double seconds, const fs::path& dir) {
  struct Level {
    int vehicles;
    ChildResult reads, stsim;
  };
  std::vector<Level> levels{{1000, {}, {}}, {10000, {}, {}}};
  for (Level& l : levels) {
    const fs::path cfg = makeScenario(dir / std::to_string(l.vehicles), seconds, l.vehicles, 20.0 * l.vehicles / 1000.0);
    Scenario s = loadScenario(cfg);
    s.plugin.actions.action = Action::None;
    s.plugin.smart.penetration = 1.0;
    const std::vector<std::string> args = sumoArguments(s);
    l.reads = inChild([&] {
      ChildResult r;
      auto b = startLibsumo(SumoLaunch{args, false, "", ""});
      b->setReads(VehicleReads{false, true});  // what the five-circle run with road prediction reads
      while (b->running()) {
        b->step();
        r.vehicleSteps += static_cast<double>(b->vehicles().size());
        r.maxVehicles = std::max(r.maxVehicles, static_cast<double>(b->vehicles().size()));
      }
      b->close();
      return r;
    });
    l.stsim = inChild([&] {
      ChildResult r;
      auto b = startLibsumo(SumoLaunch{args, false, "", ""});
      PluginConfig pc = s.plugin;
      pc.monitor.detector.kind = st::highway::DetectorKind::FiveCircle;
      HighwayPlugin p(*b, pc);
      while (b->running()) {
        b->step();
        const double c0 = st::threadCpuSeconds();
        p.update();
        r.updateCpu += st::threadCpuSeconds() - c0;
        p.takeFinished();  // as a caller would: finished episodes do not pile up
        r.vehicleSteps += static_cast<double>(b->vehicles().size());
        r.maxVehicles = std::max(r.maxVehicles, static_cast<double>(b->vehicles().size()));
      }
      p.finish();
      b->close();
      return r;
    });
  }
  std::printf("cosim_overhead --scale: motorway, downstream 20 km per 1000 vehicles preloaded, %.0f s simulated, "
              "0.1 s steps, every vehicle equipped, five-circle, actions off; each run a child process\n",
              seconds);
  std::printf("%-9s %8s %12s %12s %11s %11s %14s %12s %12s %10s\n", "preload", "max veh", "veh-steps",
              "reads CPU s", "run CPU s", "run / rd", "stsim us/v-st", "reads RSS MB", "stsim RSS MB",
              "stsim kB/v");
  std::vector<double> perStep;
  for (const Level& l : levels) {
    const double own = l.stsim.updateCpu / l.stsim.vehicleSteps * 1e6;
    const double kbPerVehicle = static_cast<double>(l.stsim.peakRssKb - l.reads.peakRssKb) / l.stsim.maxVehicles;
    perStep.push_back(own);
    std::printf("%-9d %8.0f %12.0f %12.2f %11.2f %10.2fx %14.3f %12.1f %12.1f %10.2f\n", l.vehicles,
                l.stsim.maxVehicles, l.stsim.vehicleSteps, l.reads.cpu, l.stsim.cpu, l.stsim.cpu / l.reads.cpu, own,
                static_cast<double>(l.reads.peakRssKb) / 1024.0, static_cast<double>(l.stsim.peakRssKb) / 1024.0,
                kbPerVehicle);
  }
  std::printf("target: stsim's time per vehicle-step at 10000 / at 1000 = %.2fx (target <= 1.5x)\n",
              perStep[1] / perStep[0]);
  return 0;
}

// One stsim run of `scenario` (box, actions off): its CPU by part (s), the least of `rounds`.
struct JunctionCost {
  double update = 1e300, vehicles = 1e300, lights = 1e300, persons = 1e300, step = 1e300;
  double maxVehicles = 0.0, maxPersons = 0.0;
};
void junctionRound(const fs::path& scenario, double seconds, JunctionCost& c) {
  Scenario s = loadScenario(scenario);
  s.plugin.actions.action = Action::None;
  s.plugin.smart.penetration = 1.0;
  s.plugin.monitor.detector.kind = st::highway::DetectorKind::Box;
  if (!s.end || *s.end > seconds) s.end = seconds;
  const std::vector<std::string> args = sumoArguments(s);
  auto b = startLibsumo(SumoLaunch{args, false, "", ""});
  HighwayPlugin p(*b, s.plugin);
  double update = 0.0, step = 0.0;
  while (b->running()) {
    const double c0 = st::threadCpuSeconds();
    b->step();
    const double c1 = st::threadCpuSeconds();
    p.update();
    update += st::threadCpuSeconds() - c1;
    step += c1 - c0;
    p.takeFinished();
    c.maxVehicles = std::max(c.maxVehicles, static_cast<double>(b->vehicles().size()));
    c.maxPersons = std::max(c.maxPersons, static_cast<double>(b->persons().size()));
  }
  p.finish();
  const Backend::ReadCost r = b->readCost();
  b->close();
  c.update = std::min(c.update, update);
  c.vehicles = std::min(c.vehicles, r.vehicles);
  c.lights = std::min(c.lights, r.lights);
  c.persons = std::min(c.persons, r.persons);
  c.step = std::min(c.step, step - r.vehicles - r.lights - r.persons);
}

// The persons' floor on libsumo: their list and the three getters stsim needs of each (position,
// angle, speed) a step, nothing else (no check for riders, no records), in CPU s; least of `rounds`.
double personsFloor(const fs::path& scenario, double seconds) {
  Scenario s = loadScenario(scenario);
  if (!s.end || *s.end > seconds) s.end = seconds;
  auto b = startLibsumo(SumoLaunch{sumoArguments(s), false, "", ""});
  b->setReads(VehicleReads{false, false, false, false, false});
  double cpu = 0.0, sink = 0.0;
  while (b->running()) {
    b->step();
    const double c0 = st::threadCpuSeconds();
    for (const std::string& id : libsumo::Person::getIDList()) {
      const auto p = libsumo::Person::getPosition(id);
      sink += p.x + libsumo::Person::getAngle(id) + libsumo::Person::getSpeed(id);
    }
    cpu += st::threadCpuSeconds() - c0;
  }
  b->close();
  return sink == 0.5 ? -1.0 : cpu;  // sink: the getters' results are used
}

int junctionMain(double seconds) {
  const fs::path src = STSIM_SOURCE_DIR;
  const std::pair<const char*, fs::path> nets[] = {{"crosswalk", src / "networks/crosswalk/scenario.yaml"},
                                                   {"motorway", src / "networks/motorway/scenario.yaml"}};
  JunctionCost cost[2];
  double floor = 1e300;
  for (int round = 0; round < 3; ++round) {
    for (int n = 0; n < 2; ++n) junctionRound(nets[n].second, seconds, cost[n]);
    floor = std::min(floor, personsFloor(nets[0].second, seconds));
  }
  std::printf("cosim_overhead --junction: box detector, libsumo, every vehicle equipped, actions off, %.0f s simulated "
              "(motorway: its own end); CPU s, least of 3 runs each, alternated\n",
              seconds);
  std::printf("%-10s %8s %8s %10s %12s %10s %10s %12s %14s\n", "network", "max veh", "max per", "SUMO step",
              "vehicle rd", "lights rd", "persons rd", "stsim update", "lights+persons");
  double worst = 0.0;
  for (int n = 0; n < 2; ++n) {
    const JunctionCost& c = cost[n];
    const double share = (c.lights + c.persons) / c.update;
    worst = std::max(worst, share);
    std::printf("%-10s %8.0f %8.0f %10.3f %12.3f %10.4f %10.4f %12.3f %13.1f%%\n", nets[n].first, c.maxVehicles,
                c.maxPersons, c.step, c.vehicles, c.lights, c.persons, c.update, 100.0 * share);
  }
  std::printf("crosswalk, the persons' floor on libsumo (their list and 3 getters each a step, nothing else): %.4f s = "
              "%.1f %% of stsim's update\n",
              floor, 100.0 * floor / cost[0].update);
  std::printf("target: reading the lights and the persons %.1f %% of stsim's update at most (target <= 10 %%)\n",
              100.0 * worst);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--scale") {
    ensureSumoHome();
    return scaleMain(argc > 2 ? std::atof(argv[2]) : 60.0,
                     argc > 3 ? fs::path(argv[3]) : fs::temp_directory_path() / "stsim_cosim_scale");
  }
  if (argc > 1 && std::string(argv[1]) == "--junction") {
    ensureSumoHome();
    return junctionMain(argc > 2 ? std::atof(argv[2]) : 600.0);
  }
  const double seconds = argc > 1 ? std::atof(argv[1]) : 120.0;
  const fs::path dir = argc > 2 ? fs::path(argv[2]) : fs::temp_directory_path() / "stsim_cosim_overhead";
  ensureSumoHome();
  const fs::path cfg = makeScenario(dir, seconds);
  Scenario s = loadScenario(cfg);
  s.plugin.actions.action = Action::None;
  s.plugin.smart.penetration = 1.0;
  const std::vector<std::string> args = sumoArguments(s);

  std::vector<Row> rows;
  rows.push_back(sumoProcess("sumo (reference)", args));

  rows.push_back(inProcess("libsumo, stepping only", [&] {
    std::vector<std::string> cmd{"sumo"};
    cmd.insert(cmd.end(), args.begin(), args.end());
    libsumo::Simulation::start(cmd);
    while (libsumo::Simulation::getMinExpectedNumber() > 0 && libsumo::Simulation::getTime() < seconds - 0.05)
      libsumo::Simulation::step();
    libsumo::Simulation::close();
    return 0.0;
  }));
  rows.back().note = "SUMO embedded, nothing read";
  auto readsOnly = [&](VehicleReads reads, bool traci = false) {
    return [&, reads, traci] {
      auto b = traci ? launchTraci(SumoLaunch{args, false, "", ""}) : startLibsumo(SumoLaunch{args, false, "", ""});
      b->setReads(reads);
      while (b->running()) b->step();
      b->close();
      return 0.0;
    };
  };
  rows.push_back(inProcess("libsumo backend, all variables", readsOnly(VehicleReads{})));
  rows.back().note = "+ event lists, 6 getters per vehicle and step";
  rows.push_back(inProcess("libsumo backend, five's reads", readsOnly(VehicleReads{false, true})));
  rows.back().note = "position, angle, speed, signals: 4 getters";

  auto stsim = [&](st::highway::DetectorKind k, bool traci, bool overlap = false) {
    return [&, k, traci, overlap] {
      auto b = traci ? launchTraci(SumoLaunch{args, false, "", ""}) : startLibsumo(SumoLaunch{args, false, "", ""});
      PluginConfig pc = s.plugin;
      pc.monitor.detector.kind = k;
      HighwayPlugin p(*b, pc);
      double maxV = 0.0;
      std::size_t warnings = 0;
      DetectionStage detection(p, overlap, [&] { warnings += p.takeFinished().size(); });
      double stepWall = 0.0;
      while (b->running()) {
        const auto t0 = Clock::now();
        b->step();
        stepWall += std::chrono::duration<double>(Clock::now() - t0).count();
        detection.afterStep();
        maxV = std::max(maxV, static_cast<double>(b->vehicles().size()));
      }
      lastStepWall = stepWall;
      detection.drain();
      p.finish();
      b->close();
      return maxV;
    };
  };
  rows.push_back(inProcess("stsim concentric (libsumo)", stsim(st::highway::DetectorKind::Concentric, false)));
  {
    // in line and with 2 threads alternated, each its least wall of three: on a shared machine a
    // neighbour's burst can land on either, and the overlap needs the second core free
    Row inLine, threads;
    for (int k = 0; k < 3; ++k) {
      const Row a = inProcess("stsim five (libsumo)", stsim(st::highway::DetectorKind::FiveCircle, false));
      const Row b =
          inProcess("stsim five (libsumo), 2 threads", stsim(st::highway::DetectorKind::FiveCircle, false, true));
      if (k == 0 || a.wall < inLine.wall) inLine = a;
      if (k == 0 || b.wall < threads.wall) threads = b;
    }
    inLine.note = "least wall of 3, alternated with the next";
    threads.note = "detection beside SUMO's next step; least wall of 3";
    rows.push_back(inLine);
    rows.push_back(threads);
  }
  rows.push_back(inProcess("stsim box (libsumo)", stsim(st::highway::DetectorKind::Box, false)));
  // over TraCI the SUMO child answers every subscribed variable of every vehicle: its CPU (the
  // sumo CPU column) is the part of the read floor no client can remove
  rows.push_back(inProcess("libtraci backend, all variables", readsOnly(VehicleReads{}, true)));
  rows.back().note = "launched sumo, one subscription per vehicle: 7 variables";
  rows.push_back(inProcess("libtraci backend, five's reads", readsOnly(VehicleReads{false, true}, true)));
  rows.back().note = "6 variables (the floor over TraCI)";
  rows.push_back(inProcess("stsim five (libtraci)", stsim(st::highway::DetectorKind::FiveCircle, true)));
  rows.back().note = "CPU: stsim's side; sumo CPU: the child";
  rows.push_back(inProcess("stsim five (libtraci), 2 threads", stsim(st::highway::DetectorKind::FiveCircle, true, true)));
  rows.back().note = "detection beside SUMO's next step";
  {
    std::vector<std::string> ssm = args;
    for (const char* a : {"--device.ssm.probability", "1", "--device.ssm.deterministic", "true",
                          "--device.ssm.measures", "TTC DRAC PET", "--device.ssm.file"})
      ssm.push_back(a);
    ssm.push_back((dir / "ssm.xml").string());
    rows.push_back(sumoProcess("sumo + SSM on every vehicle", ssm));
    rows.back().note = "peak RSS of any sumo child so far";
  }

  const Row& ref = rows.front();
  std::printf("cosim_overhead: motorway scaled (20 km downstream, 1000 vehicles preloaded), %.0f s simulated, "
              "0.1 s steps, every vehicle equipped, actions off\n",
              seconds);
  std::printf("%-32s %9s %9s %11s %10s %11s %9s  %s\n", "run", "wall s", "CPU s", "CPU/sumo", "wall/sumo",
              "sumo CPU s", "max veh", "note");
  for (const auto& r : rows) {
    char child[16] = "-";
    if (r.childCpu > 0.005) std::snprintf(child, sizeof child, "%.2f", r.childCpu);
    std::printf("%-32s %9.2f %9.2f %10.2fx %9.2fx %11s %9.0f  %s", r.name.c_str(), r.wall, r.cpu, r.cpu / ref.cpu,
                r.wall / ref.wall, child, r.maxVehicles, r.note.c_str());
    if (r.peakRssKb > 0) std::printf(" [peak RSS %.0f MB]", static_cast<double>(r.peakRssKb) / 1024.0);
    std::printf("\n");
  }
  auto row = [&](const std::string& name) -> const Row& {
    for (const auto& r : rows)
      if (r.name == name) return r;
    std::fprintf(stderr, "bench_cosim_overhead: no row '%s'\n", name.c_str());
    std::exit(1);
  };
  const Row& five = row("stsim five (libsumo)");
  const Row& ssm = rows.back();
  std::printf("targets: five-circle CPU %.2fx plain sumo (target <= 1.3x); sumo+SSM / five-circle CPU = %.2fx "
              "(target >= 4x)\n",
              five.cpu / ref.cpu, ssm.cpu / five.cpu);
  const Row& fiveThreads = row("stsim five (libsumo), 2 threads");
  const Row& traci = row("stsim five (libtraci)");
  const Row& traciThreads = row("stsim five (libtraci), 2 threads");
  const Row& traciFloor = row("libtraci backend, five's reads");
  std::printf("detection beside the step: five libsumo wall %.2fx plain sumo in line, %.2fx with 2 threads "
              "(%.2f of the in-line wall); five libtraci %.2fx, %.2fx (%.2f)\n",
              five.wall / ref.wall, fiveThreads.wall / ref.wall, fiveThreads.wall / five.wall, traci.wall / ref.wall,
              traciThreads.wall / ref.wall, traciThreads.wall / traci.wall);
  // what the overlap leaves on SUMO's thread: its step and reads (slower if the worker slows the
  // shared caches) and stsim's conversion and handoff
  std::printf("five libsumo, 2 threads: SUMO's step and reads %.2f s of the %.2f s wall (in line %.2f s), "
              "stsim on SUMO's thread %.2f s = %.2fx plain sumo\n",
              fiveThreads.stepWall, fiveThreads.wall, five.stepWall, fiveThreads.wall - fiveThreads.stepWall,
              (fiveThreads.wall - fiveThreads.stepWall) / ref.wall);
  std::printf("libtraci: five %.2fx plain sumo wall (target <= 3x), its read floor %.2fx, of which the SUMO "
              "child's CPU alone %.2fx\n",
              std::min(traci.wall, traciThreads.wall) / ref.wall, traciFloor.wall / ref.wall,
              traciFloor.childCpu / ref.cpu);
  return 0;
}
