#include "road_search.hpp"

#include <algorithm>
#include <map>

#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

namespace {

WarningKind kindOf(FeatureKind k) {
  switch (k) {
    case FeatureKind::Curb: return WarningKind::Curb;
    case FeatureKind::LaneMarker: return WarningKind::LaneMarker;
    case FeatureKind::Hazard: return WarningKind::Hazard;
  }
  return WarningKind::Curb;
}

// Exact prune of a segment feature: to touch the segment the shape must first reach its line,
// which it approaches at most at the normal speed, within at most the largest road safe time hMax
// (the ego's at its full speed); `support` is how far the shape reaches along the normal.
// Monotone in the support. Returns an int, 1 if the feature may be reached.
int lineReachable(const RoadSearch::FeatureLine& l, const Body& a, double support, double hMax, double accel) {
  const double s = l.n.dot(a.position - l.a);
  const Vec2 toward = s > 0.0 ? Vec2(-l.n) : l.n;
  const double approach = std::max(0.0, a.velocity.dot(toward));
  return static_cast<int>(std::abs(s) <= support + approach * hMax + 0.5 * accel * hMax * hMax + tol::kPruneSlop);
}

}  // namespace

void RoadSearch::RoadList::build(std::span<const int> features, const std::vector<FeatureLine>& featureLine,
                                 std::vector<std::pair<Vec2, Line>>& scratch) {
  if (std::equal(features.begin(), features.end(), source.begin(), source.end())) return;
  source.assign(features.begin(), features.end());
  groups.clear();
  lines.clear();
  always.clear();
  scratch.clear();
  for (int fi : features) {
    const FeatureLine& l = featureLine[fi];
    if (!l.line) {
      always.push_back(fi);
      continue;
    }
    const bool flip = l.n.x() < 0.0 || (l.n.x() == 0.0 && l.n.y() < 0.0);
    const Vec2 n = flip ? Vec2(-l.n) : l.n;
    const Vec2 u(n.y(), -n.x());
    const double ua = u.dot(l.a), ub = u.dot(l.b);
    scratch.push_back({n, {n.dot(l.a), std::min(ua, ub), std::max(ua, ub), fi}});
  }
  std::sort(scratch.begin(), scratch.end(), [](const auto& a, const auto& b) {
    if (a.first.x() != b.first.x()) return a.first.x() < b.first.x();
    if (a.first.y() != b.first.y()) return a.first.y() < b.first.y();
    return a.second.feature < b.second.feature;
  });
  for (const auto& [n, line] : scratch) {
    if (groups.empty() || groups.back().n != n) groups.push_back({n, static_cast<int>(lines.size()), 0});
    lines.push_back(line);
    groups.back().end = static_cast<int>(lines.size());
  }
}

