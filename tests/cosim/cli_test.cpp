// `stsim highway SCENARIO` end to end: outputs, determinism, bad input, Ctrl-C.
#include <gtest/gtest.h>

#include <map>

#include <algorithm>
#include <cstdlib>
#include <thread>

#include "test_util.hpp"

namespace st::cosim {
namespace {

using namespace st::cosim::test;

TEST(HighwayCli, MotorwayRunWritesWarningsSummaryAndCollisions) {
  const auto dir = freshDir("cli_run");
  const auto r = runStsim({"highway", motorway().string(), "--end", "60", "--out", dir.string()}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warnings"), std::string::npos);
  std::size_t rows = 0;
  EXPECT_TRUE(validWarningsCsv(dir / "warnings.csv", &rows));
  EXPECT_GT(rows, 10u);
  const std::string summary = slurp(dir / "summary.json");
  EXPECT_EQ(jsonString(summary, "stop_reason"), "end");
  EXPECT_EQ(jsonString(summary, "backend"), "libsumo");
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "simulated_s"), 60.0);
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "steps"), 600.0);
  EXPECT_GT(jsonNumber(summary, "sumo_seconds"), 0.0);
  EXPECT_GT(jsonNumber(summary, "stsim_seconds"), 0.0);
  EXPECT_GT(jsonNumber(summary, "color_changes"), 0.0);
  // the warnings counted in the summary are the rows of the CSV
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "total"), static_cast<double>(rows));
  EXPECT_EQ(lines(slurp(dir / "collisions.csv"))[0], "time,collider,victim,type,lane,pos,collider_speed,victim_speed,gap,contact");
}

// The main job (five-circle): cars side by side in adjacent lanes inside each other's side circles
// (a truck's reach across the 3.75 m lanes) warn with TTC 0 in zone left or right. With the
// headings parallel they are proximity states, none a rear-end conflict, and carry no DRAC; the
// headline and summary.json count them apart from SSAM's types.
TEST(HighwayCli, TheMainJobsSideBySideWarningsAreProximityNotRearEnd) {
  const auto dir = freshDir("cli_proximity");
  const auto r = runStsim({"highway", motorway().string(), "--no-map", "--out", dir.string()}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto rows = lines(slurp(dir / "warnings.csv"));
  ASSERT_GT(rows.size(), 1u);
  const auto header = splitCsv(rows[0]);
  auto col = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t kind = col("kind"), zone = col("zone"), ttc = col("min_ttc"), angle = col("heading_angle"),
                    type = col("type"), drac = col("drac");
  long sideBySide = 0, proximity = 0, rearEnd = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto f = splitCsv(rows[i]);
    ASSERT_EQ(f.size(), header.size()) << rows[i];
    if (f[type] == "proximity") {
      ++proximity;
      EXPECT_EQ(f[drac], "") << rows[i];  // excluded from DRAC
    }
    rearEnd += f[type] == "rear_end";
    if (f[kind] != "vehicle" || std::stod(f[ttc]) != 0.0 || (f[zone] != "left" && f[zone] != "right")) continue;
    if (std::stod(f[angle]) > 1.0) continue;  // converging (the ramp's taper): typed by its angle
    ++sideBySide;
    EXPECT_EQ(f[type], "proximity") << rows[i];
  }
  EXPECT_GT(sideBySide, 500);  // most of the run's warnings
  const std::string summary = slurp(dir / "summary.json");
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "proximity"), static_cast<double>(proximity));
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "rear_end"), static_cast<double>(rearEnd));
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "conflicts"),
                   jsonNumber(summary, "rear_end") + jsonNumber(summary, "lane_change") + jsonNumber(summary, "crossing"));
  EXPECT_LT(rearEnd * 5, proximity);
  // the headline: the same counts, proximity apart from the conflicts
  EXPECT_NE(r.out.find("rear_end " + std::to_string(rearEnd) + ","), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("; proximity " + std::to_string(proximity) + " (zone occupied, no collision course)"),
            std::string::npos)
      << r.out;
}

