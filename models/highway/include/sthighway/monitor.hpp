#pragma once
// The per-tick smart-car monitor (§4.3): each tick it takes every vehicle's state, hands cars
// between cells, finds each equipped car's candidate foes (its own and neighbouring cells within
// its look-ahead, or all pairs), computes TTCs with the chosen detector and raises a warning when
// TTC <= safe time. Warnings are episodes: one per (ego, foe, kind) from the first tick it holds to
// the first tick it no longer does.
//
// Closing speed, used by the safe time: car-car, the rate at which the centre distance shrinks,
// -(p_rel . v_rel) / |p_rel|; car-road, the ego's velocity towards the feature's closest point.
// Crossing a lane marker with the turn signal of that side on is not a warning.
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <sthighway/cells.hpp>
#include <sthighway/conflict.hpp>
#include <sthighway/detector.hpp>
#include <sthighway/road.hpp>
#include <sthighway/safe_time.hpp>
#include <sthighway/vehicle.hpp>

namespace st::highway {

enum class Broadphase : std::uint8_t { Cells, AllPairs };
const char* toString(Broadphase b);
bool parseBroadphase(const std::string& text, Broadphase& out);  // "cells", "all-pairs"

// How a car's motion is predicted (its shape and speed model are the detector's, DetectorConfig):
//   Road      along its road: the centre line of the lane it is on (matched by position and
//             heading), continued into the straightest successor lane (the turn its signal shows
//             at a junction), keeping its offset and lateral speed relative to the lane, its
//             body square to the lane from the next vertex on; curbs and lane markers by time to line crossing
//             in the lane frame (lateral distance over lateral speed, as lane-departure warning
//             systems do, ISO 17361). A car on no lane falls back to Straight.
//   Straight  the report's model: a straight line at its heading (headings held fixed), against
//             the curb and marker polylines.
enum class Prediction : std::uint8_t { Road, Straight };
const char* toString(Prediction p);                         // "road", "straight"
bool parsePrediction(const std::string& text, Prediction& out);

enum class WarningKind : std::uint8_t { Vehicle, Curb, LaneMarker, Hazard };
inline constexpr int kWarningKindCount = 4;
inline constexpr int kZoneCount = 8;
const char* toString(WarningKind k);  // "vehicle", "curb", "lane_marker", "hazard"

// What hindsight (hindsight.cpp) made of a warning: the following ticks confirmed the conflict,
// or it did not happen (a nuisance); unjudged while it is open or with hindsight off.
enum class Verdict : std::uint8_t { Unjudged, Confirmed, Nuisance };
const char* toString(Verdict v);  // "", "confirmed", "nuisance"

struct Warning {
  std::string ego;
  std::string foe;         // vehicle id; curb/marker/hazard name (RoadFeature::name)
  WarningKind kind = WarningKind::Vehicle;
  Zone zone = Zone::Body;  // the zone that fired first
  double begin = 0.0;      // s, first tick with TTC <= safe time
  double end = 0.0;        // s, first tick without (or the vehicle's last tick, or finish time)
  double minTtc = 0.0;     // s, smallest TTC in the episode
  double minTtcTime = 0.0; // s, when it occurred
  double safeTimeAtMin = 0.0;  // s, the safe time at that tick
  bool open = false;       // still going on
  // what happened next (hindsight)
  Verdict verdict = Verdict::Unjudged;
  double clearance = std::numeric_limits<double>::quiet_NaN();      // m, vehicle: smallest body-to-body distance in the window
  double clearanceTime = std::numeric_limits<double>::quiet_NaN();  // s, when (road: when the body touched the line)
  double deceleration = 0.0;  // m/s^2, vehicle: the strongest braking of either vehicle in the window
  bool crossed = false;       // road: the body touched the line (or hazard) within the safe time
  bool signalled = false;     // road: with the turn signal of that side on
  // The conflict at the tick of the minimum TTC (conflict.hpp). NaN: does not apply to the kind.
  double x = 0.0, y = 0.0;     // m, the ego's centre
  std::string lane;            // the ego's lane id (VehicleState::lane), empty if unknown
  double egoSpeed = 0.0;       // m/s, |velocity|
  double foeSpeed = 0.0;       // m/s; NaN for road warnings
  double headingAngle = 0.0;   // deg, between the headings (0..180); road: to the line (0..90), NaN for a hazard
  ConflictType type = ConflictType::Road;
  double drac = 0.0;           // m/s^2, deceleration rate to avoid the crash (infinite when touching)
  double maxDeltaV = 0.0;      // m/s, SSAM's MaxDeltaV; NaN for road warnings
  std::string line;            // road warnings: the curb, marker or hazard (RoadFeature::name)
  double lateralSpeed = 0.0;   // m/s, road warnings: the ego's speed towards the line; NaN for vehicles
  // SSAM's and SUMO's SSM measures of a vehicle warning (NaN for road warnings; conflict.hpp). At
  // the tick of the minimum TTC: the predicted contact point (the two bodies moved on in straight
  // lines at their velocities until their rectangles touch; NaN when not on a collision course),
  // the foe's centre, DeltaS (|v_ego - v_foe|), the conflict angle and its clock position, and the
  // perfectly inelastic crash's common velocity (speed, and heading in degrees counter-clockwise
  // from +x). Over the episode: MaxS (the larger speed of either vehicle, begin to end), the ego's
  // DR (its first negative acceleration after begin, else its lowest) and MaxD (its lowest
  // acceleration; negative: braking), measured from its speed tick to tick; the ego's centre at
  // begin and at end (at its last tick if it left).
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  double conflictX = kNone, conflictY = kNone;  // m
  double foeX = kNone, foeY = kNone;            // m
  double maxSpeed = kNone;                      // m/s, MaxS
  double deltaSpeed = kNone;                    // m/s, DeltaS
  double dr = kNone;                            // m/s^2, DR
  double maxDecel = kNone;                      // m/s^2, MaxD
  double conflictAngle = kNone;                 // deg, (-180, 180]
  double clockAngle = kNone;                    // h, 1..12
  double startX = kNone, startY = kNone;        // m
  double endX = kNone, endY = kNone;            // m
  double postCrashSpeed = kNone;                // m/s
  double postCrashHeading = kNone;              // deg, (-180, 180]
  // PET (post-encroachment time, s) of a lane_change or crossing conflict: from the first vehicle
  // leaving the conflict area to the second entering it, measured on the vehicles' later positions
  // (conflict_capture.hpp, PetWatch); NaN when one of them did not pass it within
  // kPetHorizon s of the end (or left), or with hindsight off when not by the end. Negative: both
  // were in the area at once.
  double pet = kNone;
};

// One tick of a warning episode (HighwayMonitor::recordTrajectories; SUMO's SSM device writes the
// same with --device.ssm.trajectories): from its first tick to its last with the threat. The
// episode is named as its Warning names it, by ego, foe, kind and begin (whatever the input order).
struct TrajectoryPoint {
  std::string ego, foe;
  WarningKind kind = WarningKind::Vehicle;
  double begin = 0.0;         // s, the episode's
  double time = 0.0;          // s
  double ttc = 0.0;           // s, the episode's TTC at that tick
  double drac = 0.0;          // m/s^2, DRAC then (conflict.hpp: closing speed / (2 TTC); inf touching while closing)
};
// One conflict for the analyst (conflicts.csv; conflict_book.cpp): an unordered pair of vehicles,
// at least one of them equipped, and one continuous encounter: the ticks on which the two bodies'
// exact rectangles, moved on in straight lines at their velocities (SUMO's SSM and SSAM's model),
// would touch within ConflictConfig::maxTtc (TTC*), from the first such tick (`begin`) to the
// first without (`end`; the last tick of a vehicle that left, or the run's end). Found for every
// pair whatever the detector, and counted once: kept when its minimum TTC is at most TTC* and its
// PET, where one is measured, at most ConflictConfig::maxPet (PET*). First and second vehicle as
// SSAM names them: the first is the one whose front reaches the predicted contact point first
// (the leader of a rear-end). Measures at the tick of the minimum TTC unless said otherwise.
struct Conflict {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::string first, second;          // vehicle ids
  ConflictType type = ConflictType::RearEnd;  // SSAM's angle class (never proximity or road)
  EncounterType encounter = EncounterType::Unknown;    // how their paths meet, from the lanes (at the minimum TTC)
  double begin = 0.0, end = 0.0;      // s
  double minTtc = 0.0;                // s, smallest TTC of the encounter (0: touching)
  double minTtcTime = 0.0;            // s, its first tick
  double pet = kNone;                 // s, SSAM's PET (rear-ends at the conflict point, others across the swept area); NaN: none measured
  double drac = kNone;                // m/s^2, closing speed of the centres / (2 min TTC); inf touching
  double maxSpeed = kNone;            // m/s, SSAM's MaxS: either vehicle's largest speed, begin to end
  double deltaSpeed = kNone;          // m/s, SSAM's DeltaS: |v_first - v_second|
  double dr = kNone;                  // m/s^2, SSAM's DR: the second vehicle's first negative acceleration after begin, else its lowest
  double maxD = kNone;                // m/s^2, SSAM's MaxD: the second vehicle's lowest acceleration, begin to end
  double maxDeltaV = kNone;           // m/s, SSAM's MaxDeltaV (the larger of the two below)
  double firstDeltaV = kNone, secondDeltaV = kNone;  // m/s, each vehicle's velocity change in a perfectly inelastic crash
  double conflictAngle = kNone;       // deg, (-180, 180]: the second's heading relative to the first's
  double clockAngle = kNone;          // h, 1..12
  double postCrashSpeed = kNone;      // m/s
  double postCrashHeading = kNone;    // deg, counter-clockwise from +x; NaN when the speed is 0
  double conflictX = kNone, conflictY = kNone;  // m, the predicted contact point (contactPoint)
  // m, where the two paths meet, on both lanes' centre lines (LaneMeeting: crossing, merge or
  // parting point); NaN when one follows the other or nothing is known. SSM's conflict point is
  // of this kind, the contact point above is where the bodies touch (metres earlier at a merge).
  double pathsMeetX = kNone, pathsMeetY = kNone;
  // where the paths cross, each one's lane direction there (unit; NaN else). Not in conflicts.csv:
  // the SSM validation moves the point back to where one enters the other's path, as SSM has it.
  Vec2 firstAlong = Vec2::Constant(kNone), secondAlong = Vec2::Constant(kNone);
  double firstX = kNone, firstY = kNone, secondX = kNone, secondY = kNone;  // m, the centres
  double firstSpeed = kNone, secondSpeed = kNone;                           // m/s
  double firstStartX = kNone, firstStartY = kNone, firstEndX = kNone, firstEndY = kNone;    // m, at begin and at end (its last tick)
  double secondStartX = kNone, secondStartY = kNone, secondEndX = kNone, secondEndY = kNone;
  std::string firstLane, secondLane;  // lane ids, empty if unknown
  // SUMO junction either lane lies in (the first's, else the second's), else the junction of the
  // lane the paths meet on; "" for none
  std::string junction;
  // the edge each came into the junction from (its lane's edge, or inside the junction the edge
  // before it); "" when unknown. Counted in summary.json's by_junction, not written to conflicts.csv
  std::string firstApproach, secondApproach;
  VehicleClass firstClass = VehicleClass::Passenger, secondClass = VehicleClass::Passenger;
  double firstLength = 0.0, secondLength = 0.0, firstWidth = 0.0, secondWidth = 0.0;  // m
  double tet = 0.0;                   // s, time exposed: the ticks with TTC <= TTC*, each the time since the previous tick
  double tit = 0.0;                   // s^2, time integrated: the same ticks' (TTC* - TTC) times that time
  bool open = false;                  // still going on when the run ended
};

// How long after an episode's end its PET is waited for (s; SUMO's device.ssm.extratime default).
inline constexpr double kPetHorizon = 5.0;

// An actual event hindsight counts for recall (hindsight.cpp): a near miss (two bodies, one of
// them equipped, closer than the clearance while on a collision course; one per approach) or an
// equipped car's unsignalled line crossing; and whether a warning about it was open
// HindsightConfig::lead seconds before. A list of them is where the misses can be looked at.
enum class EventKind : std::uint8_t { NearMiss, Crossing };
const char* toString(EventKind k);  // "near_miss", "crossing"

struct HindsightEvent {
  EventKind kind = EventKind::NearMiss;
  double time = 0.0;   // s, the first tick of the approach or of the crossing
  std::string ego;     // the equipped car (a near miss of two equipped cars: either)
  std::string foe;     // near miss: the other vehicle; crossing: the line (RoadFeature::name)
  double x = 0.0, y = 0.0;  // m, the ego's centre
  std::string lane;    // the ego's lane id, empty if unknown
  double speed = 0.0;  // m/s, the ego's
  double gap = std::numeric_limits<double>::quiet_NaN();           // m, near miss: body to body then
  double lateralSpeed = std::numeric_limits<double>::quiet_NaN();  // m/s, crossing: towards the line (lane frame)
  bool warned = false;  // a warning about it was open `lead` s before (what recall counts)
  // s: how long before the event the earliest warning about it (open at `time - lead` or
  // later) began; NaN: none by then. Below `lead`: warned too late.
  double lead = std::numeric_limits<double>::quiet_NaN();
};

// An equipped car's worst current threat this tick (for actions: colour, brake).
struct Alert {
  int vehicle = -1;        // index into the span given to the last step()
  WarningKind kind = WarningKind::Vehicle;
  Zone zone = Zone::Body;
  double ttc = 0.0;
  double safeTime = 0.0;   // ttc / safeTime < 0.5 is "red" in the SUMO colouring
  int foe = -1;            // the other vehicle's index (vehicle warnings), else -1
};

// Hindsight's thresholds (scenario keys `hindsight: {clearance, evasive_deceleration, lead}`).
struct HindsightConfig {
  bool enabled = true;
  double clearance = 0.5;            // m: a realized clearance below it confirms a vehicle warning
  double evasiveDeceleration = 4.0;  // m/s^2: a vehicle of unknown decel (VehicleState::decel) braking harder than this in the window confirms it too; one with a decel, braking beyond it
  double lead = 0.5;                 // s: a near miss is warned if an episode was open this long before
  double nearMissTtc = 1.5;          // s: a near miss is on a collision course: its box TTC then at most this (SSAM's 1.5 s)
};

struct MonitorConfig {
  DetectorConfig detector;
  SafeTimeConfig safeTime;
  CellConfig cells;
  Broadphase broadphase = Broadphase::Cells;
  Prediction prediction = Prediction::Road;
  bool checkRoad = true;   // curbs, lane markers, hazards
  // A car whose link is minor gives way where SUMO's priority rules have it (its line, a left
  // turn's wait point) while it can stop there; false: on at its speed (as SSM and SSAM predict)
  bool priorityRules = true;
  HindsightConfig hindsight;
  ConflictConfig conflict;  // the type thresholds (reported only)
};

struct MonitorCounters {
  std::uint64_t ticks = 0;
  std::uint64_t vehicleUpdates = 0;   // vehicle states processed
  std::uint64_t handoffs = 0;
  std::uint64_t subdivisions = 0;
  std::uint64_t reunions = 0;
  std::uint64_t candidatePairs = 0;   // (ego, foe) pairs the broad phase returned
  std::uint64_t toiChecks = 0;        // detector calls that reached the TTC kernels
  std::uint64_t featureChecks = 0;    // (ego, road feature) TTC computations
  std::uint64_t warningsBegun = 0;
  double vehicleMeters = 0.0;         // distance driven, summed over vehicles (m; persons walk none of it)
  std::uint64_t vehiclesSeen = 0;     // distinct ids, persons on foot apart:
  std::uint64_t personsSeen = 0;
  // Road prediction: vehicle updates predicted along a lane, and those on no fitting lane (or
  // stopped), predicted in a straight line.
  std::uint64_t roadPredicted = 0;
  std::uint64_t straightFallbacks = 0;
  // Of the road-predicted updates, those whose route (VehicleState::route) holds their lane's
  // edge: they are predicted along it through junctions.
  std::uint64_t routePredicted = 0;
  // Time exposed (TET, s) and time-integrated (TIT, s^2) TTC below the safe time, per kind:
  // sum over equipped cars and ticks of dt, and of dt * (t_safe - TTC) for the worst threat.
  std::array<double, kWarningKindCount> tet{};
  std::array<double, kWarningKindCount> tit{};
  // Finished and open episodes by kind and by zone.
  std::array<std::uint64_t, kWarningKindCount> warningsByKind{};
  std::array<std::uint64_t, kZoneCount> warningsByZone{};
  // Hindsight: per kind, the warnings judged and those confirmed; the run's near misses (pairs
  // with an equipped car closer than the clearance while closing, one per approach), those warned
  // `lead` s before, and the warned ones' lead times (s).
  std::array<std::uint64_t, kWarningKindCount> judged{};
  std::array<std::uint64_t, kWarningKindCount> confirmed{};
  std::uint64_t nearMisses = 0;
  std::uint64_t nearMissesWarned = 0;
  std::vector<double> nearMissLeads;
  // The run's unsignalled line crossings (an equipped car's body begins to reach across a curb,
  // or a marker without that side's signal, in its lane's frame), those warned `lead` s before,
  // and the warned ones' lead times (s).
  std::uint64_t crossings = 0;
  std::uint64_t crossingsWarned = 0;
  std::vector<double> crossingLeads;
  // Finished episodes by conflict type at their minimum TTC (equal in total to the above once
  // finish() has closed every episode).
  std::array<std::uint64_t, kConflictTypeCount> warningsByType{};
  // Conflicts (Conflict, conflicts.csv) counted by type, their TET and TIT against TTC* summed,
  // and the encounters below TTC* left out because their PET exceeded PET*.
  std::array<std::uint64_t, kConflictTypeCount> conflictsByType{};
  // ... by the junction they were in (Conflict::junction), junctions with none left out
  std::map<std::string, std::array<std::uint64_t, kConflictTypeCount>> conflictsByJunction;
  // ... and by each approach a road user of theirs came from (junction -> edge -> conflicts; a
  // conflict of two from one approach counts once there)
  std::map<std::string, std::map<std::string, std::uint64_t>> conflictsByApproach;
  // ... of those with a bicycle (either road user of class Bicycle: car-bicycle and
  // bicycle-bicycle), by type, and of them those between two bicycles
  std::array<std::uint64_t, kConflictTypeCount> conflictsWithBicycle{};
  std::uint64_t conflictsBetweenBicycles = 0;
  // ... by how their paths meet (Conflict::encounter)
  std::array<std::uint64_t, kEncounterTypeCount> conflictsByEncounter{};
  double conflictTet = 0.0;
  double conflictTit = 0.0;
  std::uint64_t conflictsOverMaxPet = 0;
};

class HighwayMonitor {
 public:
  // Throws std::invalid_argument for a bad configuration (e.g. a five-circle layout that does
  // not cover a car) or bad road geometry.
  HighwayMonitor(const RoadGeometry& road, const MonitorConfig& config);
  ~HighwayMonitor();
  HighwayMonitor(HighwayMonitor&&) noexcept;
  HighwayMonitor& operator=(HighwayMonitor&&) noexcept;

