#pragma once
// Hindsight: did the warned conflict happen? A warning is a prediction; the following ticks show
// what happened (online, from the states the monitor sees anyway; no second pass):
//   vehicle warnings: the smallest body-to-body clearance between ego and foe from the warning's
//     begin to begin + safe time + 1 s, when it occurred, and the strongest deceleration either
//     vehicle applied in that window (from its speeds tick to tick, whatever the source reports);
//   curb, lane-marker and hazard warnings: whether the body touched that line (or hazard) within
//     the safe time, and whether the turn signal of that side was on when it first did.
// A warning is confirmed when the clearance fell below HindsightConfig::clearance (a collision
// included), a vehicle braked beyond its own decel (SUMO's vType decel; hindsight.evasive_deceleration when unknown), a curb or hazard was touched,
// or a lane marker was crossed unsignalled; a nuisance otherwise. Finished warnings are held until
// their window closes (or a vehicle leaves) and handed on in the order they finished, a tick's
// together once all of them are judged (so what is handed on does not depend on the input order).
//
// Recall: the run's near misses (two bodies, one of them equipped, closer than the clearance while
// closing; one event per approach), found by a sweep of its own along the traffic's long axis (the
// pair search's candidates would not do: they are the pairs that may warn, and two cars closing
// slowly 0.3 m apart need not; stcore's uniform grid finds the same events but costs 3.4 % more of
// a step, bench/highway_detect at 1e4 cars), and
// whether an episode between the two was open `lead` seconds before (its lead time: how long
// before the event it began).
#include <cmath>
#include <cstdint>
#include <array>
#include <deque>
#include <optional>
#include <unordered_set>
#include <utility>
#include <vector>

#include <stcore/box2.hpp>
#include <sthighway/monitor.hpp>

#include "conflict_capture.hpp"
#include "lane_prediction.hpp"
#include "road_search.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

class Hindsight {
 public:
  // frames: the lane frames road warnings are judged in (a car on no lane: against the line's
  // polyline)
  Hindsight(const MonitorConfig& config, const VehicleTable& cars, const RoadSearch& road, const LanePrediction& frames,
            MonitorCounters& counters)
      : cfg_(&config), cars_(&cars), road_(&road), frames_(&frames), counters_(&counters) {}

  bool enabled() const { return cfg_->hindsight.enabled; }
  // A new episode of ego slot e against foe (slot or feature group) at time t: its window opens.
  // Returns the window's id (for finished()).
  int open(int e, int foe, WarningKind kind, double t, double safe);
  // An episode ended: its warning waits for its window's verdict, and for its PET if `pet` (a
  // crossing or merging conflict whose vehicles have not both passed the conflict area yet: watched
  // on for up to kPetHorizon s, from where the episode left it).
  void finished(Warning&& w, int window, const PetWatch* pet = nullptr);
  // After a tick's detection: the windows measure this tick's states, near misses are found.
  void observe(double t);
  // Warnings whose windows have closed, in the order they finished, appended to out.
  void release(std::vector<Warning>& out);
  // Closes every window with what it saw (the run ends) and releases everything.
  void finishAll(std::vector<Warning>& out);
  // The events found since the last call (into out, replacing its contents).
  void takeEvents(std::vector<HindsightEvent>& out) {
    out.clear();
    std::swap(out, events_);
  }

 private:
  struct Window {
    std::uint64_t egoSerial = 0, foeSerial = 0;  // foeSerial 0: a road feature group
    int ego = -1, foe = -1;
    WarningKind kind = WarningKind::Vehicle;
    double begin = 0.0, end = 0.0;  // s, measured while t <= end
    double clearance = 0.0, clearanceTime = 0.0, deceleration = 0.0;
    bool measured = false, crossed = false, signalled = false, closed = false;
    bool evasive = false;  // either vehicle braked beyond its own decel (evasiveThreshold)
    bool petLive = false;  // its PET still watched (livePets_)
    double pet = std::numeric_limits<double>::quiet_NaN();  // the PET watching found (s)
  };
  // A PET still to come, watched after its episode ended (apart from the windows, which most
  // warnings use without one)
  struct LivePet {
    int window = -1;
    double until = 0.0;
    PetWatch watch;
  };
  struct Pending {
    Warning warning;
    int window;
    std::uint64_t tick;  // the tick it ended in: a tick's warnings are released together
  };
  // The two vehicles one or more vehicle windows watch (either direction, episodes in a row; found
  // through the two cars' episode lists when a window opens): both still here, their boxes and the
  // gap bound taken once a tick for all of them, the clearance on demand. distance() and separation() of two boxes are symmetric bit for bit, so a window reads
  // the numbers it would compute itself.
  struct Track {
    std::uint64_t key = 0;  // pairKey of the serials
    int a = -1, b = -1;
    std::uint64_t serialA = 0, serialB = 0;
    int windows = 0;  // live windows on it (0: free)
    bool here = false, hasDist = false;
    double sep = 0.0, dist = 0.0;
    Box2 boxA{Vec2::Zero(), Vec2(1.0, 0.0), Vec2::Zero()}, boxB{Vec2::Zero(), Vec2(1.0, 0.0), Vec2::Zero()};
  };
  // A vehicle window while it measures, dense (written back to its Window when it closes).
  struct LiveVehicle {
    int id, track, ego, foe;
    double end;
    double clearance = 0.0, clearanceTime = 0.0, deceleration = 0.0;
    bool measured = false, evasive = false;
  };
  // An episode, for recall: of its ego (the car whose list holds it) against a vehicle (foe: its
  // serial) or a line group (foe: kLineBit | group). The episodes of a pair are the two cars'
  // lists' against each other (direction-blind), so no map of pairs is kept.
  struct PastEpisode {
    std::uint64_t foe;
    double begin, end;  // end: +inf while open
    int track;          // its window's track (-1: none; a track is valid while it has windows and the pair's key)
    int next;           // the next older in its ego's list (-1: none); the next free one when free
  };
  static constexpr std::uint64_t kLineBit = std::uint64_t{1} << 63;

