// The scenario loader's contract (every bad input named by key and line) and the stsim pool
// command end to end.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <stpool/game.hpp>
#include <stpool/report.hpp>
#include <stpool/scenario.hpp>
#include <stpool/scenario_writer.hpp>

#include "pool_test_util.hpp"

namespace st::pool {
namespace {

std::string errorOf(const std::string& yaml) {
  try {
    parseScenario(yaml, "s.yaml");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "(accepted)";
}

const char* kGood = R"(table: {width: 2.54, height: 1.27, pockets: true}
balls:
  - {number: 0, position: [0.6, 0.6]}
  - {number: 1, position: [1.9, 0.6], colour: yellow}
shots:
  - {ball: 0, speed: 2.0, angle: 0}
)";

TEST(Scenario, GoodScenarioLoads) {
  const Scenario s = parseScenario(kGood, "s.yaml");
  ASSERT_EQ(s.balls.size(), 2u);
  EXPECT_EQ(s.balls[1].colour, Colour::Yellow);
  ASSERT_EQ(s.shots.size(), 1u);
  EXPECT_DOUBLE_EQ(s.shots[0].velocity.x(), 2.0);
  EXPECT_EQ(s.space.kind, SpaceKind::Tree);
}

// decomposition_factor: auto reaches the simulator's rule, and the writer gives it back
TEST(Scenario, AutoDecompositionFactor) {
  const Scenario s = parseScenario(std::string(kGood) + "space: {kind: quadtree, decomposition_factor: auto}\n", "s.yaml");
  EXPECT_TRUE(s.space.autoFactor);
  EXPECT_TRUE(simulatorConfig(s).rule.autoFactor);
  std::ostringstream os;
  writeScenarioYaml(os, s);
  EXPECT_TRUE(parseScenario(os.str(), "w.yaml").space.autoFactor) << os.str();
  EXPECT_FALSE(parseScenario(kGood, "s.yaml").space.autoFactor);
}

TEST(Scenario, CueVectorGivesProportionalVelocity) {
  const Scenario s = parseScenario(R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [0.6, 0.6]}]
shots: [{cue: {from: [0.6, 0.6], to: [0.9, 0.2], scale: 3}}]
)", "s.yaml");
  EXPECT_DOUBLE_EQ(s.shots[0].velocity.x(), 0.9);
  EXPECT_NEAR(s.shots[0].velocity.y(), -1.2, 1e-15);
}

TEST(Scenario, RepeatedKeyNamedWithBothLines) {
  // yaml-cpp answers with the first of two equal keys; the second must not be dropped silently
  EXPECT_EQ(errorOf(std::string(kGood) + "friction: 0.1\nfriction: 0.2\n"),
            "s.yaml:8:1: friction: repeated key (first given at line 7)");
  EXPECT_EQ(errorOf("table: {width: 2.54, height: 1.27, width: 3}\nrack: standard\n"),
            "s.yaml:1:36: table.width: repeated key (first given at line 1)");
}

TEST(Scenario, MissingKeyNamedWithLine) {
  EXPECT_EQ(errorOf("table: {width: 2.54}\nrack: standard\n"), "s.yaml:1:8: table.height: missing key");
  EXPECT_EQ(errorOf("rack: standard\n"), "s.yaml:1:1: table: missing key");
  EXPECT_EQ(errorOf("table: {width: 2.54, height: 1.27}\n"),
            "s.yaml:1:1: balls: missing key (give balls, rack or random)");
}

TEST(Scenario, OverlappingBallsNamed) {
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls:
  - {number: 0, position: [0.6, 0.6]}
  - {number: 1, position: [0.65, 0.6]}
)"),
            "s.yaml:4:27: balls[1].position: ball 1 overlaps ball 0");
}

TEST(Scenario, BallOffTableNamed) {
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls:
  - {number: 0, position: [2.53, 0.6]}
)"),
            "s.yaml:3:27: balls[0].position: ball is off the table (its edge crosses a cushion)");
}