RoadSearch::RoadSearch(const RoadGeometry& road, const MonitorConfig& config, const VehicleTable& cars,
                       const LanePrediction& prediction, MonitorCounters& counters)
    : cfg_(&config), cars_(&cars), counters_(&counters), features_(deriveFeatures(road)), prediction_(&prediction) {
  std::map<std::string, int> groups;
  for (const RoadFeature& f : features_.features) {
    auto [it, inserted] = groups.emplace(std::string(toString(f.kind)) + "/" + f.name, static_cast<int>(groupName_.size()));
    if (inserted) {
      groupName_.push_back(f.name);
      groupFeatures_.emplace_back();
    }
    groupFeatures_[it->second].push_back(static_cast<int>(groupOf_.size()));
    groupOf_.push_back(it->second);
  }
  // each lane's lines: the curb or marker on either side, as deriveFeatures names them
  std::map<std::string, std::vector<int>> lanesOfEdge;
  for (int i = 0; i < static_cast<int>(road.lanes.size()); ++i)
    if (!road.lanes[i].internal) lanesOfEdge[road.lanes[i].edge].push_back(i);
  laneLines_.assign(road.lanes.size(), {-1, -1});
  auto groupNamed = [&](FeatureKind k, const std::string& name) {
    auto it = groups.find(std::string(toString(k)) + "/" + name);
    return it == groups.end() ? -1 : it->second;
  };
  for (auto& [edge, ids] : lanesOfEdge) {
    std::sort(ids.begin(), ids.end(), [&](int a, int b) { return road.lanes[a].index < road.lanes[b].index; });
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const Lane& l = road.lanes[ids[k]];
      laneLines_[ids[k]][0] = k == 0 ? groupNamed(FeatureKind::Curb, edge + ":right")
                                     : groupNamed(FeatureKind::LaneMarker, road.lanes[ids[k - 1]].id + "|" + l.id);
      laneLines_[ids[k]][1] = k + 1 == ids.size() ? groupNamed(FeatureKind::Curb, edge + ":left")
                                                  : groupNamed(FeatureKind::LaneMarker, l.id + "|" + road.lanes[ids[k + 1]].id);
    }
  }
  for (int i = 0; i < static_cast<int>(features_.features.size()); ++i)
    if (features_.features[i].kind == FeatureKind::Hazard) hazards_.push_back(i);
  for (const RoadFeature& f : features_.features) {
    const Vec2 dir = f.segment.b - f.segment.a;
    const double len = dir.norm();
    const bool line = f.kind != FeatureKind::Hazard && len > 0.0;
    featureLine_.push_back(
        {f.segment.a, f.segment.b, line ? Vec2(-dir.y() / len, dir.x() / len) : Vec2(0.0, 0.0), line ? 1 : 0});
  }
  std::vector<int> every(featureLine_.size());
  for (int i = 0; i < static_cast<int>(every.size()); ++i) every[i] = i;
  allRoad_.build(every, featureLine_, roadScratch_);
  if (!features_.features.empty()) {
    const Aabb<2> b{features_.bounds.min.array() - 10.0, features_.bounds.max.array() + 10.0};
    const double cell = std::max(25.0, b.extent().maxCoeff() / 2048.0);
    featureIndex_.emplace(SpaceKind::Cells, b, SpaceRule{8, false, 0, 1, cell});
    for (int i = 0; i < static_cast<int>(features_.features.size()); ++i) {
      const RoadFeature& f = features_.features[i];
      const Vec2 lo = f.segment.a.cwiseMin(f.segment.b).array() - f.radius;
      const Vec2 hi = f.segment.a.cwiseMax(f.segment.b).array() + f.radius;
      featureIndex_->insert(i, {lo, hi});
    }
  }
}

// Per group with equipped cars: the features any of its cars could reach within its largest road
// safe time, and of those a line only if some car could reach it at its fastest normal speed (a
// corner of the velocity box), from the nearest of its centres (a corner of the box, or on it):
// the per-ego prune with every term at the group's bound.
void RoadSearch::prepare(std::span<const CarGroup> groups) {
  if (!featureIndex_) return;
  const bool accel = cfg_->detector.motion == MotionModel::ConstantAcceleration;
  roadNear_.resize(groups.size());
  featureVisits_.resize(groups.size());
  for (std::size_t A = 0; A < groups.size(); ++A) {
    const CarGroup& ca = groups[A];
    if (ca.equipped == 0) continue;
    roadFound_.clear();
    const Vec2 va = ca.vmin.cwiseAbs().cwiseMax(ca.vmax.cwiseAbs());
    const double speed = va.norm();
    const double h = SafeTimeConfig::safeTimeBound(cfg_->safeTime.roadReactionTime, ca.ratioMax, speed);
    // a car braking to its stop line keeps its lateral speed while the speed along it falls: its
    // motion turns, under either motion model
    const double am = accel || ca.stopping ? ca.amax : 0.0;
    const double rr = ca.envMax + speed * h + 0.5 * am * h * h + 2 * tol::kPruneSlop;
    const Aabb<2> rb{ca.centres.min.array() - rr, ca.centres.max.array() + rr};
    const double ah = 0.5 * am * h * h + 2 * tol::kPruneSlop;
    for (int fi : cachedVisit(*featureIndex_, rb, featureVisits_[A])) {
      const FeatureLine& l = featureLine_[fi];
      if (l.line) {
        const double s0 = l.n.dot(ca.centres.min - l.a), s1 = l.n.dot(Vec2(ca.centres.max.x(), ca.centres.min.y()) - l.a),
                     s2 = l.n.dot(Vec2(ca.centres.min.x(), ca.centres.max.y()) - l.a), s3 = l.n.dot(ca.centres.max - l.a);
        const double sMin = std::min({s0, s1, s2, s3}), sMax = std::max({s0, s1, s2, s3});
        const double nearest = sMin > 0.0 ? sMin : sMax < 0.0 ? -sMax : 0.0;
        const double approach = std::max({std::abs(l.n.dot(ca.vmin)), std::abs(l.n.dot(ca.vmax)),
                                          std::abs(l.n.dot(Vec2(ca.vmin.x(), ca.vmax.y()))),
                                          std::abs(l.n.dot(Vec2(ca.vmax.x(), ca.vmin.y())))});
        if (nearest > ca.envMax + approach * h + ah) continue;
      }
      roadFound_.push_back(fi);
    }
    roadNear_[A].build(roadFound_, featureLine_, roadScratch_);
  }
}