  // The states of every vehicle on the road at time t (s, strictly increasing). Vehicles absent
  // from the span have left: their episodes close. Throws std::invalid_argument on a duplicate id,
  // a non-finite value or a non-positive size.
  void step(double t, std::span<const VehicleState> vehicles);
  // Closes every open episode at time t.
  void finish(double t);

  // Episodes that ended since the last call, in order of ending, each judged by hindsight (held
  // until its window, a few seconds at most, has passed).
  std::vector<Warning> takeFinished();
  // The same into `out` (replacing its contents): the monitor keeps out's old buffer, so a caller
  // that passes the same vector every tick allocates nothing once both have grown.
  void takeFinished(std::vector<Warning>& out);
  // The near misses and unsignalled crossings hindsight found since the last call, in order
  // (into `out`, replacing its contents); none with hindsight off.
  void takeEvents(std::vector<HindsightEvent>& out);
  // Records each episode's TTC and DRAC at every tick it holds (off by default: no cost).
  void recordTrajectories(bool on);
  // The points recorded since the last call, in tick order (into out, replacing its contents).
  void takeTrajectories(std::vector<TrajectoryPoint>& out);
  // Conflicts (Conflict) that ended since the last call, into out (replacing its contents), in
  // the order they were settled (a conflict waits for its PET up to kPetHorizon s).
  void takeConflicts(std::vector<Conflict>& out);
  // Episodes still open now (end == time of the last tick).
  std::vector<Warning> openWarnings() const;
  // Worst threat of each equipped car with an active warning at the last tick.
  std::span<const Alert> alerts() const;

  const MonitorCounters& counters() const;
  const MonitorConfig& config() const;
  const RoadFeatures& features() const;
  const CellNetwork& cells() const;
  double lastTime() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace st::highway
