// Scenario YAML and SUMO configuration checks: bad input gives one line naming the file and field.
#include <gtest/gtest.h>

#include <algorithm>

#include <sys/stat.h>

#include "bounded.hpp"
#include "test_util.hpp"
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "";
}

TEST(Scenario, MotorwayLoads) {
  const Scenario s = loadScenario(motorway());
  EXPECT_EQ(s.sumocfg, motorway().parent_path() / "motorway.sumocfg");
  EXPECT_EQ(s.seed, 42u);
  ASSERT_TRUE(s.end.has_value());
  EXPECT_DOUBLE_EQ(*s.end, 420.0);
  EXPECT_EQ(s.plugin.monitor.detector.kind, highway::DetectorKind::FiveCircle);
  EXPECT_DOUBLE_EQ(s.plugin.monitor.safeTime.brakeForce[1], 75000.0);
  const SumoConfigFiles f = checkSumoConfig(s.sumocfg);
  EXPECT_EQ(f.net.filename(), "motorway.net.xml");
  ASSERT_EQ(f.routes.size(), 1u);
  EXPECT_DOUBLE_EQ(*f.stepLength, 0.1);
}

TEST(Scenario, PlainSumocfgTakesItsSeed) {
  const Scenario s = loadScenario(sourceDir() / "networks/motorway/motorway.sumocfg");
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.plugin.monitor.detector.kind, highway::DetectorKind::FiveCircle);
}

// A plain .sumocfg runs the traffic it describes: SUMO gets no --seed of stsim's (which would
// replace a config's own seed, or SUMO's default 23423, without a word), the smart-car draw takes
// the seed SUMO uses, and the outputs go to out/<config name>/, not the current folder
TEST(Scenario, PlainSumocfgRunsWithItsOwnSeedIntoItsOwnFolder) {
  auto hasSeed = [](const Scenario& s) {
    const auto a = sumoArguments(s);
    return std::find(a.begin(), a.end(), "--seed") != a.end();
  };
  const Scenario own = loadScenario(sourceDir() / "networks/motorway/motorway.sumocfg");
  EXPECT_FALSE(hasSeed(own));
  ASSERT_TRUE(own.out.has_value());
  EXPECT_EQ(*own.out, std::filesystem::path("out") / "motorway");

  const auto dir = freshDir("plain_seed");
  std::filesystem::copy_file(sourceDir() / "networks/ring/ring.net.xml", dir / "ring.net.xml");
  std::ofstream(dir / "noseed.sumocfg") << "<configuration><input><net-file value=\"ring.net.xml\"/></input></configuration>";
  const Scenario none = loadScenario(dir / "noseed.sumocfg");
  EXPECT_FALSE(hasSeed(none));
  EXPECT_EQ(none.seed, 23423u);  // SUMO's default, the draw's too
  EXPECT_EQ(none.plugin.smart.seed, 23423u);

  // a YAML scenario says its seed (42 unless set): SUMO is given it
  const Scenario yaml = loadScenario(motorway());
  EXPECT_TRUE(hasSeed(yaml));
}

