#pragma once
// The collision detectors of §4.2 behind one interface (vehicleTtc / featureTtc, chosen by
// DetectorConfig::kind):
//   Concentric  inner circle vs curbs, markers, hazards; outer circle vs other cars' outer circles
//               (CheckInner, CheckOuter);
//   FiveCircle  front, rear, left, right zone circles vs the other car's body circles; the centre
//               circle vs curbs, markers, hazards (CheckFront ... CheckCenter);
//   Box         beyond the report: the exact time to collision of the two oriented rectangles,
//               the reference the circle models are measured against.
// Every circle layout covers the car's rectangle, so a circle TTC is never later than the box TTC.
// Motion: constant velocity (the report), or constant longitudinal acceleration until the car
// stops (it does not reverse). Headings are held fixed over the prediction.
#include <array>
#include <cstdint>
#include <limits>
#include <string>

#include <stcore/shapes.hpp>
#include <stcore/toi.hpp>

#include <sthighway/road.hpp>
#include <sthighway/tolerances.hpp>
#include <sthighway/vehicle.hpp>

namespace st::highway {

enum class DetectorKind : std::uint8_t { Concentric, FiveCircle, Box };
const char* toString(DetectorKind k);
bool parseDetectorKind(const std::string& text, DetectorKind& out);  // "concentric", "five", "box"

enum class MotionModel : std::uint8_t { ConstantVelocity, ConstantAcceleration };
bool parseMotionModel(const std::string& text, MotionModel& out);  // "velocity", "acceleration"

// Which circle (or shape) fired.
enum class Zone : std::uint8_t { Front, Rear, Left, Right, Center, Inner, Outer, Body };
const char* toString(Zone z);

// A circle in the car's frame, scaled by the car's size: centre (x * L/2, y * W/2), radius
// hypot(rx * L/2, ry * W/2) + margin, i.e. the circle around the sub-rectangle of half extents
// (rx * L/2, ry * W/2) centred there, grown by margin (m).
struct ZoneCircle {
  double x = 0.0;
  double y = 0.0;
  double rx = 0.0;
  double ry = 0.0;
  double margin = 0.0;
};

// Five radar zones, indexed by FiveCircleLayout::kFront ... kCenter.
struct FiveCircleLayout {
  static constexpr int kFront = 0, kRear = 1, kLeft = 2, kRight = 3, kCenter = 4;
  std::array<ZoneCircle, 5> zones{};

  // Fig. 11(a): small overlaps. Front/rear circles around the front/rear thirds, left/right
  // around the two halves of the middle third, centre circle of radius W/2.
  static FiveCircleLayout fig11a();
  // Fig. 11(b): large overlaps. Front/rear around the halves, left/right around the halves of
  // the middle half.
  static FiveCircleLayout fig11b();
};
bool parseFiveCircleLayout(const std::string& text, FiveCircleLayout& out);  // "a" (Fig. 11a), "b" (11b)

struct ConcentricLayout {
  double innerMargin = 0.0;  // inner radius = W/2 + innerMargin (m)
  double outerMargin = 0.0;  // outer radius = half diagonal + outerMargin (m)
};

struct DetectorConfig {
  DetectorKind kind = DetectorKind::FiveCircle;
  MotionModel motion = MotionModel::ConstantVelocity;
  ConcentricLayout concentric;
  FiveCircleLayout five = FiveCircleLayout::fig11a();
  int bodyCircles = 0;  // circles covering a foe's body in the five-circle model; 0: ceil(L/W)
};

// A kinematic snapshot of one car for prediction. Its rectangle is stcore's Box2 (box()), whose
// kernels (stcore/box2.hpp) the box detector and hindsight use.
struct Body {
  Vec2 position = Vec2::Zero();   // centre (m)
  Vec2 axis = Vec2(1.0, 0.0);     // unit heading
  Vec2 velocity = Vec2::Zero();   // m/s
  double acceleration = 0.0;      // along axis (m/s^2); used by ConstantAcceleration
  // The even braking (m/s^2, < 0) that stands it at a stop line ahead (VehicleState::stopDistance),
  // used under either motion model; 0: none.
  double stopAcceleration = 0.0;
  double length = 5.0;
  double width = 1.8;
  Box2 box() const { return {position, axis, Vec2(0.5 * length, 0.5 * width)}; }
};
Body bodyOf(const VehicleState& v);
// The same with the unit heading axis given (v.direction(), computed once and cached by the caller).
inline Body bodyOf(const VehicleState& v, const Vec2& axis) {
  Body b;
  b.position = v.position;
  b.axis = axis;
  b.velocity = v.speed * axis + v.lateralSpeed * Vec2(-axis.y(), axis.x());  // as v.velocity()
  b.acceleration = v.acceleration;
  b.length = v.length;
  b.width = v.width;
  // u^2 / (2 d) stands it at the line; at the line already, at once
  if (v.stopDistance < std::numeric_limits<double>::infinity() && v.speed > 0.0)
    b.stopAcceleration = -v.speed * v.speed / (2.0 * std::max(v.stopDistance, tol::kStopLineMinDistance));
  return b;
}

// The acceleration along its axis a kernel predicts a body with: its own under
// ConstantAcceleration (else none), at most the braking to its stop line.
inline double motionAcceleration(const Body& b, MotionModel motion) {
  const double own = motion == MotionModel::ConstantAcceleration ? b.acceleration : 0.0;
  return b.stopAcceleration < 0.0 ? std::min(own, b.stopAcceleration) : own;
}

// A detector's answer: stcore's Impact read as an entry (Overlapping: touching now and closing;
// Hit at t s from now; Miss: none within the horizon) and the zone that meets it.
struct Ttc {
  Impact impact;
  Zone zone = Zone::Body;
  bool found() const { return impact.acts(); }
  double t() const { return impact.actTime(); }  // s from now; 0 when touching now; infinity if none
};

// Ego's time to collision with foe, at most `horizon` seconds ahead (infinity beyond).
Ttc vehicleTtc(const DetectorConfig& cfg, const Body& ego, const Body& foe, double horizon);
// Ego's time to reach a road feature. Concentric uses the inner circle, FiveCircle the centre
// circle, Box the rectangle.
Ttc featureTtc(const DetectorConfig& cfg, const Body& ego, const RoadFeature& f, double horizon);

// How far the shape that checks road features (inner circle, centre circle or rectangle) reaches
// from the car's centre along the unit direction n; used to prune features exactly.
double roadSupport(const DetectorConfig& cfg, const Body& ego, const Vec2& n);

// The exact oriented-rectangle TTC (Box detector) under the given motion model: stcore's
// timeOfEntry (Overlapping when the rectangles touch now, Hit within horizon, else Miss).
Impact boxTtc(const Body& a, const Body& b, MotionModel motion, double horizon);

// Radius of a circle that contains every circle of the ego's layout (and its rectangle); used to
// prune pairs and size the neighbour search.
double envelopeRadius(const DetectorConfig& cfg, double length, double width);
// Half extents of an axis-aligned (world) box about the car's centre holding every shape of its
// layout, as ego and as foe; tighter than the envelope disc for long vehicles.
Vec2 envelopeExtent(const DetectorConfig& cfg, const Body& b);
// True if the layout's circles cover the rectangle (checked on construction of a monitor).
bool layoutCoversBody(const FiveCircleLayout& layout, double length, double width);

}  // namespace st::highway
