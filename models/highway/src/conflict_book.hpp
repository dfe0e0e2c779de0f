#pragma once
// The conflict book: SSAM's conflicts, one per unordered pair and continuous encounter, for the
// analyst (sthighway/monitor.hpp, Conflict). Apart from the warnings (what each driver gets,
// against its own safe time) and from the detector: every pair with an equipped car whose exact
// rectangles, moved on in straight lines at their velocities, touch within TTC*, found by a sweep
// along x whose reach bounds any such pair (so it finds what all pairs would), tick by tick.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include <sthighway/monitor.hpp>

#include "conflict_capture.hpp"
#include "lane_encounter.hpp"
#include "lane_prediction.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

// PET of a rear-end, as SSAM has it: from the first vehicle (the leader) leaving the conflict
// point to the second reaching it. The point is the predicted contact at the minimum TTC; the
// leader has left it once its back is past it, the follower reached it once its front is, each
// along its own heading at the minimum TTC, on the positions the two then take (timed between
// ticks by linear interpolation). Negative: the follower reached it before the leader had left
// (they met); NaN until both are seen.
struct RearPetWatch {
  bool active = false;
  Vec2 p = Vec2::Zero();
  int first = 0;                   // 0: the pair's a leads, 1: its b
  std::array<Vec2, 2> dir{};       // a's and b's heading
  std::array<double, 2> half{};    // half lengths
  std::array<double, 2> s{};       // last signed distance: the leader's back past p, the follower's front short of p
  double lastT = 0.0;
  double leave = std::numeric_limits<double>::quiet_NaN(), arrive = std::numeric_limits<double>::quiet_NaN();
  double pet() const {
    return active && !std::isnan(leave) && !std::isnan(arrive) ? arrive - leave : std::numeric_limits<double>::quiet_NaN();
  }
};
// A watch from the two bodies at time t, their minimum TTC `ttc` (moved on in straight lines);
// aNamedFirst: a's id is the smaller (SSAM's first when both fronts reach the point together).
void startRearPet(const Body& a, const Body& b, double ttc, double t, bool aNamedFirst, RearPetWatch& w);
// The same from the two bodies at the predicted contact (atA, atB: where and how each is headed
// then; conflicts.csv predicts a car at a merge along its lanes).
void startRearPet(const Body& a, const Body& b, const Body& atA, const Body& atB, double t, bool aNamedFirst,
                  RearPetWatch& w);
// The two centres at a later tick t (NaN: that one is gone).
void observeRearPet(const Vec2& ca, const Vec2& cb, double t, RearPetWatch& w);

class ConflictBook {
 public:
  ConflictBook(const VehicleTable& cars, const LanePrediction& paths, const MonitorConfig& config, MonitorCounters& counters)
      : cars_(&cars), paths_(&paths), cfg_(&config), counters_(&counters),
        petAngles_(PetAngles::of(config.conflict.rearEndBelowDeg)) {}

  // This tick (t; the previous tick at lastT, -inf at the first), after the table's update and
  // before its release: the pairs below TTC* into their encounters, the encounters not seen again
  // closed (at t; at lastT when one of the two left), the waiting PETs observed.
  void observe(double t, double lastT);
  // Closes every encounter at t and settles every waiting PET with what it has.
  void finish(double t);
  void take(std::vector<Conflict>& out) {
    out.clear();
    std::swap(out, settled_);
  }

 private:
  // An encounter going on: the pair's slots (a has the lower serial), its state at the minimum TTC.
  struct Encounter {
    int a = -1, b = -1;
    std::uint64_t seen = 0;  // the tick it was last below TTC*
    double begin = 0.0, minTtc = 0.0, minTtcTime = 0.0, tet = 0.0, tit = 0.0;
    Body bodyA, bodyB;       // at the minimum TTC
    Body contactA, contactB; // ... moved on to their predicted contact (straight, or along the lanes at a merge)
    int laneA = -1, laneB = -1;
    LaneMeeting meeting;  // how and where the paths meet, from the lanes, at the minimum TTC
    EpisodeTrack trackA, trackB;  // each vehicle's as ego (start, end, MaxS, DR, MaxD)
    PetWatch pet;
    RearPetWatch rearPet;
  };
  // A conflict whose encounter ended, its PET still to come (until `until`).
  struct Waiting {
    Conflict conflict;
    int a = -1, b = -1;
    std::uint64_t serialA = 0, serialB = 0;
    double until = 0.0;
    PetWatch pet;
    RearPetWatch rearPet;
    bool rearEnd = false;  // which of the two watches gives its PET
    double petNow(bool settled = false) const { return rearEnd ? rearPet.pet() : pet.pet(settled); }
  };
  using Key = std::pair<std::uint64_t, std::uint64_t>;

  void candidates();
  // The pair's box TTC within TTC* and the bodies at the contact: in straight lines, or along
  // their lanes when one of them is at a merge (LanePrediction::atMerge).
  Impact pairTtc(int a, int b, double maxTtc, Body& atA, Body& atB) const;
  LaneMeeting encounterOf(int a, int b, double ttc);
  std::string approachOf(int lane) const;
  void touch(int a, int b, double ttc, const Body& atA, const Body& atB, double t, double dt);
  void close(Encounter& en, double end, bool open);
  void settle(Conflict&& c, double pet);

  const VehicleTable* cars_;
  const LanePrediction* paths_;
  const MonitorConfig* cfg_;
  MonitorCounters* counters_;
  PetAngles petAngles_;
  std::uint64_t tick_ = 0;
  std::map<Key, Encounter> open_;  // ordered: closing order is the serials', deterministic
  std::vector<Waiting> waiting_;
  std::vector<Conflict> settled_;
  struct SweepEntry {
    double x;  // the centre's
    int slot;
    double halfDiagonal, speed;
  };
  std::vector<SweepEntry> sweep_;  // scratch
  std::vector<int> lanesA_, lanesB_;  // scratch: the lanes ahead of a pair (lane_encounter.hpp)
};

}  // namespace st::highway::detail