// The shipped SUMO configurations run with plain `sumo -c` on a machine without SUMO_HOME: their
// files name SUMO's schemas by URL, which SUMO can resolve only from SUMO_HOME (or the web), so
// they turn XML validation off.
TEST(HighwayCli, ShippedSumoConfigsRunWithoutSumoHome) {
  if (onPath("sumo").empty()) GTEST_SKIP() << "sumo not on PATH";
  const auto dir = freshDir("plain_sumo");
  for (const char* net : {"motorway", "ring", "sublane"}) {
    const auto cfg = sourceDir() / "networks" / net / (std::string(net) + ".sumocfg");
    const std::string cmd = "cd " + dir.string() + " && env -u SUMO_HOME sumo -c " + cfg.string() +
                            " --end 5 > " + (dir / net).string() + ".log 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << net << ": " << slurp(dir / (std::string(net) + ".log"));
  }
}

// SUMO's default rule counts a gap below minGap (1.5 m here) as a collision, crawling queues
// included; with collision_mingap_factor 0 only physical contacts count, and each of those must
// have been warned of by its collider (every car is equipped: touching is TTC 0).
TEST(HighwayCli, PhysicalCollisionsAreFewerAndEveryOneWarned) {
  const auto dir = freshDir("cli_mingap");
  std::filesystem::copy(motorway().parent_path(), dir / "net", std::filesystem::copy_options::recursive);
  std::string yaml = slurp(dir / "net/scenario.yaml");
  yaml += "collision_mingap_factor: 0\n";
  std::ofstream(dir / "net/physical.yaml") << yaml;
  const auto p = runStsim({"highway", (dir / "net/physical.yaml").string(), "--end", "232", "--out", (dir / "p").string()}, dir);
  ASSERT_EQ(p.code, 0) << p.err;
  const auto d = runStsim({"highway", motorway().string(), "--end", "232", "--out", (dir / "d").string()}, dir);
  ASSERT_EQ(d.code, 0) << d.err;
  const double physical = jsonNumber(slurp(dir / "p/summary.json"), "sumo_collisions");
  const double byMinGap = jsonNumber(slurp(dir / "d/summary.json"), "sumo_collisions");
  EXPECT_GE(physical, 1.0);
  EXPECT_LT(physical, byMinGap);
  const auto rows = lines(slurp(dir / "p/collision_warnings.csv"));
  ASSERT_EQ(rows.size(), 1 + static_cast<std::size_t>(physical));
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(splitCsv(rows[i])[3], "1") << rows[i];
  // the warnings themselves do not depend on how SUMO counts collisions
  EXPECT_EQ(slurp(dir / "p/warnings.csv"), slurp(dir / "d/warnings.csv"));
  // stsim's contacts (the bodies touching in the step's states) are SUMO's physical collisions,
  // whichever rule SUMO counts by; the default rule's others are minGap violations, apart
  const std::string ps = slurp(dir / "p/summary.json"), ds = slurp(dir / "d/summary.json");
  EXPECT_EQ(jsonNumber(ps, "contacts"), physical);
  EXPECT_EQ(jsonNumber(ps, "mingap_violations"), 0.0);
  EXPECT_EQ(jsonNumber(ds, "contacts"), physical);
  EXPECT_EQ(jsonNumber(ds, "mingap_violations"), byMinGap - physical);
  EXPECT_EQ(slurp(dir / "d/collision_warnings.csv"), slurp(dir / "p/collision_warnings.csv"));
  for (const auto& row : lines(slurp(dir / "p/collisions.csv"))) {
    if (row.rfind("time,", 0) == 0) continue;
    EXPECT_EQ(splitCsv(row).back(), "1") << row;  // each physical report touches
  }
  // docs/outputs.md's conventions: SUMO's numbers in full (the shortest text that reads back, so
  // 210.4, not 210.400), worked-out ones (gap, lead time) to 0.001 with trailing zeros dropped:
  // in neither does a fraction end in 0
  for (const char* file : {"p/collisions.csv", "p/collision_warnings.csv", "d/collisions.csv"}) {
    const auto all = lines(slurp(dir / file));
    for (std::size_t i = 1; i < all.size(); ++i)
      for (const auto& f : splitCsv(all[i])) {
        if (f.find('.') == std::string::npos || f.find_first_not_of("-0123456789.") != std::string::npos) continue;
        EXPECT_NE(f.back(), '0') << file << ": " << all[i];
        EXPECT_NE(f.back(), '.') << file << ": " << all[i];
      }
  }
}

