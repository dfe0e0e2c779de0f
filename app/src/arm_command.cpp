// stsim arm: the robot-arm collision monitor over a scenario's sensor stream.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <starm/replay.hpp>
#include <starm/scenario.hpp>
#include <starm/service.hpp>
#include <starm/settings.hpp>
#include <starm/stream.hpp>
#include <starm/study.hpp>
#include <starm/urdf.hpp>
#include <stnet/frame.hpp>
#include <stio/format.hpp>
#include <stio/json.hpp>
#include <stio/output.hpp>
#include <stsim/cli.hpp>
#include <stsim/commands.hpp>

#include "setting_options.hpp"
#include "stop_signals.hpp"

namespace st::cli {

namespace {

namespace fs = std::filesystem;

// JSON has no NaN (null) or infinity (an infinite time to collision is the string "inf").
std::string num(double x) { return std::isinf(x) ? io::jsonString(io::number(x)) : io::jsonNumber(x, 9); }

// What the run saw of the real geometry: the closest tested pair over the run, first contact.
struct Watch {
  double minDistance = INFINITY;
  double firstContact = NAN;
  void see(const arm::Monitor& m) {
    const arm::Warning& n = m.nearest();
    if (n.arm < 0) return;
    minDistance = std::min(minDistance, n.distance);
    if (std::isnan(firstContact) && n.distance <= 0.0) firstContact = n.t;
  }
};

void writeSummary(const fs::path& file, const std::string& scenario, const arm::Monitor& m, const arm::RunStats& st,
                  const std::string& broadphase, const std::string& error, bool closedLoop, const Watch& watch,
                  const arm::SeparationMonitor* ssm, const arm::DeadlineWatch& deadline) {
  const arm::MonitorCounters& c = m.counters();
  io::JsonText j(9, io::Infinity::Text);
  j << "{\n  \"scenario\": " << scenario << ",\n";
  j << "  \"status\": " << std::string_view(!error.empty() ? "error" : st.interrupted ? "interrupted" : "ok") << ",\n";
  if (!error.empty()) j << "  \"error\": " << error << ",\n";
  if (st.interrupted) j << "  \"stopped_at_s\": " << m.time() << ",\n";
  j << "  \"loop\": " << std::string_view(closedLoop ? "closed" : "open") << ",\n";
  j << "  \"min_distance_m\": " << watch.minDistance << ",\n  \"first_contact_s\": " << watch.firstContact
    << ",\n";
  j << "  \"arms\": " << m.armCount() << ",\n  \"obstacles\": " << m.obstacles().size() << ",\n";
  j << "  \"capsules\": " << m.capsuleCount() << ",\n";
  j << "  \"safe_time_s\": " << (m.safety().safeTime()) << ",\n  \"horizon_s\": " << (m.safety().lookAhead())
    << ",\n  \"min_separation_m\": " << (m.safety().minSeparation) << ",\n";
  j << "  \"cycles\": " << st.cycles << ",\n  \"warnings\": " << c.warnings << ",\n  \"stops\": " << c.stops << ",\n";
  j << "  \"first_stop_s\": {";
  for (int a = 0; a < m.armCount(); ++a) {
    if (a) j << ", ";
    j << m.arm(a).name << ": " << (a < static_cast<int>(st.firstStop.size()) ? st.firstStop[a] : NAN);
  }
  j << "},\n";
  double maxUs = 0.0, sum = 0.0;
  for (double v : st.latencyUs) maxUs = std::max(maxUs, v), sum += v;
  j << "  \"latency_us\": {\"p50\": " << (arm::percentile(st.latencyUs, 50)) << ", \"p99\": "
    << (arm::percentile(st.latencyUs, 99)) << ", \"max\": " << maxUs << ", \"mean\": "
    << (st.latencyUs.empty() ? 0.0 : sum / static_cast<double>(st.latencyUs.size())) << "},\n";
  j << "  \"deadline\": {\"budget_us\": " << deadline.budgetUs << ", \"missed\": " << deadline.missed
    << ", \"cycles\": " << deadline.cycles << ", \"first_miss_s\": "
    << (deadline.misses.empty() ? NAN : deadline.misses.front().first) << ", \"worst_us\": " << deadline.worstUs
    << ", \"worst_at_s\": " << deadline.worstT << "},\n";
  if (ssm) {
    const arm::SsmCounters& sc = ssm->counters();
    const arm::SsmConfig& cf = ssm->config();
    j << "  \"ssm\": {\"response\": " << arm::toString(cf.response) << ", \"T_r_s\": " << cf.reactionTime
      << ", \"T_s_s\": " << cf.stoppingTime << ", \"stop_cycles\": " << sc.stopCycles << ", \"scaled_cycles\": "
      << sc.scaledCycles << ", \"violations\": " << sc.violations << ", \"contacts\": " << sc.contacts
      << ", \"contacts_within_limit\": " << sc.contactsWithinLimit << ", \"contacts_above_limit\": "
      << sc.contactsAboveLimit << ", \"pfl_cycles\": " << sc.pflCycles
      << ", \"min_separation_m\": " << sc.minSeparation << "},\n";
  }
  j << "  \"broadphase\": " << broadphase << ",\n";
  // the brute force (--broadphase none) has no regions to report
  if (const Space<3>* sp = m.space(); sp->kind() != SpaceKind::None) {
    j << "  \"octree\": {\"decomposition_factor\": " << sp->rule().decompositionFactor
      << ", \"max_depth\": " << sp->rule().maxDepth << ", \"subdivisions\": " << sp->counters().subdivisions
      << ", \"reunions\": " << sp->counters().reunions << ", \"transfers\": " << sp->counters().transfers
      << ", \"leaves_at_end\": " << sp->leaves().size() << ", \"refiled\": " << c.refiled << "},\n";
  }
  j << "  \"candidate_pairs\": " << c.candidatePairs << ",\n  \"candidate_pairs_per_cycle\": "
    << (st.cycles ? static_cast<double>(c.candidatePairs) / static_cast<double>(st.cycles) : 0.0) << ",\n";
  j << "  \"exact_pairs\": " << c.exactPairs << ",\n  \"advance_steps\": " << c.advanceSteps
    << ",\n  \"capped_advances\": " << c.cappedAdvances << "\n}\n";
  io::writeTextFile(file, j.str());
}

// The settings a command line gives (starm/settings.hpp): --set KEY=VALUE[,...] and the options
// that stand for one key (--response: ssm.response), checked by the table when the scenario is
// read, over the file's values.
std::vector<arm::SettingOverride> settingOverrides(const Args& args) {
  return cli::settingOverrides(args, {{"response", "ssm.response"}},
                               [](std::string_view key) -> const io::SettingSpec* { return arm::findSetting(key); },
                               "arm", "");
}

// A scenario with the command line's settings over its own: a bad value names its option.
arm::Scenario loadWithSettings(const std::string& path, const std::vector<arm::SettingOverride>& overrides) {
  try {
    return arm::loadScenario(path, overrides);
  } catch (const arm::SettingError& e) {
    overrideError(overrides, e, "");
  }
}

// An option that stands for a number key of the table (its default, its checks, its words).
double settingOption(const Args& args, const std::string& option, const char* key) {
  const arm::Setting& s = *arm::findSetting(key);
  arm::Scenario scratch;
  try {
    arm::applySettingText(scratch, s, args.get(option));
  } catch (const arm::SettingError& e) {
    throw UsageError("--" + option + ": " + e.problem());
  }
  return std::get<double>(s.get(scratch));
}

// Persons beside working arms: binary STOP against speed scaling, closed loop, on each scenario.
int runCoexistenceStudy(const Args& args) {
  std::vector<std::string> files;
  if (args.positionalValue(0)) {
    files.push_back(*args.positionalValue(0));
  } else {
    // every shipped scenario with persons: person_*.yaml
    const fs::path dir = args.get("shipped");
    if (!fs::is_directory(dir)) throw UsageError("--shipped: " + dir.string() + " is not a folder (give --shipped DIR or a SCENARIO)");
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".yaml" && e.path().filename().string().rfind("person_", 0) == 0)
        files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw UsageError("--shipped: no person_*.yaml in " + dir.string());
  }
  constexpr arm::SsmResponse kResponses[] = {arm::SsmResponse::Stop, arm::SsmResponse::Scaling, arm::SsmResponse::Pfl};
  // progress per case: [0] no person (the reference), then stop, scaling, pfl
  double sumProgress[4] = {0.0, 0.0, 0.0, 0.0};
  const fs::path out = args.get("out");
  fs::create_directories(out);
  io::CsvRowWriter csv(out / "coexistence.csv",
                      "case,response,contacts,contacts_within_limit,contacts_above_limit,violations,stops,stop_cycles,"
                      "scaled_cycles,pfl_cycles,min_separation_m,min_slack_m,progress,duration_s");
  std::printf("coexistence study: persons beside working arms, closed loop (progress: the arms' program time over the "
              "clock time; none: no person, the task's own pace; contacts above: faster than the touched region's PFL "
              "limit)\n\n");
  std::printf("  %-16s %-8s %8s %6s %10s %6s %11s %13s %10s %10s %11s %9s\n", "case", "response", "contacts", "above",
              "below S_p", "STOPs", "STOP cycles", "scaled cycles", "pfl cycles", "min sep m", "min slack m", "progress");
  const auto ratio = [](double a, double b) { return b > 0.0 ? a / b : INFINITY; };
  for (const std::string& f : files) {
    const arm::Scenario sc = arm::loadScenario(f);
    if (sc.persons.empty()) throw UsageError(f + ": no persons: the coexistence study needs a scenario with persons:");
    const std::string name = fs::path(f).stem().string();
    double progress[4] = {0.0, 0.0, 0.0, 0.0};
    for (int k = 0; k < 4; ++k) {
      const arm::CoexistenceOutcome o = k == 0 ? arm::runWithoutPersons(sc) : arm::runCoexistence(sc, kResponses[k - 1]);
      const char* response = k == 0 ? "none" : arm::toString(kResponses[k - 1]);
      progress[k] = o.progress;
      std::printf("  %-16s %-8s %8llu %6llu %10llu %6d %11llu %13llu %10llu %10.4f %11.4f %9.4f\n", name.c_str(), response,
                  static_cast<unsigned long long>(o.contacts), static_cast<unsigned long long>(o.contactsAboveLimit),
                  static_cast<unsigned long long>(o.violations), o.stops, static_cast<unsigned long long>(o.stopCycles),
                  static_cast<unsigned long long>(o.scaledCycles), static_cast<unsigned long long>(o.pflCycles),
                  o.minSeparation, o.minSlack, o.progress);
      std::ostringstream line;
      line << io::csvField(name) << ',' << response << ',' << o.contacts << ',' << o.contactsWithinLimit << ','
           << o.contactsAboveLimit << ',' << o.violations << ',' << o.stops << ',' << o.stopCycles << ','
           << o.scaledCycles << ',' << o.pflCycles << ',' << num(o.minSeparation) << ',' << num(o.minSlack) << ','
           << num(o.progress) << ',' << num(o.duration);
      csv.row(line.str());
    }
    // time for the same work over no person's (none / response progress), and the most any
    // response could gain over stop: none / stop
    std::printf("  %-16s throughput over stop: scaling %.3fx, pfl %.3fx (at most %.3fx: none over stop); time over "
                "none: stop %.3fx, scaling %.3fx, pfl %.3fx\n",
                "", ratio(progress[2], progress[1]), ratio(progress[3], progress[1]), ratio(progress[0], progress[1]),
                ratio(progress[0], progress[1]), ratio(progress[0], progress[2]), ratio(progress[0], progress[3]));
    for (int i = 0; i < 4; ++i) sumProgress[i] += progress[i];
  }
  if (files.size() > 1)
    std::printf("\n  all %zu cases, summed progress: throughput over stop: scaling %.3fx, pfl %.3fx (at most %.3fx); "
                "time over none: stop %.3fx, scaling %.3fx, pfl %.3fx\n",
                files.size(), ratio(sumProgress[2], sumProgress[1]), ratio(sumProgress[3], sumProgress[1]),
                ratio(sumProgress[0], sumProgress[1]), ratio(sumProgress[0], sumProgress[1]),
                ratio(sumProgress[0], sumProgress[2]), ratio(sumProgress[0], sumProgress[3]));
  csv.flush();
  std::printf("\n-> %s\n", (out / "coexistence.csv").c_str());
  return 0;
}

int runStudy(const Args& args) {
  if (args.get("study") == "coexistence") return runCoexistenceStudy(args);
  if (args.get("study") != "stopping") throw UsageError("--study: expected stopping or coexistence");
  arm::StudyConfig cfg;
  cfg.randomCourses = static_cast<int>(args.getInt("courses"));
  if (cfg.randomCourses < 0 || cfg.randomCourses > 100000) throw UsageError("--courses: expected 0..100000");
  cfg.seed = static_cast<std::uint64_t>(args.getInt("seed"));
  cfg.stoppingTime = settingOption(args, "stopping-time", "braking.stopping_time");
  if (!args.has("no-shipped")) {
    const fs::path dir = args.get("shipped");
    for (const char* n : {"two_pandas", "iiwa_truss", "panda_clutter"}) {
      const fs::path f = dir / (std::string(n) + ".yaml");
      if (!fs::exists(f)) throw UsageError("--shipped: " + f.string() + " not found (give --shipped DIR or --no-shipped)");
      cfg.shipped.push_back(f.string());
    }
  }
  const arm::StudyResult r = arm::stoppingStudy(cfg);
  const fs::path out = args.get("out");
  fs::create_directories(out);
  io::CsvRowWriter csv(out / "stopping_study.csv",
                      "assumed_stopping_s,safe_time_s,needed_s,courses,contacts_open,contacts_closed,"
                      "contacts_closed_moving,min_distance_closed_m,median_min_distance_closed_m");
  std::printf("stopping study: %zu shipped + %d random courses (seed %llu), arms brake in %.3f s after a %.3f s delay\n\n",
              cfg.shipped.size(), cfg.randomCourses, static_cast<unsigned long long>(cfg.seed), cfg.stoppingTime,
              r.rows.empty() ? 0.0 : r.rows.front().needed - cfg.stoppingTime - 0.001);
  std::printf("shipped scenarios at their own safety terms:\n");
  std::printf("  %-16s %8s  %-22s  %-22s\n", "scenario", "safe s", "open: contact / min m", "closed: contact / min m");
  for (const arm::ShippedRow& s : r.shipped) {
    auto cell = [](const arm::CourseOutcome& o) {
      char b[64];
      if (o.contact) std::snprintf(b, sizeof b, "at %.3f s / %.4f", o.firstContact, o.minDistance);
      else std::snprintf(b, sizeof b, "none / %.4f", o.minDistance);
      return std::string(b);
    };
    std::printf("  %-16s %8.3f  %-22s  %-22s\n", fs::path(s.name).stem().c_str(), s.safeTime, cell(s.open).c_str(),
                cell(s.closed).c_str());
  }
  std::printf("\nall %zu courses, closed loop, the monitor's stopping term varied (safe time = cycle + reaction + it);\n"
              "needed = the arms' stopping time + delay + one cycle; open loop touches on %d courses:\n\n",
              cfg.shipped.size() + static_cast<std::size_t>(cfg.randomCourses),
              r.rows.empty() ? 0 : r.rows.front().contactsOpen);
  std::printf("  %9s %9s %11s %9s %9s %13s %13s  %s\n", "assumed s", "safe s", "safe-needed", "contacts", "(moving)",
              "min dist m", "median min m", "failing courses");
  for (const arm::StudyRow& row : r.rows) {
    std::string fails;
    for (const std::string& f : row.failures) {
      if (!fails.empty()) fails += ' ';
      fails += f.rfind("random:", 0) == 0 ? f : fs::path(f).stem().string();
    }
    if (row.contactsClosed > static_cast<int>(row.failures.size())) fails += " ...";
    std::printf("  %9.3f %9.3f %+11.3f %4d/%-4d %9d %13.4f %13.4f  %s\n", row.assumedStopping, row.safeTime,
                row.safeTime - row.needed, row.contactsClosed, row.courses, row.contactsClosedMoving, row.minDistanceClosed,
                row.medianMinDistanceClosed, fails.c_str());
    std::ostringstream line;
    line << num(row.assumedStopping) << ',' << num(row.safeTime) << ',' << num(row.needed) << ',' << row.courses << ','
         << row.contactsOpen << ',' << row.contactsClosed << ',' << row.contactsClosedMoving << ','
         << num(row.minDistanceClosed) << ',' << num(row.medianMinDistanceClosed);
    csv.row(line.str());
  }
  csv.flush();
  std::printf("\n-> %s\n", (out / "stopping_study.csv").c_str());
  return 0;
}

// An integer option in [lo, hi], refused naming the option (a 0 or -1 never quietly becomes 1).
long intIn(const Args& args, const std::string& name, long lo, long hi) {
  const long v = args.getInt(name);
  if (v < lo || v > hi)
    throw UsageError("--" + name + ": expected " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + args.get(name));
  return v;
}

net::HostPort hostPort(const std::string& option, const std::string& text) {
  const auto hp = net::parseHostPort(text);
  if (!hp) throw UsageError("--" + option + ": expected HOST:PORT, got '" + text + "'");
  return *hp;
}

// --connect HOST:PORT, which a client of the service needs.
net::HostPort connectOption(const Args& args) {
  if (args.get("connect").empty()) throw UsageError("--connect HOST:PORT is required");
  return hostPort("connect", args.get("connect"));
}

int runServe(int argc, const char* const* argv) {
  Args args("arm serve",
            "The arm service: sensor clients send joint readings and obstacle poses over TCP (protocol in "
            "models/arm/README.md); each cycle every subscriber gets OK / WARN / STOP, the nearest pair and its "
            "time to collision. Writes verdicts.csv and connections.csv to --out as it goes.");
  args.positional("SCENARIO", "scenario YAML (arms, obstacles, safety terms; its motion is not used)");
  args.option("listen", "HOST:PORT", "address to listen on (port 0: pick one and print it)", "127.0.0.1:0");
  args.option("token", "TEXT", "shared token every client must present (required off loopback)", "");
  args.option("out", "DIR", "folder of the logs", "arm-serve");
  args.option("max-connections", "N", "clients served at once past HELLO (more are told and closed)", "128");
  args.option("max-pending", "N", "connections waiting for their HELLO, apart from the clients' slots (one more "
              "closes the oldest)", "16");
  args.option("hello-timeout", "MS", "time a connection has to say HELLO", "2000");
  args.option("frame-timeout", "MS", "time a client has to finish a frame it has begun", "2000");
  args.option("budget-us", "US", "a cycle computing longer than this is STOP for every arm (cause deadline); "
              "default the scenario's cycle time, 0: not watched", "");
  args.option("set", "KEY=VALUE,...", "settings over the scenario's (stsim arm --settings lists them)", "");
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  const net::HostPort hp = hostPort("listen", args.get("listen"));
  arm::ServiceConfig cfg;
  cfg.net.address = hp.host == "localhost" ? "127.0.0.1" : hp.host;
  cfg.net.port = hp.port;
  cfg.maxClients = static_cast<std::size_t>(intIn(args, "max-connections", 1, 100000));
  cfg.maxPending = static_cast<std::size_t>(intIn(args, "max-pending", 1, 100000));
  cfg.helloTimeout = std::chrono::milliseconds(intIn(args, "hello-timeout", 1, 3600000));
  cfg.net.frameTimeout = std::chrono::milliseconds(intIn(args, "frame-timeout", 1, 3600000));
  cfg.token = args.get("token");
  cfg.logDir = args.get("out");
  const arm::Scenario sc = loadWithSettings(*args.positionalValue(0), settingOverrides(args));
  cfg.cycleBudgetUs = args.get("budget-us").empty() ? sc.safety.cycleTime * 1e6 : args.getDouble("budget-us");
  if (!(cfg.cycleBudgetUs >= 0.0 && cfg.cycleBudgetUs <= 3.6e9))
    throw UsageError("--budget-us: expected a time in 0..3.6e9 us, got " + args.get("budget-us"));
  boost::asio::io_context io;
  arm::ArmService service(io, sc, cfg);
  std::cout << "arm serve: listening on " << cfg.net.address << ":" << service.port() << std::endl;
  const int sig = service.run();
  const arm::ServiceCounters& c = service.counters();
  std::cout << "arm serve: " << (sig ? StopSignals::name(sig) : "stopped") << ", " << c.connections
            << " connections, " << c.readings << " readings, " << c.cycles << " cycles, " << c.verdictsSent
 << " verdicts, " << c.rejected << " refused, " << c.deadlineMisses << " cycles over the "
            << num(cfg.cycleBudgetUs) << " us budget (STOP) -> " << (fs::path(cfg.logDir) / "verdicts.csv").string()
            << std::endl;
  return sig ? 128 + sig : 0;  // 130, 143, 129: as every command (stop_signals.hpp)
}

int runStreamCommand(int argc, const char* const* argv) {
  Args args("arm stream",
            "Replays a recorded sensor trace (t, arm, q..., qdot...) to an arm service, applies its STOPs to the "
            "replay (closed loop through the network) and records verdicts and round-trip times.");
  args.positional("SENSORS", "CSV sensor trace (stsim arm SCENARIO --record-trace FILE writes one)");
  args.option("connect", "HOST:PORT", "the service", "");
  args.option("rate", "X", "replay speed (1: real time; 0: as fast as the verdicts come back)", "1");
  args.option("token", "TEXT", "shared token of the service", "");
  args.option("stopping-time", "S", "how this replay brakes on STOP (s; as braking.stopping_time)",
              arm::defaultText("braking.stopping_time"));
  args.option("delay", "S", "from a STOP verdict to braking (s; as braking.delay)", arm::defaultText("braking.delay"));
  args.flag("open-loop", "record verdicts but do not brake");
  args.option("out", "DIR", "folder of stream_verdicts.csv", "arm-stream");
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  const net::HostPort hp = connectOption(args);
  arm::StreamConfig cfg;
  cfg.host = hp.host;
  cfg.port = hp.port;
  cfg.token = args.get("token");
  cfg.trace = *args.positionalValue(0);
  cfg.rate = args.getDouble("rate");
  // 0 is "as fast as possible"; otherwise a speed whose trace times stay a sleep the clock can
  // hold (1e-20 overflowed into no sleep at all: full speed)
  if (!(cfg.rate == 0.0 || (cfg.rate >= 1e-3 && cfg.rate <= 1e6)))
    throw UsageError("--rate: expected 0 (as fast as possible) or a speed in 0.001..1e6, got " + args.get("rate"));
  cfg.closedLoop = !args.has("open-loop");
  cfg.braking.stoppingTime = settingOption(args, "stopping-time", "braking.stopping_time");
  cfg.braking.delay = settingOption(args, "delay", "braking.delay");
  cfg.outDir = args.get("out");
  arm::StreamResult r;
  auto report = [&] {
    double mx = 0;
    for (double v : r.rttUs) mx = std::max(mx, v);
    std::cout << "arm stream (" << (cfg.closedLoop ? "closed" : "open") << " loop): " << r.cycles << " cycles, "
              << r.verdicts << " verdicts, " << r.timeouts << " unanswered, " << r.stopCycles
              << " STOP cycles, round trip p50 " << num(arm::percentile(r.rttUs, 50)) << " us p99 "
              << num(arm::percentile(r.rttUs, 99)) << " us max " << num(mx) << " us";
    for (std::size_t a = 0; a < r.armNames.size(); ++a)
      std::cout << ", " << io::printable(r.armNames[a]) << ": first STOP " << num(r.firstStop[a]) << " s, "
                << (r.finalSpeed[a] == 0.0 ? "stopped" : "moving");
    std::cout << ", min distance " << num(r.minDistance) << " m -> "
              << (fs::path(cfg.outDir) / "stream_verdicts.csv").string() << std::endl;
  };
  // Ctrl-C, SIGTERM, SIGHUP: the replay stops after a whole cycle, its log rows whole
  StopSignals stopSignals;
  cfg.stopRequested = StopSignals::requested;
  try {
    arm::runStream(cfg, r);
  } catch (...) {
    report();
    throw;
  }
  report();
  if (const int sig = StopSignals::signal()) {
    std::cerr << "stsim arm stream: " << StopSignals::name(sig) << ": "
              << (r.interrupted ? "interrupted after " + std::to_string(r.cycles) + " cycles" : std::string("at the end"))
              << "; results so far written\n";
    return 128 + sig;
  }
  return 0;
}

int runResetCommand(int argc, const char* const* argv) {
  Args args("arm reset",
            "Releases the STOPs an arm service holds since an arm's sensor fell silent (a deliberate restart; "
            "an arm whose sensor is not current again stays held, and its verdicts say 'latched').");
  args.option("connect", "HOST:PORT", "the service", "");
  args.option("token", "TEXT", "shared token of the service", "");
  args.option("arms", "A,B", "the arms to reset, by name (default: all)", "");
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  const net::HostPort hp = connectOption(args);
  std::vector<std::string> arms;
  std::stringstream list(args.get("arms"));
  for (std::string a; std::getline(list, a, ',');)
    if (!a.empty()) arms.push_back(a);
  const std::vector<std::string> named = arm::resetLatches(hp.host, hp.port, args.get("token"), arms);
  std::cout << "arm reset:";
  for (const std::string& a : named) std::cout << ' ' << io::printable(a);
  std::cout << std::endl;
  return 0;
}

// stsim arm ROBOT.urdf: the model a scenario's `models: {NAME: {urdf: ROBOT.urdf}}` gets, its
// bodies by link name and the self pairs that touch at the zero pose (candidates for `allow`).
int describeUrdf(const std::string& path) {
  const arm::ArmModel m = arm::loadUrdf(path);
  std::printf("%s: robot %s, %d moving joints, %d bodies, %zu capsules\n", path.c_str(), m.name.c_str(), m.dof(),
              m.bodies(), m.capsules.size());
  for (int b = 0; b < m.bodies(); ++b) {
    std::string links, joint;
    for (const auto& [link, body] : m.links)
      if (body == b && link != m.bodyNames[b]) links += (links.empty() ? " (with " : ", ") + link;
    if (!links.empty()) links += ")";
    if (b >= 1 && b <= m.dof()) {
      const arm::Joint& j = m.joints[b - 1];
      joint = " after " + (j.type == arm::JointType::Prismatic ? std::string("prismatic ") : std::string("revolute ")) +
              j.name + " [" + io::number(j.lower) + ", " + io::number(j.upper) + "]";
    }
    const auto caps = std::count_if(m.capsules.begin(), m.capsules.end(), [&](const arm::LinkCapsule& c) { return c.body == b; });
    std::printf("  body %d %s%s%s: %ld capsules\n", b, m.bodyNames[b].c_str(), links.c_str(), joint.c_str(), static_cast<long>(caps));
  }
  const auto touching = arm::selfContacts(m, std::vector<double>(m.dof(), 0.0), 0.0);
  std::printf("self pairs touching at the zero pose (adjacent bodies are allowed): %s\n", touching.empty() ? "none" : "");
  for (const arm::BodyContact& c : touching)
    std::printf("  %s - %s  %s m\n", m.bodyNames[c.a].c_str(), m.bodyNames[c.b].c_str(), io::number(c.distance).c_str());
  return 0;
}

// stsim arm's options
Args armArgs() {
  Args args("arm",
            "Robot-arm collision monitor: forward kinematics, capsules in a dynamic octree, time to collision by "
            "conservative advancement, warnings and STOP per arm (closed loop: STOP brakes the arm). Writes "
            "warnings.csv and summary.json.\n  stsim arm serve SCENARIO --listen 127.0.0.1:PORT   the service "
            "(stsim arm serve --help)\n  stsim arm stream --connect HOST:PORT SENSORS.csv     its sensor client\n  stsim arm "
            "reset --connect HOST:PORT [--arms A,B]  release STOPs held since a sensor fell silent");
  args.positional("SCENARIO", "scenario YAML (arms, obstacles, octree rule, safety terms, sensor trace or waypoints), "
                  "or a robot's .urdf: its bodies by link name and the self pairs touching at the zero pose",
                  false);
  args.option("out", "DIR", "output folder", "arm-out");
  args.option("broadphase", "KIND", "octree (default, from the scenario) or none (all pairs, the reference)", "");
  args.flag("open-loop", "STOP is flagged but the arms keep moving (default: closed loop, a STOP brakes the arm)");
  args.option("study", "NAME", "stopping: contacts open vs closed loop against safe time and stopping time; "
              "coexistence: persons beside a working arm, binary STOP vs speed scaling vs PFL (SCENARIO, or every "
              "person_*.yaml in --shipped)", "");
  args.option("courses", "N", "--study: random two-Panda courses", "200");
  args.option("seed", "N", "--study: seed of the random courses", "1");
  args.option("stopping-time", "S", "--study: the arms' real stopping time (s; as braking.stopping_time)",
              arm::defaultText("braking.stopping_time"));
  args.option("shipped", "DIR", "--study: folder of the shipped scenarios", "models/arm/scenarios");
  args.flag("no-shipped", "--study: random courses only");
  args.option("budget-us", "US", "compute budget of a cycle (readings + detection + persons); default the cycle "
              "time. Cycles over it are counted, listed in deadlines.csv and flagged", "");
  args.option("response", "R", "persons: stop (binary), scaling (speed factor) or pfl (scaling, contact within ISO/TS 15066 Annex A's limits), instead of the scenario's ssm.response", "");
  args.option("record-trace", "FILE", "write the readings applied as a CSV sensor trace (for stsim arm stream)", "");
  args.option("set", "KEY=VALUE,...", "settings over the scenario's, e.g. safety.stopping_time=0.3 (checked as "
              "in the YAML; --settings lists them)", "");
  args.flag("settings", "print every setting (key, range, default, what it sets) and exit; with SCENARIO and "
            "--set, the values in effect");
  return args;
}

// One ssm.csv row: arm a's verdict against its nearest person this cycle.
std::string ssmRow(const arm::Monitor& m, int a, const arm::SsmVerdict& v, const arm::PersonSet& persons) {
  const arm::SeparationTerms& T = v.terms;
  std::ostringstream line;
  line << num(m.time()) << ',' << io::csvField(m.arm(a).name) << ',' << io::csvField(arm::bodyName(m.arm(a).model, v.armBody))
       << ',' << io::csvField(persons.name(v.person)) << ',' << arm::bodyParts()[v.part].name << ','
       << arm::toString(arm::bodyParts()[v.part].region) << ',' << num(v.separation) << ',' << num(v.required) << ','
       << num(T.sh) << ',' << num(T.sr) << ',' << num(T.ss) << ',' << num(T.c) << ',' << num(T.zd) << ',' << num(T.zr)
       << ',' << T.dominant() << ',' << num(v.robotSpeed) << ',' << num(v.allowedSpeed) << ',' << num(v.factor) << ','
       << (v.stop ? "STOP" : v.factor < 1.0 ? "SCALE" : "OK");
  return line.str();
}

// One warnings.csv row.
std::string warningRow(const arm::Monitor& m, const arm::Warning& w) {
  std::ostringstream line;
  line << num(w.t) << ',' << io::csvField(m.arm(w.arm).name) << ',' << io::csvField(arm::bodyName(m.arm(w.arm).model, w.body))
       << ',' << w.capsule << ',' << io::csvField(arm::otherName(m, w)) << ',' << num(w.distance) << ',' << num(w.ttc)
       << ',' << (w.outcome == Outcome::Overlapping ? "separation" : "ttc") << ',' << (w.stop ? "STOP" : "");
  return line.str();
}

// The run's CSV files, written cycle by cycle.
struct CycleLogs {
  io::CsvRowWriter warnings, deadlines;
  std::unique_ptr<io::CsvRowWriter> ssm;  // with persons only

