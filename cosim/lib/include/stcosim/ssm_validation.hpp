#pragma once
// Validation against SUMO's own SSM (surrogate safety measures) device, run in the same simulation:
// every vehicle carries an SSM device writing its conflicts with TTC time series (trajectories).
//
// 1. Following encounters: for every SSM sample of type FOLLOWING_FOLLOWER (ego follows foe on the
//    same lane) with a TTC, the exact box TTC of the same pair under constant velocity. Two
//    conventions are accounted for: SSM's gap is bumper to bumper (the leader's back minus the
//    follower's front, without minGap), which is what the box detector measures from the bodies;
//    and SSM stamps a sample with the time at the start of the step whose result it evaluates,
//    one step (deltaT) earlier than the simulation time libsumo reports after that step, so the
//    sample at T is compared with our state at T + deltaT. SSM writes with --precision digits.
//    On the same samples, SSM's DRAC (run with TTC, DRAC and PET) against ours.
// 2. Recall: every SSM conflict (any order of the pair, following types) whose minimum TTC is below
//    the ego's safe time at that moment must have raised a car-car warning for the same pair from
//    each detector (concentric, five-circle, box), running side by side on the same states.
// 3. Precision: the share of each detector's car-car warnings for which SSM recorded an encounter
//    of the same pair overlapping in time with a TTC; the rest are broken down by zone: warnings
//    SSM cannot see (lateral and lane-change conflicts, which SSM's following/merging/crossing
//    geometry does not cover).
// 4. PET: on the pairs both see one (SSM on merging and crossing encounters, stsim on lane_change
//    and crossing conflicts), the box detector's episode's PET against SSM's. A PET is a duration,
//    so the time-stamp shift cancels in it.
// 5. The conflict point, on the box detector's rear_end episodes on a collision course whose
//    minimum-TTC tick SSM has as a following sample of the same pair with a TTC (SSM's following
//    point is the leader's back, a rear-end geometry). The conventions differ and SSM's is
//    converted to ours: SSM's point is the leader's back now; ours is where the bodies, moved on in
//    straight lines, touch. So SSM's point is moved on by the leader's velocity times SSM's TTC
//    (both from SSM's own output at that sample). Across the leader's path ours is the middle of
//    the touching part, SSM's the leader's centre line: they coincide for vehicles on their lane's
//    centre (not in the sublane model), so the distance along the leader's path is kept apart.
//    Both see the same approach when SSM's TTC at that sample is within the TTC tolerance of ours
//    (in the sublane model SSM takes vehicles beside each other in a lane as following, gap 0).
// 6. The conflict point where paths cross or merge: SSM's is where the follower (the later into
//    the conflict area) enters it, a fixed place on its lane at the leader's near side; ours, the
//    bodies' contact, lies on that side too when the follower's front meets the leader's side,
//    so the two are compared along the follower's path (its velocity in SSM's output); across it
//    ours is the middle of the touching part, SSM's the follower's centre line.
#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include <stcore/vec.hpp>
#include <sthighway/detector.hpp>
#include <sthighway/monitor.hpp>
#include <stcosim/backend.hpp>