// The sublane network exists to produce lane-marker and curb warnings (lateral drift, filtering).
TEST(HighwayCli, SublaneNetworkRaisesLaneMarkerAndCurbWarnings) {
  const auto dir = freshDir("cli_sublane");
  const auto r = runStsim({"highway", (sourceDir() / "networks/sublane/scenario.yaml").string(), "--end", "90",
                           "--out", dir.string()},
                          dir);
  ASSERT_EQ(r.code, 0) << r.err;
  std::size_t markers = 0, curbs = 0;
  for (const auto& l : lines(slurp(dir / "warnings.csv"))) {
    markers += l.find(",lane_marker,") != std::string::npos;
    curbs += l.find(",curb,") != std::string::npos;
  }
  EXPECT_GT(markers, 20u);
  EXPECT_GT(curbs, 5u);
}

// A live run and the replay of its own FCD output (the attributes models/highway/README.md names,
// 6 decimals) give the same warnings: every vehicle and road warning, same ego, foe, kind, zone,
// begin and end, minimum TTC within the trace's precision. Both go through the one conversion
// (sumo_conversion.hpp); the replay's lateral speed is posLat's change (a sublane run's), none
// for a lane change made in one step. SUMO labels its outputs with the time a step began, the
// live run with the time after it: the replay's times are one step (0.1 s) earlier. The sublane
// network (drifts across markers) and the motorway (lane changes in one step); the intersection
// and the crosswalk (persons on foot) with the routes the cars drove (SUMO's --vehroute-output)
// and the light's states (SaveTLSStates), where conflicts.csv is compared too; and the roundabout
// (no light: the priority rules from the network alone) with the routes.
TEST(HighwayCli, LiveRunAndTheReplayOfItsFcdGiveTheSameWarnings) {
  for (const std::string net : {"sublane", "motorway", "intersection", "crosswalk", "roundabout"}) {
    const auto dir = freshDir("cli_replay_" + net);
    const auto src = sourceDir() / "networks" / net;
    const auto fcd = dir / "trace.fcd.xml";
    const bool lights = net == "intersection" || net == "crosswalk", junction = lights || net == "roundabout";
    const auto tls = dir / "tls.xml", routes = dir / "routes.xml";
    std::ofstream(dir / "tls.add.xml") << "<additional><timedEvent type=\"SaveTLSStates\" source=\"C\" dest=\""
                                       << tls.string() << "\"/></additional>\n";
    std::ofstream(dir / "live.yaml") << "sumocfg: " << (src / (net + ".sumocfg")).string()
                                     << "\nseed: 42\nend: " << (junction ? 300 : 90) << "\naction: none\ndetector: "
                                     << (junction ? "box" : "five") << "\n"
                                     << "safe_time: {vehicle_reaction: 1.0, road_reaction: 0.5}\n"
                                     << "sumo_args: [--fcd-output, " << fcd.string()
                                     << ", --fcd-output.attributes, 'x,y,angle,type,speed,lane,pos,signals,acceleration,posLat',"
                                     << " --precision, '6'"
                                     << (lights ? ", --additional-files, " + (dir / "tls.add.xml").string() : std::string())
                                     << (junction ? ", --vehroute-output, " + routes.string() +
                                                        ", --vehroute-output.write-unfinished, 'true'"
                                                  : std::string())
                                     << "]\n";
    const auto live = runStsim({"highway", (dir / "live.yaml").string(), "--no-map", "--out", (dir / "live").string()}, dir);
    ASSERT_EQ(live.code, 0) << live.err;
    std::vector<std::string> args{"highway", "--fcd", fcd.string(), "--net", (src / (net + ".net.xml")).string(),
                                  "--vtypes", (src / (net + ".rou.xml")).string(), "--detector", junction ? "box" : "five",
                                  "--no-map", "--out", (dir / "replay").string()};
    if (lights) args.insert(args.end(), {"--tls-states", tls.string()});
    if (junction) args.insert(args.end(), {"--routes", routes.string()});
    const auto replay = runStsim(args, dir);
    ASSERT_EQ(replay.code, 0) << replay.err;
    // ego, foe, kind, zone, begin, end (ms, the replay's moved on by the step) -> min TTC
    auto rows = [](const std::filesystem::path& p, long shiftMs) {
      std::map<std::string, double> out;
      const auto ls = lines(slurp(p));
      for (std::size_t i = 1; i < ls.size(); ++i) {
        const auto f = splitCsv(ls[i]);
        const long begin = std::lround(std::stod(f[4]) * 1000.0) + shiftMs, end = std::lround(std::stod(f[5]) * 1000.0) + shiftMs;
        const std::string key = f[0] + " " + f[1] + " " + f[2] + " " + f[3] + " " + std::to_string(begin) + " " + std::to_string(end);
        EXPECT_TRUE(out.emplace(key, std::stod(f[6])).second) << key;
      }
      return out;
    };
    const auto a = rows(dir / "live/warnings.csv", 0), b = rows(dir / "replay/warnings.csv", 100);
    EXPECT_GT(a.size(), net == "sublane" ? 400u : net == "intersection" ? 10u : net == "roundabout" ? 0u : 50u);  // intersection: 14
    ASSERT_EQ(a.size(), b.size()) << net;
    for (const auto& [key, ttc] : a) {
      const auto it = b.find(key);
      ASSERT_NE(it, b.end()) << net << ": live warning " << key << " not in the replay";
      if (std::isfinite(ttc)) {
        EXPECT_NEAR(it->second, ttc, 1e-4) << net << ": " << key;
      } else {
        EXPECT_EQ(it->second, ttc) << net << ": " << key;
      }
    }
    if (net == "roundabout") {
      // the replay reads the priority rules from the network: without them its entries are warned
      std::vector<std::string> blind = args;
      *(std::find(blind.begin(), blind.end(), "--out") + 1) = (dir / "replay_blind").string();
      blind.insert(blind.end(), {"--set", "priority_rules=false"});
      ASSERT_EQ(runStsim(blind, dir).code, 0);
      EXPECT_GT(rows(dir / "replay_blind/warnings.csv", 100).size(), a.size() + 20) << net;
      continue;
    }
    if (!junction) continue;
    // conflicts.csv: first, second, type, encounter (read from the lanes both ways), begin, end (ms,
    // the replay's moved on) -> min TTC; the columns by their header
    auto conflicts = [](const std::filesystem::path& p, long shiftMs) {
      std::map<std::string, double> out;
      const auto ls = lines(slurp(p));
      const auto head = splitCsv(ls.at(0));
      const auto col = [&](const char* name) {
        const auto it = std::find(head.begin(), head.end(), name);
        EXPECT_NE(it, head.end()) << name;
        return static_cast<std::size_t>(it - head.begin());
      };
      const std::size_t first = col("first"), second = col("second"), type = col("type"), encounter = col("encounter"),
                        begin = col("begin"), end = col("end"), ttc = col("min_ttc");
      for (std::size_t i = 1; i < ls.size(); ++i) {
        const auto f = splitCsv(ls[i]);
        const long from = std::lround(std::stod(f.at(begin)) * 1000.0) + shiftMs, to = std::lround(std::stod(f.at(end)) * 1000.0) + shiftMs;
        out.emplace(f[first] + " " + f[second] + " " + f[type] + " " + f[encounter] + " " + std::to_string(from) + " " +
                        std::to_string(to),
                    std::stod(f.at(ttc)));
      }
      return out;
    };
    const auto ca = conflicts(dir / "live/conflicts.csv", 0), cb = conflicts(dir / "replay/conflicts.csv", 100);
    EXPECT_GT(ca.size(), net == "intersection" ? 3u : 20u) << net;  // 4 at the intersection in these 300 s
    EXPECT_EQ(ca.size(), cb.size()) << net;
    for (const auto& [key, ttc] : ca) {
      const auto it = cb.find(key);
      ASSERT_NE(it, cb.end()) << net << ": live conflict " << key << " not in the replay";
      EXPECT_NEAR(it->second, ttc, 1e-4) << net << ": " << key;
    }
  }
}