TEST(Scenario, NegativeRadiusNamed) {
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls:
  - {number: 0, position: [0.6, 0.6], radius: -0.01}
)"),
            "s.yaml:3:47: balls[0].radius: must be positive, got -0.01");
}

TEST(Scenario, UnknownSpaceKindNamed) {
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {kind: octopus}\n"),
            "s.yaml:7:15: space.kind: must be one of quadtree, cells, single, none, got 'octopus'");
}

TEST(Scenario, OtherBadInputsNamed) {
  EXPECT_EQ(errorOf(std::string(kGood) + "until: -3\n"), "s.yaml:7:8: until: must be positive, got -3");
  EXPECT_EQ(errorOf(std::string(kGood) + "frobnicate: 1\n"), "s.yaml:7:1: frobnicate: unknown key");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {divisions: 3}\n"), "s.yaml:7:20: space.divisions: must be one of 2, 4, got '3'");
  EXPECT_EQ(errorOf(std::string(kGood) + "friction: lots\n"), "s.yaml:7:11: friction: must be a number, got 'lots'");
  // io::wrongTypeText's one wording, as the cosim scenario's and the batch experiment's readers say it
  EXPECT_EQ(errorOf(std::string(kGood) + "space: cells\n"), "s.yaml:7:8: space: must be a mapping");
  EXPECT_EQ(errorOf("table: {width: 2.54, height: 1.27}\nrack: standard\nshots: 3\n"), "s.yaml:3:8: shots: must be a list");
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [0.6, 0.6]}]
shots: [{ball: 5, speed: 1, angle: 0}]
)"),
            "s.yaml:3:16: shots[0].ball: no ball number 5");
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [0.6, 0.6]}]
shots: [{ball: 0, speed: 1}]
)"),
            "s.yaml:3:9: shots[0].angle: missing key");
  EXPECT_EQ(errorOf("table: [1, 2"), "s.yaml:1:1: (syntax): end of sequence flow not found");
  // a complex key used to escape as yaml-cpp's "bad conversion" with no file or key
  EXPECT_EQ(errorOf("table: {width: 2.54, height: 1.27}\n? [1, 2]\n: 3\nrack: standard\n"),
            "s.yaml:2:3: (key): keys must be names");
}

TEST(Scenario, AbsurdFrictionAndTableSizesAreNamedAsThemselves) {
  // each is named as its own key (not as until, the event limit, nor as the rack's overlap)
  EXPECT_EQ(errorOf(std::string(kGood) + "friction: 1e308\n"),
            "s.yaml:7:11: friction: 1e+308 m/s^2 is more than any cloth's rolling resistance (at most 100 m/s^2)");
  EXPECT_EQ(errorOf("table: {width: 1e300, height: 1.27}\nrack: {kind: standard}\n"),
            "s.yaml:1:16: table.width: 1e+300 m is more than any table's (at most 100 m)");
  EXPECT_EQ(errorOf("table: {width: 2.54, height: 1e300}\nrack: {kind: standard}\n"),
            "s.yaml:1:30: table.height: 1e+300 m is more than any table's (at most 100 m)");
}

TEST(Scenario, ADeviceOrBinaryIsNamedNotABadAlloc) {
  // /dev/zero ended in std::bad_alloc naming no file
  try {
    loadScenario("/dev/zero");
    ADD_FAILURE() << "/dev/zero loaded";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/zero: holds a NUL byte: not a text file"), std::string::npos) << e.what();
  }
}

