#pragma once
// The episode book: each equipped car's threats of a tick merged into its warning episodes (one
// per ego and foe or road feature group, from the first tick it holds to the first it no longer
// does), the exposure counters (TET, TIT), the tick's alerts and the finished warnings.
#include <array>
#include <vector>

#include <sthighway/monitor.hpp>

#include "conflict_capture.hpp"
#include "hindsight.hpp"
#include "pair_test.hpp"
#include "road_search.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

class EpisodeBook {
 public:
  EpisodeBook(const VehicleTable& cars, const LanePrediction& paths, const RoadSearch& road, Hindsight& hindsight,
              const MonitorConfig& config, MonitorCounters& counters)
      : cars_(&cars), paths_(&paths), road_(&road), hindsight_(&hindsight), cfg_(&config), counters_(&counters),
        petAngles_(PetAngles::of(config.conflict.rearEndBelowDeg)) {}

  // Time exposed and integrated deficit over the interval dt that just ended, from the threats of
  // its first tick.
  void accumulateExposure(double dt);
  // A new tick: per-slot state for the table's new slots, an empty alert list.
  void beginTick();
  // Ends every open episode of slot s at endTime.
  void close(int s, double endTime);
  // Merges ego e's threats of this tick (at time t) into its episodes. Sorts `threats`.
  void merge(int e, double t, std::vector<Threat>& threats);
  // After every ego's merge.
  void endTick() { std::swap(pool_, poolNext_); }

  std::vector<Warning>& finished() { return finished_; }
  std::vector<Warning> openWarnings() const;
  std::span<const Alert> alerts() const { return alerts_; }
  void recordTrajectories(bool on) { recordSeries_ = on; }
  void takeTrajectories(std::vector<TrajectoryPoint>& out) {
    out.clear();
    std::swap(out, series_);
  }
  void clearAlerts() { alerts_.clear(); }

 private:
  // An open warning, compact (no strings: the pool is rewritten every tick): the names are looked
  // up when it ends, while the foe's slot still holds it (a slot is reused no earlier than the
  // tick after its car left, and every episode against that car ends on that tick).
  struct Episode {
    std::uint64_t key = 0;
    int foe = -1;  // slot, or feature group
    WarningKind kind = WarningKind::Vehicle;
    Zone zone = Zone::Body;
    int capture = -1;  // into captures_: the state at the minimum TTC, kept out of the pool
    double begin = 0.0, end = 0.0, minTtc = 0.0, minTtcTime = 0.0, safeTimeAtMin = 0.0;
    int window = -1;  // its hindsight window (-1: hindsight off)
  };
  // what the exposure counters need of a car's threats at its last tick
  struct Exposure {
    std::array<double, kWarningKindCount> deficit{};
    std::array<bool, kWarningKindCount> exposed{};
  };

  Warning warningOf(int e, const Episode& ep, bool open) const;
  // an ended episode to hindsight, or straight to the finished warnings; its capture freed
  void emit(int e, const Episode& ep);
  int newCapture(int e, const Threat& th);
  // a new minimum TTC of a vehicle episode: its PET watch starts over there
  void startPetAt(ConflictCapture& c, int e, const Threat& th) const;
  // a later tick of episode ep (its ego e here at t): the track and the PET watch
  void advance(int e, const Episode& ep, double t);
  // the tick t of ego e's episode begun at `begin` against threat th, into the series
  void record(int e, const Threat& th, double begin, double t);
  void ensure(std::size_t n);

  const VehicleTable* cars_;
  const LanePrediction* paths_;  // the lane a capture reports
  const RoadSearch* road_;
  Hindsight* hindsight_;
  const MonitorConfig* cfg_;
  MonitorCounters* counters_;
  // Open episodes of every car, contiguous in the order the cars were processed at the last tick
  // (keys ascending per car): a tick reads them in that order and writes the next pool in the
  // same order, so the bookkeeping streams through memory instead of chasing per-car lists.
  std::vector<Episode> pool_, poolNext_;
  std::vector<int> openBegin_, openCount_;  // per slot, into pool_
  std::vector<Exposure> exposure_;          // per slot
  std::vector<ConflictCapture> captures_;  // by Episode::capture, slots reused (freeCaptures_)
  std::vector<int> freeCaptures_;
  std::vector<Warning> finished_;
  std::vector<Alert> alerts_;
  double tNow_ = 0.0;  // the tick being merged
  PetAngles petAngles_;
  bool recordSeries_ = false;
  std::vector<TrajectoryPoint> series_;  // recorded ticks not yet taken
};

}  // namespace st::highway::detail