  CycleLogs(const fs::path& out, bool persons)
      : warnings(out / "warnings.csv", "t_s,arm,link,capsule,other,distance_m,ttc_s,reason,stop"),
        deadlines(out / "deadlines.csv", "t_s,compute_us,budget_us") {
    if (persons)
      ssm = std::make_unique<io::CsvRowWriter>(out / "ssm.csv",
          "t_s,arm,link,person,part,region,separation_m,S_p_m,S_h_m,S_r_m,S_s_m,C_m,Z_d_m,Z_r_m,dominant,v_r_mps,"
          "allowed_mps,factor,verdict");
  }
  void flush() {
    warnings.flush();
    deadlines.flush();
    if (ssm) ssm->flush();
  }
};

// The console's account of a finished run: one line, and one more when cycles missed their deadline.
void printRun(const arm::Monitor& monitor, const arm::RunStats& stats, bool closedLoop, const Watch& watch,
              const arm::SeparationMonitor* ssm, const arm::DeadlineWatch& deadline, const fs::path& out) {
  const auto& c = monitor.counters();
  std::cout << "arm (" << (closedLoop ? "closed" : "open") << " loop): " << stats.cycles << " cycles, " << c.warnings
            << " warnings, " << c.stops << " STOPs, "
            << (std::isnan(watch.firstContact) ? std::string("no contact") : "first contact at " + num(watch.firstContact) + " s")
            << ", min distance " << num(watch.minDistance) << " m, latency p50 "
            << num(arm::percentile(stats.latencyUs, 50)) << " us p99 " << num(arm::percentile(stats.latencyUs, 99))
            << " us";
  if (ssm) {
    const arm::SsmCounters& k = ssm->counters();
    std::cout << ", persons (" << arm::toString(ssm->config().response) << "): " << k.stopCycles << " STOP cycles, "
              << k.scaledCycles << " scaled, " << k.violations << " below S_p unstopped, " << k.contacts
              << " contacts (" << k.contactsAboveLimit << " above the PFL limit), min separation " << num(k.minSeparation)
              << " m";
  }
  std::cout << " -> " << (out / "summary.json").string() << ", " << (out / "replay.html").string() << "\n";
  if (deadline.missed > 0)
    std::cout << "arm: DEADLINE MISSED: " << deadline.missed << " of " << deadline.cycles << " cycles over the "
              << num(deadline.budgetUs) << " us budget (first at " << num(deadline.misses.front().first) << " s, worst "
              << num(deadline.worstUs) << " us at " << num(deadline.worstT) << " s) -> "
              << (out / "deadlines.csv").string() << "\n";
}

// The readings the monitor gets: the closed loop's drive (a STOP brakes the arm) or the scenario's
// open sensor, recorded to a trace file when asked.
struct Sensors {
  std::unique_ptr<arm::ClosedLoopSensor> drive;  // closed loop only
  std::unique_ptr<arm::SensorSource> open;       // open loop only
  std::unique_ptr<arm::RecordingSensor> recorder;
  arm::SensorSource* source = nullptr;  // what the monitor reads: one of the three
};

Sensors makeSensors(const arm::Scenario& sc, bool closedLoop, const std::string& recordTrace) {
  Sensors s;
  if (closedLoop) s.drive = arm::makeClosedLoopSensor(sc);
  else s.open = arm::makeSensor(sc);
  s.source = closedLoop ? static_cast<arm::SensorSource*>(s.drive.get()) : s.open.get();
  if (!recordTrace.empty()) {
    std::vector<std::string> names;
    for (const arm::ArmInstance& a : sc.arms) names.push_back(a.name);
    s.recorder = std::make_unique<arm::RecordingSensor>(*s.source, recordTrace, names);
    s.source = s.recorder.get();
  }
  return s;
}

int runCourse(const Args& args, const std::string& path);

int runArm(int argc, const char* const* argv) {
  if (argc > 0 && std::string(argv[0]) == "serve") return runServe(argc - 1, argv + 1);
  if (argc > 0 && std::string(argv[0]) == "reset") return runResetCommand(argc - 1, argv + 1);
  if (argc > 0 && std::string(argv[0]) == "stream") return runStreamCommand(argc - 1, argv + 1);
  Args args = armArgs();
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  if (args.has("settings")) {
    const std::vector<arm::SettingOverride> overrides = settingOverrides(args);
    if (!args.positionalValue(0)) {
      if (!overrides.empty()) throw UsageError("--settings: " + overrides.front().option + " needs a SCENARIO");
      std::cout << arm::settingsReferenceMarkdown();
      return 0;
    }
    const arm::Scenario sc = loadWithSettings(*args.positionalValue(0), overrides);
    std::cout << arm::settingsReferenceMarkdown(&sc, "in effect");
    return 0;
  }
  if (args.has("study")) {
    if (args.positionalValue(0) && args.get("study") != "coexistence")
      throw UsageError("--study stopping takes no SCENARIO");
    return runStudy(args);
  }
  if (!args.positionalValue(0)) throw UsageError("missing argument SCENARIO (see stsim arm --help)");
  const std::string path = *args.positionalValue(0);
  if (fs::path(path).extension() == ".urdf") return describeUrdf(path);
  return runCourse(args, path);
}

// A scenario's course run: the monitor cycle by cycle, its logs, summary.json and replay.html.
int runCourse(const Args& args, const std::string& path) {
  const bool closedLoop = !args.has("open-loop");
  arm::Scenario sc = loadWithSettings(path, settingOverrides(args));
  const std::string bp = args.get("broadphase");
  if (bp == "none") sc.broad.kind = SpaceKind::None;
  else if (!bp.empty() && bp != "octree" && bp != "tree") throw UsageError("--broadphase: expected octree or none");
  arm::Monitor monitor = arm::makeMonitor(sc);
  const Sensors sensors = makeSensors(sc, closedLoop, args.get("record-trace"));
  arm::ClosedLoopSensor* drive = sensors.drive.get();
  Watch watch;
  // persons: speed and separation monitoring beside the collision monitor
  arm::PersonSet persons = arm::makePersons(sc);
  arm::DeadlineWatch deadline;
  deadline.budgetUs = args.get("budget-us").empty() ? sc.safety.cycleTime * 1e6 : args.getDouble("budget-us");
  if (!(deadline.budgetUs > 0.0 && deadline.budgetUs <= 3.6e9))
    throw UsageError("--budget-us: expected a time in (0, 3.6e9] us, got " + args.get("budget-us"));
  std::unique_ptr<arm::SeparationMonitor> ssm;
  if (persons.size() > 0) ssm = std::make_unique<arm::SeparationMonitor>(sc.ssm, monitor.armCount());
  // the picture: replay.html, the cell and each arm's STOPs with their cause
  arm::ReplayRecorder replay(monitor, persons.size() > 0 ? &persons : nullptr);
  const std::string replayTitle = fs::path(path).filename().string() + (closedLoop ? " (closed loop)" : " (open loop)");

  const fs::path out = args.get("out");
  fs::create_directories(out);
  CycleLogs logs(out, ssm != nullptr);
  arm::RunStats stats;
  const std::string bpName = sc.broad.kind == SpaceKind::None ? "none" : toString(sc.broad.kind);
  // Ctrl-C, SIGTERM, SIGHUP: the run stops after a whole cycle and writes what it has
  StopSignals stopSignals;
  try {
    arm::run(monitor, *sensors.source, stats, [&](const arm::Monitor& m) {
      if (ssm) {
        // the persons' check is part of the cycle's compute time
        const auto t0 = std::chrono::steady_clock::now();
        arm::separationStep(m, persons, *ssm, drive);
        stats.latencyUs.back() += std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
        for (int a = 0; a < m.armCount(); ++a)
          if (ssm->verdict(a).person >= 0) logs.ssm->row(ssmRow(m, a, ssm->verdict(a), persons));
      } else if (drive) {
        drive->observe(m, m.time());
      }
      deadline.see(m.time(), stats.latencyUs.back());
      if (stats.latencyUs.back() > deadline.budgetUs)
        logs.deadlines.row(num(m.time()) + ',' + num(stats.latencyUs.back()) + ',' + num(deadline.budgetUs));
      watch.see(m);
      replay.see(m, persons.size() > 0 ? &persons : nullptr, ssm.get());
      for (const arm::Warning& w : m.warnings()) logs.warnings.row(warningRow(m, w));
      if (!m.warnings().empty()) logs.warnings.flush();
    }, StopSignals::requested);
  } catch (const std::exception& e) {
    // results so far stay on disk; the first failure is the one reported (a full disk fails both)
    try {
      logs.flush();
    } catch (const std::exception&) {
    }
    try {
      writeSummary(out / "summary.json", path, monitor, stats, bpName, e.what(), closedLoop, watch, ssm.get(), deadline);
      replay.write(out / "replay.html", replayTitle);
    } catch (const std::exception&) {
    }
    throw;
  }
  logs.flush();
  writeSummary(out / "summary.json", path, monitor, stats, bpName, "", closedLoop, watch, ssm.get(), deadline);
  replay.write(out / "replay.html", replayTitle);
  printRun(monitor, stats, closedLoop, watch, ssm.get(), deadline, out);
  if (const int sig = StopSignals::signal()) {
    std::cout.flush();
    std::cerr << "stsim arm: " << StopSignals::name(sig) << ": "
              << (stats.interrupted ? "interrupted at t = " + num(monitor.time()) + " s" : std::string("at the end"))
              << "; results so far written\n";
    return 128 + sig;
  }
  return 0;
}

}  // namespace

Command armCommand() {
  return {"arm", "robot-arm collision monitor (capsules, octree, time to collision, STOP)", runArm};
}

}  // namespace st::cli
