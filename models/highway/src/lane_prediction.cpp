#include "lane_prediction.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "car_shape.hpp"

#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

namespace {

inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
inline Vec2 leftNormal(const Vec2& u) { return {-u.y(), u.x()}; }

constexpr double kSegmentCell = 25.0;  // m: the segment grid's cells (coarser on huge networks)

// The first segment of each run of one lane's segments in a cell's list (the list is in point
// order: lane by lane, along each lane).
void firstOfRuns(std::span<const int> segments, const std::vector<int>& pointLane, std::vector<int>& runs) {
  runs.clear();
  for (int seg : segments)
    if (runs.empty() || pointLane[runs.back()] != pointLane[seg]) runs.push_back(seg);
}

// Arc length driven after tau s from speed u at acceleration a (stopping, not reversing, when a < 0).
inline double driven(double u, double a, double tau) {
  if (a < 0.0 && u + a * tau < 0.0) return u > 0.0 ? -0.5 * u * u / a : 0.0;
  return u * tau + 0.5 * a * tau * tau;
}
// The first tau >= 0 at which driven(u, a, tau) reaches s > 0 (infinity if never).
inline double timeToDrive(double u, double a, double s) {
  if (std::abs(a) <= tol::kAccelerationEpsilon) return u > 0.0 ? s / u : std::numeric_limits<double>::infinity();
  const double disc = u * u + 2.0 * a * s;
  if (disc < 0.0) return std::numeric_limits<double>::infinity();  // stops first
  // the smaller positive root of a/2 tau^2 + u tau - s, in the cancellation-free form
  return 2.0 * s / (u + std::sqrt(disc));
}

// Whether axis turns from the lane's direction dir by more than tol::kMergeBend.
inline bool turnedFrom(const Vec2& dir, const Vec2& axis) {
  return std::abs(std::atan2(cross2(dir, axis), dir.dot(axis))) > tol::kMergeBend;
}

// How far a path departs from the straight line p0 + v t, at a piece's ends: from the straight
// line, less what the acceleration may add (the prunes allow |a| t^2 / 2 already):
// |p - p0 - v t| + scale |driven - u t| bounds the affine part there; a lane whose scale exceeds 1
// adds (scale - 1) |driven - u t| at most (growEnvelopes).
struct DeviationBound {
  Vec2 p0, v;
  double u, acc;
  double dev = 0.0;
  void add(const Vec2& p, double tk, double scale) {
    dev = std::max(dev, (p - p0 - v * tk).norm() + scale * std::abs(driven(u, acc, tk) - u * tk));
  }
};

// The distance between segments a0-a1 and b0-b1 (0 where they cross).
double segmentDistance(const Vec2& a0, const Vec2& a1, const Vec2& b0, const Vec2& b1) {
  const Vec2 da = a1 - a0, db = b1 - b0, w = b0 - a0;
  const double den = cross2(da, db);
  if (den != 0.0) {
    const double s = cross2(w, db) / den, u = cross2(w, da) / den;
    if (s >= 0.0 && s <= 1.0 && u >= 0.0 && u <= 1.0) return 0.0;
  }
  const Segment A{a0, a1}, B{b0, b1};
  return std::min({(closestPointOnSegment(B, a0) - a0).norm(), (closestPointOnSegment(B, a1) - a1).norm(),
                   (closestPointOnSegment(A, b0) - b0).norm(), (closestPointOnSegment(A, b1) - b1).norm()});
}

}  // namespace

LanePrediction::LanePrediction(const RoadGeometry& road, const MonitorConfig& config, VehicleTable& cars,
                               MonitorCounters& counters)
    : cfg_(&config), cars_(&cars), counters_(&counters), alongLanes_(config.prediction == Prediction::Road) {
  addLanes(road);
  const std::unordered_map<std::string, std::vector<int>> byEdge = setEdges(road);
  findSuccessors();
  findPredecessors();
  setExitEdges();
  markLaneDrops(byEdge);
  if (pt_.empty()) return;
  buildSegmentGrid();
  markCrowded();
}

// each lane's points (closer ones dropped), arcs, width and scale
void LanePrediction::addLanes(const RoadGeometry& road) {
  const int n = static_cast<int>(road.lanes.size());
  lanes_.resize(n);
  for (int i = 0; i < n; ++i) {
    const Lane& l = road.lanes[i];
    NetLane& nl = lanes_[i];
    nl.first = static_cast<int>(pt_.size());
    nl.width = l.width;
    nl.internal = l.internal;
    double arc = 0.0;
    for (const Vec2& q : l.shape) {
      if (nl.count > 0 && (q - pt_.back()).norm() <= tol::kMinSegmentLength) continue;
      if (nl.count > 0) arc += (q - pt_.back()).norm();
      pt_.push_back(q);
      cum_.push_back(arc);
      ++nl.count;
    }
    nl.length = arc;
    // a car moves scale times its reported speed along the shape (bounded: a wrong length
    // stays a wrong speed, not an absurd one)
    if (l.length > 0.0 && arc > 0.0) nl.scale = std::clamp(arc / l.length, 0.25, 4.0);
  }
}

// the lanes of each edge (returned, for a lane drop), and each lane's edge index (VehicleState::route)
std::unordered_map<std::string, std::vector<int>> LanePrediction::setEdges(const RoadGeometry& road) {
  const int n = static_cast<int>(road.lanes.size());
  std::unordered_map<std::string, std::vector<int>> byEdge;
  for (int i = 0; i < n; ++i) byEdge[road.lanes[i].edge].push_back(i);
  edgeIds_ = edgeIds(road);
  for (int e = 0; e < static_cast<int>(edgeIds_.size()); ++e)
    for (int i : byEdge[edgeIds_[e]]) lanes_[i].edge = e;
  return byEdge;
}

int LanePrediction::junctionEntry(int lane) const {
  for (int hop = 0; hop < 4 && internalLane(lane); ++hop) {
    const std::span<const int> before = predecessors(lane);
    if (before.empty() || !internalLane(before.front())) break;
    lane = before.front();
  }
  return lane;
}

