#include <sthighway/conflict.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace st::highway {

const char* toString(ConflictType t) {
  switch (t) {
    case ConflictType::RearEnd: return "rear_end";
    case ConflictType::LaneChange: return "lane_change";
    case ConflictType::Crossing: return "crossing";
    case ConflictType::Proximity: return "proximity";
    case ConflictType::Road: return "road";
  }
  return "?";
}

double relativeHeadingDeg(double headingA, double headingB) {
  constexpr double kPi = 3.14159265358979323846;
  // the difference folded into [0, pi] (remainder keeps it exact for large headings)
  const double d = std::fabs(std::remainder(headingA - headingB, 2.0 * kPi));
  return std::min(d, kPi) * (180.0 / kPi);
}

ConflictType conflictType(double deg, const ConflictConfig& config) {
  if (deg < config.rearEndBelowDeg) return ConflictType::RearEnd;
  if (deg > config.crossingAboveDeg) return ConflictType::Crossing;
  return ConflictType::LaneChange;
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

}  // namespace st::highway