void RoadSearch::threatsOf(int e, int group, std::vector<Threat>& out) {
  if (!featureIndex_) return;
  if (!prediction_->straight(e)) {
    laneThreats(e, out);
    return;
  }
  const VehicleTable& t = *cars_;
  // a bound on the ego's road safe times (the one at its full speed, grown by the relative slop
  // over the rounding), from the cached brake ratio without roadSafeTime's division: it only
  // prunes, and a larger one prunes less
  const double hMax =
      SafeTimeConfig::safeTimeBound(cfg_->safeTime.roadReactionTime, t.brakeRatio[e], t.vel[e].norm()) * (1.0 + tol::kBoundRelativeSlop);
  const RoadList& list = group < 0 ? allRoad_ : roadNear_[group];
  counters_->featureChecks += list.size();
  // first every line against a bound on the shape's support towards it (no wider than the
  // envelope, and most lines are further off than that), without branches and without a call:
  // lineReachable with the line's offset from the ego as n . centre - n . a (rounded otherwise,
  // by far less than the prune's slop); checkFeature then prunes with the support itself. The
  // few lines within that reach are pruned again with a tighter horizon: while the ego's centre
  // projects inside the segment, the closest point is the foot of the normal, so the road safe
  // time's closing speed is exactly the approach speed towards the line (tr + k approach, a
  // fraction of hMax for a car keeping its lane); near or beyond an end it may be the full speed
  // (hMax)
  const Body& a = t.body[e];
  const double accel =
      cfg_->detector.motion == MotionModel::ConstantAcceleration || a.stopAcceleration < 0.0 ? t.accelAbs[e] : 0.0;
  const SupportBound& sb = t.shape[e].road;
  const Vec2 normal(-a.axis.y(), a.axis.x());
  if (featureNear_.size() < list.size()) featureNear_.resize(list.size());
  const double tr = cfg_->safeTime.roadReactionTime, brake = t.brakeRatio[e];
  const double grow = 0.5 * accel * hMax * hMax + tol::kPruneSlop;
  int near = 0;
  for (const RoadList::Group& g : list.groups) {
    const double support = (sb.base + sb.along * std::abs(a.axis.dot(g.n)) + sb.across * std::abs(normal.dot(g.n))) *
                           (1.0 + tol::kBoundRelativeSlop);
    const double along = g.n.dot(a.position), speed = g.n.dot(a.velocity);
    for (int j = g.begin; j < g.end; ++j) {
      const RoadList::Line& l = list.lines[j];
      const double offset = along - l.c;
      const double approach = std::max(0.0, offset > 0.0 ? -speed : speed);
      if (!(std::abs(offset) <= support + approach * hMax + grow)) continue;  // most lines
      const double tangent = g.n.y() * a.position.x() - g.n.x() * a.position.y();  // (n.y, -n.x) . centre
      if (tangent > l.lo + tol::kPruneSlop && tangent < l.hi - tol::kPruneSlop) {
        const double h = SafeTimeConfig::safeTimeBound(tr, brake, approach) * (1.0 + tol::kBoundRelativeSlop);
        if (!(std::abs(offset) <= support + approach * h + 0.5 * accel * h * h + tol::kPruneSlop)) continue;
      }
      featureNear_[near++] = l.feature;
    }
  }
  for (int fi : list.always) featureNear_[near++] = fi;
  for (int k = 0; k < near; ++k) checkFeature(e, featureNear_[k], hMax, out);
}