  bool alive(const Window& w) const;
  int trackFor(int e, int foe, std::uint64_t key);
  // The episode list of slot s's car, its head: the slot's earlier car's episodes freed first.
  int& listOf(int s);
  // The head of slot s's episode list for reading (-1: none, or the list of the slot's earlier car).
  int firstOf(int s) const {
    return s < static_cast<int>(listHead_.size()) && listOwner_[s] == cars_->slots[s].serial ? listHead_[s] : -1;
  }
  // A new episode of ego slot e at t, at the head of its list (what is over for good dropped).
  void addEpisode(int e, std::uint64_t foe, double t, int track);
  int freeEpisode(int i);
  // The open episodes of ego slot e against foe end at `end`.
  void endEpisodes(int e, std::uint64_t egoSerial, std::uint64_t foe, double end);
  // Drops the episodes that ended before `before` (freed lists of cars gone).
  void pruneEpisodes(double before);
  void measureTracks();
  void measureVehicles(double t);
  // The braking (m/s^2) beyond which slot s's braking is evasive: its own decel (SUMO's vType
  // decel: beyond it SUMO brakes in an emergency) when known, with kDecelSlack for the speed
  // differences' rounding; else hindsight.evasive_deceleration.
  double evasiveThreshold(int s) const {
    const double d = cars_->decel[s];
    return std::isnan(d) ? cfg_->hindsight.evasiveDeceleration : d + kDecelSlack;
  }
  static constexpr double kDecelSlack = 0.01;  // m/s^2
  void closeVehicle(std::size_t i);
  void measure(Window& w, double t);
  void watchPets(double t);
  void judge(Warning& w, const Window& win);
  // The near misses' stages: the axis the cars spread along most and the largest envelope; the
  // cars sorted along it (order_); their state loaded contiguous (sweep*_, the largest half
  // diagonal returned); the sweep over them, which fills nearNow_ and records the new ones.
  void findNearMisses(double t);
  struct SweepSpread {
    int axis;     // 0: x, 1: y
    double rmax;  // m, the largest envelope
  };
  static SweepSpread spreadOf(const VehicleTable& c);
  void sortAlong(int axis);
  double loadSweep();
  void sweepNearMisses(double t, int axis, double reach, double hmax);
  std::optional<double> nearMissGap(int a, int b, const Vec2& p) const;
  void noteNearMiss(int a, int b, double gap, double t);
  void findCrossings(double t);
  // Of the episodes of slot a against foe (and of slot b against fromB, if b >= 0) still open
  // `lead` s before t or later, begun by t: how long before t the earliest began (NaN: none), and
  // whether one was open `lead` s before t (recall's test).
  struct Lead {
    double lead;
    bool warned;
  };
  Lead leadOf(int a, std::uint64_t foe, int b, std::uint64_t fromB, double t) const;
  void leadIn(int head, std::uint64_t foe, double t, Lead& out) const;
  // An event of ego slot e at t: counted by its kind, its lead time kept if warned, listed.
  void record(HindsightEvent&& ev, int e, double t, const Lead& lead);
  static std::uint64_t pairKey(std::uint64_t a, std::uint64_t b) {
    return a < b ? (a << 32) | b : (b << 32) | a;
  }

  const MonitorConfig* cfg_;
  const VehicleTable* cars_;
  const RoadSearch* road_;
  const LanePrediction* frames_;
  MonitorCounters* counters_;
  std::vector<HindsightEvent> events_;
  std::vector<Window> windows_;
  std::vector<int> freeWindows_;
  std::vector<int> live_;  // road windows still measuring
  std::vector<LivePet> livePets_;
  std::vector<LiveVehicle> liveVehicles_;  // vehicle windows still measuring
  std::vector<std::uint64_t> serialOf_;    // per slot: the serial of the car that holds it
  std::vector<Track> tracks_;
  std::vector<int> freeTracks_;
  std::deque<Pending> pending_;
  // the episodes, newest first in a list per slot (of the car listOwner_ names), in one pool
  std::vector<PastEpisode> episodes_;
  int freeEpisode_ = -1;
  std::vector<int> listHead_;
  std::vector<std::uint64_t> listOwner_;
  std::vector<std::array<int, 2>> touching_;  // per slot: the lines (groups) its body touched last tick
  std::vector<char> along_;                    // per slot: alongside its lane last tick (its lines applied)
  std::unordered_set<std::uint64_t> nearBefore_, nearNow_;
  std::vector<std::pair<double, int>> order_;  // the sweep's order (coordinate, slot), kept
  // the sweep's cars in its order, contiguous: centre, velocity, half diagonal, equipped
  std::vector<Vec2> sweepCentre_, sweepVel_;
  std::vector<double> sweepHalfDiag_;
  std::vector<char> sweepEquipped_;
  std::vector<std::uint64_t> seen_;            // per slot: the sweep that ordered it
  std::uint64_t stamp_ = 0;
  double lastPrune_ = 0.0;
  std::uint64_t tick_ = 0;
};

}  // namespace st::highway::detail
