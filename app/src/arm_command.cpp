// stsim arm: the robot-arm collision monitor over a scenario's sensor stream.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <starm/scenario.hpp>
#include <stsim/cli.hpp>
#include <stsim/commands.hpp>

namespace st::cli {

namespace {

namespace fs = std::filesystem;

std::string num(double x) {
  if (std::isnan(x)) return "null";
  if (std::isinf(x)) return x > 0 ? "\"inf\"" : "\"-inf\"";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

std::string quoted(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (c == '\n') {
      o += "\\n";
      continue;
    }
    o += c;
  }
  return o + "\"";
}

void writeSummary(const fs::path& file, const std::string& scenario, const arm::Monitor& m, const arm::RunStats& st,
                  const std::string& broadphase, const std::string& error) {
  const arm::MonitorCounters& c = m.counters();
  std::ostringstream j;
  j << "{\n  \"scenario\": " << quoted(scenario) << ",\n";
  j << "  \"status\": " << quoted(error.empty() ? "ok" : "error") << ",\n";
  if (!error.empty()) j << "  \"error\": " << quoted(error) << ",\n";
  j << "  \"arms\": " << m.armCount() << ",\n  \"obstacles\": " << m.obstacles().size() << ",\n";
  j << "  \"capsules\": " << m.capsuleCount() << ",\n";
  j << "  \"safe_time_s\": " << num(m.safety().safeTime()) << ",\n  \"horizon_s\": " << num(m.safety().lookAhead())
    << ",\n  \"min_separation_m\": " << num(m.safety().minSeparation) << ",\n";
  j << "  \"cycles\": " << st.cycles << ",\n  \"warnings\": " << c.warnings << ",\n  \"stops\": " << c.stops << ",\n";
  j << "  \"first_stop_s\": {";
  for (int a = 0; a < m.armCount(); ++a)
    j << (a ? ", " : "") << quoted(m.arm(a).name) << ": " << num(a < static_cast<int>(st.firstStop.size()) ? st.firstStop[a] : NAN);
  j << "},\n";
  double maxUs = 0.0, sum = 0.0;
  for (double v : st.latencyUs) maxUs = std::max(maxUs, v), sum += v;
  j << "  \"latency_us\": {\"p50\": " << num(arm::percentile(st.latencyUs, 50)) << ", \"p99\": "
    << num(arm::percentile(st.latencyUs, 99)) << ", \"max\": " << num(maxUs) << ", \"mean\": "
    << num(st.latencyUs.empty() ? 0.0 : sum / static_cast<double>(st.latencyUs.size())) << "},\n";
  j << "  \"broadphase\": " << quoted(broadphase) << ",\n";
  if (const Space<3>* sp = m.space()) {
    j << "  \"octree\": {\"decomposition_factor\": " << sp->rule().decompositionFactor
      << ", \"max_depth\": " << sp->rule().maxDepth << ", \"subdivisions\": " << sp->counters().subdivisions
      << ", \"reunions\": " << sp->counters().reunions << ", \"transfers\": " << sp->counters().transfers
      << ", \"leaves_at_end\": " << sp->leaves().size() << ", \"refiled\": " << c.refiled << "},\n";
  }
  j << "  \"candidate_pairs\": " << c.candidatePairs << ",\n  \"candidate_pairs_per_cycle\": "
    << num(st.cycles ? static_cast<double>(c.candidatePairs) / static_cast<double>(st.cycles) : 0.0) << ",\n";
  j << "  \"exact_pairs\": " << c.exactPairs << ",\n  \"advance_steps\": " << c.advanceSteps
    << ",\n  \"capped_advances\": " << c.cappedAdvances << "\n}\n";
  std::ofstream out(file);
  out << j.str();
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
}

int runArm(int argc, const char* const* argv) {
  Args args("arm",
            "Robot-arm collision monitor: forward kinematics, capsules in a dynamic octree, time to collision by "
            "conservative advancement, warnings and STOP per arm. Writes warnings.csv and summary.json.");
  args.positional("SCENARIO", "scenario YAML (arms, obstacles, octree rule, safety terms, sensor trace or waypoints)");
  args.option("out", "DIR", "output folder", "arm-out");
  args.option("broadphase", "KIND", "octree (default, from the scenario) or none (all pairs, the reference)", "");
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  const std::string path = *args.positionalValue(0);
  arm::Scenario sc = arm::loadScenario(path);
  const std::string bp = args.get("broadphase");
  if (bp == "none") sc.broad.kind = SpaceKind::None;
  else if (!bp.empty() && bp != "octree" && bp != "tree") throw UsageError("--broadphase: expected octree or none");
  arm::Monitor monitor = arm::makeMonitor(sc);
  auto sensor = arm::makeSensor(sc);

  const fs::path out = args.get("out");
  fs::create_directories(out);
  std::ofstream csv(out / "warnings.csv");
  if (!csv) throw std::runtime_error((out / "warnings.csv").string() + ": cannot write");
  csv << "t_s,arm,link,capsule,other,distance_m,ttc_s,reason,stop\n";
  arm::RunStats stats;
  const std::string bpName = sc.broad.kind == SpaceKind::None ? "none" : toString(sc.broad.kind);
  try {
    arm::run(monitor, *sensor, stats, [&](const arm::Monitor& m) {
      for (const arm::Warning& w : m.warnings()) {
        csv << num(w.t) << ',' << m.arm(w.arm).name << ',' << arm::bodyName(m.arm(w.arm).model, w.body) << ','
            << w.capsule << ',' << arm::otherName(m, w) << ',' << num(w.distance) << ',' << num(w.ttc) << ','
            << (w.outcome == arm::Approach::Touching ? "separation" : "ttc") << ',' << (w.stop ? "STOP" : "") << '\n';
      }
      if (!m.warnings().empty()) csv.flush();
    });
  } catch (const std::exception& e) {
    // results so far stay on disk
    csv.flush();
    writeSummary(out / "summary.json", path, monitor, stats, bpName, e.what());
    throw;
  }
  csv.flush();
  writeSummary(out / "summary.json", path, monitor, stats, bpName, "");
  const auto& c = monitor.counters();
  std::cout << "arm: " << stats.cycles << " cycles, " << c.warnings << " warnings, " << c.stops << " STOPs, latency p50 "
            << num(arm::percentile(stats.latencyUs, 50)) << " us p99 " << num(arm::percentile(stats.latencyUs, 99))
            << " us -> " << (out / "summary.json").string() << "\n";
  return 0;
}

}  // namespace

Command armCommand() {
  return {"arm", "robot-arm collision monitor (capsules, octree, time to collision, STOP)", runArm};
}

}  // namespace st::cli