// hMax: at least the ego's largest road safe time (the one at its full speed)
void RoadSearch::checkFeature(int e, int fi, double hMax, std::vector<Threat>& out) const {
  const VehicleTable& t = *cars_;
  const RoadFeature& f = features_.features[fi];
  const Body& a = t.body[e];
  const double accel =
      cfg_->detector.motion == MotionModel::ConstantAcceleration || a.stopAcceleration < 0.0 ? t.accelAbs[e] : 0.0;
  if (featureLine_[fi].line) {
    const double s = featureLine_[fi].n.dot(a.position - f.segment.a);
    const Vec2 toward = s > 0.0 ? Vec2(-featureLine_[fi].n) : featureLine_[fi].n;
    if (!lineReachable(featureLine_[fi], a, roadSupport(cfg_->detector, a, toward), hMax, accel)) return;
  }
  const Vec2 closest = f.kind == FeatureKind::Hazard ? f.segment.a : closestPointOnSegment(f.segment, a.position);
  const Vec2 d = closest - a.position;
  const double dist = d.norm();
  const double closing = dist > 0.0 ? a.velocity.dot(d) / dist : a.velocity.norm();
  const double safe = cfg_->safeTime.roadSafeTime(t.mass[e], closing, t.vclass[e]);
  if (dist > t.env[e] + f.radius + a.velocity.norm() * safe + 0.5 * accel * safe * safe + tol::kPruneSlop) return;
  const Ttc ttc = featureTtc(cfg_->detector, a, f, safe);
  if (!ttc.found() || ttc.t() > safe) return;
  if (f.kind == FeatureKind::LaneMarker) {
    // crossing with the matching turn signal on is a lane change, not a warning
    double side = cross(a.axis, d);
    if (std::abs(side) < 1e-9) side = cross(a.axis, a.velocity);
    const std::uint8_t need = side > 0.0 ? kSignalLeft : kSignalRight;
    if (t.signals[e] & need) return;
  }
  const int g = groupOf_[fi];
  out.push_back({kFeatureBit | static_cast<std::uint64_t>(g), kindOf(f.kind), ttc.zone, ttc.t(), safe, g, fi});
}

// The feature of a group closest to p (for the conflict record's line direction).
int RoadSearch::nearestFeature(int group, const Vec2& p) const {
  int best = -1;
  double bestD = std::numeric_limits<double>::infinity();
  for (int fi : groupFeatures_[group]) {
    const double d = (closestPointOnSegment(features_.features[fi].segment, p) - p).squaredNorm();
    if (d < bestD) {
      bestD = d;
      best = fi;
    }
  }
  return best;
}

