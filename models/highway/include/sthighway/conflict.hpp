#pragma once
// What a traffic-safety analyst records of a conflict at its tick of minimum TTC: its type by the
// angle between the two headings (FHWA's SSAM convention), and its severity: the deceleration
// that would avoid it (DRAC) and the change of velocity an impact at that moment would cause
// (SSAM's MaxDeltaV). Plain numbers, SI units; degrees only where SSAM states its thresholds.
#include <cstdint>

#include <stcore/vec.hpp>

namespace st::highway {

// Road warnings (curb, lane marker, hazard) are of type Road: SSAM's types are of vehicle pairs.
enum class ConflictType : std::uint8_t { RearEnd, LaneChange, Crossing, Road };
inline constexpr int kConflictTypeCount = 4;
const char* toString(ConflictType t);  // "rear_end", "lane_change", "crossing", "road"

struct ConflictConfig {
  // SSAM: a conflict angle below 30 degrees is a rear-end, above 85 degrees a crossing, a
  // lane change between. Scenario keys conflict.rear_end_below / conflict.crossing_above.
  double rearEndBelowDeg = 30.0;
  double crossingAboveDeg = 85.0;
};

// The angle between two headings (rad, counter-clockwise from +x), in degrees in [0, 180].
double relativeHeadingDeg(double headingA, double headingB);

// The type of a vehicle-vehicle conflict at relative heading angle `deg` (in [0, 180]). A
// head-on approach (near 180) is a crossing, as in SSAM when no lane information decides it.
ConflictType conflictType(double deg, const ConflictConfig& config);

// The deceleration rate to avoid the crash (m/s^2): the constant deceleration of the relative
// motion that stops the closing before contact, v^2 / (2 gap) with the gap the closing speed
// covers until contact (gap = v ttc): v / (2 ttc). 0 when not closing (v <= 0), infinite at
// ttc 0 with v > 0 (already in contact). Car-road: v is the speed towards the line.
double decelerationToAvoid(double closingSpeed, double ttc);

// SSAM's MaxDeltaV: both vehicles as point masses in a perfectly inelastic impact at velocities
// va, vb; each changes velocity by the other's share of the mass times |va - vb|. The larger of
// the two (the lighter vehicle's), m/s.
double maxDeltaV(double massA, const Vec2& va, double massB, const Vec2& vb);
// The change of velocity of vehicle A alone in that impact (m/s).
double deltaV(double massA, const Vec2& va, double massB, const Vec2& vb);

}  // namespace st::highway