namespace st::cosim {

// SUMO's SSM encounter types used here (MSDevice_SSM::EncounterType).
inline constexpr int kSsmFollowing = 1;
inline constexpr int kSsmFollowingFollower = 2;
inline constexpr int kSsmFollowingLeader = 3;
inline constexpr int kSsmMergingLeader = 6;
inline constexpr int kSsmMergingFollower = 7;
inline constexpr int kSsmCrossingLeader = 10;
inline constexpr int kSsmCrossingFollower = 11;
inline constexpr int kSsmEgoEnteredArea = 12;  // 12-16: one or both in or past the conflict area
inline constexpr int kSsmFoeEnteredArea = 13;
inline constexpr int kSsmEgoLeftArea = 15;
inline constexpr int kSsmFoeLeftArea = 16;

// SSM's encounter classes at one sample, its types folded: following 1-3, on adjacent lanes 4,
// merging 5-8, crossing 9-11, following passed 18 (it was following and is no more: their lanes
// part), merging passed 19, oncoming 20. Its types 12-17 (a vehicle has entered or left the
// conflict area) and 111 (collision) are the class of the pair's last sample before them
// (ssmEncounterClassAt); 0 (no conflict ahead) is None.
enum class SsmEncounterClass : int { None, Following, Adjacent, Merging, Crossing, FollowingPassed, MergingPassed, Oncoming };
SsmEncounterClass ssmEncounterClass(int ssmType);
// SSM's class of the encounter c at its sample i, as above.
SsmEncounterClass ssmEncounterClassAt(const struct SsmConflict& c, std::size_t i);
// "none", "following", "adjacent", "merging", "crossing", "following_passed", "merging_passed", "oncoming"
const char* toString(SsmEncounterClass c);
// The class of SSM's that ours names: opposing is a crossing to SSM, diverging a following that
// has passed (the lanes part); a pedestrian's SSM has none (None).
SsmEncounterClass ssmClassOf(highway::EncounterType e);

// SSM's PET position farther than this from one of the two paths (m): half SUMO's lane width,
// beyond any point where the two bodies could meet (SsmConflict::petOffPath).
inline constexpr double kSsmPetOffPath = 1.6;

struct SsmConflict {
  std::string ego, foe;
  double begin = 0.0, end = 0.0;
  std::vector<double> times;
  std::vector<int> types;
  std::vector<double> ttc;   // NaN where SSM has none ("NA")
  std::vector<double> drac;  // m/s², per sample as ttc; empty when SSM ran without DRAC
  // per sample (trajectories), network x/y; NaN where "NA": the conflict point (the leader's back
  // on following types, the lanes' meeting point on merging and crossing) and the velocities
  std::vector<Vec2> conflictPoints, egoVelocities, foeVelocities;
  // and the two fronts, per sample as above (empty when the file has none)
  std::vector<Vec2> egoPositions, foePositions;
  double minTtc = 0.0, minTtcTime = 0.0;
  int minTtcType = -1;
  Vec2 minTtcPosition = kNoPoint;
  bool hasMin = false;
  // the PET, SSM's time being the later vehicle's entry into the conflict area (interpolated
  // between steps)
  double pet = 0.0, petTime = 0.0;
  int petType = -1;
  Vec2 petPosition = kNoPoint;
  bool hasPet = false;
  // How far SSM's PET position lies from the path the farther of the two fronts took over the
  // encounter (m; NaN without positions). SSM's point is on one path; where they could meet it is
  // within about half a body width of the other's (0.75-1.4 m measured on crossings). SUMO's
  // left turns split at an internal junction put it on the turner's path 2.2-7.1 m from the
  // other's: a PET of another place (networks/intersection/README.md).
  double petOffPath() const;
  static inline const Vec2 kNoPoint{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
};

// Reads an SSM output file. Throws ScenarioError naming the file on malformed content.
std::vector<SsmConflict> readSsmOutput(const std::filesystem::path& path);

// The SUMO options that equip every vehicle with an SSM device writing to `file`.
// `threshold` (s): an encounter is logged as a conflict when its TTC falls below it.
std::vector<std::string> ssmArguments(const std::filesystem::path& file, double threshold);

struct DetectorValidation {
  std::string detector;
  std::uint64_t conflicts = 0;       // SSM conflicts with min TTC below the safe time
  std::uint64_t recalled = 0;        // ... that this detector also warned about
  std::vector<std::string> missed;   // "ego>foe@t" of the first few misses
  std::uint64_t warnings = 0;        // this detector's car-car warnings (episodes) by equipped egos
  std::uint64_t confirmed = 0;       // ... with an SSM encounter of the pair overlapping in time
  std::array<std::uint64_t, highway::kZoneCount> unseenByZone{};  // the rest, by zone
  // The same counting SSAM's types alone (highway/conflict.hpp: proximity warnings, zones meeting
  // with no collision course, left out): the conflicts that recalled an SSM conflict, the
  // conflicts among the car-car warnings and those SSM also saw.
  std::uint64_t recalledByConflicts = 0;
  std::uint64_t conflictWarnings = 0;
  std::uint64_t conflictsConfirmed = 0;
  // The shares, NaN when there is nothing to count (no conflict to recall, no warning to
  // confirm): a run without SSM conflicts has no recall, not a perfect one. JSON writes null.
  double recall() const { return share(recalled, conflicts); }
  double precision() const { return share(confirmed, warnings); }
  double conflictRecall() const { return share(recalledByConflicts, conflicts); }
  double conflictPrecision() const { return share(conflictsConfirmed, conflictWarnings); }
  static double share(std::uint64_t part, std::uint64_t whole) {
    return whole == 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(part) / static_cast<double>(whole);
  }
};

// The agreement of one measure on the cases both sides have: |ours - SSM's| against a tolerance.
struct Agreement {
  explicit Agreement(double tol) : tolerance(tol) {}
  double tolerance;
  std::uint64_t matched = 0;   // cases both have
  std::uint64_t within = 0;    // ... |error| <= tolerance
  double maxAbsError = std::numeric_limits<double>::quiet_NaN();   // NaN without a matched case
  double sumAbsError = 0.0;
  std::string worst;           // "ego>foe@t" of the largest error (when add() is told)
  void add(double absError, const std::string& what = {});
  double meanAbsError() const;    // NaN: none matched
  double withinFraction() const;  // NaN: none matched
};

struct ValidationReport {
  double deltaT = 0.0;
  std::uint64_t ssmConflicts = 0;
  std::uint64_t followingSamples = 0;   // SSM following-follower samples with a TTC
  // 1. of those, the samples where the box detector has a TTC too: |box - ssm| (s)
  Agreement ttc{0.02};
  // ... split by the pair's headings: the same (a car following in its lane, where SSM's gap along
  // the lanes is the straight one) or apart by more than kSameHeadingDeg (a turn: SSM's gap runs
  // along the curved lanes, the box TTC is SSAM's, on straight lines, so they differ by definition)
  Agreement ttcSameHeading{0.02}, ttcTurning{0.02};
  // and on those samples where SSM has a DRAC: ours (the closing speed of the centres over twice
  // the box TTC, conflicts.csv's) against SSM's (the speed difference squared over twice the gap),
  // |ours - SSM's| (m/s²)
  std::uint64_t dracSamples = 0;
  Agreement drac{0.1};
  // The same statistic without the time-stamp shift (for the record: shows why it is needed).
  std::uint64_t withinUnshifted = 0, matchedUnshifted = 0;
  std::vector<DetectorValidation> detectors;
  // 4. PET (s): SSM's conflicts with a PET, the box detector's episodes with one, and on the pairs
  // both have (same ordered pair, overlapping in time, the episode's PET horizon included)
  std::uint64_t ssmPets = 0, stsimPets = 0;
  Agreement pet{0.1};
  // ... of those, the ones whose SSM point lies off the other's path (SsmConflict::petOffPath
  // beyond kSsmPetOffPath: a PET of another place) and the agreement on the rest
  std::uint64_t petOffPath = 0;
  Agreement petOnPaths{0.1};
  // and the analyst's PET: SSM's encounters with a PET (each pair and PET time once: SSM logs an
  // encounter from both vehicles' devices), conflicts.csv's conflicts with one, and the encounters
  // both have (same pair, SSM's PET time within the conflict's begin and its end plus the PET
  // horizon): |conflicts.csv's PET - SSM's| (s)
  std::uint64_t ssmPetEncounters = 0, conflictPets = 0;
  Agreement conflictPet{0.1};
  std::uint64_t conflictPetOffPath = 0;  // as petOffPath, petOnPaths
  Agreement conflictPetOnPaths{0.1};
  // 5. the conflict point (m): the box detector's episodes with a contact point; of those, the
  // rear_end ones SSM has as a following sample with a TTC at the minimum-TTC tick (the distance between
  // the points, whatever the TTCs), and of these the ones where both see the same approach, SSM's
  // TTC within `tolerance` of ours: the distance, and its part along the leader's path
  std::uint64_t pointEpisodes = 0;
  Agreement pointAnyTtc{0.5}, point{0.5}, pointAlong{0.5};
  // the same episodes with SSM's point as it is, not moved on (for the record: shows why it is needed)
  Agreement pointUnconverted{0.5};
  // 6. the conflict point where paths cross or merge (m): the box detector's lane_change and
  // crossing episodes with a contact point that SSM has as a crossing or merging sample with a
  // leader at the minimum-TTC tick: SSM's point (where the later vehicle, the follower, enters the
  // conflict area) against ours along the follower's path, and the distance
  std::uint64_t crossingEpisodes = 0;
  Agreement crossingAlong{0.5}, crossingPoint{0.5};
  // 6b. the same like for like, from conflicts.csv: the conflicts whose paths meet where they cross
  // or merge (`paths_meet_x`), those SSM has as a crossing or merging sample at the minimum-TTC
  // tick, and the distance from SSM's point to the entry of the vehicle its type names as SSM
  // places it: at a merge the merge point, at a crossing half the other's width before the
  // crossing along its lane. Those with SSM's point more than kSsmPetOffPath off the other's lane
  // (SUMO's left turn split at its wait point) are counted apart, the rest compared on their own
  std::uint64_t pathsMeetConflicts = 0, pathsMeetOffPath = 0;
  Agreement pathsMeet{0.5}, pathsMeetOnPaths{0.5};
  // 7. how the paths meet: conflicts.csv's conflicts whose encounter is known (from the lanes),
  // those SSM logs the pair at the minimum-TTC tick with a class (ssmEncounterClassAt), and those
  // whose class is SSM's; counted by (ours, SSM's) too
  std::uint64_t encounterConflicts = 0, encounterMatched = 0, encounterAgree = 0;
  std::map<std::string, std::uint64_t> encounterPairs;  // "ours/ssm" -> count
  // 8. conflicts.csv's conflicts by encounter: how many, how many SSM logged with a finite TTC
  // during the conflict (begin to end, one step either side), and how many of the rest collided in
  // that time (SUMO's contact of the pair, where SSM logs no TTC), and how many of the rest came
  // closer than hindsight's clearance at SUMO's positions from its begin to the end of its PET
  // horizon (what happened next, for the encounters SSM cannot see). SSM predicts following, merging and crossing
  // (opposing is its crossing): `ssmModels` sums those; diverging (a car closing on a turner that
  // stands on another lane of the junction), adjacent and pedestrian are outside its model.
  struct EncounterPrecision {
    std::uint64_t conflicts = 0, seen = 0, collided = 0, close = 0;
  };
  std::map<std::string, EncounterPrecision> byEncounter;  // hw::toString(encounter), "unknown" too
  EncounterPrecision ssmModels;
  std::uint64_t conflicts() const {
    std::uint64_t n = 0;
    for (const auto& [name, p] : byEncounter) n += p.conflicts;
    return n;
  }
};
std::string toJson(const ValidationReport& r);
// The printed line: samples within tolerance and each detector's recall and precision, a figure
// with nothing to count said as such ("recall n/a (no SSM conflict below the safe time)").
std::string summaryLine(const ValidationReport& r);

// Runs the three detectors side by side on the same states and keeps a compact record of every
// vehicle's body per tick, to evaluate SSM's output after the run.
class SsmValidator {
 public:
  SsmValidator(const highway::RoadGeometry& road, const highway::MonitorConfig& base, double deltaT);
  ~SsmValidator();
  void record(double t, std::span<const highway::VehicleState> states);
  void finish(double t);
  // `contacts`: SUMO's collisions whose bodies touched (each once), the truth where SSM logs no TTC
  ValidationReport evaluate(const std::vector<SsmConflict>& conflicts, std::span<const SumoCollision> contacts = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace st::cosim
