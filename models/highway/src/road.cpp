#include <sthighway/road.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <unordered_set>

#include <sthighway/tolerances.hpp>

namespace st::highway {

const char* toString(FeatureKind k) {
  switch (k) {
    case FeatureKind::Curb: return "curb";
    case FeatureKind::LaneMarker: return "lane_marker";
    case FeatureKind::Hazard: return "hazard";
  }
  return "curb";
}

std::vector<Vec2> offsetPolyline(const std::vector<Vec2>& line, double offset) {
  // drop repeated points: a zero-length segment has no normal
  std::vector<Vec2> p;
  p.reserve(line.size());
  for (const Vec2& q : line)
    if (p.empty() || (q - p.back()).norm() > tol::kMinSegmentLength) p.push_back(q);
  if (p.size() < 2) return {};
  std::vector<Vec2> out(p.size());
  auto normalOf = [&](std::size_t i) { return leftNormal(p[i + 1] - p[i]); };
  out.front() = p.front() + offset * normalOf(0);
  out.back() = p.back() + offset * normalOf(p.size() - 2);
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    // mitre: along the bisector of the two normals, long enough to keep both offsets exact
    const Vec2 n1 = normalOf(i - 1), n2 = normalOf(i);
    Vec2 m = n1 + n2;
    const double mn = m.norm();
    if (mn < 1e-12) {  // a U-turn in the shape: no mitre exists, keep the first normal
      out[i] = p[i] + offset * n1;
      continue;
    }
    m /= mn;
    const double cosHalf = std::max(m.dot(n1), 1.0 / tol::kMaxMiterRatio);
    out[i] = p[i] + (offset / cosHalf) * m;
  }
  return out;
}

namespace {

void addPolyline(RoadFeatures& rf, FeatureKind kind, const std::vector<Vec2>& pts, int section,
                 const std::string& name) {
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    RoadFeature f;
    f.kind = kind;
    f.segment = Segment{pts[i], pts[i + 1]};
    f.section = section;
    f.name = name;
    rf.features.push_back(std::move(f));
  }
}

void grow(Aabb<2>& b, bool& first, const Vec2& p, double r) {
  const Vec2 lo = p.array() - r, hi = p.array() + r;
  if (first) {
    b = {lo, hi};
    first = false;
  } else {
    b.min = b.min.cwiseMin(lo);
    b.max = b.max.cwiseMax(hi);
  }
}

}  // namespace

std::vector<std::string> edgeIds(const RoadGeometry& road) {
  std::vector<std::string> ids;
  std::unordered_set<std::string> seen;
  for (const Lane& l : road.lanes)
    if (seen.insert(l.edge).second) ids.push_back(l.edge);
  return ids;
}

RoadFeatures deriveFeatures(const RoadGeometry& road) {
  RoadFeatures rf;
  bool first = true;
  // group the lanes of each edge, ordered by index, edges in order of first appearance
  std::map<std::string, int> sectionOf;
  std::vector<std::vector<const Lane*>> lanesOf;
  for (const Lane& l : road.lanes) {
    if (l.shape.size() < 2) throw std::invalid_argument("lane '" + l.id + "': shape needs at least two points");
    if (!(l.width > 0.0) || !std::isfinite(l.width))
      throw std::invalid_argument("lane '" + l.id + "': width must be positive");
    for (const Vec2& p : l.shape) {
      if (!p.allFinite()) throw std::invalid_argument("lane '" + l.id + "': non-finite shape point");
      grow(rf.bounds, first, p, 0.5 * l.width);
    }
    if (l.internal) continue;
    auto [it, inserted] = sectionOf.emplace(l.edge, static_cast<int>(rf.sections.size()));
    if (inserted) {
      rf.sections.push_back(l.edge);
      lanesOf.emplace_back();
    }
    lanesOf[it->second].push_back(&l);
  }
  for (std::size_t s = 0; s < lanesOf.size(); ++s) {
    auto& lanes = lanesOf[s];
    std::sort(lanes.begin(), lanes.end(), [](const Lane* a, const Lane* b) { return a->index < b->index; });
    const int sec = static_cast<int>(s);
    const Lane& right = *lanes.front();
    const Lane& left = *lanes.back();
    addPolyline(rf, FeatureKind::Curb, offsetPolyline(right.shape, -0.5 * right.width), sec, right.edge + ":right");
    for (std::size_t k = 0; k + 1 < lanes.size(); ++k)
      addPolyline(rf, FeatureKind::LaneMarker, offsetPolyline(lanes[k]->shape, 0.5 * lanes[k]->width), sec,
                  lanes[k]->id + "|" + lanes[k + 1]->id);
    addPolyline(rf, FeatureKind::Curb, offsetPolyline(left.shape, 0.5 * left.width), sec, left.edge + ":left");
  }
  for (const Hazard& h : road.hazards) {
    if (!h.position.allFinite() || !(h.radius > 0.0))
      throw std::invalid_argument("hazard '" + h.id + "': needs a finite position and a positive radius");
    RoadFeature f;
    f.kind = FeatureKind::Hazard;
    f.segment = Segment{h.position, h.position};
    f.radius = h.radius;
    f.name = h.id;
    rf.features.push_back(std::move(f));
    grow(rf.bounds, first, h.position, h.radius);
  }
  return rf;
}

}  // namespace st::highway
