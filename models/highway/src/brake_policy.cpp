#include <sthighway/brake_policy.hpp>

#include <algorithm>
#include <cmath>

namespace st::highway {

std::optional<BrakeCommand> brakeFor(const VehicleState& ego, const VehicleState& foe, const BrakeSettings& s) {
  // the foe in our frame: ahead along our heading, closing along it, beside it
  const Vec2 d = ego.direction();
  const double ahead = (foe.position - ego.position).dot(d);
  const double closing = ego.speed - foe.velocity().dot(d);
  const double side = std::abs((foe.position - ego.position).dot(Vec2(-d.y(), d.x())));
  // in our path: a slow car in the next lane is no reason to brake
  const bool inPath = side < 0.5 * (ego.width + foe.width);
  if (!(ahead > 0.0 && closing > 0.0 && inPath)) return std::nullopt;
  // the deceleration that sheds the closing speed within the gap left
  const double gap = ahead - 0.5 * (ego.length + foe.length) - s.standstillGap;
  const double needed = gap > 0.0 ? closing * closing / (2.0 * gap) : s.maxDeceleration;
  const double decel = std::min(needed, s.maxDeceleration);
  if (decel < s.deceleration) return std::nullopt;
  return BrakeCommand{std::max(0.0, ego.speed - closing), decel, closing / decel};
}

}  // namespace st::highway