TEST(HighwayCli, DeterministicForASeedAndPenetrationDrawsThatShare) {
  const auto dir = freshDir("cli_seed");
  auto go = [&](const std::string& name, const std::string& seed) {
    const auto r = runStsim({"highway", motorway().string(), "--end", "120", "--penetration", "0.5", "--seed", seed,
                             "--out", (dir / name).string()},
                            dir);
    EXPECT_EQ(r.code, 0) << r.err;
    return slurp(dir / name / "warnings.csv");
  };
  const std::string a = go("a", "7"), b = go("b", "7"), c = go("c", "8");
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  const std::string summary = slurp(dir / "a/summary.json");
  const double equipped = jsonNumber(summary, "equipped_vehicles"), seen = jsonNumber(summary, "vehicles");
  EXPECT_GT(seen, 100.0);
  // binomial(n, 0.5) within 4 sd
  EXPECT_NEAR(equipped / seen, 0.5, 4.0 * 0.5 / std::sqrt(seen));
}

TEST(HighwayCli, MissingNetworkFileIsOneLineError) {
  const auto dir = freshDir("cli_missing_net");
  std::ofstream(dir / "x.sumocfg") << "<configuration><input><net-file value=\"absent.net.xml\"/>"
                                      "<route-files value=\"absent.rou.xml\"/></input></configuration>";
  const auto r = runStsim({"highway", (dir / "x.sumocfg").string(), "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 1);
  const auto ls = lines(r.err);
  ASSERT_EQ(ls.size(), 1u) << r.err;
  EXPECT_NE(ls[0].find("absent.net.xml"), std::string::npos) << ls[0];
  EXPECT_NE(ls[0].find("does not exist"), std::string::npos) << ls[0];
}

TEST(HighwayCli, MissingRouteFileIsOneLineError) {
  const auto dir = freshDir("cli_missing_routes");
  std::filesystem::copy_file(sourceDir() / "networks/motorway/motorway.net.xml", dir / "m.net.xml");
  std::ofstream(dir / "x.sumocfg") << "<configuration><input><net-file value=\"m.net.xml\"/>"
                                      "<route-files value=\"absent.rou.xml\"/></input></configuration>";
  std::ofstream(dir / "s.yaml") << "sumocfg: x.sumocfg\n";
  const auto r = runStsim({"highway", (dir / "s.yaml").string(), "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 1);
  const auto ls = lines(r.err);
  ASSERT_EQ(ls.size(), 1u) << r.err;
  EXPECT_NE(ls[0].find("route-files"), std::string::npos) << ls[0];
  EXPECT_NE(ls[0].find("absent.rou.xml"), std::string::npos) << ls[0];
}

TEST(HighwayCli, MissingScenarioAndMalformedYamlAreOneLineErrors) {
  const auto dir = freshDir("cli_bad_yaml");
  auto r = runStsim({"highway", (dir / "nothing.yaml").string()}, dir);
  EXPECT_EQ(r.code, 1);
  ASSERT_EQ(lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("nothing.yaml: no such file"), std::string::npos) << r.err;
  std::ofstream(dir / "bad.yaml") << "sumocfg: ../x.sumocfg\nend: soon\n";
  r = runStsim({"highway", (dir / "bad.yaml").string()}, dir);
  EXPECT_EQ(r.code, 1);
  ASSERT_EQ(lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("bad.yaml:2: end: must be a number"), std::string::npos) << r.err;
}

// SUMO refusing its inputs at start: SUMO prints some errors itself and spreads others over
// several lines; the user sees one line naming the config and SUMO's reason, exit 1.
TEST(HighwayCli, SumoStartErrorsAreOneLine) {
  const auto dir = freshDir("cli_sumo_start");
  std::filesystem::copy_file(sourceDir() / "networks/motorway/motorway.net.xml", dir / "m.net.xml");
  // a route over an edge the network does not have (SUMO's message spans two lines)
  std::ofstream(dir / "r.rou.xml") << "<routes><vType id=\"car\"/><vehicle id=\"a\" type=\"car\" depart=\"0\">"
                                      "<route edges=\"nosuchedge\"/></vehicle></routes>";
  std::ofstream(dir / "a.sumocfg") << "<configuration><input><net-file value=\"m.net.xml\"/>"
                                      "<route-files value=\"r.rou.xml\"/></input></configuration>";
  // an end before the begin (SUMO prints "Error: ..." itself and throws "Process Error")
  std::ofstream(dir / "b.rou.xml") << "<routes/>";
  std::ofstream(dir / "b.sumocfg") << "<configuration><input><net-file value=\"m.net.xml\"/>"
                                      "<route-files value=\"b.rou.xml\"/></input>"
                                      "<time><begin value=\"10\"/><end value=\"5\"/></time></configuration>";
  // an option SUMO does not know, through the scenario's sumo_args
  std::ofstream(dir / "c.yaml") << "sumocfg: b.sumocfg\nend: 20\nsumo_args: [\"--no-such-option\", \"1\"]\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"a.sumocfg", "'nosuchedge' within the route for vehicle 'a' is not known"},
      {"b.sumocfg", "The end time should be after the begin time"},
      {"c.yaml", "no-such-option"}};
  for (const auto& [input, reason] : cases) {
    const auto r = runStsim({"highway", (dir / input).string(), "--out", (dir / ("out_" + input)).string()}, dir);
    EXPECT_EQ(r.code, 1) << input << ": " << r.err;
    const auto ls = lines(r.err);
    ASSERT_EQ(ls.size(), 1u) << input << ": " << r.err;
    EXPECT_NE(ls[0].find("SUMO failed to start"), std::string::npos) << ls[0];
    EXPECT_NE(ls[0].find(reason), std::string::npos) << ls[0];
    EXPECT_EQ(ls[0].find("Process Error"), std::string::npos) << ls[0];
  }
}

void expectCtrlCStopsCleanly(const std::string& name, const std::vector<std::string>& extra) {
  const auto dir = freshDir(name);
  // the ring's vehicles circle for hours of simulated time, so the run cannot end on its own
  // before the signal, however fast the machine
  const auto ring = sourceDir() / "networks/ring/scenario.yaml";
  constexpr double kEnd = 36000.0;
  std::vector<std::string> args{"highway", ring.string(), "--end", "36000", "--out", (dir / "out").string()};
  args.insert(args.end(), extra.begin(), extra.end());
  StsimProcess p(args, dir);
  // signal once the run has stepped and written a warning (the ring has its first ones within
  // 11 s of simulated time): not before the handler is installed, not before t > 0; no sleeps
  ASSERT_TRUE(waitForWarningRows(dir / "out/warnings.csv", p)) << p.err();
  p.signal(SIGINT);
  const int code = p.wait();
  EXPECT_EQ(code, 130) << p.err();
  EXPECT_NE(p.err().find("interrupted at t = "), std::string::npos) << p.err();
  std::size_t rows = 0;
  EXPECT_TRUE(validWarningsCsv(dir / "out/warnings.csv", &rows));
  const std::string summary = slurp(dir / "out/summary.json");
  EXPECT_EQ(jsonString(summary, "stop_reason"), "interrupted");
  const double simulated = jsonNumber(summary, "simulated_s");
  EXPECT_GT(simulated, 0.0);
  EXPECT_LT(simulated, kEnd);
  EXPECT_DOUBLE_EQ(jsonNumber(summary, "total"), static_cast<double>(rows));
}

TEST(HighwayCli, CtrlCStopsCleanlyWithResultsFlushed) { expectCtrlCStopsCleanly("cli_sigint", {}); }

// with detection on the worker (which blocks signals): the signal lands on SUMO's thread
TEST(HighwayCli, CtrlCStopsTheThreadedRunCleanlyToo) {
  expectCtrlCStopsCleanly("cli_sigint_threads", {"--action", "none", "--threads", "2"});
}

}  // namespace
}  // namespace st::cosim

namespace st::cosim {
namespace {

using namespace st::cosim::test;

// The inserted-vehicle count SUMO itself reports in its --statistic-output.
long sumoInserted(const std::filesystem::path& stats) {
  const std::string xml = slurp(stats);
  std::smatch m;
  if (!std::regex_search(xml, m, std::regex("<vehicles[^>]* inserted=\"([0-9]+)\""))) return -1;
  return std::stol(m[1].str());
}

// demand_scale is SUMO's --scale: stsim's departed count equals plain SUMO's inserted count with the
// same scale and seed (action none: stsim does not steer), and the scenario key equals the option.
TEST(HighwayCli, DemandScaleIsSumosScale) {
  const auto dir = freshDir("cli_scale");
  const auto cfg = sourceDir() / "networks/motorway/motorway.sumocfg";
  std::vector<long> counts;
  for (const char* scale : {"0.5", "1.5"}) {
    const auto out = dir / (std::string("stsim") + scale);
    const auto r = runStsim({"highway", motorway().string(), "--end", "90", "--action", "none", "--scale", scale,
                             "--out", out.string()},
                            dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto stats = dir / (std::string("sumo") + scale + ".xml");
    const std::string cmd = "sumo -c " + cfg.string() + " --seed 42 --end 90 --scale " + scale +
                            " --collision.action warn --xml-validation never --no-step-log true --no-warnings true --statistic-output " +
                            stats.string() + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const long inserted = sumoInserted(stats);
    ASSERT_GT(inserted, 0) << slurp(stats);
    EXPECT_DOUBLE_EQ(jsonNumber(slurp(out / "summary.json"), "departed"), static_cast<double>(inserted)) << scale;
    counts.push_back(inserted);
  }
  EXPECT_LT(counts[0], counts[1]);  // the scale did reach SUMO
  // the YAML key: a scenario next to the original, so its relative sumocfg resolves
  const auto yaml = sourceDir() / "networks/motorway" / ("scale_test_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(yaml) << "sumocfg: motorway.sumocfg\nseed: 42\nend: 90\naction: none\ndemand_scale: 0.5\n";
  const auto r = runStsim({"highway", yaml.string(), "--out", (dir / "yaml").string()}, dir);
  std::filesystem::remove(yaml);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_DOUBLE_EQ(jsonNumber(slurp(dir / "yaml/summary.json"), "departed"), static_cast<double>(counts[0]));
}

TEST(HighwayCli, BadDemandScaleNamesTheKey) {
  const auto dir = freshDir("cli_bad_scale");
  std::ofstream(dir / "s.yaml") << "sumocfg: x.sumocfg\ndemand_scale: lots\n";
  const auto r = runStsim({"highway", (dir / "s.yaml").string()}, dir);
  EXPECT_EQ(r.code, 1);
  ASSERT_EQ(lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("s.yaml:2: demand_scale: must be a number"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace st::cosim
