// How two paths meet, read from the lanes (lane_encounter.hpp), on a junction built by hand whose
// relations are known from its drawing: each pair of lane lists against the encounter the
// geometry makes it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "lane_encounter.hpp"
#include "roads.hpp"
#include "vehicle_table.hpp"

namespace st::highway {
namespace {

using detail::LanePrediction;

// A four-arm junction at the origin, right-hand traffic, SUMO's naming: approaches s_in (two
// lanes), n_in, w_in, e_in; exits n_out, s_out, e_out, w_out; junction lanes :C_k_0 from the end of
// the lane they leave to the start of the lane they reach. The left turn from the south is split
// at its wait point (1, -2), as SUMO splits it, its second part crossing the oncoming straight.
RoadGeometry junction() {
  RoadGeometry r;
  auto lane = [&](const std::string& edge, int index, std::vector<Vec2> shape) {
    Lane l = laneOf(edge, index, std::move(shape));
    l.internal = edge[0] == ':';
    r.lanes.push_back(l);
  };
  lane("s_in", 0, {Vec2(2.0, -100.0), Vec2(2.0, -10.0)});
  lane("s_in", 1, {Vec2(5.2, -100.0), Vec2(5.2, -10.0)});
  lane(":C_0", 0, {Vec2(2.0, -10.0), Vec2(2.0, 10.0)});                      // south, straight on
  lane("n_out", 0, {Vec2(2.0, 10.0), Vec2(2.0, 100.0)});
  lane(":C_1", 0, {Vec2(2.0, -10.0), Vec2(1.0, -2.0)});                      // south, left: to the wait point
  lane(":C_2", 0, {Vec2(1.0, -2.0), Vec2(-10.0, 2.0)});                      // ... and on
  lane("w_out", 0, {Vec2(-10.0, 2.0), Vec2(-100.0, 2.0)});
  lane("n_in", 0, {Vec2(-2.0, 100.0), Vec2(-2.0, 10.0)});
  lane(":C_3", 0, {Vec2(-2.0, 10.0), Vec2(-2.0, -10.0)});                    // north, straight on
  lane("s_out", 0, {Vec2(-2.0, -10.0), Vec2(-2.0, -100.0)});
  lane("w_in", 0, {Vec2(-100.0, -2.0), Vec2(-10.0, -2.0)});
  lane(":C_4", 0, {Vec2(-10.0, -2.0), Vec2(10.0, -2.0)});                    // west, straight on
  lane("e_out", 0, {Vec2(10.0, -2.0), Vec2(100.0, -2.0)});
  lane("e_in", 0, {Vec2(100.0, 2.0), Vec2(10.0, 2.0)});
  lane(":C_5", 0, {Vec2(10.0, 2.0), Vec2(6.0, 6.0), Vec2(2.0, 10.0)});       // east, right onto n_out
  return r;
}

struct Junction {
  RoadGeometry road = junction();
  MonitorConfig cfg;
  MonitorCounters counters;
  detail::VehicleTable cars{cfg, counters};
  LanePrediction lanes{road, cfg, cars, counters};