TEST(Scenario, MissingNetworkOrRouteFileIsNamed) {
  const auto dir = freshDir("missing_files");
  std::ofstream(dir / "a.sumocfg") << "<configuration><input><net-file value=\"gone.net.xml\"/></input></configuration>";
  std::string e = errorOf([&] { checkSumoConfig(dir / "a.sumocfg"); });
  EXPECT_NE(e.find("net-file"), std::string::npos) << e;
  EXPECT_NE(e.find("gone.net.xml"), std::string::npos) << e;
  std::filesystem::copy_file(sourceDir() / "networks/motorway/motorway.net.xml", dir / "m.net.xml");
  std::ofstream(dir / "b.sumocfg") << "<configuration><input><net-file value=\"m.net.xml\"/>"
                                      "<route-files value=\"m.rou.xml,missing.rou.xml\"/></input></configuration>";
  e = errorOf([&] { checkSumoConfig(dir / "b.sumocfg"); });
  EXPECT_NE(e.find("route-files"), std::string::npos) << e;
  EXPECT_NE(e.find("m.rou.xml"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
}

// SUMO stops on these with its own words and no file (a repeated id, perhaps when the second
// departs minutes into the run) or takes them (a mass param of NaN, which stsim met as the vehicle
// departed): named file:line before SUMO starts
TEST(Scenario, RouteFileMistakesSumoWouldNotNameAreNamed) {
  const auto dir = freshDir("route_mistakes");
  const auto ring = sourceDir() / "networks/ring";
  std::filesystem::copy_file(ring / "ring.net.xml", dir / "ring.net.xml");
  const std::string routes = slurp(ring / "ring.rou.xml");
  auto config = [&](const std::string& name, const std::string& rou, const std::string& more = "") {
    std::ofstream(dir / (name + ".rou.xml")) << rou;
    std::ofstream(dir / (name + ".sumocfg")) << "<configuration><input><net-file value=\"ring.net.xml\"/>"
                                                "<route-files value=\"" << name << ".rou.xml" << more
                                             << "\"/></input></configuration>";
    return dir / (name + ".sumocfg");
  };
  auto lineOf = [](const std::string& text, const std::string& what) {
    return 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find(what)), '\n');
  };
  // the shipped file passes
  EXPECT_EQ(errorOf([&] { checkSumoConfig(config("ok", routes)); }), "");
  // a vehicle id twice
  std::string dup = routes;
  dup.replace(dup.find("<vehicle id=\"v01\""), 17, "<vehicle id=\"v00\"");
  const std::string file = (dir / "dup.rou.xml").string();
  EXPECT_EQ(errorOf([&] { checkSumoConfig(config("dup", dup)); }),
            file + ":" + std::to_string(lineOf(dup, "id=\"v00\" type=\"car\"")) +
                ": <vehicle id=\"v00\">: the id is given twice (first at line " + std::to_string(lineOf(dup, "id=\"v00\"")) +
                "); SUMO would stop on it");
  // a trip with a vehicle's id, in a second route file; a comment does not count
  std::ofstream(dir / "more.rou.xml") << "<routes>\n<!-- <trip id=\"v02\"/> -->\n  <trip id = 'v03' from=\"north\" to=\"south\" depart=\"5\"/>\n</routes>\n";
  EXPECT_EQ(errorOf([&] { checkSumoConfig(config("two", routes, ",more.rou.xml")); }),
            (dir / "more.rou.xml").string() + ":3: <trip id=\"v03\">: the id is given twice (first at " +
                (dir / "two.rou.xml").string() + ":" + std::to_string(lineOf(routes, "id=\"v03\"")) + "); SUMO would stop on it");
  // a flow may share a vehicle's id (SUMO takes it); two flows may not
  std::ofstream(dir / "twoflows.rou.xml") << "<routes>\n  <flow id=\"v03\" begin=\"0\" end=\"9\" number=\"1\" from=\"north\" to=\"south\"/>\n"
                                         "  <flow id=\"v03\" begin=\"0\" end=\"9\" number=\"1\" from=\"north\" to=\"south\"/>\n</routes>\n";
  EXPECT_NE(errorOf([&] { checkSumoConfig(config("flows", routes, ",twoflows.rou.xml")); })
                .find("twoflows.rou.xml:3: <flow id=\"v03\">: the id is given twice (first at line 2)"),
            std::string::npos);
  // a vType mass of NaN
  std::string nan = routes;
  nan.replace(nan.find("value=\"1400\""), 12, "value=\"nan\"");
  const std::string e = errorOf([&] { checkSumoConfig(config("nan", nan)); });
  EXPECT_EQ(e.rfind((dir / "nan.rou.xml").string() + ":" + std::to_string(lineOf(nan, "\"nan\"")) + ": ", 0), 0u) << e;
  EXPECT_NE(e.find("'nan'"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// A configuration or a network named as route or additional files: SUMO would read no vehicle
// from it and say nothing (a run with no traffic, exit 0); it is refused naming the file
TEST(Scenario, AConfigOrNetworkNamedAsRoutesIsRefused) {
  const auto dir = freshDir("routes_not_routes");
  const auto ring = sourceDir() / "networks/ring";
  std::filesystem::copy_file(ring / "ring.net.xml", dir / "ring.net.xml");
  std::filesystem::copy_file(ring / "ring.rou.xml", dir / "ring.rou.xml");
  auto config = [&](const std::string& name, const std::string& key, const std::string& files) {
    std::ofstream(dir / (name + ".sumocfg")) << "<?xml version=\"1.0\"?>\n<!-- <routes> in a comment -->\n"
                                                "<configuration><input><net-file value=\"ring.net.xml\"/><" << key
                                             << " value=\"" << files << "\"/></input></configuration>";
    return dir / (name + ".sumocfg");
  };
  EXPECT_EQ(errorOf([&] { checkSumoConfig(config("ok", "route-files", "ring.rou.xml")); }), "");
  EXPECT_EQ(errorOf([&] { checkSumoConfig(config("cfg", "route-files", "ring.rou.xml,ok.sumocfg")); }),
            (dir / "cfg.sumocfg").string() + ": route-files '" + (dir / "ok.sumocfg").string() +
                "' is a SUMO configuration, not a route file");
  EXPECT_EQ(errorOf([&] { checkSumoConfig(config("net", "additional-files", "ring.net.xml")); }),
            (dir / "net.sumocfg").string() + ": additional-files '" + (dir / "ring.net.xml").string() +
                "' is a SUMO network, not an additional file");
}

// The same with a configuration whose root is not <configuration>: SUMO's tools write
// <sumoConfiguration> (and <duarouterConfiguration>, ...), which SUMO takes as a route file with
// 0 vehicles, warning only "Found root element 'sumoConfiguration'"; it is refused too
TEST(Scenario, AConfigOfAnyRootNamedAsRoutesIsRefused) {
  const auto dir = freshDir("routes_other_config");
  const auto ring = sourceDir() / "networks/ring";
  std::filesystem::copy_file(ring / "ring.net.xml", dir / "ring.net.xml");
  std::filesystem::copy_file(ring / "ring.rou.xml", dir / "ring.rou.xml");
  auto config = [&](const std::string& name, const std::string& root, const std::string& routes) {
    std::ofstream(dir / name) << "<?xml version=\"1.0\"?>\n<" << root << "><input><net-file value=\"ring.net.xml\"/>"
                              << "<route-files value=\"" << routes << "\"/></input></" << root << ">\n";
    return dir / name;
  };
  config("sumo.sumocfg", "sumoConfiguration", "ring.rou.xml");
  config("dua.sumocfg", "duarouterConfiguration", "ring.rou.xml");
  config("odd.sumocfg", "options", "ring.rou.xml");
  for (const char* named : {"sumo.sumocfg", "dua.sumocfg", "odd.sumocfg"}) {
    const auto cfg = config("c.sumocfg", "configuration", std::string("ring.rou.xml,") + named);
    EXPECT_EQ(errorOf([&] { checkSumoConfig(cfg); }), cfg.string() + ": route-files '" + (dir / named).string() +
                                                           "' is a SUMO configuration, not a route file");
  }
  // routes in a file named .sumocfg are routes still
  std::filesystem::copy_file(dir / "ring.rou.xml", dir / "routes.sumocfg");
  EXPECT_EQ(errorOf([&] { checkSumoConfig(config("r.sumocfg", "configuration", "routes.sumocfg")); }), "");
  // the command: one line naming the file and the field, exit 1, before SUMO starts
  const auto cfg = config("c.sumocfg", "configuration", "sumo.sumocfg");
  const RunResult r = runStsim({"highway", cfg.string(), "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_EQ(r.err, "stsim highway: error: " + cfg.string() + ": route-files '" + (dir / "sumo.sumocfg").string() +
                       "' is a SUMO configuration, not a route file\n");
}

// A file name longer than the system allows threw std::filesystem_error ("status: File name too
// long") naming no sumocfg (fuzz finding, fuzz/corpus/cosim_scenario/name_too_long.sumocfg)
TEST(Scenario, AFileNameTooLongIsNamedWithItsConfig) {
  const auto dir = freshDir("name_too_long");
  std::ofstream(dir / "a.sumocfg") << "<configuration><input><net-file value=\"" << std::string(300, 'n')
                                   << ".net.xml\"/></input></configuration>";
  const std::string e = errorOf([&] { checkSumoConfig(dir / "a.sumocfg"); });
  EXPECT_EQ(e.rfind((dir / "a.sumocfg").string() + ": net-file '", 0), 0u) << e;
  EXPECT_NE(e.find("File name too long"), std::string::npos) << e;
  EXPECT_NE(errorOf([&] { loadScenario(dir / (std::string(300, 'y') + ".yaml")); }).find("File name too long"),
            std::string::npos);
}

TEST(Scenario, MalformedYamlNamesFileAndLine) {
  const auto dir = freshDir("bad_yaml");
  std::ofstream(dir / "s.yaml") << "sumocfg: x.sumocfg\ndetector: [five\n";
  std::string e = errorOf([&] { loadScenario(dir / "s.yaml"); });
  EXPECT_NE(e.find("s.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("malformed YAML"), std::string::npos) << e;
}

TEST(Scenario, UnknownKeyAndBadValuesAreNamed) {
  const auto dir = freshDir("bad_keys");
  std::ofstream(dir / "a.yaml") << "sumocfg: x.sumocfg\ndetectr: five\n";
  std::string e = errorOf([&] { loadScenario(dir / "a.yaml"); });
  EXPECT_NE(e.find("a.yaml:2: detectr: unknown key"), std::string::npos) << e;
  std::ofstream(dir / "b.yaml") << "sumocfg: x.sumocfg\npenetration: 1.5\n";
  e = errorOf([&] { loadScenario(dir / "b.yaml"); });
  EXPECT_NE(e.find("b.yaml:2: penetration: must be in [0, 1]"), std::string::npos) << e;
  std::ofstream(dir / "c.yaml") << "sumocfg: x.sumocfg\nsafe_time: {brake_force: {lorry: 1}}\n";
  e = errorOf([&] { loadScenario(dir / "c.yaml"); });
  EXPECT_NE(e.find("safe_time.brake_force.lorry: unknown key"), std::string::npos) << e;
  std::ofstream(dir / "d.yaml") << "detector: five\n";
  e = errorOf([&] { loadScenario(dir / "d.yaml"); });
  EXPECT_NE(e.find("sumocfg: missing"), std::string::npos) << e;
}

TEST(Scenario, RepeatedKeysAndDirectoriesAreErrors) {
  const auto dir = freshDir("repeated_keys");
  // yaml-cpp keeps the first of two equal keys: seed 43 would run with 42 without a word
  std::ofstream(dir / "a.yaml") << "sumocfg: x.sumocfg\nseed: 42\nseed: 43\n";
  std::string e = errorOf([&] { loadScenario(dir / "a.yaml"); });
  EXPECT_NE(e.find("a.yaml:3: seed: repeated key (first given at line 2)"), std::string::npos) << e;
  std::ofstream(dir / "b.yaml") << "sumocfg: x.sumocfg\ncells: {length: 100, length: 200}\n";
  e = errorOf([&] { loadScenario(dir / "b.yaml"); });
  EXPECT_NE(e.find("b.yaml:2: cells.length: repeated key"), std::string::npos) << e;
  std::filesystem::create_directories(dir / "d.yaml");
  e = errorOf([&] { loadScenario(dir / "d.yaml"); });
  EXPECT_NE(e.find("d.yaml: is a directory"), std::string::npos) << e;
}

TEST(Scenario, BrakeSettingsAndTheRetiredDurationKey) {
  const auto dir = freshDir("brake_keys");
  std::filesystem::copy(motorway().parent_path(), dir / "net", std::filesystem::copy_options::recursive);
  std::ofstream(dir / "a.yaml") << "sumocfg: net/motorway.sumocfg\naction: brake\n"
                                   "brake: {deceleration: 2.5, max_deceleration: 6, standstill_gap: 2}\n";
  const Scenario s = loadScenario(dir / "a.yaml");
  EXPECT_EQ(s.plugin.actions.action, Action::Brake);
  EXPECT_DOUBLE_EQ(s.plugin.actions.brake.deceleration, 2.5);
  EXPECT_DOUBLE_EQ(s.plugin.actions.brake.maxDeceleration, 6.0);
  EXPECT_DOUBLE_EQ(s.plugin.actions.brake.standstillGap, 2.0);
  std::ofstream(dir / "b.yaml") << "sumocfg: net/motorway.sumocfg\nbrake:\n  duration: 1.0\n";
  std::string e = errorOf([&] { loadScenario(dir / "b.yaml"); });
  EXPECT_NE(e.find("b.yaml:3: brake.duration: no longer used"), std::string::npos) << e;
  std::ofstream(dir / "c.yaml") << "sumocfg: net/motorway.sumocfg\nbrake: {deceleration: 5, max_deceleration: 4}\n";
  e = errorOf([&] { loadScenario(dir / "c.yaml"); });
  EXPECT_NE(e.find("brake.max_deceleration: must be at least brake.deceleration"), std::string::npos) << e;
}

TEST(Scenario, ConflictTypeThresholds) {
  const auto dir = freshDir("conflict_keys");
  std::filesystem::copy(motorway().parent_path(), dir / "net", std::filesystem::copy_options::recursive);
  EXPECT_DOUBLE_EQ(loadScenario(motorway()).plugin.monitor.conflict.rearEndBelowDeg, 30.0);  // SSAM's
  EXPECT_DOUBLE_EQ(loadScenario(motorway()).plugin.monitor.conflict.crossingAboveDeg, 85.0);
  std::ofstream(dir / "a.yaml") << "sumocfg: net/motorway.sumocfg\nconflict: {rear_end_below: 20, crossing_above: 70}\n";
  const Scenario s = loadScenario(dir / "a.yaml");
  EXPECT_DOUBLE_EQ(s.plugin.monitor.conflict.rearEndBelowDeg, 20.0);
  EXPECT_DOUBLE_EQ(s.plugin.monitor.conflict.crossingAboveDeg, 70.0);
  std::ofstream(dir / "b.yaml") << "sumocfg: net/motorway.sumocfg\nconflict: {rear_end_below: 50, crossing_above: 40}\n";
  std::string e = errorOf([&] { loadScenario(dir / "b.yaml"); });
  EXPECT_NE(e.find("conflict.crossing_above: must be at least conflict.rear_end_below"), std::string::npos) << e;
  std::ofstream(dir / "c.yaml") << "sumocfg: net/motorway.sumocfg\nconflict: {crossing_above: 200}\n";
  e = errorOf([&] { loadScenario(dir / "c.yaml"); });
  EXPECT_NE(e.find("conflict.crossing_above"), std::string::npos) << e;
}

TEST(Scenario, IncidentsAreReadAndTheirMistakesNamed) {
  const Scenario s = loadScenario(sourceDir() / "networks/motorway/incident.yaml");
  ASSERT_EQ(s.plugin.incidents.size(), 4u);
  EXPECT_DOUBLE_EQ(s.plugin.incidents[1].time, 200.0);
  EXPECT_DOUBLE_EQ(s.plugin.incidents[1].x, 2400.0);
  EXPECT_DOUBLE_EQ(s.plugin.incidents[1].y, -1.88);
  EXPECT_DOUBLE_EQ(s.plugin.incidents[1].deceleration, 8.0);
  EXPECT_DOUBLE_EQ(s.plugin.incidents[1].hold, 20.0);
  const auto dir = freshDir("incident_keys");
  auto errorIn = [&](const std::string& yaml) {
    std::ofstream(dir / "i.yaml") << "sumocfg: x.sumocfg\n" << yaml;
    return errorOf([&] { loadScenario(dir / "i.yaml"); });
  };
  std::string e = errorIn("incidents: {time: 1}\n");
  EXPECT_NE(e.find("i.yaml:2: incidents: must be a list"), std::string::npos) << e;
  e = errorIn("incidents:\n  - {time: 5, near: [1, 2, 3]}\n");
  EXPECT_NE(e.find("incidents[0].near: must be [x, y]"), std::string::npos) << e;
  e = errorIn("incidents:\n  - {time: 5, near: [1, 2]}\n  - {near: [1, 2]}\n");
  EXPECT_NE(e.find("i.yaml:4: incidents[1].time: missing"), std::string::npos) << e;
  e = errorIn("incidents:\n  - {time: 5, near: [1, 2], decel: 3}\n");
  EXPECT_NE(e.find("incidents[0].decel: unknown key"), std::string::npos) << e;
  e = errorIn("incidents:\n  - {time: 5, near: [1, 2], deceleration: 0}\n");
  EXPECT_NE(e.find("incidents[0].deceleration: must be in [0.1, 50]"), std::string::npos) << e;
}

// SUMO's collision rule: by default a gap below the follower's minGap is a "collision"; the
// factor 0 leaves physical contact only. The key reaches SUMO's command line.
TEST(Scenario, CollisionMinGapFactorReachesSumo) {
  const auto dir = freshDir("mingap");
  std::filesystem::copy(motorway().parent_path(), dir / "net", std::filesystem::copy_options::recursive);
  std::ofstream(dir / "a.yaml") << "sumocfg: net/motorway.sumocfg\ncollision_mingap_factor: 0\n";
  const Scenario s = loadScenario(dir / "a.yaml");
  ASSERT_TRUE(s.collisionMinGapFactor.has_value());
  const auto args = sumoArguments(s);
  const auto it = std::find(args.begin(), args.end(), "--collision.mingap-factor");
  ASSERT_NE(it, args.end());
  EXPECT_EQ(*std::next(it), "0");
  const auto plain = sumoArguments(loadScenario(motorway()));
  EXPECT_EQ(std::find(plain.begin(), plain.end(), "--collision.mingap-factor"), plain.end());
}

// scenarioKeys() is what the reader accepts (and what a batch may sweep): each key, nested as its
// dots say, is known to the reader (its value may still be wrong), and a near miss is not.
TEST(Scenario, EveryListedKeyIsKnownToTheReader) {
  const auto dir = freshDir("listed_keys");
  auto yamlFor = [](const std::string& dotted) {
    std::string yaml = "sumocfg: x.sumocfg\n", indent;
    std::size_t from = 0;
    if (dotted == "sumocfg") return yaml;
    while (true) {
      const std::size_t dot = dotted.find('.', from);
      yaml += indent + dotted.substr(from, dot - from) + (dot == std::string::npos ? ": 0\n" : ":\n");
      if (dot == std::string::npos) return yaml;
      indent += "  ";
      from = dot + 1;
    }
  };
  ASSERT_GT(scenarioKeys().size(), 30u);
  for (const std::string& k : scenarioKeys()) {
    std::ofstream(dir / "k.yaml") << yamlFor(k);
    const std::string e = errorOf([&] { loadScenario(dir / "k.yaml"); });
    EXPECT_EQ(e.find("unknown key"), std::string::npos) << k << ": " << e;
    std::ofstream(dir / "k.yaml") << yamlFor(k + "x");
    EXPECT_NE(errorOf([&] { loadScenario(dir / "k.yaml"); }).find(k + "x: unknown key"), std::string::npos) << k;
  }
}

// A typo in smart_types would equip nobody without a word; whole-number keys must not be
// truncated silently; an empty file names itself.
TEST(Scenario, UnknownSmartTypeFractionalIntegersAndEmptyFileAreNamed) {
  const auto dir = freshDir("smart_types");
  const std::string cfg = (sourceDir() / "networks/motorway/motorway.sumocfg").string();
  std::ofstream(dir / "a.yaml") << "sumocfg: " << cfg << "\nsmart_types: [truck, lorry]\n";
  std::string e = errorOf([&] { loadScenario(dir / "a.yaml"); });
  EXPECT_NE(e.find("a.yaml:2: smart_types[1]: unknown vType 'lorry'"), std::string::npos) << e;
  EXPECT_NE(e.find("define: car, truck"), std::string::npos) << e;  // motorway.rou.xml's vTypes
  // the route file's types and SUMO's default type are accepted
  std::ofstream(dir / "b.yaml") << "sumocfg: " << cfg << "\nsmart_types: [truck, DEFAULT_VEHTYPE]\n";
  EXPECT_EQ(errorOf([&] { loadScenario(dir / "b.yaml"); }), "");
  EXPECT_EQ(loadScenario(dir / "b.yaml").plugin.smart.types, (std::vector<std::string>{"truck", "DEFAULT_VEHTYPE"}));
  std::ofstream(dir / "c.yaml") << "sumocfg: " << cfg << "\nseed: 1.5\n";
  e = errorOf([&] { loadScenario(dir / "c.yaml"); });
  EXPECT_NE(e.find("c.yaml:2: seed: must be a whole number, got 1.5"), std::string::npos) << e;
  std::ofstream(dir / "d.yaml") << "sumocfg: " << cfg << "\ncells: {decomposition_factor: 2.7}\n";
  e = errorOf([&] { loadScenario(dir / "d.yaml"); });
  EXPECT_NE(e.find("d.yaml:2: cells.decomposition_factor: must be a whole number"), std::string::npos) << e;
  std::ofstream(dir / "e.yaml") << "";
  e = errorOf([&] { loadScenario(dir / "e.yaml"); });
  EXPECT_NE(e.find("e.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("scenario: must be a mapping"), std::string::npos) << e;
}

}  // namespace
}  // namespace st::cosim

namespace st::cosim {
namespace {

// `sumocfg: /dev/zero` (a device with no end) and a FIFO (which waits for a writer) as the
// configuration or a route file: each is one line naming the file, at once.
TEST(Scenario, ASumocfgThatIsNoFileIsRefusedAtOnce) {
  const auto dir = freshDir("sumocfg_device");
  ASSERT_EQ(::mkfifo((dir / "fifo.sumocfg").c_str(), 0644), 0);
  EXPECT_EQ(st::test::errorWithin([] { checkSumoConfig("/dev/zero"); }), "/dev/zero: holds a NUL byte: not a text file");
  std::ofstream(dir / "zero.yaml") << "sumocfg: /dev/zero\n";
  EXPECT_EQ(st::test::errorWithin([&] { checkSumoConfig(loadScenario(dir / "zero.yaml").sumocfg); }),
            "/dev/zero: holds a NUL byte: not a text file");
  std::ofstream(dir / "fifo.yaml") << "sumocfg: fifo.sumocfg\n";
  EXPECT_EQ(st::test::errorWithin([&] { loadScenario(dir / "fifo.yaml"); }),
            (dir / "fifo.yaml").string() + ":1: sumocfg: " + (dir / "fifo.sumocfg").string() + ": is a FIFO, not a file");
  // a route file that is a FIFO: named with its configuration
  std::ofstream(dir / "r.sumocfg") << "<configuration><input><net-file value=\"" << (sourceDir() / "networks/ring/ring.net.xml").string()
                                   << "\"/><route-files value=\"fifo.sumocfg\"/></input></configuration>\n";
  EXPECT_EQ(st::test::errorWithin([&] { checkSumoConfig(dir / "r.sumocfg"); }),
            (dir / "r.sumocfg").string() + ": route-files: " + (dir / "fifo.sumocfg").string() + ": is a FIFO, not a file");
}

// sumo_args that cannot work in a run stsim drives (`--remote-port` would make embedded SUMO wait
// for a client for ever, `-c` replace the configuration, ...) are refused naming the argument
TEST(Scenario, SumoArgsThatCannotWorkInARunAreNamed) {
  const auto dir = freshDir("sumo_args_refused");
  const std::string cfg = (sourceDir() / "networks/ring/ring.sumocfg").string();
  for (const std::string arg : {"--remote-port", "--remote-port=47555", "--num-clients", "-c", "--configuration-file",
                                "--save-configuration", "--version", "--help", "--start", "--quit-on-end", "--game",
                                "--demo"}) {
    std::ofstream(dir / "s.yaml") << "sumocfg: " << cfg << "\nsumo_args: [--end, \"20\", \"" << arg << "\", \"1\"]\n";
    const std::string e = errorOf([&] { loadScenario(dir / "s.yaml"); });
    EXPECT_EQ(e.rfind((dir / "s.yaml").string() + ":2: sumo_args: " + arg + " cannot work in a run stsim drives: it ", 0), 0u)
        << arg << ": " << e;
  }
  std::ofstream(dir / "ok.yaml") << "sumocfg: " << cfg << "\nsumo_args: [--end, \"20\", --fcd-output, fcd.xml, --delay, \"5\"]\n";
  EXPECT_EQ(errorOf([&] { loadScenario(dir / "ok.yaml"); }), "");
}

}  // namespace
}  // namespace st::cosim