TEST(Scenario, FrozenRackLoadsAndRackErrorsNameTheRack) {
  // gap 0 puts neighbours 2r apart up to roundoff: touching, not overlapping (it used to be
  // refused as "ball 9 overlaps ball 1")
  const Scenario s = parseScenario("table: {width: 2.54, height: 1.27}\nrack: {gap: 0}\n", "s.yaml");
  ASSERT_EQ(s.balls.size(), 16u);
  int touching = 0;
  for (std::size_t i = 0; i < s.balls.size(); ++i)
    for (std::size_t j = i + 1; j < s.balls.size(); ++j)
      if (std::abs((s.balls[i].position - s.balls[j].position).norm() - 2.0 * kBallRadius) < 1e-12) ++touching;
  EXPECT_EQ(touching, 30);  // the triangle of 15 has 3 * (1 + 2 + 3 + 4) = 30 contacts
  // a real overlap is still refused; a generated ball is named by the key that made it
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls:
  - {number: 0, position: [0.6, 0.6]}
  - {number: 1, position: [0.657, 0.6]}
)"),
            "s.yaml:4:27: balls[1].position: ball 1 overlaps ball 0");
  EXPECT_EQ(errorOf("table: {width: 2.54, height: 1.27}\nrack: {apex: [2.45, 0.6]}\n"),
            "s.yaml:2:7: rack: ball 10: ball is off the table (its edge crosses a cushion)");
}

TEST(Scenario, AbsurdSpeedsAndMarginNamed) {
  // 1e300 m/s used to run, overflow positions and fly the ball off the table
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [0.6, 0.6]}]
shots:
  - {ball: 0, speed: 1e300, angle: 30}
)"),
            "s.yaml:4:5: shots[0]: speed must be at most 1000 m/s");
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [0.6, 0.6]}]
shots:
  - ball: 0
    cue: {from: [0, 0], to: [800, 800]}
)"),
            "s.yaml:4:5: shots[0]: speed must be at most 1000 m/s");
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [0.6, 0.6], velocity: [0, -2000]}]
)"),
            "s.yaml:2:31: balls[0].velocity: speed must be at most 1000 m/s");
  EXPECT_EQ(errorOf("table: {width: 2.54, height: 1.27}\nrandom: {count: 3, speed: 1e4}\n"),
            "s.yaml:2:27: random.speed: must be between 0 and 1000 m/s");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {kind: cells, margin: 0}\n"), "s.yaml:7:30: space.margin: must be positive, got 0");
  // the limit itself is accepted
  EXPECT_EQ(errorOf(R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [0.6, 0.6]}]
shots: [{ball: 0, speed: 1000, angle: 30}]
space: {kind: cells, margin: 2}
)"),
            "(accepted)");
}

// A key of another space kind would do nothing: refused, naming the kind it belongs to.
TEST(Scenario, SpaceKeysOfAnotherKindAreRefused) {
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {margin: 2}\n"),
            "s.yaml:7:17: space.margin: only for kind cells (this space is quadtree)");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {kind: quadtree, cell_size: 0.1}\n"),
            "s.yaml:7:36: space.cell_size: only for kind cells (this space is quadtree)");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {kind: cells, decomposition_factor: 5}\n"),
            "s.yaml:7:44: space.decomposition_factor: only for kind quadtree (this space is cells)");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {kind: single, max_depth: 3}\n"),
            "s.yaml:7:34: space.max_depth: only for kind quadtree (this space is single)");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {kind: cells, cell_size: 0.1, margin: 0.3}\n"), "(accepted)");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {decomposition_factor: 5, divisions: 2, max_depth: 4}\n"), "(accepted)");
}