// successors: the lanes that start where a lane ends (SUMO's junction-internal lanes start at
// the end of the lane they leave and end at the start of the lane they reach); the straightest
void LanePrediction::findSuccessors() {
  const int n = static_cast<int>(lanes_.size());
  auto key = [](const Vec2& p) {
    return (static_cast<std::int64_t>(std::floor(p.x())) << 32) ^ static_cast<std::int64_t>(std::floor(p.y()) + (1 << 30));
  };
  std::unordered_map<std::int64_t, std::vector<int>> starts;
  for (int i = 0; i < n; ++i)
    if (lanes_[i].count >= 2) starts[key(pt_[lanes_[i].first])].push_back(i);
  constexpr double kJoin = 0.1;  // m: a successor starts this close to the lane's end
  constexpr double kTurn = 0.35;  // rad (20 degrees): a successor turning more is a turn
  std::vector<std::pair<double, int>> found;  // a lane's successors: |turn|, lane
  for (int a = 0; a < n; ++a) {
    lanes_[a].succBegin = lanes_[a].succEnd = static_cast<int>(succ_.size());
    const NetLane& la = lanes_[a];
    if (la.count < 2) continue;
    found.clear();
    const Vec2 end = pt_[la.first + la.count - 1];
    const Vec2 endDir = (end - pt_[la.first + la.count - 2]).normalized();
    // each successor's turn: to the direction it leaves in (a junction lane's last segment; it
    // starts along the lane it leaves), signed, to the left positive
    double left = kTurn, right = -kTurn;
    for (double dx : {-kJoin, kJoin})
      for (double dy : {-kJoin, kJoin}) {
        auto it = starts.find(key(end + Vec2(dx, dy)));
        if (it == starts.end()) continue;
        for (int b : it->second) {
          const NetLane& lb = lanes_[b];
          if (b == a || (pt_[lb.first] - end).norm() > kJoin) continue;
          const int k = lb.internal ? lb.count - 2 : 0;
          const Vec2 out = (pt_[lb.first + k + 1] - pt_[lb.first + k]).normalized();
          const double turn = std::atan2(cross2(endDir, out), endDir.dot(out));
          found.emplace_back(std::abs(turn), b);
          NetLane& l = lanes_[a];
          if (turn > left || (turn == left && b < l.nextLeft)) left = turn, l.nextLeft = b;
          if (turn < right || (turn == right && b < l.nextRight)) right = turn, l.nextRight = b;
        }
      }
    // the straightest first, the lower index among equals (the four probes may find a lane twice)
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    for (const auto& [turn, b] : found) succ_.push_back(b);
    lanes_[a].succEnd = static_cast<int>(succ_.size());
    if (!found.empty()) lanes_[a].next = found.front().second;
  }
}

// each lane's predecessors: the lanes it succeeds (a counting sort of succ_ by successor)
void LanePrediction::findPredecessors() {
  const int n = static_cast<int>(lanes_.size());
  predStart_.assign(n + 1, 0);
  for (int b : succ_) ++predStart_[b + 1];
  for (int a = 0; a < n; ++a) predStart_[a + 1] += predStart_[a];
  pred_.resize(succ_.size());
  {
    std::vector<int> next(predStart_.begin(), predStart_.end() - 1);
    for (int a = 0; a < n; ++a)
      for (int k = lanes_[a].succBegin; k < lanes_[a].succEnd; ++k) pred_[next[succ_[k]]++] = a;
  }
}

// the edge a car reaches: its own on a normal lane; through a junction's lanes, the first
// normal lane's (a junction lane has one successor, another junction lane at most a few times)
void LanePrediction::setExitEdges() {
  const int n = static_cast<int>(lanes_.size());
  for (int a = 0; a < n; ++a) {
    int b = a;
    for (int hop = 0; hop < 8 && b >= 0 && lanes_[b].internal; ++hop) b = lanes_[b].next;
    lanes_[a].exitEdge = b >= 0 && !lanes_[b].internal ? lanes_[b].edge : lanes_[a].edge;
  }
}

// a lane without successor ends the road for its cars only where its edge goes on (a lane drop);
// where no lane of the edge goes on, the cars leave the network (or the net has no junction lanes)
void LanePrediction::markLaneDrops(const std::unordered_map<std::string, std::vector<int>>& byEdge) {
  for (const auto& [edge, ids] : byEdge) {
    bool on = false;
    for (int a : ids) on = on || lanes_[a].next >= 0;
    for (int a : ids) lanes_[a].drops = on && lanes_[a].next < 0;
    bool merge = false;
    for (int a : ids) merge = merge || lanes_[a].drops;
    for (int a : ids) lanes_[a].merge = merge;
  }
}

