// Validation against SUMO's SSM device in the same run (the independent truth): the box detector's
// TTC on following encounters, and the recall of every detector for SSM conflicts below the safe
// time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <vector>

#include <stcosim/scenario.hpp>
#include <stcosim/ssm_validation.hpp>
#include <sthighway/sumo_files.hpp>

#include "test_util.hpp"

namespace st::cosim {
namespace {

using namespace st::cosim::test;

// `stsim highway SCENARIO OPTIONS --validate-ssm` into a fresh folder `name`: the run and the
// validation.json it wrote (the rest in testDir(name))
struct Validated {
  test::RunResult run;
  std::string json;
};
Validated validated(const std::string& name, const std::filesystem::path& scenario, std::vector<std::string> options) {
  const auto dir = freshDir(name);
  std::vector<std::string> args{"highway", scenario.string()};
  args.insert(args.end(), options.begin(), options.end());
  args.insert(args.end(), {"--validate-ssm", "--out", dir.string()});
  Validated v{runStsim(args, dir), ""};
  v.json = slurp(dir / "validation.json");
  return v;
}

TEST(SsmValidation, BoxTtcMatchesSsmAndDetectorsRecallEveryConflict) {
  // 240 s of the motorway include SSM conflicts below the safe time (rear-end near misses
  // around t = 210-230 s)
  const auto [r, v] = validated("ssm", motorway(), {"--end", "240"});
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_FALSE(v.empty());

  // following encounters: >= 99 % of matched samples within 0.02 s
  const double matched = jsonNumber(v, "matched_samples");
  EXPECT_GT(matched, 10000.0);
  EXPECT_GE(jsonNumber(v, "matched_samples") / jsonNumber(v, "ssm_samples"), 0.99);
  EXPECT_GE(jsonNumber(v, "within_fraction"), 0.99) << v;
  // the largest difference is named, as ego>foe@t (where an analyst looks first)
  const auto worst = v.find("\"worst\": \"", v.find("\"following\""));
  ASSERT_LT(worst, v.find("without_time_shift")) << v;
  const std::string named = v.substr(worst + 10, v.find('"', worst + 10) - worst - 10);
  EXPECT_TRUE(std::regex_match(named, std::regex(R"([^>@]+>[^>@]+@[0-9.]+)"))) << named;
  // without the one-step time shift the match fails: the shift is real, not a tolerance artefact
  const auto shift = v.find("without_time_shift");
  EXPECT_LT(jsonNumber(v, "within_tolerance", shift) / jsonNumber(v, "matched_samples", shift), 0.5) << v;
  // DRAC on the same samples (SSM run with TTC DRAC PET): SSM's speed difference squared over
  // twice the gap against ours, the closing speed over twice the box TTC: the same on a following
  // pair when the TTCs agree, so within 0.1 m/s² on >= 99 %, far below it at worst
  const auto drac = v.find("\"drac\"");
  ASSERT_NE(drac, std::string::npos) << v;
  EXPECT_GE(jsonNumber(v, "ssm_samples", drac), 0.99 * matched) << v;
  EXPECT_EQ(jsonNumber(v, "matched", drac), jsonNumber(v, "ssm_samples", drac)) << v;
  EXPECT_GE(jsonNumber(v, "within_fraction", drac), 0.99) << v;
  EXPECT_LT(jsonNumber(v, "max_abs_error_m_s2", drac), 0.01) << v;

  // the conflict point: SSM's (the leader's back now) moved on by the leader's velocity times
  // SSM's TTC, both from SSM's output, is where the box detector's bodies touch: within 0.5 m on
  // >= 99 % of the box episodes SSM has as following with the same TTC at the minimum-TTC tick
  const auto cp = v.find("\"conflict_point\"");
  ASSERT_NE(cp, std::string::npos) << v;
  const double following = jsonNumber(v, "ssm_following", cp);
  EXPECT_GE(following, 20.0) << v;  // the check has something to check
  EXPECT_LE(following, jsonNumber(v, "box_episodes", cp));
  EXPECT_GE(jsonNumber(v, "matched", cp), 0.95 * following) << v;  // lane-centred: the same TTC
  EXPECT_GE(jsonNumber(v, "within_fraction", cp), 0.99) << v;
  EXPECT_LT(jsonNumber(v, "max_abs_error_m", cp), 0.5) << v;
  // SSM's point as it is (where the leader's back is now) is not the contact: the conversion is real
  const auto raw = v.find("\"without_moving_on\"", cp);
  ASSERT_NE(raw, std::string::npos) << v;
  EXPECT_LT(jsonNumber(v, "within_tolerance", raw), 0.2 * jsonNumber(v, "matched", raw)) << v;
  // PET: SSM has one only for merging and crossing encounters at junctions; the ramp merges by a
  // lane change, which SSM sees as following, so there is nothing to compare here (the PET
  // agreement is tested on a crossing, below). Nor has the box: its lane-change warnings at the
  // ramp's nose, the only ones with a PET, were straight lines from SUMO's heading out of the
  // junction (SSM saw none of them); along the lanes there are none
  const auto pet = v.find("\"pet\"");
  ASSERT_NE(pet, std::string::npos) << v;
  EXPECT_EQ(jsonNumber(v, "ssm_pets", pet), 0.0) << v;
  EXPECT_EQ(jsonNumber(v, "stsim_pets", pet), 0.0) << v;
  EXPECT_EQ(jsonNumber(v, "matched", pet), 0.0) << v;

  // recall per detector: every SSM conflict below the safe time was warned about
  for (const char* d : {"concentric", "five", "box"}) {
    const auto at = v.find("\"detector\": \"" + std::string(d) + "\"");
    ASSERT_NE(at, std::string::npos) << d;
    const double conflicts = jsonNumber(v, "ssm_conflicts_below_safe_time", at);
    EXPECT_GE(conflicts, 5.0) << d;  // the check has something to check
    EXPECT_EQ(jsonNumber(v, "recalled", at), conflicts) << d << "\n" << v;
    EXPECT_GT(jsonNumber(v, "warnings", at), 0.0) << d;
    // the conflicts alone (proximity left out: the zones alongside, which SSM cannot see) are a
    // part of the warnings that SSM sees more of; the box's warnings are all conflicts
    const auto c = v.find("\"conflicts\": {", at);
    ASSERT_NE(c, std::string::npos) << d;
    EXPECT_LE(jsonNumber(v, "warnings", c), jsonNumber(v, "warnings", at)) << d;
    EXPECT_GE(jsonNumber(v, "precision", c), jsonNumber(v, "precision", at)) << d << "\n" << v;
    if (std::string(d) == "box") {
      EXPECT_EQ(jsonNumber(v, "warnings", c), jsonNumber(v, "warnings", at));
    }
    if (std::string(d) == "five") {
      EXPECT_GT(jsonNumber(v, "precision", c), 3.0 * jsonNumber(v, "precision", at)) << v;
    }
  }
}

// A figure with nothing to count says so: two cars far apart give SSM nothing, so there is no
// recall (null, "n/a"), not a perfect one; the same for precision and the TTC agreement.
TEST(SsmValidation, NothingToCountIsReportedAsSuchNotAsOne) {
  highway::MonitorConfig config;
  config.checkRoad = false;
  SsmValidator validator(highway::RoadGeometry{}, config, 0.1);
  // the two cars made once, moved each tick
  std::vector<highway::VehicleState> cars(2);
  cars[0].id = "a";
  cars[0].handle = 0;
  cars[0].speed = 20.0;
  cars[1].id = "b";
  cars[1].handle = 1;
  cars[1].speed = 20.0;
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.1 * k;
    cars[0].position = {20.0 * t, 0.0};
    cars[1].position = {1000.0 + 20.0 * t, 0.0};
    validator.record(t, cars);
  }
  validator.finish(2.0);
  const ValidationReport r = validator.evaluate({});
  ASSERT_EQ(r.detectors.size(), 3u);
  EXPECT_TRUE(std::isnan(r.ttc.withinFraction()));
  for (const auto& d : r.detectors) {
    EXPECT_EQ(d.conflicts, 0u) << d.detector;
    EXPECT_EQ(d.warnings, 0u) << d.detector;
    EXPECT_TRUE(std::isnan(d.recall())) << d.detector;
    EXPECT_TRUE(std::isnan(d.precision())) << d.detector;
  }
  const std::string json = toJson(r);
  EXPECT_NE(json.find("\"recall\": null"), std::string::npos) << json;
  EXPECT_EQ(json.find("\"recall\": 1"), std::string::npos) << json;
  EXPECT_NE(json.find("\"within_fraction\": null"), std::string::npos) << json;
  const std::string line = summaryLine(r);
  EXPECT_EQ(line.find("recall 1.000"), std::string::npos) << line;
  EXPECT_NE(line.find("box recall n/a (no SSM conflict below the safe time)"), std::string::npos) << line;
  // nor a PET or conflict-point agreement without a case both sides have
  EXPECT_TRUE(std::isnan(r.pet.withinFraction()));
  EXPECT_TRUE(std::isnan(r.point.withinFraction()));
  EXPECT_NE(line.find("0 PETs, none on both sides; 0 conflicts' PETs, none on both sides; 0 conflict points, none on both sides;"), std::string::npos) << line;
  EXPECT_NE(json.find("\"pet\": {\"ssm_pets\": 0, \"stsim_pets\": 0, \"matched\": 0, \"tolerance_s\": 0.1, "
                      "\"within_tolerance\": 0, \"within_fraction\": null"), std::string::npos) << json;

