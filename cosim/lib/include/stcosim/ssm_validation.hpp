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
// 2. Recall: every SSM conflict (any order of the pair, following types) whose minimum TTC is below
//    the ego's safe time at that moment must have raised a car-car warning for the same pair from
//    each detector (concentric, five-circle, box), running side by side on the same states.
// 3. Precision: the share of each detector's car-car warnings for which SSM recorded an encounter
//    of the same pair overlapping in time with a TTC; the rest are broken down by zone: warnings
//    SSM cannot see (lateral and lane-change conflicts, which SSM's following/merging/crossing
//    geometry does not cover).
#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <sthighway/detector.hpp>
#include <sthighway/monitor.hpp>

namespace st::cosim {

// SUMO's SSM encounter types used here (MSDevice_SSM::EncounterType).
inline constexpr int kSsmFollowing = 1;
inline constexpr int kSsmFollowingFollower = 2;
inline constexpr int kSsmFollowingLeader = 3;

struct SsmConflict {
  std::string ego, foe;
  double begin = 0.0, end = 0.0;
  std::vector<double> times;
  std::vector<int> types;
  std::vector<double> ttc;   // NaN where SSM has none ("NA")
  double minTtc = 0.0, minTtcTime = 0.0;
  int minTtcType = -1;
  bool hasMin = false;
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
  double recall() const { return conflicts == 0 ? 1.0 : static_cast<double>(recalled) / static_cast<double>(conflicts); }
  double precision() const { return warnings == 0 ? 1.0 : static_cast<double>(confirmed) / static_cast<double>(warnings); }
};

struct ValidationReport {
  double deltaT = 0.0;
  std::uint64_t ssmConflicts = 0;
  std::uint64_t followingSamples = 0;   // SSM following-follower samples with a TTC
  std::uint64_t matchedSamples = 0;     // ... where the box detector has a TTC too
  std::uint64_t within = 0;             // ... |box - ssm| <= tolerance
  double tolerance = 0.02;
  double maxAbsError = 0.0;
  double meanAbsError = 0.0;
  // The same statistic without the time-stamp shift (for the record: shows why it is needed).
  std::uint64_t withinUnshifted = 0, matchedUnshifted = 0;
  std::vector<DetectorValidation> detectors;
  double withinFraction() const {
    return matchedSamples == 0 ? 0.0 : static_cast<double>(within) / static_cast<double>(matchedSamples);
  }
};
std::string toJson(const ValidationReport& r);

// Runs the three detectors side by side on the same states and keeps a compact record of every
// vehicle's body per tick, to evaluate SSM's output after the run.
class SsmValidator {
 public:
  SsmValidator(const highway::RoadGeometry& road, const highway::MonitorConfig& base, double deltaT);
  ~SsmValidator();
  void record(double t, std::span<const highway::VehicleState> states);
  void finish(double t);
  ValidationReport evaluate(const std::vector<SsmConflict>& conflicts) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace st::cosim