// the segment grid over every lane's segments, each grown by the widest half lane and a metre
void LanePrediction::buildSegmentGrid() {
  const int n = static_cast<int>(lanes_.size());
  Vec2 lo = pt_[0], hi = pt_[0];
  for (const Vec2& q : pt_) {
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  double maxWidth = 0.0;
  for (const NetLane& l : lanes_) maxWidth = std::max(maxWidth, l.width);
  const double grow = 0.5 * maxWidth + 1.0;
  const Vec2 origin = lo - Vec2::Constant(grow);
  const Vec2 ext = hi - lo + Vec2::Constant(2.0 * grow);
  segments_ = StaticGrid<2>(origin, ext, kSegmentCell);
  pointLane_.assign(pt_.size(), -1);
  for (int i = 0; i < n; ++i) std::fill_n(pointLane_.begin() + lanes_[i].first, lanes_[i].count, i);
  segments_.build(static_cast<int>(pt_.size()), [&](int p) -> std::optional<Aabb<2>> {
    const int l = pointLane_[p];
    if (p + 1 >= lanes_[l].first + lanes_[l].count) return std::nullopt;  // a lane's last point
    const Vec2 a = pt_[p], b = pt_[p + 1];
    return Aabb<2>{a.cwiseMin(b) - Vec2::Constant(grow), a.cwiseMax(b) + Vec2::Constant(grow)};
  });
}

// crowded segments: another lane's area overlaps this one's (a junction, a diverge, lanes that
// meet end to start). Elsewhere lanes lie side by side at their half widths' sum, so no other
// lane can be nearer a centre inside this lane by kSwitch: a car there keeps it unsearched.
void LanePrediction::markCrowded() {
  crowded_.assign(pt_.size(), 0);
  std::vector<int> runs;
  for (int c = 0; c < segments_.cellCount(); ++c) {
    firstOfRuns(segments_.objectsIn(c), pointLane_, runs);
    for (std::size_t i = 0; i < runs.size(); ++i)
      for (std::size_t j = i + 1; j < runs.size(); ++j) {
        const int pa = runs[i], pb = runs[j], la = pointLane_[pa], lb = pointLane_[pb];
        if (la == lb) continue;
        if (crowded_[pa] && crowded_[pb]) continue;
        const double apart = 0.5 * (lanes_[la].width + lanes_[lb].width) - 0.01;
        if (segmentDistance(pt_[pa], pt_[pa + 1], pt_[pb], pt_[pb + 1]) < apart) crowded_[pa] = crowded_[pb] = 1;
      }
  }
}

// The projection of p on a lane's centre line, walking from segment seg: forward while p lies
// beyond a segment's end, else back while before its start; beyond the line's ends the first and
// last segments are extended.
LanePrediction::Projection LanePrediction::project(int lane, const Vec2& p, int seg) const {
  const NetLane& l = lanes_[lane];
  const int nseg = l.count - 1;
  seg = std::clamp(seg, 0, nseg - 1);
  auto along = [&](int k) {
    const Vec2 a = pt_[l.first + k];
    const double len = cum_[l.first + k + 1] - cum_[l.first + k];
    return std::pair{(p - a).dot((pt_[l.first + k + 1] - a) / len), len};
  };
  auto [t, len] = along(seg);
  bool moved = false;
  while (t > len && seg + 1 < nseg) {
    ++seg;
    std::tie(t, len) = along(seg);
    moved = true;
  }
  if (!moved)
    while (t < 0.0 && seg > 0) {
      --seg;
      std::tie(t, len) = along(seg);
    }
  const Vec2 a = pt_[l.first + seg];
  const Vec2 u = (pt_[l.first + seg + 1] - a) / len;
  Projection pr;
  pr.seg = seg;
  pr.dir = u;
  pr.s = cum_[l.first + seg] + t;
  pr.d = cross2(u, p - a);
  return pr;
}

// How far to the left of the centre line (at the centre's projection pr) the middle of the chord
// between the line's points half a body length behind and ahead lies: where a body whose front and
// rear follow the line has its centre. 0 unless a vertex lies between them on the lane. Beyond
// the lane's ends the line goes on straight (the lanes before and after a junction lane mostly
// do: a bus in a tight turn has its rear on the lane it came from).
double LanePrediction::chordOffset(int lane, const Projection& pr, double half) const {
  const NetLane& l = lanes_[lane];
  auto at = [&](double s, int seg) {
    while (seg + 2 < l.count && cum_[l.first + seg + 1] < s) ++seg;
    while (seg > 0 && cum_[l.first + seg] > s) --seg;
    const Vec2 a = pt_[l.first + seg], b = pt_[l.first + seg + 1];
    return std::pair{seg, Vec2(a + (s - cum_[l.first + seg]) / (cum_[l.first + seg + 1] - cum_[l.first + seg]) * (b - a))};
  };
  const auto [rearSeg, rear] = at(pr.s - half, pr.seg);
  const auto [frontSeg, front] = at(pr.s + half, pr.seg);
  if (rearSeg == frontSeg) return 0.0;
  const Vec2 foot = pt_[l.first + pr.seg] + (pr.s - cum_[l.first + pr.seg]) * pr.dir;
  return cross2(pr.dir, 0.5 * (rear + front) - foot);
}

// The centre lies in the lane (within slack of its sides, and not beyond its ends by more than
// kEndSlack) and the car heads along it (within 60 degrees). A body that follows a tight curve (a
// turn inside a junction) has its centre on the chord from its rear to its front, inside the bend
// by more than the lane's half width: there its offset less the chord's counts (half: half the
// body's length).
bool LanePrediction::fits(int lane, const Projection& pr, const Vec2& axis, double slack, double half) const {
  constexpr double kEndSlack = 0.5;  // m
  const NetLane& l = lanes_[lane];
  if (!(pr.s >= -kEndSlack && pr.s <= l.length + kEndSlack && axis.dot(pr.dir) >= 0.5)) return false;
  const double side = 0.5 * l.width + slack;
  return std::abs(pr.d) <= side || std::abs(pr.d - chordOffset(lane, pr, half)) <= side;
}

// The lane the car's centre is on: its last lane while the centre stays near its centre line; else
// the lane nearby that fits best (the centre in it, heading along it: a successor past the end, a
// neighbour after a lane change, the other branch where two lanes diverge), unless the last lane
// still holds the centre within kKeep of its side and no other lane is nearer by kSwitch (a car
// driving on a marker does not flap between two lanes).
int LanePrediction::match(int slot, const Vec2& p, const Vec2& axis, Projection& out) const {
  // a pedestrian walks where no lane leads it (crosswalks, sidewalks, across): a straight line
  if (cars_->vclass[slot] == VehicleClass::Pedestrian) return -1;
  constexpr double kCentred = 0.3;  // m: a car this near its last lane's centre line keeps it, unsearched
  constexpr double kKeep = 0.25;    // m beyond the lane's side a car is still on its last lane
  constexpr double kSwitch = 0.25;  // m nearer another lane's centre line must be to take the car
  const LaneFrame& f = frame_[slot];
  const double half = 0.5 * cars_->body[slot].length;
  int kept = -1;
  Projection keep;
  if (f.lane >= 0 && cars_->slots[slot].present) {
    keep = project(f.lane, p, f.seg);
    if (keep.s <= lanes_[f.lane].length && fits(f.lane, keep, axis, kKeep, half)) {
      kept = f.lane;
      if (std::abs(keep.d) <= kCentred ||
          (std::abs(keep.d) <= halfWidth(f.lane) && !crowded_[lanes_[f.lane].first + keep.seg])) {
        out = keep;
        return kept;
      }
    }
  }
  int best = -1;
  Projection found;
  double bestScore = std::numeric_limits<double>::infinity();
  int prevLane = -1;
  for (int seg : segments_.objectsIn(segments_.cellOf(p))) {
    // a lane's run of segments through the cell is projected once, from its first segment
    const int lane = pointLane_[seg];
    if (lane == prevLane) continue;
    prevLane = lane;
    const Projection pr = project(lane, p, seg - lanes_[lane].first);
    if (!fits(lane, pr, axis, 0.0, half)) continue;
    // nearest centre line first, then the better aligned (overlapping junction lanes), then the lower index
    const double score = std::abs(pr.d) - 1e-3 * axis.dot(pr.dir);
    if (score < bestScore) {
      bestScore = score;
      best = lane;
      found = pr;
    }
  }
  if (kept >= 0 && (best < 0 || best == kept || !(std::abs(found.d) < std::abs(keep.d) - kSwitch))) {
    out = keep;
    return kept;
  }
  if (best >= 0) out = found;
  return best;
}

// The lane a car's path takes after `lane` ends, -1 if none. Along its route where it has one:
// routeAt is the index in the route of the edge the lane drives on or reaches (-1: off its route),
// moved on as the path enters the next edge. Off its route: the turn its signal shows at the
// junction ahead (SUMO signals its turns), else straight on.
int LanePrediction::successor(int slot, int lane, int& routeAt) const {
  const NetLane& l = lanes_[lane];
  const auto& route = cars_->route[slot];
  if (routeAt >= 0) {
    // a junction lane goes on to the edge it reaches; a normal lane to its route's next edge
    const int at = l.internal ? routeAt : routeAt + 1;
    const int want = at < kRouteAhead ? route[at] : -1;
    if (want >= 0)
      for (int k = l.succBegin; k < l.succEnd; ++k)
        if (lanes_[succ_[k]].exitEdge == want) {
          routeAt = at;
          return succ_[k];
        }
    // the route leaves from another lane of this edge (the car changes lanes first), or is over
    routeAt = -1;
  }
  const std::uint8_t sig = cars_->signals[slot];
  return (sig & kSignalLeft) && l.nextLeft >= 0 ? l.nextLeft : (sig & kSignalRight) && l.nextRight >= 0 ? l.nextRight : l.next;
}

void LanePrediction::lanesAhead(int slot, double reach, std::vector<int>& out) const {
  out.clear();
  int ln = reportedLane(slot);
  if (ln < 0 || ln >= static_cast<int>(lanes_.size())) return;
  int routeAt = -1;
  for (int k = 0; k < kRouteAhead && routeAt < 0; ++k)
    if (cars_->route[slot][k] == lanes_[ln].exitEdge) routeAt = k;
  // the first lane from the centre's arc on it (the frame's, where this lane is the frame's)
  const LaneFrame& f = frame_[slot];
  double ahead = lanes_[ln].length - (f.lane == ln ? std::clamp(f.s, 0.0, lanes_[ln].length) : 0.0);
  out.push_back(ln);
  while (ahead < reach && static_cast<int>(out.size()) < kLanesAhead) {
    ln = successor(slot, ln, routeAt);
    if (ln < 0 || std::find(out.begin(), out.end(), ln) != out.end()) break;
    out.push_back(ln);
    ahead += lanes_[ln].length;
  }
}

Body LanePrediction::bodyAt(std::span<const PathPiece> path, const Body& now, MotionModel motion, double t) {
  std::size_t i = 0;
  while (i + 1 < path.size() && path[i + 1].t0 <= t) ++i;
  const PathPiece& pc = path[i];
  const double tau = t - pc.t0;
  const double a = motionAcceleration(now, motion);
  Body b = now;
  const double speed = a < 0.0 ? std::max(0.0, pc.speed + a * tau) : pc.speed + a * tau;
  b.position = pc.p + (pc.scale * driven(pc.speed, a, tau)) * pc.dir + (pc.lateral * tau) * pc.normal;
  b.velocity = (pc.scale * speed) * pc.dir + pc.lateral * pc.normal;
  b.acceleration = pc.scale * now.acceleration;
  b.stopAcceleration = pc.scale * now.stopAcceleration;
  b.axis = pc.axis;
  return b;
}

Ttc LanePrediction::vehicleTtc(int e, int f, double horizon) const {
  const VehicleTable& c = *cars_;
  const DetectorConfig& dc = cfg_->detector;
  if (straight_[e] && straight_[f]) return st::highway::vehicleTtc(dc, c.body[e], c.shape[e], c.body[f], c.shape[f], horizon);
  const auto pe = path(e), pf = path(f);
  std::size_t i = 0, j = 0;
  double t = 0.0;
  while (true) {
    while (i + 1 < pe.size() && pe[i + 1].t0 <= t) ++i;
    while (j + 1 < pf.size() && pf[j + 1].t0 <= t) ++j;
    double end = horizon;
    if (i + 1 < pe.size()) end = std::min(end, pe[i + 1].t0);
    if (j + 1 < pf.size()) end = std::min(end, pf[j + 1].t0);
    // a straight path at its start is the body itself
    const Body a = straight_[e] && t == 0.0 ? c.body[e] : bodyAt(pe.subspan(i), c.body[e], dc.motion, t);
    const Body b = straight_[f] && t == 0.0 ? c.body[f] : bodyAt(pf.subspan(j), c.body[f], dc.motion, t);
    // the cached shapes while a body keeps its heading (they depend on it)
    const CarShape sa = a.axis == c.body[e].axis ? c.shape[e] : carShape(dc, a);
    const CarShape sb = b.axis == c.body[f].axis ? c.shape[f] : carShape(dc, b);
    Ttc r = st::highway::vehicleTtc(dc, a, sa, b, sb, end - t);
    if (r.found()) {
      r.impact = delayed(r.impact, t);
      return r;
    }
    if (!(end < horizon)) return {};
    t = end;
  }
}

Impact LanePrediction::boxTtcAlong(int e, int f, double horizon, Body& atE, Body& atF) const {
  const VehicleTable& c = *cars_;
  constexpr MotionModel kMotion = MotionModel::ConstantVelocity;
  const auto pe = path(e), pf = path(f);
  std::size_t i = 0, j = 0;
  double t = 0.0;
  while (true) {
    while (i + 1 < pe.size() && pe[i + 1].t0 <= t) ++i;
    while (j + 1 < pf.size() && pf[j + 1].t0 <= t) ++j;
    double end = horizon;
    if (i + 1 < pe.size()) end = std::min(end, pe[i + 1].t0);
    if (j + 1 < pf.size()) end = std::min(end, pf[j + 1].t0);
    // a straight path at its start is the body itself
    const Body a = straight_[e] && t == 0.0 ? c.body[e] : bodyAt(pe.subspan(i), c.body[e], kMotion, t);
    const Body b = straight_[f] && t == 0.0 ? c.body[f] : bodyAt(pf.subspan(j), c.body[f], kMotion, t);
    const Impact hit = boxTtc(a, b, kMotion, end - t);
    if (hit.acts()) {
      const double r = hit.actTime();
      atE = a;
      atF = b;
      atE.position += r * a.velocity;
      atF.position += r * b.velocity;
      return delayed(hit, t);
    }
    if (!(end < horizon)) return {};
    t = end;
  }
}

double LanePrediction::beyondLine(int slot, int side, bool shape) const {
  const LaneFrame& f = frame_[slot];
  return (side == 1 ? f.d : -f.d) + (shape ? f.halfShape : f.halfBody) - halfWidth(f.lane);
}

bool LanePrediction::alongside(int slot) const {
  const LaneFrame& f = frame_[slot];
  const double half = 0.5 * cars_->body[slot].length;
  return f.lane >= 0 && f.s >= half && f.s <= lanes_[f.lane].length - half;
}

void LanePrediction::update(double t) {
  VehicleTable& c = *cars_;
  const std::size_t n = c.body.size();
  if (frame_.size() < n) {
    frame_.resize(n);
    prevD_.resize(n);
    prevT_.resize(n);
    prevLane_.resize(n, -1);
    prevAlong_.resize(n, 0);
    prevPos_.resize(n, Vec2::Zero());
    horizon_.resize(n);
    pieceBegin_.resize(n);
    pieceEnd_.resize(n);
    straight_.resize(n);
    merge_.resize(n);
    prevBent_.resize(n);
    deviation_.resize(n);
    matched_.resize(n, -1);
  }
  for (int s : c.arrived) frame_[s] = LaneFrame{};
  // the longest safe time any pair can ask of a car: tr + k (|v_e| + |v_f|) at the largest k and
  // speed this tick (a closing speed is at most the relative speed)
  double ratioMax = 0.0, vMax = 0.0;
  for (int s : c.active) {
    ratioMax = std::max(ratioMax, c.brakeRatio[s]);
    vMax = std::max(vMax, c.vel[s].norm());
  }
  const double tr = std::max(cfg_->safeTime.vehicleReactionTime, cfg_->safeTime.roadReactionTime);
  pieces_.clear();
  for (int s : c.active) {
    horizon_[s] = SafeTimeConfig::safeTimeBound(tr, ratioMax, c.vel[s].norm() + vMax) * (1.0 + 1e-9) + 1e-9;
    predict(s, t);
  }
}

double QuietLine::angleBound(const Vec2& unit) const {
  const double along = dir_.dot(unit);
  return along > 0.0 ? std::abs(cross2(dir_, unit)) / along : std::numeric_limits<double>::infinity();
}

void QuietLine::add(const Vec2& e, double dS, const Vec2& laneDir, double scale, double gap) {
  if (!open_) return;
  arc_ += dS;
  const double len = e.norm();
  angle_ = std::max({angle_, angleBound(laneDir), len > 0.0 ? angleBound(e / len) : std::numeric_limits<double>::infinity()});
  const double r = dS > 0.0 ? len / dS : std::numeric_limits<double>::infinity();
  rMin_ = std::min(rMin_, r);
  rMax_ = std::max(rMax_, r);
  sMin_ = std::min(sMin_, scale);
  gaps_ += gap;
  const double a = 2.0 * angle_, reach = half_ * rMax_;
  const double offset = gaps_ * (1.0 + rMax_ / sMin_) + reach * a + 0.25 * reach * a * a + 0.5 * half_ * (rMax_ - rMin_);
  if (offset <= 0.5 * tol::kChordOffset && a <= 0.5 * tol::kMergeBend)
    end_ = arc_;
  else
    open_ = false;
}

// A car's path this tick: its lane and motion in the lane's frame (matchMotion), its frame and
// last-tick state kept (setFrame); then the straight line, or along the lanes: the centre line
// ahead (traceLine), the pieces laid on it (layPieces), the envelopes grown by how far the path
// departs from the straight line (growEnvelopes). The stages are defined inline below: called
// once per car and tick, their calls cost 0.8 % of bench/highway_detect's instructions (cachegrind).
void LanePrediction::predict(int slot, double t) {
  const Body& b = cars_->body[slot];
  const double h = horizon_[slot];
  const LaneMotion m = matchMotion(slot, t);
  pieceBegin_[slot] = static_cast<int>(pieces_.size());
  const double acc = motionAcceleration(b, cfg_->detector.motion);
  constexpr double kMinPathSpeed = 0.1;  // m/s: slower cars are predicted where they are (straight)
  setFrame(slot, t, m);
  merge_[slot] = 0;
  deviation_[slot] = 0.0;
  if (!alongLanes_ || m.lane < 0 || m.u < kMinPathSpeed) {
    predictStraight(slot, m.lane);
    return;
  }
  ++counters_->roadPredicted;
  straight_[slot] = 0;
  const NetLane& l = lanes_[m.lane];
  // where its route holds this lane's edge, the path follows the route
  int routeAt = -1;
  for (int k = 0; k < kRouteAhead && routeAt < 0; ++k)
    if (cars_->route[slot][k] == l.exitEdge) routeAt = k;
  if (routeAt >= 0) ++counters_->routePredicted;
  // a body in a junction (on a junction lane, or half on the lane it leaves) has an offset that
  // moves with the lanes' geometry (SUMO places it on the chord between its front and its rear),
  // not with the car: no lateral motion is predicted, and on the lanes after this one it is
  // predicted on their centre lines
  PathPlan plan;
  plan.lane = m.lane;
  plan.pr = m.pr;
  plan.routeAt = routeAt;
  plan.u = m.u;
  plan.acc = acc;
  plan.horizon = h;
  plan.straddles = l.internal || !alongside(slot);
  plan.lateral = plan.straddles ? 0.0 : m.lateral;
  plan.bent = m.bent;
  // the path: from the centre's foot on the centre line along the lanes, far enough for the horizon
  const Vec2 n0 = leftNormal(m.pr.dir);
  plan.line.foot = pt_[l.first + m.pr.seg] + (m.pr.s - cum_[l.first + m.pr.seg]) * m.pr.dir;
  // zero up to rounding: the path starts at the centre (and leaves the chord's offset behind)
  plan.off = b.position - plan.line.foot - (m.pr.d + m.chord) * n0;
  plan.need = driven(m.u, acc, h) + 1.0;
  plan.line.half = 0.5 * b.length;
  plan.line.quietEnd = traceLine(slot, plan.lane, plan.pr, routeAt, plan.line.foot, plan.need + plan.line.half);
  plan.line.backLine = plan.line.foot + m.chord * n0 - plan.line.half * b.axis;
  const PathBound bound = layPieces(slot, b, plan, frame_[slot]);
  pieceEnd_[slot] = static_cast<int>(pieces_.size());
  growEnvelopes(slot, bound, m.u, acc, h);
}

inline LanePrediction::LaneMotion LanePrediction::matchMotion(int slot, double t) {
  const VehicleTable& c = *cars_;
  const Body& b = c.body[slot];
  const bool wasHere = frame_[slot].lane >= 0;
  LaneMotion m;
  Projection& pr = m.pr;
  const int lane = match(slot, b.position, b.axis, pr);
  m.lane = lane;
  matched_[slot] = lane;
  // the car's own offset: less the chord's (a body whose front and rear follow the centre line
  // across a vertex sits inside the bend: a 12 m truck on a 14 degree joint 0.7 m off the line)
  const double chord = lane >= 0 ? chordOffset(lane, pr, 0.5 * b.length) : 0.0;
  m.chord = chord;
  pr.d -= chord;
  m.u = lane >= 0 ? b.velocity.dot(pr.dir) : 0.0;
  // the lateral speed, from the offset tick to tick while the car drives along one edge: in the
  // lane's own frame, or (a lane change whose centre crossed the marker) with the last position
  // moved into this lane's frame, the smaller of the two, so a lane change SUMO makes in one step
  // (a jump) is no lateral motion and a centre drifting across the marker is what it moved.
  // Out of a junction (the last offset moved with the lanes' geometry: a body straddling a
  // junction sits on the chord from its front to its rear) or onto another edge (the offset was
  // measured against another road's line): what its heading carries across the lane, as a
  // source's lateral speed there is no better (an FCD replay's backward difference turns SUMO's
  // one-step lane change into tens of m/s where SUMO reports none). At first sight: the source's.
  // At a merge (an edge with a lane that drops) a body out of a junction is headed by the bend it
  // left, not by its motion: SUMO heads it from its rear, still on the junction lane, to its front,
  // 30 to 40 degrees off the lane at a ramp's nose (more after a lane change there); its offset
  // then sits off the line by that chord. So it has no lateral motion there, nor at the tick after
  // (its last offset was the chord's), and its body is predicted square to the lane.
  double& lateral = m.lateral;
  lateral = lane >= 0 ? b.velocity.dot(leftNormal(pr.dir)) : 0.0;
  const bool before = lane >= 0 && wasHere && c.slots[slot].present && t > prevT_[slot] && prevLane_[slot] >= 0;
  const bool mergeEdge = lane >= 0 && lanes_[lane].merge;
  if (before && !(prevAlong_[slot] && lanes_[lane].edge == lanes_[prevLane_[slot]].edge)) {
    m.bent = mergeEdge;
    lateral = m.bent ? 0.0 : b.velocity.dot(b.axis) * b.axis.dot(leftNormal(pr.dir));
  } else if (before && mergeEdge && prevBent_[slot]) {
    lateral = 0.0;
  } else if (before) {
    const double dt = t - prevT_[slot];
    lateral = (pr.d - prevD_[slot]) / dt;
    if (lane != prevLane_[slot]) {
      const double common = (pr.d + chord - project(lane, prevPos_[slot], pr.seg).d) / dt;
      if (std::abs(common) < std::abs(lateral)) lateral = common;
    }
  }
  return m;
}

// the car's frame this tick, and what the next tick's matchMotion reads of it
inline void LanePrediction::setFrame(int slot, double t, const LaneMotion& m) {
  const Body& b = cars_->body[slot];
  LaneFrame& f = frame_[slot];
  f = LaneFrame{};
  if (m.lane >= 0) {
    f.lane = m.lane;
    f.seg = m.pr.seg;
    f.s = m.pr.s;
    f.d = m.pr.d;
    f.dir = m.pr.dir;
    f.speed = m.u;
    f.lateral = m.lateral;
    // the half widths beyondLine reads: the body's, and the detector's road shape square to the lane
    Body square = b;
    square.axis = m.pr.dir;
    f.halfBody = 0.5 * b.width;
    f.halfShape = roadSupport(cfg_->detector, square, leftNormal(m.pr.dir));
  }
  prevLane_[slot] = f.lane;
  prevBent_[slot] = m.bent ? 1 : 0;
  prevAlong_[slot] = alongside(slot);
  prevD_[slot] = f.d;
  prevT_[slot] = t;
  prevPos_[slot] = b.position;
}

// the straight line: the body's own motion
inline void LanePrediction::predictStraight(int slot, int lane) {
  const Body& b = cars_->body[slot];
  const Vec2 n = leftNormal(b.axis);
  pieces_.push_back({0.0, b.position, b.axis, n, b.axis, b.velocity.dot(b.axis), b.velocity.dot(n)});
  pieceEnd_[slot] = static_cast<int>(pieces_.size());
  straight_[slot] = 1;
  if (alongLanes_) ++(lane < 0 ? counters_->straightFallbacks : counters_->roadPredicted);
}

// The centre line ahead of the foot (vertices at arcs lineS_, points linePt_), along the lanes
// the path takes from lane (its route from routeAt), until arc `reach` (as far as the body's
// front may reach); returns the arc up to which the line is too straight for onChord to lay a
// body on a chord.
inline double LanePrediction::traceLine(int slot, int lane, const Projection& pr, int routeAt, const Vec2& foot,
                                 double reach) {
  lineS_.assign(1, 0.0);
  linePt_.assign(1, foot);
  QuietLine quiet(pr.dir, 0.5 * cars_->body[slot].length);
  for (int ln = lane, seg = pr.seg, at = routeAt; lineS_.back() < reach;) {
    const NetLane& cl = lanes_[ln];
    const Vec2 dir = lineS_.size() == 1 ? pr.dir : Vec2((pt_[cl.first + seg + 1] - pt_[cl.first + seg]).normalized());
    const Vec2 end = pt_[cl.first + seg + 1];
    const Vec2 e = end - linePt_.back();
    const double dS = std::max(0.0, e.dot(dir)) / cl.scale;
    if (quiet.open())
      quiet.add(e, dS, dir, cl.scale, lineS_.size() > 1 ? (pt_[cl.first + seg] - linePt_.back()).norm() : 0.0);
    lineS_.push_back(lineS_.back() + dS);
    linePt_.push_back(end);
    if (++seg + 1 >= cl.count) {
      ln = successor(slot, ln, at);
      seg = 0;
      if (ln < 0 || lanes_[ln].count < 2) break;
    }
  }
  quiet.finish();
  return quiet.end();
}

// The centre line's point at arc S (traceLine's); behind the foot: the straight line to where
// the back is now, in the centre line's frame.
inline Vec2 LanePrediction::linePoint(const PathLine& line, double S) const {
  if (S <= 0.0) return line.foot + (line.half > 0.0 ? -S / line.half : 0.0) * (line.backLine - line.foot);
  std::size_t k = 1;
  while (k + 1 < lineS_.size() && lineS_[k] < S) ++k;
  if (k >= lineS_.size()) return line.foot;  // no line ahead (a lane of one point)
  const double len = lineS_[k] - lineS_[k - 1];
  return linePt_[k - 1] + (len > 0.0 ? (S - lineS_[k - 1]) / len : 0.0) * (linePt_[k] - linePt_[k - 1]);
}

// the body centred at arc S (its centre line's point q, direction dir) laid on the chord where
// the line bends under it: its centre (in the line's frame) and axis; false: square to the lane
inline bool LanePrediction::onChord(const PathLine& line, double S, const Vec2& q, const Vec2& dir, Vec2& centre,
                             Vec2& axis) const {
  const double half = line.half;
  if (S >= half && S + half <= line.quietEnd) return false;
  const Vec2 ahead = linePoint(line, S + half), behind = linePoint(line, S - half);
  const Vec2 span = ahead - behind, m = 0.5 * (ahead + behind);
  if (!(span.norm() > 0.5 * half) || ((m - q).norm() <= tol::kChordOffset &&
                                   std::abs(std::atan2(cross2(dir, span), dir.dot(span))) <= tol::kMergeBend))
    return false;
  centre = m;
  axis = span.normalized();
  return true;
}

// The pieces of the path along the lanes (pieces_), from the car's centre until its horizon, and
// how far they depart from its straight line; a dropped lane ahead into f (endGap, endLane).
// One loop over the path's segments, each laid in one pass (a bend's chord relayed in place):
// split, its state (the lane, segment, point, arc, time) would cross every call.
inline LanePrediction::PathBound LanePrediction::layPieces(int slot, const Body& b, const PathPlan& p, LaneFrame& f) {
  const double u = p.u, acc = p.acc, h = p.horizon, lateral = p.lateral, half = p.line.half;
  const Projection& pr = p.pr;
  DeviationBound deviation{b.position, b.velocity, u, acc};
  PathBound out;
  // at a merge (atMerge): on a junction lane or an edge with a lane that drops, headed off its
  // lane (SUMO's chord across a vertex or a junction), or (below) entering a junction lane or a
  // bend within TTC*
  const double maxTtc = cfg_->conflict.maxTtc;
  out.merge = lanes_[p.lane].internal || lanes_[p.lane].merge || turnedFrom(pr.dir, b.axis);
  int ln = p.lane, seg = pr.seg, routeAt = p.routeAt;
  Vec2 q = p.line.foot;  // the path's point at arc S from the car
  double S = 0.0;  // arc from the car, in the source's lengths (Lane::length: times at the speed it gives)
  double tk = 0.0;
  while (true) {
    const NetLane& cl = lanes_[ln];
    const Vec2 dir = seg == pr.seg && ln == p.lane ? pr.dir : Vec2((pt_[cl.first + seg + 1] - pt_[cl.first + seg]).normalized());
    const Vec2 nk = leftNormal(dir);
    const double uk = std::max(0.0, u + acc * tk);
    const bool first = pieces_.size() == static_cast<std::size_t>(pieceBegin_[slot]);
    const double dk = p.straddles && ln != p.lane ? 0.0 : f.d + lateral * tk;
    Vec2 pk = first ? b.position : Vec2(p.off + q + dk * nk);
    // the body as it is now, then square to its lane from the next vertex on: it follows the lane
    // (a yaw against the lane's segment is mostly SUMO's front-to-rear chord across a joint) ...
    Vec2 axis = first && !p.bent ? b.axis : dir;
    // ... or, where the lane bends under it, on SUMO's chord from its back to its front (turned
    // about its centre, a 10 m truck's back would swing 1.5 m into the next lane on a 5.6 m corner)
    const bool chorded = !first && onChord(p.line, S, q, dir, pk, axis);
    if (chorded) pk += p.off + dk * nk;
    out.turns = out.turns || axis != b.axis;
    pieces_.push_back({tk, pk, dir, nk, axis, uk, lateral, cl.scale});
    out.maxScale = std::max(out.maxScale, cl.scale);
    deviation.add(pk, tk, cl.scale);
    // this piece ends at the segment's end, if the path goes on
    // (along it: a centre just past a lane's end, on its extension, has no segment left)
    const double segEnd = S + std::max(0.0, (pt_[cl.first + seg + 1] - q).dot(dir)) / cl.scale;
    // a body on a bend's chord is laid again every quarter of its length until it is square to
    // the lane (its heading turns as its back and front follow the bend); one square to it, once
    // its front is a quarter length past the segment's end, if the line bends there
    double subEnd = chorded ? S + std::min(0.5 * half, tol::kChordRelay) : segEnd - 0.75 * half;
    Vec2 unusedCentre, unusedAxis;
    if (!chorded && subEnd > S && !onChord(p.line, subEnd, q + ((subEnd - S) * cl.scale) * dir, dir, unusedCentre, unusedAxis))
      subEnd = segEnd;
    if (subEnd > S && subEnd < segEnd) {
      const double tSub = subEnd < p.need ? timeToDrive(u, acc, subEnd) : std::numeric_limits<double>::infinity();
      const double te = std::min(tSub, h);
      deviation.add(pk + ((driven(u, acc, te) - S) * cl.scale) * dir + (lateral * (te - tk)) * nk, te, cl.scale);
      if (!(tSub < h)) break;
      q += ((subEnd - S) * cl.scale) * dir;
      S = subEnd;
      tk = tSub;
      continue;
    }
    const auto [nln, nseg] = nextSegment(slot, ln, seg, routeAt, segEnd, f);
    const double tEnd = nln >= 0 && segEnd < p.need ? timeToDrive(u, acc, segEnd) : std::numeric_limits<double>::infinity();
    if (!(tEnd < h)) {
      // the last piece: its deviation at the horizon
      const double tau = h - tk;
      deviation.add(pk + ((driven(u, acc, h) - S) * cl.scale) * dir + (lateral * tau) * nk, h, cl.scale);
      break;
    }
    deviation.add(pk + ((driven(u, acc, tEnd) - S) * cl.scale) * dir + (lateral * (tEnd - tk)) * nk, tEnd, cl.scale);
    ln = nln;
    seg = nseg;
    // a junction lane, or a bend, within TTC*
    const Vec2 next = (pt_[lanes_[ln].first + seg + 1] - pt_[lanes_[ln].first + seg]).normalized();
    out.merge = out.merge || (tEnd <= maxTtc && (lanes_[ln].internal || turnedFrom(pr.dir, next)));
    q = pt_[lanes_[ln].first + seg];
    S = segEnd;
    tk = tEnd;
  }
  out.dev = deviation.dev;
  return out;
}

// The segment after seg of lane ln (the lane's successor's first at its end; -1: the path ends
// there, a dropped lane's end kept in f as endGap at arc segEnd).
inline std::pair<int, int> LanePrediction::nextSegment(int slot, int ln, int seg, int& routeAt, double segEnd,
                                                LaneFrame& f) const {
  const NetLane& cl = lanes_[ln];
  int nln = ln, nseg = seg + 1;
  if (nseg + 1 >= cl.count) {
    nln = successor(slot, ln, routeAt);
    nseg = 0;
    if (nln < 0 || lanes_[nln].count < 2) {
      if (cl.drops && f.endLane < 0) {
        f.endGap = segEnd;
        f.endLane = ln;
      }
      nln = -1;
    }
  }
  return {nln, nseg};
}

// The envelopes grown by the path's deviation, its merge flag.
inline void LanePrediction::growEnvelopes(int slot, const PathBound& bound, double u, double acc, double h) {
  VehicleTable& c = *cars_;
  // |driven - u t| grows with t: within a piece of scale s the path's own acceleration part
  // exceeds the prunes' allowance by (s - 1) |driven - u t| at most, largest at the horizon
  const double dev = bound.dev + (bound.maxScale - 1.0) * std::abs(driven(u, acc, h) - u * h);
  // the straight prunes hold with the envelopes grown by the deviation (and a rounding margin)
  const double grow = dev * (1.0 + 1e-9) + tol::kPruneSlop;
  // a body that turns on its path has other world extents: every shape lies within its envelope
  // radius of the centre, whatever the heading
  const Vec2 own = bound.turns ? Vec2(c.ownExt[slot].cwiseMax(Vec2::Constant(c.ownEnv[slot]))) : c.ownExt[slot];
  c.ext[slot] = own + Vec2::Constant(grow);
  c.env[slot] = c.ownEnv[slot] + grow;
  c.pairState[slot].ext = c.ext[slot];
  c.pairState[slot].env = c.env[slot];
  deviation_[slot] = grow;
  merge_[slot] = bound.merge && h >= cfg_->conflict.maxTtc ? 1 : 0;
}

}  // namespace st::highway::detail