TEST(Scenario, ShippedScenariosLoad) {
  for (const char* name : {"break", "bank_shot", "box100", "practice"}) {
    const std::string path = std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/" + name + ".yaml";
    EXPECT_NO_THROW(loadScenario(path)) << path;
  }
  EXPECT_EQ(loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/box100.yaml").balls.size(), 100u);
}

// The friction scenario plays three shots in sequence, each from the rest state the previous one
// left: every shot ends at rest (all kinetic energy gone, every ball still), the next begins there.
TEST(Scenario, PracticeShotsFollowOneAnotherFromRest) {
  const Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/practice.yaml");
  ASSERT_EQ(s.shots.size(), 3u);
  ASSERT_GT(s.friction, 0.0);
  Game g(s, simulatorConfig(s));
  const RunRecord run = playScenario(g, s);
  ASSERT_EQ(run.error, "");
  ASSERT_EQ(run.shots.size(), 3u);
  for (std::size_t k = 0; k < run.shots.size(); ++k) {
    const ShotSummary& sh = run.shots[k];
    EXPECT_EQ(sh.ending, ShotEnd::Rest) << "shot " << k;
    EXPECT_EQ(sh.keEnd, 0.0) << "shot " << k;
    EXPECT_GT(sh.keStart, 0.0) << "shot " << k;
    EXPECT_LT(sh.end - sh.start, s.until) << "shot " << k;
    if (k > 0) {
      EXPECT_EQ(sh.start, run.shots[k - 1].end) << "shot " << k;
    }
  }
  // the cue's strike is the only energy put in: 1/2 m v^2 with v from the scenario
  EXPECT_NEAR(run.shots[1].keStart, 0.5 * kBallMass * 2.5 * 2.5, 1e-12);
  EXPECT_NEAR(run.shots[2].keStart, 0.5 * kBallMass * s.shots[2].velocity.squaredNorm(), 1e-12);
  EXPECT_TRUE(g.atRest());
}

// ---- the command --------------------------------------------------------------------------------

using test::Ran;
using test::runStsim;
using test::slurp;
using test::tempDir;

TEST(PoolCommand, BreakWritesEveryOutput) {
  const auto dir = tempDir("break");
  const Ran r = runStsim("pool " + std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/break.yaml --out " + dir.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("collision checks"), std::string::npos) << r.out;
  for (const char* f : {"events.csv", "summary.json", "table.svg", "animation.html"})
    EXPECT_TRUE(std::filesystem::file_size(dir / f) > 100) << f;
  // every logged event is in the summary's total
  const std::string csv = slurp(dir / "events.csv");
  const auto rows = std::count(csv.begin(), csv.end(), '\n') - 1;
  const std::string json = slurp(dir / "summary.json");
  EXPECT_NE(json.find("\"total\": " + std::to_string(rows) + "}"), std::string::npos) << json;
  const std::string html = slurp(dir / "animation.html");
  EXPECT_EQ(html.find("http"), std::string::npos);  // self-contained: nothing fetched
  EXPECT_NE(slurp(dir / "table.svg").find("stroke-dasharray"), std::string::npos);  // space drawn
}

TEST(PoolCommand, ScenarioNameCannotCloseTheAnimationsScript) {
  // the name goes into animation.html's <script> block as JSON: "</script>" in it ended the
  // block and the <img onerror> after it ran
  const auto dir = tempDir("inject");
  std::filesystem::create_directories(dir);
  std::string text = slurp(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/break.yaml");
  const auto at = text.find("name: break");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 11, "name: \"</script><img src=x onerror=alert(1)><!--\"");
  std::ofstream(dir / "evil.yaml") << text;
  const Ran r = runStsim("pool " + (dir / "evil.yaml").string() + " --until 0.1 --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string html = slurp(dir / "out" / "animation.html");
  // one script element, closed once, by the page itself; no markup of the name's
  EXPECT_EQ(html.find("<img"), std::string::npos) << "the name's markup is in the page";
  EXPECT_EQ(html.find("<!--"), std::string::npos);
  const auto close = html.find("</script>");
  ASSERT_NE(close, std::string::npos);
  EXPECT_EQ(html.find("</script>", close + 1), std::string::npos);
  EXPECT_LT(html.find("\\u003c/script\\u003e\\u003cimg src=x onerror=alert(1)\\u003e"), close) << "the title is not kept";
}

TEST(PoolCommand, OverridesAndUsageErrors) {
  const std::string scen = std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/break.yaml";
  const Ran a = runStsim("pool " + scen + " --space single --until 1");
  EXPECT_EQ(a.code, 0) << a.out;
  EXPECT_NE(a.out.find("space single"), std::string::npos) << a.out;
  EXPECT_EQ(runStsim("pool " + scen + " --space octopus").code, 2);
  EXPECT_EQ(runStsim("pool " + scen + " --df 0").code, 2);
  EXPECT_EQ(runStsim("pool").code, 2);
}

// The command line's overrides skipped the YAML's checks: `--space cells --df 7` ran, while
// `space: {kind: cells, decomposition_factor: 7}` is refused. They go through the checks of their
// keys now, the problem named at the flag in one line, exit 2 (usage); `--df auto` is taken as
// `decomposition_factor: auto` is.
TEST(PoolCommand, OverridesAreCheckedAsTheirYamlKeys) {
  const std::string scen = std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/break.yaml";
  const Ran cells = runStsim("pool " + scen + " --space cells --df 7 --until 0.1");
  EXPECT_EQ(cells.code, 2) << cells.out;
  EXPECT_EQ(cells.out, "stsim pool: option --df: only for kind quadtree (this space is cells)\n");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {kind: cells, decomposition_factor: 7}\n"),
            "s.yaml:7:44: space.decomposition_factor: only for kind quadtree (this space is cells)");
  // the same words as the YAML's, for each flag
  EXPECT_EQ(runStsim("pool " + scen + " --df 0").out, "stsim pool: option --df: must be in [1, 1000000000], got 0\n");
  EXPECT_EQ(runStsim("pool " + scen + " --df 2.5").out,
            "stsim pool: option --df: must be a whole number, got 2.5\n");
  EXPECT_EQ(runStsim("pool " + scen + " --space octopus").out,
            "stsim pool: option --space: must be one of quadtree, cells, single, none, got 'octopus'\n");
  EXPECT_EQ(runStsim("pool " + scen + " --until -3").out, "stsim pool: option --until: must be positive, got -3\n");
  EXPECT_EQ(runStsim("pool " + scen + " --until inf").out, "stsim pool: option --until: must be a finite number, got inf\n");
  EXPECT_EQ(errorOf(std::string(kGood) + "space: {decomposition_factor: 0}\n"),
            "s.yaml:7:31: space.decomposition_factor: must be in [1, 1000000000], got 0");
  // --df auto runs, as the YAML's auto does; and a number after the YAML's auto turns it off
  const Ran aut = runStsim("pool " + scen + " --df auto --until 0.5");
  EXPECT_EQ(aut.code, 0) << aut.out;
  EXPECT_NE(aut.out.find("space tree df=auto"), std::string::npos) << aut.out;
  const Ran seven = runStsim("pool " + scen + " --space quadtree --df 7 --until 0.5");
  EXPECT_EQ(seven.code, 0) << seven.out;
  EXPECT_NE(seven.out.find("space tree df=7"), std::string::npos) << seven.out;
}

// box100 with --until 1e12 would run to the library's bound (2 000 000 events, a 269 MB
// events.csv). The run stops at --max-events (200 000 unless raised): the error names events.csv
// and the option, exit 1, and the rows written are whole.
TEST(PoolCommand, ARunawayTimeLimitStopsAtTheEventLimitNamingTheFile) {
  const std::string box = std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/box100.yaml";
  auto lastLine = [](const std::string& out) {
    const auto end = out.find_last_not_of('\n');
    return out.substr(out.rfind('\n', end) + 1, end - out.rfind('\n', end));
  };
  auto rows = [](const std::string& csv) { return std::count(csv.begin(), csv.end(), '\n') - 1; };
  for (const auto& [limit, option] : {std::pair{200000L, std::string()}, std::pair{5000L, std::string(" --max-events 5000")}}) {
    const auto dir = tempDir("runaway" + std::to_string(limit));
    const Ran r = runStsim("pool " + box + " --until 1e12" + option + " --out " + dir.string());
    EXPECT_EQ(r.code, 1) << r.out;
    const std::string line = lastLine(r.out);
    EXPECT_EQ(line.rfind("stsim pool: error: " + (dir / "events.csv").string() + ": stopped at the limit of " +
                             std::to_string(limit) + " events at t = ",
                         0),
              0u)
        << line;
    EXPECT_NE(line.find("raise --max-events (at most 2000000) or lower until (or --until)"), std::string::npos) << line;
    const std::string csv = slurp(dir / "events.csv");
    EXPECT_EQ(rows(csv), limit);
    ASSERT_FALSE(csv.empty());
    EXPECT_EQ(csv.back(), '\n');  // whole rows
    EXPECT_LT(std::filesystem::file_size(dir / "events.csv"), 40u << 20);
    EXPECT_NE(slurp(dir / "summary.json").find("stopped at the limit of " + std::to_string(limit) + " events"),
              std::string::npos);
  }
  // a limit out of range is a usage error naming the option
  for (const char* bad : {"0", "-1", "2000001"}) {
    const Ran r = runStsim("pool " + box + " --max-events " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_NE(r.out.find("--max-events: expected 1..2000000, got " + std::string(bad)), std::string::npos) << r.out;
  }
  // without --out the error names the scenario
  const Ran r = runStsim("pool " + box + " --until 1e12 --max-events 100");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lastLine(r.out).rfind("stsim pool: error: " + box + ": stopped at the limit of 100 events", 0), 0u) << r.out;
}

TEST(PoolCommand, BadScenarioIsOneLineNonZero) {
  const auto dir = tempDir("bad");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "table: {width: 2.54, height: 1.27}\nballs:\n  - {number: 0, position: [5, 5]}\n";
  const Ran r = runStsim("pool " + (dir / "bad.yaml").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_NE(r.out.find("stsim pool: error: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(":3:27: balls[0].position: ball is off the table"), std::string::npos) << r.out;
}

// Shot 2 strikes a ball that shot 1 pocketed: exit 1, but shot 1's record is written.
TEST(PoolCommand, ResultsBeforeAFailureAreFlushed) {
  const auto dir = tempDir("flush");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "s.yaml") << R"(table: {width: 2.54, height: 1.27}
balls: [{number: 0, position: [1.27, 0.5]}, {number: 1, position: [0.3, 0.3]}]
shots:
  - {ball: 0, speed: 2, angle: -90}
  - {ball: 0, speed: 2, angle: 0}
)";
  const Ran r = runStsim("pool " + (dir / "s.yaml").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("error: shot 2: ball 0 was pocketed"), std::string::npos) << r.out;
  const std::string csv = slurp(dir / "out" / "events.csv");
  EXPECT_NE(csv.find(",pocket,0,0,1,"), std::string::npos) << csv;
  EXPECT_NE(slurp(dir / "out" / "summary.json").find("\"error\": \"shot 2: ball 0 was pocketed\""), std::string::npos);
}

}  // namespace
}  // namespace st::pool

namespace st::pool {
namespace {

// An angle of 1e308 is named as the angle (not the speed); a second document after --- is refused
TEST(Scenario, AnAbsurdAngleAndASecondDocumentAreNamed) {
  std::string shot = kGood;
  shot.replace(shot.find("angle: 0"), 8, "angle: 1e308");
  EXPECT_EQ(errorOf(shot), "s.yaml:6:34: shots[0].angle: must be between -360 and 360 degrees");
  EXPECT_EQ(errorOf(std::string(kGood) + "---\nuntil: 3\n"),
            "s.yaml:8:1: (syntax): a second YAML document (after ---): the file must hold one");
  // a document end marker or an empty document after --- is still one document
  EXPECT_EQ(errorOf(std::string(kGood) + "...\n"), "(accepted)");
  EXPECT_EQ(errorOf(std::string(kGood) + "---\n"), "(accepted)");
}

}  // namespace
}  // namespace st::pool