  // the same through stsim: the motorway's first 10 s hold no SSM conflict below the safe time
  const auto [run, v] = validated("ssm_none", motorway(), {"--end", "10", "--no-map"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.out.find("recall 1.000"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("five recall n/a (no SSM conflict below the safe time)"), std::string::npos) << run.out;
  EXPECT_EQ(jsonNumber(v, "ssm_conflicts_below_safe_time", v.find("\"five\"")), 0.0) << v;
  EXPECT_NE(v.find("\"recall\": null"), std::string::npos) << v;

  // with something to count the figures are the shares (3 of 4 recalled, 1 of 2 confirmed)
  DetectorValidation d;
  d.conflicts = 4;
  d.recalled = 3;
  d.warnings = 2;
  d.confirmed = 1;
  EXPECT_DOUBLE_EQ(d.recall(), 0.75);
  EXPECT_DOUBLE_EQ(d.precision(), 0.5);
}

// SSM's output as SUMO 1.15 writes it with "TTC PET" and trajectories: the minimum TTC's and the
// PET's position and time are read, "NA" as NaN, and a malformed position is a one-line error
// naming the file.
TEST(SsmValidation, ReadsPetAndConflictPoints) {
  const auto dir = freshDir("ssm_read");
  const std::string head = R"(<SSMLog>
    <conflict begin="1.000000" end="1.200000" ego="a" foe="b">
        <timeSpan values="1.000000 1.100000"/>
        <typeSpan values="2 17"/>
        <egoPosition values="10.000000,-1.500000 11.000000,-1.500000"/>
        <egoVelocity values="10.000000,0.000000 10.000000,0.000000"/>
        <foePosition values="20.000000,-1.500000 NA"/>
        <foeVelocity values="8.000000,0.000000 NA"/>
        <conflictPoint values=")";
  const std::string tail = R"( NA"/>
        <TTCSpan values="2.500000 NA"/>
        <minTTC time="1.000000" position="15.400000,-1.500000" type="2" value="2.500000"/>
        <PET time="1.137000" position="16.000000,-2.000000" type="17" value="0.420000"/>
    </conflict>
    <conflict begin="3.000000" end="3.000000" ego="b" foe="a">
        <timeSpan values="3.000000"/>
        <typeSpan values="4"/>
        <egoPosition values="NA"/>
        <egoVelocity values="NA"/>
        <foePosition values="NA"/>
        <foeVelocity values="NA"/>
        <conflictPoint values="NA"/>
        <TTCSpan values="NA"/>
        <minTTC time="NA" position="NA" type="NA" value="NA"/>
        <PET time="NA" position="NA" type="NA" value="NA"/>
    </conflict>
</SSMLog>
)";
  const auto good = dir / "ssm.xml";
  {
    std::ofstream(good) << head << "15.400000,-1.500000" << tail;
  }
  const auto c = readSsmOutput(good);
  ASSERT_EQ(c.size(), 2u);
  ASSERT_EQ(c[0].conflictPoints.size(), 2u);
  EXPECT_DOUBLE_EQ(c[0].conflictPoints[0].x(), 15.4);
  EXPECT_TRUE(std::isnan(c[0].conflictPoints[1].x()));
  EXPECT_TRUE(std::isnan(c[0].foeVelocities[1].y()));
  EXPECT_DOUBLE_EQ(c[0].egoVelocities[1].x(), 10.0);
  ASSERT_TRUE(c[0].hasMin);
  EXPECT_DOUBLE_EQ(c[0].minTtcPosition.x(), 15.4);
  ASSERT_TRUE(c[0].hasPet);
  EXPECT_DOUBLE_EQ(c[0].pet, 0.42);
  EXPECT_DOUBLE_EQ(c[0].petTime, 1.137);
  EXPECT_EQ(c[0].petType, 17);
  EXPECT_DOUBLE_EQ(c[0].petPosition.y(), -2.0);
  ASSERT_EQ(c[0].egoPositions.size(), 2u);
  EXPECT_DOUBLE_EQ(c[0].egoPositions[1].x(), 11.0);
  EXPECT_TRUE(std::isnan(c[0].foePositions[1].x()));
  EXPECT_FALSE(c[1].hasMin);
  EXPECT_FALSE(c[1].hasPet);
  EXPECT_TRUE(std::isnan(c[1].petPosition.x()));

  const auto bad = dir / "bad.xml";
  {
    std::ofstream(bad) << head << "15.4;-1.5" << tail;
  }
  try {
    readSsmOutput(bad);
    FAIL() << "a malformed position was read";
  } catch (const ScenarioError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(bad.string()), std::string::npos) << what;
    EXPECT_NE(what.find("15.4;-1.5"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    // at the line of the <conflictPoint> that holds it, the last of `head`
    const auto line = 1 + std::count(head.begin(), head.end(), '\n');
    EXPECT_EQ(what.rfind(bad.string() + ":" + std::to_string(line) + ": ", 0), 0u) << what;
  }
}

// A file cut short (SUMO's run killed before it closed its output) or garbled is refused, by
// file and line, rather than read in part.
TEST(SsmValidation, RefusesACutShortOrGarbledFileByItsLine) {
  const auto dir = freshDir("ssm_garbled");
  auto refusal = [&](const std::string& name, const std::string& text) {
    const auto file = dir / name;
    std::ofstream(file) << text;
    try {
      readSsmOutput(file);
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  const std::string open = "<SSMLog>\n  <conflict begin=\"1\" end=\"1\" ego=\"a\" foe=\"b\">\n    <timeSpan values=\"1\"/>\n";
  EXPECT_EQ(refusal("cut.xml", open),
            (dir / "cut.xml").string() + ":4: unexpected end of file: <conflict> (line 2) is not closed");
  EXPECT_EQ(refusal("unquoted.xml", open + "    <typeSpan values=2/>\n  </conflict>\n</SSMLog>\n"),
            (dir / "unquoted.xml").string() + ":4: attribute 'values' of <typeSpan> is not quoted");
  EXPECT_EQ(refusal("number.xml", open + "    <typeSpan values=\"2\"/>\n    <TTCSpan values=\"1.5x\"/>\n  </conflict>\n</SSMLog>\n"),
            (dir / "number.xml").string() + ":5: SSM output has a malformed number '1.5x'");
  EXPECT_EQ(refusal("lengths.xml", open + "  </conflict>\n</SSMLog>\n"),
            (dir / "lengths.xml").string() +
                ":2: SSM conflict a/b has time, type, TTC, conflict point and velocity series of different lengths "
                "(trajectories off?)");
  const std::string bare = "<SSMLog>\n  <conflict begin=\"1\" end=\"1\" ego=\"a\" foe=\"b\">\n";
  EXPECT_EQ(refusal("pet.xml", bare + "    <PET time=\"NA\" position=\"NA\" type=\"17\" value=\"0.4\"/>\n  </conflict>\n</SSMLog>\n"),
            (dir / "pet.xml").string() + ":3: SSM conflict a/b has a PET without a time");
  EXPECT_EQ(refusal("other.xml", "<?xml version=\"1.0\"?>\n<collisions>\n</collisions>\n"),
            (dir / "other.xml").string() + ":2: not an SSM output file (no <SSMLog>)");
  EXPECT_EQ(refusal("empty.xml", ""), (dir / "empty.xml").string() + ":1: not an SSM output file (no <SSMLog>)");
}

// SSM's PET position against the two paths, worked by hand: a left turner's front from the west
// (y = -1.6, turning north at x = 0) and a straight car's westbound on y = 4.8. The point where
// they meet lies on both paths; SSM's (-4.8, -0.64) of the actuated network's wn.2 x ew.1 lies on
// the turner's path 5.44 m from the straight car's, a PET of another place.
TEST(SsmValidation, PetPositionOffTheOtherPathIsTold) {
  SsmConflict c;
  c.egoPositions = {{-20.0, -1.6}, {-4.8, -0.64}, {-2.0, 0.5}, {0.0, 3.0}, {0.5, 8.0}};
  c.foePositions = {{20.0, 4.8}, {5.0, 4.8}, SsmConflict::kNoPoint, {-10.0, 4.8}};
  c.petPosition = {-4.8, -0.64};
  EXPECT_NEAR(c.petOffPath(), 4.8 + 0.64, 1e-12);
  EXPECT_GT(c.petOffPath(), kSsmPetOffPath);
  // a right-angle crossing's point: where the follower enters the area, half a body width (0.9 m)
  // short of the leader's path, on its own
  c.petPosition = {0.3, 3.9};
  const double onEgo = std::abs((Vec2(0.3, 3.9) - Vec2(0.0, 3.0)).dot(Vec2(0.5, 5.0).normalized().unitOrthogonal()));
  EXPECT_NEAR(c.petOffPath(), std::max(0.9, onEgo), 1e-12);
  EXPECT_LE(c.petOffPath(), kSsmPetOffPath);
  c.egoPositions.clear();
  c.foePositions.clear();
  EXPECT_TRUE(std::isnan(c.petOffPath()));  // no paths: not known, and not counted off
}

// The lane drop (the shipped merge, sublane model): where SSM sees the approach we see (the same
// TTC at our minimum-TTC tick), its conflict point moved on to the contact is ours along the
// leader's path. Across it the conventions differ (ours the middle of the touching part, SSM's
// the leader's centre line), which the full distance shows.
TEST(SsmValidation, LaneDropConflictPointsAgreeAlongTheLeadersPath) {
  const auto [r, v] = validated("ssm_lanedrop", sourceDir() / "networks/sublane/scenario.yaml", {"--no-map"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto cp = v.find("\"conflict_point\"");
  ASSERT_NE(cp, std::string::npos) << v;
  const double matched = jsonNumber(v, "matched", cp);
  EXPECT_GE(matched, 10.0) << v;  // the check has something to check
  const auto along = v.find("\"along_leader_path\"", cp);
  ASSERT_NE(along, std::string::npos) << v;
  EXPECT_EQ(jsonNumber(v, "matched", along), matched);
  EXPECT_GE(jsonNumber(v, "within_fraction", along), 0.99) << v;
  EXPECT_LT(jsonNumber(v, "max_abs_error_m", along), 0.5) << v;
  // across the path they differ: the full distance is not within the tolerance everywhere
  EXPECT_GT(jsonNumber(v, "max_abs_error_m", cp), 0.5) << v;
  // the lane drop merges by lane changes: SSM has no PET here, ours has the lane changes'
  const auto pet = v.find("\"pet\"");
  EXPECT_EQ(jsonNumber(v, "ssm_pets", pet), 0.0) << v;
  EXPECT_GT(jsonNumber(v, "stsim_pets", pet), 0.0) << v;
}

// The hand-built ramps (networks/onramp: a short and a long acceleration lane, the nose a bend
// at 31 degrees; networks/lanedrop: 3 to 2 lanes), against SUMO's SSM device in the same run: the
// box detector's conflicts are SSM's (precision >= 0.9, every SSM conflict below the safe time
// recalled), conflicts.csv's are too (a pair SSM logged at overlapping times, >= 0.9), and no
// conflict typed rear_end has its bodies a lane apart at the minimum TTC (>= 3.75 m, the lane
// width, across the first's lane: SSAM's class is by angle alone, and a straight line from SUMO's
// heading at the nose gave such rear-ends, 18 of 32 on the short design).
TEST(SsmValidation, RampsConflictsAreSsmsAndNoRearEndIsALaneApart) {
  const std::pair<const char*, const char*> ramps[] = {{"networks/onramp/short.yaml", "networks/onramp/short.net.xml"},
                                                       {"networks/onramp/long.yaml", "networks/onramp/long.net.xml"},
                                                       {"networks/lanedrop/scenario.yaml", "networks/lanedrop/lanedrop.net.xml"}};
  int k = 0;
  for (const auto& [scenario, net] : ramps) {
    SCOPED_TRACE(scenario);
    const std::string name = "ssm_ramp" + std::to_string(k++);
    const auto [r, v] = validated(name, sourceDir() / scenario, {"--no-map"});
    // the folder validated() ran in (freshDir's)
    const auto dir = std::filesystem::temp_directory_path() / ("stsim_cosim_test_" + std::to_string(::getpid())) / name;
    ASSERT_EQ(r.code, 0) << r.err;
    // the box detector against SSM
    const auto at = v.find("\"detector\": \"box\"");
    ASSERT_NE(at, std::string::npos) << v;
    const double below = jsonNumber(v, "ssm_conflicts_below_safe_time", at);
    EXPECT_GE(below, 5.0) << v;  // the check has something to check
    EXPECT_EQ(jsonNumber(v, "recalled", at), below) << v;
    const auto c = v.find("\"conflicts\": {", at);
    ASSERT_NE(c, std::string::npos) << v;
    EXPECT_GE(jsonNumber(v, "warnings", c), 10.0) << v;
    EXPECT_GE(jsonNumber(v, "precision", c), 0.9) << v;

    // conflicts.csv against SSM's encounters (its times one step earlier than ours) and the lanes
    const std::vector<SsmConflict> ssm = readSsmOutput(dir / "ssm.xml");
    const highway::RoadGeometry road = highway::readSumoNet(sourceDir() / net);
    const std::vector<std::string> rows = lines(slurp(dir / "conflicts.csv"));
    ASSERT_GE(rows.size(), 6u);  // a header and at least five conflicts
    const std::vector<std::string> head = splitCsv(rows[0]);
    auto col = [&](const char* column) {
      const auto it = std::find(head.begin(), head.end(), column);
      EXPECT_NE(it, head.end()) << column;
      return static_cast<std::size_t>(it - head.begin());
    };
    const std::size_t first = col("first"), second = col("second"), type = col("type"), begin = col("begin"),
                      end = col("end"), fx = col("first_x"), fy = col("first_y"), sx = col("second_x"),
                      sy = col("second_y"), lane = col("first_lane");
    std::size_t seen = 0, rearEnds = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
      const std::vector<std::string> f = splitCsv(rows[i]);
      const double b = std::stod(f[begin]), e = std::stod(f[end]);
      bool logged = false;
      for (const SsmConflict& s : ssm)
        if (std::minmax(s.ego, s.foe) == std::minmax(f[first], f[second]) && s.begin + 0.1 <= e + 0.11 && b <= s.end + 0.21)
          logged = true;
      seen += logged ? 1 : 0;
      if (f[type] != "rear_end") continue;
      ++rearEnds;
      // across the first's lane at its centre: the direction of the lane's segment nearest to it
      const Vec2 p1(std::stod(f[fx]), std::stod(f[fy])), p2(std::stod(f[sx]), std::stod(f[sy]));
      const auto l = std::find_if(road.lanes.begin(), road.lanes.end(), [&](const highway::Lane& x) { return x.id == f[lane]; });
      ASSERT_NE(l, road.lanes.end()) << f[lane];
      Vec2 u(1.0, 0.0);
      double nearest = INFINITY;
      for (std::size_t j = 0; j + 1 < l->shape.size(); ++j) {
        const Segment seg{l->shape[j], l->shape[j + 1]};
        const double d = (closestPointOnSegment(seg, p1) - p1).norm();
        if (d < nearest && (seg.b - seg.a).norm() > 0.0) nearest = d, u = (seg.b - seg.a).normalized();
      }
      const Vec2 rel = p2 - p1;
      EXPECT_LT(std::abs(u.x() * rel.y() - u.y() * rel.x()), l->width)
          << f[first] << " " << f[second] << " @" << f[begin] << " lane " << f[lane];
    }
    EXPECT_GE(rearEnds, 5u);
    EXPECT_GE(static_cast<double>(seen), 0.9 * static_cast<double>(rows.size() - 1)) << seen << " of " << rows.size() - 1;
  }
}

// PET where SSM computes one: a right-angle crossing at a junction (tests/data/crossing). Every
// box episode with a PET has SSM's PET of the same pair, within 0.1 s (a duration: the time-stamp
// shift cancels). And the crossings' conflict points.
// At a signalised junction (networks/intersection, 300 s): where the two cars head the same way the
// box TTC is SSM's to 0.02 s on every sample, as on the motorway; in a turn SSM's gap runs along the
// curved lanes and ours (SSAM's) on straight lines, so those are counted apart, and the two parts
// are the whole.
TEST(SsmValidation, FollowingTtcAtAJunctionIsSsmsWhereBothHeadTheSameWay) {
  const auto [r, v] =
      validated("ssm_junction_following", sourceDir() / "networks/intersection/scenario.yaml", {"--end", "300", "--no-map"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto fol = v.find("\"following\"");
  ASSERT_NE(fol, std::string::npos) << v;
  const auto same = v.find("\"same_heading\"", fol), turn = v.find("\"turning\"", fol);
  ASSERT_NE(same, std::string::npos) << v;
  ASSERT_NE(turn, std::string::npos) << v;
  const double nSame = jsonNumber(v, "matched", same), nTurn = jsonNumber(v, "matched", turn);
  EXPECT_GE(nSame, 5000.0) << v;  // the check has something to check
  EXPECT_GE(nTurn, 50.0) << v;    // ... and the junction has turning followers
  EXPECT_EQ(nSame + nTurn, jsonNumber(v, "matched_samples", fol)) << v;
  EXPECT_EQ(jsonNumber(v, "within_tolerance", same), nSame) << v;
  EXPECT_LT(jsonNumber(v, "max_abs_error_s", same), 1e-3) << v;
  EXPECT_NE(r.out.find(" % of the " + std::to_string(static_cast<long>(nTurn)) + " in a turn)"), std::string::npos) << r.out;
}

TEST(SsmValidation, PetAndCrossingPointsAgreeWithSsmOnACrossing) {
  // the minor road's cars predicted on at their speed, as SSM does: with the priority rules they
  // give way while they can and meet no one inside the safe time (no warning, no PET)
  const auto [r, v] = validated("ssm_crossing", sourceDir() / "tests/data/crossing/crossing.sumocfg",
                                {"--set", "priority_rules=false", "--no-map"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto pet = v.find("\"pet\"");
  ASSERT_NE(pet, std::string::npos) << v;
  const double matched = jsonNumber(v, "matched", pet);
  EXPECT_GE(matched, 10.0) << v;  // the check has something to check
  EXPECT_EQ(matched, jsonNumber(v, "stsim_pets", pet)) << v;
  EXPECT_GE(jsonNumber(v, "ssm_pets", pet), matched) << v;
  EXPECT_GE(jsonNumber(v, "within_fraction", pet), 0.99) << v;
  EXPECT_LT(jsonNumber(v, "max_abs_error_s", pet), 0.1) << v;
  EXPECT_NE(r.out.find(" PETs, 100.00 % within 0.1 s of SSM's;"), std::string::npos) << r.out;
  // at a right angle SSM's points lie where the two could meet: none off the other's path
  EXPECT_EQ(jsonNumber(v, "ssm_off_path", pet), 0.0) << v;
  EXPECT_EQ(jsonNumber(v, "matched", v.find("\"on_both_paths\"", pet)), matched) << v;
  // the analyst's: conflicts.csv's PETs against SSM's encounters of the same pair (each once)
  const auto mine = v.find("\"conflicts\": {", pet);
  ASSERT_NE(mine, std::string::npos) << v;
  const double both = jsonNumber(v, "matched", mine);
  EXPECT_GE(both, 5.0) << v;
  EXPECT_EQ(both, jsonNumber(v, "conflict_pets", mine)) << v;
  EXPECT_LT(jsonNumber(v, "ssm_encounters", mine), jsonNumber(v, "ssm_pets", pet)) << v;  // both devices' logs, once
  EXPECT_GE(jsonNumber(v, "within_fraction", mine), 0.99) << v;
  EXPECT_LT(jsonNumber(v, "max_abs_error_s", mine), 0.1) << v;
  EXPECT_NE(r.out.find(" conflicts' PETs, 100.00 % within 0.1 s of SSM's;"), std::string::npos) << r.out;

  // the conflict point of the crossings: SSM's is where the follower enters the conflict area (the
  // leader's near side on its lane), ours the bodies' contact, on that side: the same place along
  // the follower's path; across it ours is the middle of the touching part, within half the
  // follower's width (0.9 m) of SSM's on its centre line
  const auto cross = v.find("\"crossing\": {", v.find("\"conflict_point\""));
  ASSERT_NE(cross, std::string::npos) << v;
  const double points = jsonNumber(v, "matched", cross);
  EXPECT_GE(points, 20.0) << v;
  EXPECT_GE(points, 0.75 * jsonNumber(v, "box_episodes", cross)) << v;
  EXPECT_GE(jsonNumber(v, "within_fraction", cross), 0.99) << v;
  EXPECT_LT(jsonNumber(v, "max_abs_error_m", cross), 0.5) << v;
  const auto dist = v.find("\"distance\"", cross);
  ASSERT_NE(dist, std::string::npos) << v;
  EXPECT_EQ(jsonNumber(v, "matched", dist), points);
  EXPECT_LT(jsonNumber(v, "max_abs_error_m", dist), 0.9 + 0.5) << v;
}

TEST(SsmValidation, EncountersReadFromTheLanesAreSsmsAtJunctions) {
  // conflicts.csv's encounter (from the lanes each takes) against SSM's own encounter type of the
  // pair at the minimum-TTC tick, on the networks whose conflicts SSAM's angles type otherwise:
  // the intersection (the cars predicted on at their speed, as SSM predicts them) has left turns
  // across oncoming traffic (SSM: crossing) and straight cars closing up on a turner at its wait
  // point (SSM: following, then passed, as the lanes part); the roundabout's entries merge (SSAM's
  // angles call them lane changes and crossings)
  struct Case {
    const char* name;
    const char* scenario;
    std::vector<std::pair<std::string, double>> least;  // "ours/ssm" pairs and their least count
    double leastPrecision;  // of the conflicts SSM models
    double mostOutsideJunctions;  // summary.json's conflicts between junctions
  };
  const Case cases[] = {
      {"ssm_encounter_intersection", "networks/intersection/scenario.yaml",
       {{"opposing/crossing", 3}, {"diverging/following_passed", 5}}, 0.8, 0.0},
      // the roundabout's merges start before the ring's junction lanes: counted at the junction
      // where their paths meet
      {"ssm_encounter_roundabout", "networks/roundabout/scenario.yaml", {{"merging/merging", 15}}, 0.9, 2.0},
  };
  for (const Case& c : cases) {
    const auto [r, v] = validated(c.name, sourceDir() / c.scenario, {"--set", "priority_rules=false", "--no-map"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto e = v.find("\"encounter\": {");
    ASSERT_NE(e, std::string::npos) << v;
    const double matched = jsonNumber(v, "matched", e);
    EXPECT_GE(matched, 10.0) << c.name << v;  // something to check
    EXPECT_GE(matched, 0.7 * jsonNumber(v, "conflicts", e)) << c.name << v;
    EXPECT_EQ(jsonNumber(v, "agree", e), matched) << c.name << v;
    for (const auto& [pair, least] : c.least) EXPECT_GE(jsonNumber(v, pair, e), least) << c.name << " " << pair << v;
    // the conflicts of the encounters SSM predicts: SSM logged the pair with a finite TTC while
    // each lasted (or SUMO had them touch); the intersection's diverging ones are outside its model
    const auto models = v.find("\"where_ssm_models\"", e);
    ASSERT_NE(models, std::string::npos) << v;
    EXPECT_GE(jsonNumber(v, "conflicts", models), c.least.front().second) << c.name << v;
    EXPECT_GE(jsonNumber(v, "precision", models), c.leastPrecision) << c.name << v;
    // where the paths meet (from the lanes) against SSM's conflict point, like for like: every
    // conflict of a crossing or merge SSM logs at its minimum-TTC tick, its point within 0.5 m of
    // SSM's where that lies on both paths (SSM puts a split left turn's at its wait point)
    const auto meet = v.find("\"paths_meet\": {");
    ASSERT_NE(meet, std::string::npos) << v;
    const double withPoint = jsonNumber(v, "conflicts", meet);
    EXPECT_GE(withPoint, c.least.front().second) << c.name << v;
    EXPECT_EQ(jsonNumber(v, "matched", meet), withPoint) << c.name << v;
    const auto onPaths = v.find("\"on_both_paths\"", meet);
    const double compared = jsonNumber(v, "matched", onPaths);
    EXPECT_EQ(compared + jsonNumber(v, "ssm_off_path", meet), withPoint) << c.name << v;
    if (compared > 0) {
      EXPECT_GE(jsonNumber(v, "within_tolerance", onPaths), 0.9 * compared) << c.name << v;
    }
    const std::string summary = slurp(testDir(c.name) / "summary.json");
    const auto by = summary.find("\"by_junction\"");
    ASSERT_NE(by, std::string::npos) << summary;
    EXPECT_LE(jsonNumber(summary, "outside_junctions", by), c.mostOutsideJunctions) << c.name << summary;
  }
}

TEST(SsmValidation, WhereCrossingPathsMeetIsSsmsConflictPoint) {
  // crossings with the priority rules on: cars across cars at the actuated signal, a car across a
  // cyclist (0.7 m wide: SSM's entry half a bicycle before the crossing) and cyclists across each
  // other. Where SSM's point lies on both paths, ours is within 0.5 m of it.
  for (const char* net : {"actuated", "bicycles"}) {
    const std::string name = std::string("ssm_paths_meet_") + net;
    const auto [r, v] =
        validated(name, sourceDir() / "networks" / net / "scenario.yaml", {"--no-map"});
    ASSERT_EQ(r.code, 0) << r.err;
    const auto meet = v.find("\"paths_meet\": {");
    ASSERT_NE(meet, std::string::npos) << v;
    const auto onPaths = v.find("\"on_both_paths\"", meet);
    EXPECT_GE(jsonNumber(v, "matched", onPaths), 2.0) << net << v;  // something to compare
    EXPECT_EQ(jsonNumber(v, "within_tolerance", onPaths), jsonNumber(v, "matched", onPaths)) << net << v;
  }
}

}  // namespace
}  // namespace st::cosim
