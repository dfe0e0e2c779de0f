#pragma once
// The brake-on-warning policy: given a smart car and the foe it is warned of, whether it brakes and
// how. Pure (two vehicle states and the settings), so a SUMO run, a replay, Python or a test ask
// the same question; the caller applies the answer (cosim's plugin with SUMO's slowDown).
#include <optional>

#include <sthighway/vehicle.hpp>

namespace st::highway {

struct BrakeSettings {
  // A car brakes only once matching its foe's speed within the gap needs at least this (m/s^2):
  // gentler cases are the driver's.
  double deceleration = 3.0;
  double maxDeceleration = 9.0;  // m/s^2, the hardest it brakes (SUMO's default emergencyDecel for cars)
  double standstillGap = 1.0;    // m, the gap it keeps to its foe
};

struct BrakeCommand {
  double targetSpeed = 0.0;   // m/s: the foe's speed along our heading, not below 0
  double deceleration = 0.0;  // m/s^2: the gap's v^2/(2 gap), at most maxDeceleration
  double duration = 0.0;      // s: closing speed / deceleration
};

// Brake for a foe ahead in our path (the bodies overlap sideways now) that is slower along our
// heading, down to its speed and not to a standstill: braking for a foe behind or alongside, or
// harder than needed, only moves the conflict to the vehicles behind. The deceleration is the
// closing speed's v^2 / (2 gap), the gap being the bumper-to-bumper distance less standstillGap
// (used up already: maxDeceleration); none when it is below `deceleration`.
std::optional<BrakeCommand> brakeFor(const VehicleState& ego, const VehicleState& foe, const BrakeSettings& s);

}  // namespace st::highway
