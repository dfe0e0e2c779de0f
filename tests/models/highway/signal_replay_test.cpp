// Traffic lights for an FCD replay (sumo_signals.hpp): the shipped intersection's controlled links
// as its .net.xml writes them, the link a car takes chosen by its blinker, the state at each time
// the last record at or before it, and bad SaveTLSStates files refused with file:line.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <sthighway/sumo_files.hpp>
#include <sthighway/sumo_signals.hpp>

namespace st::highway {
namespace {

namespace fs = std::filesystem;

fs::path intersectionNet() { return fs::path(STSIM_SOURCE_DIR) / "networks/intersection/intersection.net.xml"; }

fs::path writeFile(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("stsim_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

// the 16 links of C: 0-3 from n_in (0 right, 1-2 straight, 3 left), then e_in, s_in, w_in
std::string states(char north, char northLeft, char rest) {
  std::string s(16, rest);
  s[0] = s[1] = s[2] = north;
  s[3] = northLeft;
  return s;
}

TEST(SignalReplay, LinksOfTheNetworkAndTheStateAtEachTime) {
  const SignalLinks links = readSignalLinks(intersectionNet());
  ASSERT_EQ(links.lights.size(), 1u);
  EXPECT_EQ(links.lights[0], "C");
  ASSERT_EQ(links.byLane.at("n_in_0").size(), 2u);
  ASSERT_EQ(links.byLane.at("n_in_1").size(), 2u);
  EXPECT_EQ(links.byLane.at("n_in_1")[1].index, 3);
  EXPECT_EQ(links.byLane.at("n_in_1")[1].dir, 'l');
  EXPECT_DOUBLE_EQ(links.laneLength.at("n_in_1"), 189.6);

  const fs::path file = writeFile("tls.xml", "<tlsStates>\n"
                                             "  <tlsState time=\"0.00\" id=\"C\" programID=\"0\" phase=\"0\" state=\"" +
                                                 states('G', 'g', 'r') + "\"/>\n" +
                                             "  <tlsState time=\"42.00\" id=\"C\" programID=\"0\" phase=\"1\" state=\"" +
                                                 states('y', 'y', 'r') + "\"/>\n" +
                                             "  <tlsState time=\"45.00\" id=\"C\" programID=\"0\" phase=\"2\" state=\"" +
                                                 states('r', 'r', 'G') + "\"/>\n</tlsStates>\n");
  SignalStates st(file, links);
  SumoVehicleRecord r;
  // before the first record: unknown, no light
  st.advanceTo(-1.0);
  nextSignalOf(links, st, "n_in_1", 100.0, 0, r);
  EXPECT_EQ(r.nextSignal, 0);
  st.advanceTo(10.0);
  nextSignalOf(links, st, "n_in_1", 100.0, 0, r);  // no blinker: straight on, link 2
  EXPECT_EQ(r.nextSignal, 'G');
  EXPECT_DOUBLE_EQ(r.nextSignalDistance, 89.6);
  // left blinker: link 3, on its minor green; the turner gives way at its wait point, the end of
  // its first internal lane (:C_3_0, 5.01 m; its exit into :C_16_0 is minor)
  EXPECT_DOUBLE_EQ(links.waitLength.at(":C_3_0"), 5.01);
  nextSignalOf(links, st, "n_in_1", 100.0, kSumoBlinkerLeft, r);
  EXPECT_EQ(r.nextSignal, 'm');
  EXPECT_DOUBLE_EQ(r.nextSignalDistance, 89.6 + 5.01);
  nextSignalOf(links, st, ":C_3_0", 1.0, 0, r);  // in the junction, before its wait point
  EXPECT_EQ(r.nextSignal, 'm');
  EXPECT_DOUBLE_EQ(r.nextSignalDistance, 4.01);
  nextSignalOf(links, st, "n_in_0", 189.0, kSumoBlinkerRight, r);  // right: link 0
  EXPECT_EQ(r.nextSignal, 'G');
  EXPECT_NEAR(r.nextSignalDistance, 0.6, 1e-12);
  st.advanceTo(42.0);  // a record at exactly t counts
  nextSignalOf(links, st, "n_in_1", 100.0, 0, r);
  EXPECT_EQ(r.nextSignal, 'y');
  st.advanceTo(44.9);
  nextSignalOf(links, st, "n_in_1", 100.0, 0, r);
  EXPECT_EQ(r.nextSignal, 'y');
  st.advanceTo(50.0);
  nextSignalOf(links, st, "n_in_1", 100.0, 0, r);
  EXPECT_EQ(r.nextSignal, 'r');
  nextSignalOf(links, st, "e_in_1", 100.0, 0, r);
  EXPECT_EQ(r.nextSignal, 'G');
  // on its red the left turner stands at the stop line, not at its wait point
  nextSignalOf(links, st, "n_in_1", 100.0, kSumoBlinkerLeft, r);
  EXPECT_EQ(r.nextSignal, 'r');
  EXPECT_DOUBLE_EQ(r.nextSignalDistance, 89.6);
  // inside the junction or leaving it: no light ahead
  nextSignalOf(links, st, ":C_1_1", 1.0, 0, r);
  EXPECT_EQ(r.nextSignal, 0);
  nextSignalOf(links, st, "s_out_0", 1.0, 0, r);
  EXPECT_EQ(r.nextSignal, 0);
  fs::remove(file);
}

// A junction without a light: its minor links (the roundabout's entries give way to the ring,
// netconvert's state m) from the network, its major ones (the ring) none
TEST(SignalReplay, PriorityJunctionsGiveWayAtTheirLine) {
  const SignalLinks links = readSignalLinks(fs::path(STSIM_SOURCE_DIR) / "networks/roundabout/roundabout.net.xml");
  EXPECT_TRUE(links.lights.empty());
  const auto entry = links.byEdges.find("n_in\nrN_rW");
  ASSERT_NE(entry, links.byEdges.end());
  EXPECT_EQ(entry->second.light, -1);
  EXPECT_EQ(entry->second.fixed, 'm');
  // on the ring (the net's connection rN_rW -> rW_rS, state M): major, straight through, none
  EXPECT_EQ(links.byEdges.count("rN_rW\nrW_rS"), 0u);
  const SignalStates st(links);  // no light, no recorded state needed
  SumoVehicleRecord r;
  const std::string n = "n_in", next = "rN_rW";
  nextSignalOf(links, st, "n_in_0", 150.0, 0, r, &n, &next);
  EXPECT_EQ(r.nextSignal, 'm');
  EXPECT_DOUBLE_EQ(r.nextSignalDistance, links.laneLength.at("n_in_0") - 150.0);
  // and without the priority rules the entry is not read at all
  EXPECT_TRUE(readSignalLinks(fs::path(STSIM_SOURCE_DIR) / "networks/roundabout/roundabout.net.xml", false).byEdges.empty());
}

TEST(SignalReplay, BadStatesFilesNameFileAndLine) {
  const SignalLinks links = readSignalLinks(intersectionNet());
  const std::string ok = states('G', 'g', 'r');
  struct Case {
    std::string body, message;
  };
  const Case cases[] = {
      {"<tlsState time=\"0\" id=\"X\" state=\"" + ok + "\"/>", ":2: <tlsState> light 'X' is not in the network"},
      {"<tlsState time=\"0\" id=\"C\" state=\"GGG\"/>", ":2: <tlsState id=\"C\"> state 'GGG' is shorter than the light's 16 links"},
      {"<tlsState time=\"0\" id=\"C\" state=\"" + std::string(16, 'x') + "\"/>", "is not SUMO's link states"},
      {"<tlsState time=\"5\" id=\"C\" state=\"" + ok + "\"/>\n<tlsState time=\"4\" id=\"C\" state=\"" + ok + "\"/>",
       ":3: <tlsState> times must not go back"},
      {"<tlsState id=\"C\" state=\"" + ok + "\"/>", ":2: <tlsState> lacks attribute 'time'"},
      {"", "holds no <tlsState>"},
  };
  for (const Case& c : cases) {
    const fs::path file = writeFile("bad_tls.xml", "<tlsStates>\n" + c.body + "\n</tlsStates>\n");
    try {
      SignalStates st(file, links);
      ADD_FAILURE() << "accepted: " << c.body;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind(file.string(), 0), 0u) << e.what();
    }
    fs::remove(file);
  }
}

// Routes for a replay: SUMO's --vehroute-output (a rerouted vehicle's last route is the one it
// drove) and a plain route file (a vehicle naming a route defined before it); errors name the line.
TEST(SignalReplay, RoutesFromVehrouteOutputAndRouteFiles) {
  const fs::path file = writeFile("routes.xml",
                                  "<routes>\n"
                                  "  <route id=\"r0\" edges=\"n_in s_out\"/>\n"
                                  "  <vehicle id=\"a\" depart=\"0\" route=\"r0\"/>\n"
                                  "  <vehicle id=\"b\" depart=\"1\">\n"
                                  "    <routeDistribution>\n"
                                  "      <route replacedOnEdge=\"e_in\" edges=\"e_in w_out\"/>\n"
                                  "      <route edges=\"e_in  n_out\"/>\n"
                                  "    </routeDistribution>\n"
                                  "  </vehicle>\n"
                                  "  <person id=\"p\" depart=\"0\"><walk edges=\"n_in\"/></person>\n"
                                  "</routes>\n");
  const VehicleRoutes routes = readSumoRoutes(file);
  ASSERT_EQ(routes.size(), 2u);
  EXPECT_EQ(routes.at("a"), (std::vector<std::string>{"n_in", "s_out"}));
  EXPECT_EQ(routes.at("b"), (std::vector<std::string>{"e_in", "n_out"}));
  fs::remove(file);
  const std::pair<std::string, std::string> bad[] = {
      {"<routes>\n<vehicle id=\"a\" route=\"nowhere\"/>\n</routes>", ":2: <vehicle id=\"a\"> route 'nowhere' is not defined before it"},
      {"<routes>\n<vehicle id=\"a\"><route edges=\" \"/></vehicle>\n</routes>", ":2: <route> has no edges"},
      {"<routes>\n</routes>", "holds no <vehicle>"},
  };
  for (const auto& [body, message] : bad) {
    const fs::path f = writeFile("bad_routes.xml", body);
    try {
      readSumoRoutes(f);
      ADD_FAILURE() << "accepted: " << body;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
    fs::remove(f);
  }
}

}  // namespace
}  // namespace st::highway
