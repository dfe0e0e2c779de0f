#pragma once
// What a traffic-safety analyst records of a conflict at its tick of minimum TTC: its type by the
// angle between the two headings (FHWA's SSAM convention), and its severity: the deceleration
// that would avoid it (DRAC) and the change of velocity an impact at that moment would cause
// (SSAM's MaxDeltaV). Plain numbers, SI units; degrees only where SSAM states its thresholds.
#include <cstdint>

#include <stcore/shapes.hpp>
#include <stcore/vec.hpp>
#include <sthighway/vehicle.hpp>

namespace st::highway {

// SSAM's types (RearEnd, LaneChange, Crossing) are of vehicle pairs on a collision course: the
// two bodies (their exact rectangles) are predicted to meet within the safe time at the tick of
// minimum TTC. A vehicle and a pedestrian on a collision course are of type Pedestrian whatever
// the angle (SSAM has no such class; SUMO's SSM sees no persons). A vehicle warning whose bodies
// are not, only the detector's zones (a circle that already overlaps the other car side by side
// in the next lane, TTC 0, or will), is Proximity: a blind-spot or close-following state, not a
// conflict of any angle class; it keeps its zone and has no DRAC. Road warnings (curb, lane
// marker, hazard) are of type Road.
enum class ConflictType : std::uint8_t { RearEnd, LaneChange, Crossing, Pedestrian, Proximity, Road };
inline constexpr int kConflictTypeCount = 6;
// "rear_end", "lane_change", "crossing", "pedestrian", "proximity", "road"
const char* toString(ConflictType t);
// True for SSAM's three angle classes (vehicle pairs: what SUMO's SSM can confirm).
inline bool isSsamType(ConflictType t) {
  return t == ConflictType::RearEnd || t == ConflictType::LaneChange || t == ConflictType::Crossing;
}
// The conflicts proper, in the order every table lists them: SSAM's three and the pedestrian's.
inline constexpr ConflictType kConflictTypes[] = {ConflictType::RearEnd, ConflictType::LaneChange,
                                                  ConflictType::Crossing, ConflictType::Pedestrian};
inline bool isConflictType(ConflictType t) { return isSsamType(t) || t == ConflictType::Pedestrian; }
// The warnings' types whose paths cross or merge, so that one passes the conflict point after
// the other: PET is measured for them (a pedestrian's at any angle: its crosswalk).
inline bool crossesPaths(ConflictType t) {
  return t == ConflictType::LaneChange || t == ConflictType::Crossing || t == ConflictType::Pedestrian;
}

// How two road users' paths meet, read from the lanes each drives on and takes next (SUMO's SSM
// names its encounters so: following, merging, crossing; opposing, diverging and adjacent split
// what SSM leaves out or lumps together). Following: one is on a lane the other's path takes;
// merging: from different lanes onto a common one; diverging: from a common lane end onto lanes
// that part (a straight car behind a turner waiting at its wait point); crossing: lanes that cross
// inside a junction; opposing: a crossing between approaches heading at each other (a left turn
// across oncoming traffic); adjacent: lanes of one edge with no lane in common ahead (a lane
// change); pedestrian: a person is one of the two. Unknown: no lanes (straight prediction, or a
// car off the network), or none of these within the lanes ahead.
enum class EncounterType : std::uint8_t { Unknown, Following, Merging, Diverging, Crossing, Opposing, Adjacent, Pedestrian };
inline constexpr int kEncounterTypeCount = 8;
// "unknown", "following", "merging", "diverging", "crossing", "opposing", "adjacent", "pedestrian"
const char* toString(EncounterType e);

struct ConflictConfig {
  // SSAM: a conflict angle below 30 degrees is a rear-end, above 85 degrees a crossing, a
  // lane change between. Scenario keys conflict.rear_end_below / conflict.crossing_above.
  double rearEndBelowDeg = 30.0;
  double crossingAboveDeg = 85.0;
  // SSAM's thresholds of a conflict (conflicts.csv): its minimum TTC at most maxTtc (TTC*, SSAM's
  // default 1.5 s; also what TET and TIT are measured against) and its PET, where one is
  // measured, at most maxPet (PET*, SSAM's 5 s). Scenario keys conflict.max_ttc / conflict.max_pet.
  double maxTtc = 1.5;
  double maxPet = 5.0;
};

// The angle between two headings (rad, counter-clockwise from +x), in degrees in [0, 180].
double relativeHeadingDeg(double headingA, double headingB);

// The type of a conflict at relative heading angle `deg` (in [0, 180]) between road users of
// classes a and b: Pedestrian if either is one, else SSAM's class of the angle (a head-on
// approach, near 180, is a crossing, as in SSAM when no lane information decides it).
ConflictType conflictType(double deg, const ConflictConfig& config);
ConflictType conflictType(double deg, VehicleClass a, VehicleClass b, const ConflictConfig& config);

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
// The common velocity after that impact (SSAM's PostCrashV and PostCrashHeading): momentum
// conserved, (m_a v_a + m_b v_b) / (m_a + m_b) (m/s).
Vec2 postCrashVelocity(double massA, const Vec2& va, double massB, const Vec2& vb);

// SSAM's conflict angle (deg, in (-180, 180]): the foe's heading relative to the ego's,
// counter-clockwise positive, so positive when the foe comes from the ego's right (heads to its
// left), negative from its left; 0 the same heading (rear-end), 180 head-on. Unit headings.
double conflictAngleDeg(const Vec2& egoAxis, const Vec2& foeAxis);
// That angle as a clock position on the ego (SSAM's clock angle): the nearest hour 1..12, 12 the
// same heading, 3 from the right, 6 head-on, 9 from the left.
int clockPosition(double conflictAngleDeg);

// The contact point of two touching (or overlapping) boxes: the midpoint of their closest points,
// found from the corners (two convex polygons' closest pair has a corner of one of them), averaged
// over the corners within `tie` of the closest (m) so that an edge against an edge gives the
// middle of their common segment. For boxes apart: the midpoint of the closest pair.
Vec2 contactPoint(const Box2& a, const Box2& b, double tie);

}  // namespace st::highway
