#include <sthighway/conflict.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <stcore/box2.hpp>

namespace st::highway {

const char* toString(ConflictType t) {
  switch (t) {
    case ConflictType::RearEnd: return "rear_end";
    case ConflictType::LaneChange: return "lane_change";
    case ConflictType::Crossing: return "crossing";
    case ConflictType::Pedestrian: return "pedestrian";
    case ConflictType::Proximity: return "proximity";
    case ConflictType::Road: return "road";
  }
  return "?";
}

const char* toString(EncounterType e) {
  switch (e) {
    case EncounterType::Unknown: return "unknown";
    case EncounterType::Following: return "following";
    case EncounterType::Merging: return "merging";
    case EncounterType::Diverging: return "diverging";
    case EncounterType::Crossing: return "crossing";
    case EncounterType::Opposing: return "opposing";
    case EncounterType::Adjacent: return "adjacent";
    case EncounterType::Pedestrian: return "pedestrian";
  }
  return "?";
}

double relativeHeadingDeg(double headingA, double headingB) {
  // the difference folded into [0, pi] (remainder keeps it exact for large headings)
  const double d = std::fabs(std::remainder(headingA - headingB, 2.0 * std::numbers::pi));
  return toDegrees(std::min(d, std::numbers::pi));
}

ConflictType conflictType(double deg, const ConflictConfig& config) {
  if (deg < config.rearEndBelowDeg) return ConflictType::RearEnd;
  if (deg > config.crossingAboveDeg) return ConflictType::Crossing;
  return ConflictType::LaneChange;
}

ConflictType conflictType(double deg, VehicleClass a, VehicleClass b, const ConflictConfig& config) {
  if (a == VehicleClass::Pedestrian || b == VehicleClass::Pedestrian) return ConflictType::Pedestrian;
  return conflictType(deg, config);
}

double decelerationToAvoid(double closingSpeed, double ttc) {
  if (!(closingSpeed > 0.0)) return 0.0;
  if (ttc <= 0.0) return std::numeric_limits<double>::infinity();
  return closingSpeed / (2.0 * ttc);
}

double deltaV(double massA, const Vec2& va, double massB, const Vec2& vb) {
  return massB / (massA + massB) * (va - vb).norm();
}

double maxDeltaV(double massA, const Vec2& va, double massB, const Vec2& vb) {
  return std::max(massA, massB) / (massA + massB) * (va - vb).norm();
}

Vec2 postCrashVelocity(double massA, const Vec2& va, double massB, const Vec2& vb) {
  return (massA * va + massB * vb) / (massA + massB);
}

double conflictAngleDeg(const Vec2& egoAxis, const Vec2& foeAxis) {
  // atan2 of the sine and cosine: accurate near 0 and 180 as acos is not; -180 folds to 180
  const double deg = toDegrees(std::atan2(cross(egoAxis, foeAxis), egoAxis.dot(foeAxis)));
  return deg <= -180.0 ? 180.0 : deg;
}

int clockPosition(double conflictAngleDeg) {
  // 30 degrees an hour, clockwise from 12 (the angle is counter-clockwise from the right: +90 is 3)
  const int h = static_cast<int>(std::lround(conflictAngleDeg / 30.0)) % 12;
  return h <= 0 ? h + 12 : h;
}

namespace {
// the point of box b closest to p (p itself when inside)
Vec2 closestPoint(const Box2& b, const Vec2& p) {
  const Vec2 d = p - b.center, n = b.normal();
  const double u = std::clamp(d.dot(b.axis), -b.halfExtents.x(), b.halfExtents.x());
  const double v = std::clamp(d.dot(n), -b.halfExtents.y(), b.halfExtents.y());
  return b.center + u * b.axis + v * n;
}
}  // namespace

Vec2 contactPoint(const Box2& a, const Box2& b, double tie) {
  // each corner of one box with its closest point on the other: distance and midpoint
  std::array<std::pair<double, Vec2>, 8> pairs;
  int k = 0;
  for (const auto& [from, to] : {std::pair<const Box2*, const Box2*>{&a, &b}, {&b, &a}})
    for (const Vec2& c : corners(*from)) {
      const Vec2 q = closestPoint(*to, c);
      pairs[k++] = {(q - c).norm(), 0.5 * (q + c)};
    }
  double best = std::numeric_limits<double>::infinity();
  for (const auto& pr : pairs) best = std::min(best, pr.first);
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (const auto& pr : pairs)
    if (pr.first <= best + tie) sum += pr.second, ++n;
  return sum / n;
}

}  // namespace st::highway