// A car on a lane: time to line crossing in the lane frame (ISO 17361's lane departure warning):
// the lateral distance from the shape that checks road features (inner circle, centre circle or
// rectangle) to the lane's line on the side it moves towards, over its lateral speed; the road
// safe time at that lateral speed. A curve the car follows is no departure. At a lane end with no
// successor (a lane drop), the time until the shape's front reaches the end, against the curb of
// that side. Hazards along the predicted path, piece by piece.
void RoadSearch::laneThreats(int e, std::vector<Threat>& out) const {
  const VehicleTable& t = *cars_;
  const LaneFrame& f = prediction_->frame(e);
  const DetectorConfig& dc = cfg_->detector;
  const Zone zone = dc.kind == DetectorKind::Concentric ? Zone::Inner : dc.kind == DetectorKind::FiveCircle ? Zone::Center : Zone::Body;
  const double tr = cfg_->safeTime.roadReactionTime;
  const double twiceBrake = t.pairState[e].twiceBrakeForce;
  auto add = [&](int g, double ttc, double closing) {
    const double safe = SafeTimeConfig::safeTimeOf(tr, t.mass[e], closing, twiceBrake);
    if (!(ttc <= safe)) return;
    const int fi = nearestFeature(g, t.body[e].position);
    out.push_back({kFeatureBit | static_cast<std::uint64_t>(g), kindOf(features_.features[fi].kind), zone, ttc, safe, g, fi});
  };
  for (int side = 0; side < 2 && prediction_->alongside(e); ++side) {
    const int g = lineOf(f.lane, side);
    if (g < 0) continue;
    counters_->featureChecks += 1;
    const double closing = side == 1 ? f.lateral : -f.lateral;
    if (!(closing > 0.0)) continue;  // parallel or moving away: touching it is no threat
    if (features_.features[groupFeatures_[g].front()].kind == FeatureKind::LaneMarker &&
        (t.signals[e] & (side == 1 ? kSignalLeft : kSignalRight)))
      continue;  // a signalled lane change
    const double gap = -prediction_->beyondLine(e, side, true);
    add(g, gap <= 0.0 ? 0.0 : gap / closing, closing);
  }
  if (std::isfinite(f.endGap)) {
    // the curb on the side the lane drops from (a lane between others that ends has none)
    auto curb = [&](int side) {
      const int g = lineOf(f.endLane, side);
      return g >= 0 && features_.features[groupFeatures_[g].front()].kind == FeatureKind::Curb ? g : -1;
    };
    const int g = curb(0) >= 0 ? curb(0) : curb(1);
    if (g >= 0 && f.speed > 0.0) {
      counters_->featureChecks += 1;
      const double gap = f.endGap - roadSupport(dc, t.body[e], f.dir) / prediction_->scale(f.endLane);
      const double a = motionAcceleration(t.body[e], dc.motion);
      double ttc = 0.0;
      if (gap > 0.0) {
        const double disc = f.speed * f.speed + 2.0 * a * gap;
        ttc = std::abs(a) <= tol::kAccelerationEpsilon ? gap / f.speed
              : disc < 0.0                             ? std::numeric_limits<double>::infinity()
                                                       : 2.0 * gap / (f.speed + std::sqrt(disc));
      }
      add(g, ttc, f.speed);
    }
  }
  if (hazards_.empty()) return;
  const auto path = prediction_->path(e);
  const Body& now = t.body[e];
  for (int fi : hazards_) {
    const RoadFeature& h = features_.features[fi];
    const Vec2 d = h.segment.a - now.position;
    const double dist = d.norm();
    const double closing = dist > 0.0 ? now.velocity.dot(d) / dist : now.velocity.norm();
    const double safe = cfg_->safeTime.roadSafeTime(t.mass[e], closing, t.vclass[e]);
    // the path stays within env - ownEnv (its deviation) of the straight line
    if (dist > t.env[e] + h.radius + now.velocity.norm() * safe + 0.5 * t.accelAbs[e] * safe * safe + tol::kPruneSlop) continue;
    counters_->featureChecks += 1;
    for (std::size_t i = 0; i < path.size() && path[i].t0 <= safe; ++i) {
      const double end = i + 1 < path.size() ? std::min(safe, path[i + 1].t0) : safe;
      const Body b = LanePrediction::bodyAt(path.subspan(i), now, dc.motion, path[i].t0);
      const Ttc r = featureTtc(dc, b, h, end - path[i].t0);
      if (r.found()) {
        const int g = groupOf_[fi];
        out.push_back({kFeatureBit | static_cast<std::uint64_t>(g), WarningKind::Hazard, r.zone, path[i].t0 + r.t(), safe, g, fi});
        break;
      }
    }
  }
}

}  // namespace st::highway::detail
