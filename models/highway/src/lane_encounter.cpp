#include "lane_encounter.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

namespace st::highway::detail {

namespace {
// Two lane ends this close are one point: SUMO starts a junction's lanes at the end of the lane
// they leave and ends them at the start of the lane they reach (m; its shapes are to 0.01 m).
constexpr double kSamePoint = 0.5;
// Approaches heading at each other: their junction lanes start more than 135 degrees apart.
constexpr double kOpposingCos = -0.70710678118654752;

bool contains(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

// Whether polylines p and q cross away from the ends they share: a point where a segment of one
// meets a segment of the other, not within kSamePoint of an end of p that is an end of q too
// (lanes leaving one lane's end, reaching one lane's start, or one going on from the other touch
// there without crossing).
// Returns the first such point along p, with the directions of p's and q's segments there.
struct Cross {
  Vec2 at, alongP, alongQ;
};
std::optional<Cross> crossAway(std::span<const Vec2> p, std::span<const Vec2> q) {
  if (p.size() < 2 || q.size() < 2) return std::nullopt;
  Vec2 shared[4];
  int nShared = 0;
  for (const Vec2& x : {p.front(), p.back()})
    if ((x - q.front()).norm() <= kSamePoint || (x - q.back()).norm() <= kSamePoint) shared[nShared++] = x;
  for (std::size_t i = 1; i < p.size(); ++i)
    for (std::size_t k = 1; k < q.size(); ++k) {
      const Vec2 d = p[i] - p[i - 1], e = q[k] - q[k - 1], w = q[k - 1] - p[i - 1];
      const double den = cross(d, e);
      if (den == 0.0) continue;  // parallel: side by side, not across
      const double f = cross(w, e) / den, g = cross(w, d) / den;
      if (f < 0.0 || f > 1.0 || g < 0.0 || g > 1.0) continue;
      const Vec2 x = p[i - 1] + f * d;
      bool atShared = false;
      for (int j = 0; j < nShared; ++j) atShared = atShared || (x - shared[j]).norm() <= kSamePoint;
      if (!atShared) return Cross{x, d.normalized(), e.normalized()};
    }
  return std::nullopt;
}

Vec2 startDirection(std::span<const Vec2> shape) { return (shape[1] - shape[0]).normalized(); }

// The direction a lane's car came into its junction in: the start of the first of the junction
// lanes it has driven (SUMO splits a left turn at its wait point; the second part starts turned).
Vec2 approachDirection(const LanePrediction& lanes, int lane) {
  return startDirection(lanes.laneShape(lanes.junctionEntry(lane)));
}
}  // namespace

namespace {
LaneMeeting meeting(EncounterType type, const Vec2& point, int lane) {
  LaneMeeting m;
  m.type = type;
  m.point = point;
  m.lane = lane;
  return m;
}

// The shapes of the lanes of la against lb's: across each other (Crossing, or Opposing where their
// lanes start heading at each other), else reaching one point (Merging) or leaving one (Diverging);
// Unknown if none.
LaneMeeting byShapes(const LanePrediction& lanes, std::span<const int> la, std::span<const int> lb) {
  LaneMeeting merging, diverging;
  for (int x : la)
    for (int y : lb) {
      const std::span<const Vec2> p = lanes.laneShape(x), q = lanes.laneShape(y);
      if (p.size() < 2 || q.size() < 2 || x == y) continue;
      if (const std::optional<Cross> c = crossAway(p, q))
        return {approachDirection(lanes, x).dot(approachDirection(lanes, y)) < kOpposingCos ? EncounterType::Opposing
                                                                                           : EncounterType::Crossing,
                c->at, x, c->alongP, c->alongQ};
      if (merging.lane < 0 && (p.back() - q.back()).norm() <= kSamePoint)
        merging = meeting(EncounterType::Merging, p.back(), x);
      if (diverging.lane < 0 && (p.front() - q.front()).norm() <= kSamePoint)
        diverging = meeting(EncounterType::Diverging, p.front(), x);
    }
  return merging.lane >= 0 ? merging : diverging;
}

// Of a merge onto lane x, common to both lists: a junction lane it is reached by (the one before
// it on either path), else x itself
int mergeLane(const LanePrediction& lanes, const std::vector<int>& la, const std::vector<int>& lb, int x) {
  for (const std::vector<int>* l : {&la, &lb}) {
    const auto at = std::find(l->begin(), l->end(), x);
    if (at != l->begin() && at != l->end() && lanes.internalLane(*(at - 1))) return *(at - 1);
  }
  return x;
}
}  // namespace

LaneMeeting laneEncounter(const LanePrediction& lanes, const std::vector<int>& la, const std::vector<int>& lb) {
  if (la.empty() || lb.empty()) return {};
  // one is on a lane the other's path takes: one follows the other
  if (contains(la, lb.front()) || contains(lb, la.front())) return {EncounterType::Following};
  // from different lanes onto a common one, at its start
  for (int x : la)
    if (contains(lb, x)) return meeting(EncounterType::Merging, lanes.laneShape(x).front(), mergeLane(lanes, la, lb, x));
  if (const LaneMeeting m = byShapes(lanes, la, lb); m.type != EncounterType::Unknown) return m;
  // a body that has just left a junction lane where the paths cross or part (a turn's first part,
  // up to its wait point) still covers it: the lanes onto each one's first, inside a junction
  auto behind = [&](const std::vector<int>& l) {
    std::vector<int> out;
    if (lanes.internalLane(l.front()))
      for (int p : lanes.predecessors(l.front()))
        if (lanes.internalLane(p)) out.push_back(p);
    return out;
  };
  const std::vector<int> ba = behind(la), bb = behind(lb);
  if (!ba.empty() || !bb.empty()) {
    if (const LaneMeeting m = byShapes(lanes, ba, lb); m.type != EncounterType::Unknown) return m;
    if (const LaneMeeting m = byShapes(lanes, la, bb); m.type != EncounterType::Unknown) return m;
  }
  if (lanes.laneEdge(la.front()) >= 0 && lanes.laneEdge(la.front()) == lanes.laneEdge(lb.front()))
    return {EncounterType::Adjacent};
  return {};
}

LaneMeeting laneEncounter(const LanePrediction& lanes, int a, int b, double reachA, double reachB,
                          std::vector<int>& scratchA, std::vector<int>& scratchB) {
  lanes.lanesAhead(a, reachA, scratchA);
  lanes.lanesAhead(b, reachB, scratchB);
  return laneEncounter(lanes, scratchA, scratchB);
}

}  // namespace st::highway::detail