  // lane ids -> indices
  std::vector<int> ids(const std::vector<std::string>& names) const {
    std::vector<int> out;
    for (const std::string& n : names)
      for (int i = 0; i < static_cast<int>(road.lanes.size()); ++i)
        if (road.lanes[i].id == n) out.push_back(i);
    EXPECT_EQ(out.size(), names.size());
    return out;
  }
  detail::LaneMeeting meet(const std::vector<std::string>& a, const std::vector<std::string>& b) const {
    const detail::LaneMeeting ab = detail::laneEncounter(lanes, ids(a), ids(b));
    const detail::LaneMeeting ba = detail::laneEncounter(lanes, ids(b), ids(a));
    EXPECT_EQ(ab.type, ba.type) << "not symmetric";
    EXPECT_EQ(std::isnan(ab.point.x()), std::isnan(ba.point.x())) << "not symmetric";
    if (!std::isnan(ab.point.x())) {
      EXPECT_LT((ab.point - ba.point).norm(), 1e-9) << "not symmetric";
    }
    return ab;
  }
  EncounterType of(const std::vector<std::string>& a, const std::vector<std::string>& b) const { return meet(a, b).type; }
  std::string laneName(int lane) const { return lane >= 0 ? road.lanes[static_cast<std::size_t>(lane)].id : ""; }
};

TEST(LaneEncounter, EachRelationOfAJunctionDrawnByHand) {
  const Junction j;
  const std::vector<std::string> southStraight{"s_in_0", ":C_0_0", "n_out_0"};
  // one on a lane the other's path takes
  EXPECT_EQ(j.of(southStraight, {":C_0_0", "n_out_0"}), EncounterType::Following);
  EXPECT_EQ(j.of(southStraight, {"s_in_0", ":C_0_0"}), EncounterType::Following);
  // onto one lane from two: by the common lane, or by the junction lanes' common end alone
  EXPECT_EQ(j.of(southStraight, {"e_in_0", ":C_5_0", "n_out_0"}), EncounterType::Merging);
  EXPECT_EQ(j.of({"s_in_0", ":C_0_0"}, {"e_in_0", ":C_5_0"}), EncounterType::Merging);
  // a straight car behind a turner standing at its wait point: their lanes leave one point
  EXPECT_EQ(j.of(southStraight, {":C_1_0", ":C_2_0", "w_out_0"}), EncounterType::Diverging);
  // ... also once the turner is past it (its body still covers the lane it left)
  EXPECT_EQ(j.of(southStraight, {":C_2_0", "w_out_0"}), EncounterType::Diverging);
  // across: at right angles a crossing; the left turn across the oncoming straight opposing,
  // before its wait point and after (its approach is the south's either way)
  EXPECT_EQ(j.of(southStraight, {"w_in_0", ":C_4_0", "e_out_0"}), EncounterType::Crossing);
  EXPECT_EQ(j.of({"s_in_0", ":C_1_0", ":C_2_0"}, {"n_in_0", ":C_3_0", "s_out_0"}), EncounterType::Opposing);
  EXPECT_EQ(j.of({":C_2_0", "w_out_0"}, {":C_3_0", "s_out_0"}), EncounterType::Opposing);
  // the oncoming straights pass each other: nothing in common, not one edge
  EXPECT_EQ(j.of(southStraight, {"n_in_0", ":C_3_0", "s_out_0"}), EncounterType::Unknown);
  // side by side on one edge, no lane in common ahead
  EXPECT_EQ(j.of({"s_in_0"}, {"s_in_1"}), EncounterType::Adjacent);
  // no lanes: not known
  EXPECT_EQ(detail::laneEncounter(j.lanes, {}, j.ids(southStraight)).type, EncounterType::Unknown);
}

TEST(LaneEncounter, WhereThePathsMeetOnTheDrawing) {
  // the points worked out from the drawing above: on both centre lines, on a junction lane
  const Junction j;
  const std::vector<std::string> southStraight{"s_in_0", ":C_0_0", "n_out_0"};
  auto expectAt = [&](const detail::LaneMeeting& m, const Vec2& at, const char* what) {
    EXPECT_LT((m.point - at).norm(), 1e-9) << what << ": " << m.point.transpose();
    EXPECT_EQ(m.lane >= 0 && j.road.lanes[static_cast<std::size_t>(m.lane)].internal, true) << what << " " << j.laneName(m.lane);
  };
  // x = 2 across y = -2
  const detail::LaneMeeting across = j.meet(southStraight, {"w_in_0", ":C_4_0", "e_out_0"});
  expectAt(across, Vec2(2.0, -2.0), "crossing");
  EXPECT_LT((across.alongA - Vec2(0.0, 1.0)).norm(), 1e-12) << "north, the first path's lane";
  EXPECT_LT((across.alongB - Vec2(1.0, 0.0)).norm(), 1e-12) << "east, the second's";
  // onto n_out at its start (2, 10), reached by a junction lane
  expectAt(j.meet(southStraight, {"e_in_0", ":C_5_0", "n_out_0"}), Vec2(2.0, 10.0), "merging");
  expectAt(j.meet({"s_in_0", ":C_0_0"}, {"e_in_0", ":C_5_0"}), Vec2(2.0, 10.0), "merging by the ends");
  // the left turn's second part (1, -2) -> (-10, 2) across x = -2: 3/11 of the way, y = -2 + 12/11
  expectAt(j.meet({"s_in_0", ":C_1_0", ":C_2_0"}, {"n_in_0", ":C_3_0", "s_out_0"}), Vec2(-2.0, -2.0 + 12.0 / 11.0),
           "opposing");
  // the lanes leaving the south approach's end (2, -10)
  expectAt(j.meet(southStraight, {":C_1_0", ":C_2_0", "w_out_0"}), Vec2(2.0, -10.0), "diverging");
  // no point where one follows the other or they run side by side
  EXPECT_TRUE(std::isnan(j.meet(southStraight, {":C_0_0", "n_out_0"}).point.x()));
  EXPECT_EQ(j.meet(southStraight, {":C_0_0", "n_out_0"}).lane, -1);
  EXPECT_TRUE(std::isnan(j.meet({"s_in_0"}, {"s_in_1"}).point.x()));
}

TEST(LaneEncounter, LanesAheadFollowTheRoute) {
  // a car 20 m before the junction on s_in_0, its route turning left to w_out: its lanes ahead
  // are the left turn's, in order, as far as it reaches
  Junction j;
  VehicleState v;
  v.id = "a";
  v.position = Vec2(2.0, -30.0);
  v.heading = 0.5 * 3.141592653589793;
  v.speed = 10.0;
  v.lane = j.ids({"s_in_0"}).front();
  const std::vector<std::string> edges = edgeIds(j.road);
  auto edge = [&](const std::string& e) {
    return static_cast<int>(std::find(edges.begin(), edges.end(), e) - edges.begin());
  };
  v.route.fill(-1);
  v.route[0] = edge("s_in");
  v.route[1] = edge("w_out");
  j.cars.update(0.0, std::vector<VehicleState>{v});
  j.lanes.update(0.0);
  const int slot = j.cars.active.front();
  std::vector<int> out;
  j.lanes.lanesAhead(slot, 30.0, out);  // 20 m to the junction, 8.1 m more to the wait point
  EXPECT_EQ(out, j.ids({"s_in_0", ":C_1_0", ":C_2_0"}));
  j.lanes.lanesAhead(slot, 25.0, out);
  EXPECT_EQ(out, j.ids({"s_in_0", ":C_1_0"}));
  j.lanes.lanesAhead(slot, 5.0, out);
  EXPECT_EQ(out, j.ids({"s_in_0"}));
  // without its route: the straightest successor
  v.route.fill(-1);
  j.cars.update(0.1, std::vector<VehicleState>{v});
  j.lanes.update(0.1);
  j.lanes.lanesAhead(slot, 30.0, out);
  EXPECT_EQ(out, j.ids({"s_in_0", ":C_0_0"}));
}

}  // namespace
}  // namespace st::highway
