// stsim highway --fcd with hostile traces: every bad input is one line naming the file and line,
// a non-zero exit, and what was read before it is written out.
#include <gtest/gtest.h>

#include "cosim/test_util.hpp"

namespace {

namespace fs = std::filesystem;
using st::cosim::test::freshDir;
using st::cosim::test::lines;
using st::cosim::test::runStsim;
using st::cosim::test::slurp;

const std::string kNet = std::string(STSIM_SOURCE_DIR) + "/networks/motorway/motorway.net.xml";
const std::string kRoutes = std::string(STSIM_SOURCE_DIR) + "/networks/motorway/motorway.rou.xml";

// Two good timesteps, then a third whose vehicle carries `bad` in place of its usual attributes.
std::string trace(const std::string& bad) {
  const std::string good = "x=\"2853.97\" y=\"-9.38\" angle=\"90.00\" type=\"car\" speed=\"23.50\" lane=\"downstream_0\"";
  return "<fcd-export>\n"
         "<timestep time=\"0\">\n<vehicle id=\"a\" " + good + "/>\n</timestep>\n"
         "<timestep time=\"1\">\n<vehicle id=\"a\" " + good + "/>\n</timestep>\n"
         "<timestep time=\"2\">\n<vehicle id=\"a\" " + bad + "/>\n</timestep>\n"
         "</fcd-export>\n";
}

struct Outcome {
  int code;
  std::string err;
  fs::path out;
};

Outcome replay(const std::string& name, const std::string& text, std::vector<std::string> extra = {}) {
  const fs::path dir = freshDir("fcd_" + name);
  std::ofstream(dir / "t.fcd.xml") << text;
  std::vector<std::string> args{"highway", "--fcd", (dir / "t.fcd.xml").string(), "--net", kNet, "--out", (dir / "out").string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto r = runStsim(args, dir);
  return {r.code, r.err, dir / "out"};
}

void expectInputError(const Outcome& o, const std::string& mention) {
  EXPECT_EQ(o.code, 1) << o.err;  // an error, not a crash (a signal) or a silent success
  EXPECT_NE(o.err.find("t.fcd.xml:9: "), std::string::npos) << o.err;
  EXPECT_NE(o.err.find(mention), std::string::npos) << o.err;
  EXPECT_EQ(lines(o.err).size(), 1u) << o.err;
  // the two good timesteps were replayed and summarised
  const std::string summary = slurp(o.out / "summary.json");
  EXPECT_NE(summary.find("\"ticks\": 2,"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"error\": "), std::string::npos) << summary;
}

TEST(HighwayFcd, FarOutsideTheNetworkOrTooFastIsAnInputError) {
  const std::string rest = " angle=\"90.00\" type=\"car\" lane=\"downstream_0\"";
  // 1e300 crashed the cell placement; 1e9 was accepted as 2e6 vehicle-km
  for (const std::string pos : {"x=\"1e300\" y=\"-9.38\"", "x=\"1e15\" y=\"-9.38\"", "x=\"1e9\" y=\"-9.38\"",
                                "x=\"2853.97\" y=\"-1e300\""})
    expectInputError(replay("far", trace(pos + rest + " speed=\"23.5\"")), "outside");
  expectInputError(replay("fast", trace("x=\"2853.97\" y=\"-9.38\"" + rest + " speed=\"1e300\"")), "speed 1e+300 m/s");
  expectInputError(replay("accel", trace("x=\"2853.97\" y=\"-9.38\"" + rest + " speed=\"20\" acceleration=\"1e300\"")),
                   "acceleration");
  expectInputError(replay("long", trace("x=\"2853.97\" y=\"-9.38\"" + rest + " speed=\"20\" length=\"1e300\"")),
                   "length and width must be at most");
}

TEST(HighwayFcd, AngleNegativeSpeedAndUnclosedVehiclesAreInputErrors) {
  // each of these is an input error, exit 1 (an angle of 1e300 would change the warnings)
  const std::string pos = "x=\"2853.97\" y=\"-9.38\" type=\"car\" lane=\"downstream_0\"";
  expectInputError(replay("angle", trace(pos + " angle=\"1e300\" speed=\"20\"")),
                   "<vehicle id=\"a\"> angle 1e+300 is not a heading (degrees, 0..360)");
  expectInputError(replay("backwards", trace(pos + " angle=\"90\" speed=\"-5\"")),
                   "<vehicle id=\"a\"> speed -5 m/s is negative");
  const std::string good = pos + " angle=\"90.00\" speed=\"23.50\"";
  expectInputError(replay("unclosed", "<fcd-export>\n"
                                      "<timestep time=\"0\">\n<vehicle id=\"a\" " + good + "/>\n</timestep>\n"
                                      "<timestep time=\"1\">\n<vehicle id=\"a\" " + good + "/>\n</timestep>\n"
                                      "<timestep time=\"2\">\n<vehicle id=\"a\" " + good + ">\n</timestep>\n"
                                      "</fcd-export>\n"),
                   "<vehicle> is not closed (expected \"/>\" or </vehicle> before line 10)");
}

TEST(HighwayFcd, EndAndSeedAreCheckedAsForASumoRun) {
  // --end -1 and --seed -1 on a replay exited 0; both are checked by the scenario's specs
  // (sthighway/run_settings.hpp), in the words of a scenario file
  const std::string good = trace("x=\"2853.97\" y=\"-9.38\" angle=\"90\" type=\"car\" speed=\"20\" lane=\"downstream_0\"");
  const Outcome end = replay("end", good, {"--end", "-1"});
  EXPECT_EQ(end.code, 2) << end.err;
  EXPECT_NE(end.err.find("--end: must be in (0, 1000000000] s, got -1"), std::string::npos) << end.err;
  const Outcome seed = replay("seed", good, {"--seed", "-1"});
  EXPECT_EQ(seed.code, 2) << seed.err;
  EXPECT_NE(seed.err.find("--seed: must be in [0, 2147483647], got -1"), std::string::npos) << seed.err;
}

TEST(HighwayFcd, ADeviceOfNulBytesIsNamedNotReadForEver) {
  // --fcd /dev/zero hung (killed at 30 s): it is no XML, and says so at once
  const fs::path dir = freshDir("fcd_zero");
  const auto r = runStsim({"highway", "--fcd", "/dev/zero", "--net", kNet, "--out", (dir / "out").string()}, dir,
                          {"timeout", "20"});
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("/dev/zero:1: a NUL byte: not an XML text file"), std::string::npos) << r.err;
}

TEST(HighwayFcd, UnknownLanesAndTypesAreInputErrors) {
  const std::string pos = "x=\"2853.97\" y=\"-9.38\" angle=\"90.00\" speed=\"23.5\"";
  expectInputError(replay("lane", trace(pos + " type=\"car\" lane=\"nosuch_0\"")), "lane 'nosuch_0' is not in");
  // with --vtypes the file is the list of types; without it a type's class is guessed from its name
  expectInputError(replay("type", trace(pos + " type=\"hovercraft\" lane=\"downstream_0\""), {"--vtypes", kRoutes}),
                   "type 'hovercraft' is not defined in");
  EXPECT_EQ(replay("guess", trace(pos + " type=\"hovercraft\" lane=\"downstream_0\"")).code, 0);
}

TEST(HighwayFcd, EmptyFilesAndDirectoriesAreNamed) {
  const Outcome empty = replay("empty", "<fcd-export>\n</fcd-export>\n");
  EXPECT_EQ(empty.code, 1);
  EXPECT_NE(empty.err.find("t.fcd.xml: holds no <timestep>"), std::string::npos) << empty.err;
  const Outcome zero = replay("zero", "");
  EXPECT_EQ(zero.code, 1);
  EXPECT_NE(zero.err.find("holds no <timestep>"), std::string::npos) << zero.err;

  const fs::path dir = freshDir("fcd_dir");
  auto r = runStsim({"highway", "--fcd", dir.string(), "--net", kNet, "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(dir.string() + ": is a directory"), std::string::npos) << r.err;
  std::ofstream(dir / "none.xml") << "<routes>\n</routes>\n";
  std::ofstream(dir / "t.fcd.xml") << trace("x=\"2853.97\" y=\"-9.38\" angle=\"90\" speed=\"1\"");
  r = runStsim({"highway", "--fcd", (dir / "t.fcd.xml").string(), "--net", kNet, "--vtypes", (dir / "none.xml").string(),
                "--out", (dir / "out").string()},
               dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("none.xml: defines no <vType>"), std::string::npos) << r.err;
}

// A trace carries no light states: on a network with traffic lights the replay says so once
// (a live run reads them), on one without it says nothing.
TEST(HighwayFcd, ATraceOnANetworkWithLightsSaysTheyAreNotRead) {
  const std::string good = "x=\"-1.60\" y=\"150.00\" angle=\"180.00\" type=\"car\" speed=\"10.00\" lane=\"n_in_1\"";
  const fs::path dir = freshDir("fcd_lights");
  std::ofstream(dir / "t.fcd.xml") << "<fcd-export>\n<timestep time=\"0\">\n<vehicle id=\"a\" " + good +
                                          "/>\n</timestep>\n</fcd-export>\n";
  const auto r = runStsim({"highway", "--fcd", (dir / "t.fcd.xml").string(), "--net",
                           std::string(STSIM_SOURCE_DIR) + "/networks/intersection/intersection.net.xml", "--no-map", "--out",
                           (dir / "out").string()},
                          dir);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find("has 1 traffic light(s); an FCD trace carries no light states"), std::string::npos) << r.err;
  const Outcome quiet = replay("no_lights", trace("x=\"2863.97\" y=\"-9.38\" angle=\"90.00\" type=\"car\" speed=\"23.50\""),
                               {"--no-map"});
  EXPECT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("traffic light"), std::string::npos) << quiet.err;
}

}  // namespace
