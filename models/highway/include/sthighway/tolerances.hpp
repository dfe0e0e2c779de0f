#pragma once
// Every tolerance of the highway model, in one place (SI units), and the tuning constants that
// change only its work (the five-circle skips, the broad phase's bins). stcore's own are in
// stcore/tolerances.hpp; these are about vehicles and roads.

namespace st::highway::tol {

// Two shapes closer than this count as touching when the exact box TTC is evaluated at a
// candidate time (m). Larger hides near misses of a few mm; smaller loses touching contacts to
// roundoff of positions ~1e4 m.
inline constexpr double kContactSlop = 1e-7;

// Corners within this of the closest pair count alike when the conflict point of two touching
// rectangles is placed (conflict.hpp contactPoint, m): an edge flat against an edge gives the
// middle of their common part. Far above the roundoff of a predicted touch (1e-9 m at 1e4 m), far
// below a car's size; a heading difference under about 0.03 degrees counts as flat.
inline constexpr double kContactPointTie = 1e-3;

// Two fronts reaching a conflict point within this of each other (s, or m for fronts already at
// or past it) reach it together: SSAM's first of the pair is then the smaller id, not whichever
// rounding favours (a replay's 6-decimal trace against the live run's doubles differ by ~1e-7 m).
inline constexpr double kArrivalTie = 1e-6;

// Consecutive polyline points closer than this are merged before offsetting (m); SUMO shapes
// carry duplicate points at joints and their zero-length segments have no normal.
inline constexpr double kMinSegmentLength = 1e-6;

// A mitred joint of an offset polyline is clamped to this many times the offset, so a sharp
// turn does not throw a marker far off the road (dimensionless).
inline constexpr double kMaxMiterRatio = 4.0;

// Every pruning bound (neighbour reach, envelope tests, road line test) is grown by this (m), so
// pruning never removes a contact the kernels would report within their own slop (touching counts).
// Far above the kernels' slop, far below any physical distance.
inline constexpr double kPruneSlop = 1e-6;

// Relative growth of the cheap pair bounds that stand in for an exact prune (closing speed <=
// |v_x| + |v_y|, so the safe time is at most the one at that speed), dimensionless. Roundoff
// makes the exact quantities a few ulps (1e-16) off their real values; this keeps each bound
// above the exact one it replaces, so it never prunes a pair the exact test keeps.
inline constexpr double kBoundRelativeSlop = 1e-12;

// Hindsight's near misses (hindsight.cpp, sweepNearMisses): a pair's box distance is computed only
// when its centres are closer than the two half diagonals (a body lies within its half diagonal of
// its centre) and the clearance and this (m). Far above the rounding of a centre distance at 1e4 m
// (1e-12 m), far below any clearance; without it a pair whose box distance rounds just below the
// clearance could be skipped by the centre test.
inline constexpr double kNearMissMargin = 1e-6;

// Accelerations below this are treated as zero: the constant-velocity kernels are used (m/s^2).
inline constexpr double kAccelerationEpsilon = 1e-9;

// A car closer than this to its stop line brakes as if it were this far (m): at the line, at once.
inline constexpr double kStopLineMinDistance = 1e-4;
// A driver giving way (stopDistanceOf: g, m, =) brakes at its decel from the last step it can
// still stop in, so SUMO's record of it hovers on "can stop": its front is counted one step of
// SUMO's (default 0.1 s) travel further back, u^2 <= 2 b (d + u dt), or a yielding car that SUMO
// then stands at its line reads as one that has taken its gap (s).
inline constexpr double kYieldStepSlack = 0.1;

// How far past its body's length and its travel until the contact a car's lanes are read to type
// an encounter (lane_encounter.hpp; m): a car standing at its line reaches the junction lane
// beyond it, and a turner inside the junction the lane it leaves onto.
inline constexpr double kEncounterReach = 10.0;

// A car whose path turns by more than this within TTC*, or whose body is turned off its lane by
// more than this, is at a merge (lane_prediction.hpp, atMerge; rad, 1 degree): conflicts.csv
// predicts it along its lanes, not in a straight line. A ramp's nose or its curve (the shipped
// motorway's turns by 10.9 degrees 100 m before the nose, and SUMO heads a car past that vertex
// by the chord from its rear, 4 degrees off for a few ticks); a straight lane's polyline joints
// turn by hundredths of a degree. Smaller takes polyline noise for a bend (the same result, more
// cost); larger leaves gentle curves and the chord's last degrees in straight lines.
inline constexpr double kMergeBend = 0.0174533;

// The five-circle TTC skips a zone circle x body circle pair before its square root when the
// pair provably cannot win, so the result stays bit for bit: the clearance a skipped pair keeps
// (m), far above the rounding of the skip test and of toiBalls' hit time (under 1e-5 m at the
// scales below); a larger margin skips less, a much smaller one could skip a pair whose hit time
// rounds into the window. The skip is used only within these scales: distances and travel under
// kSkipRange (m), radii under kSkipRadius (m), and (for the sure-entry test) a relative speed over
// kSkipSpeed (m/s), far above toiBalls' standstill.
inline constexpr double kSkipMargin = 1e-3;
inline constexpr double kSkipRange = 1e3;
inline constexpr double kSkipRadius = 100.0;
inline constexpr double kSkipSpeed = 1e-6;

// The cells broad phase puts each cell's compact cars in a bin of their own (the vehicle table
// marks each car wide or compact, vehicle_table.cpp; cell_pair_search.cpp bins them): a
// brake ratio m / (2 F_brake) at most kCompactBrakeRatio (s per m/s; a 1.5 t car on 12 kN is
// 0.0625, a 15 t truck on 75 kN 0.1), an envelope extent at most kCompactExtent (m; a 5 x 1.8 m
// car's outer circle is 2.7, a 12 m truck's 6.1) and a lateral speed at most kCompactLateralSpeed
// (m/s; weaving in the lane, not a lane change). Speed only: the warnings do not depend on them.
inline constexpr double kCompactBrakeRatio = 0.08;
inline constexpr double kCompactExtent = 3.5;
inline constexpr double kCompactLateralSpeed = 0.5;

// SUMO's bodies along their paths (sumo_conversion.hpp PathBodies):
// - a front that moves more than kLaneJump sideways of its last step's direction in one step has
//   changed lanes at once (SUMO without the sublane model), and its back with it (m; a lane is at
//   least 2.5 m wide, a front on a 5 m corner at 8 m/s turns its step by 0.1 m);
// - one that moves more than kTrailBreak in a step was teleported: its trail starts again (m);
// - a back-to-front chord within kChordSlack of the length is a straight body (m: on a 500 m
//   motorway curve a 5 m car's chord is 2e-5 m short, and such bodies stay exactly as before);
// - the point of the trail a length of path behind the front is SUMO's back only if it lies within
//   kBackOffLine of the line SUMO's angle draws through the front (m: a trail sampled every 1 m
//   on a 5.6 m corner strays 0.02 m from the lane, a lane change 3 m, a 1 s trace metres).
inline constexpr double kLaneJump = 1.0;
inline constexpr double kTrailBreak = 100.0;
inline constexpr double kChordSlack = 1e-3;
inline constexpr double kBackOffLine = 0.25;

// A predicted body whose chord (from the lanes' centre line half its length behind to half ahead)
// has its middle within kChordOffset of the centre line and turns from the lane by at most
// kMergeBend is laid square to the lane (lane_prediction.cpp; m: a 12 m truck on a motorway's
// polyline joints of hundredths of a degree sits 2e-3 m inside, on a 5.6 m corner metres).
inline constexpr double kChordOffset = 0.02;
// ... and a body on a chord is laid again every kChordRelay of its path at most (m): between two
// lays it moves in a straight line along the lane at its centre while its front follows the bend
// (a 10 m truck leaving a roundabout by a 7 m exit, laid every quarter length, 2.2 m, had its
// front corner 0.9 m off its path, in the entry lane beside it).
inline constexpr double kChordRelay = 1.0;

}  // namespace st::highway::tol
