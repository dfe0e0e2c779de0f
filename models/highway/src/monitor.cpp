#include <sthighway/monitor.hpp>
#include <sthighway/settings.hpp>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "conflict_book.hpp"
#include "episode_book.hpp"
#include "hindsight.hpp"
#include "lane_prediction.hpp"
#include "pair_search.hpp"
#include "road_search.hpp"
#include "vehicle_table.hpp"

namespace st::highway {

const char* toString(Broadphase b) { return b == Broadphase::Cells ? "cells" : "all-pairs"; }
bool parseBroadphase(const std::string& text, Broadphase& out) {
  if (text == "cells") out = Broadphase::Cells;
  else if (text == "all-pairs" || text == "allpairs") out = Broadphase::AllPairs;
  else return false;
  return true;
}

const char* toString(Prediction p) { return p == Prediction::Road ? "road" : "straight"; }
bool parsePrediction(const std::string& text, Prediction& out) {
  if (text == "road") out = Prediction::Road;
  else if (text == "straight") out = Prediction::Straight;
  else return false;
  return true;
}

const char* toString(WarningKind k) {
  switch (k) {
    case WarningKind::Vehicle: return "vehicle";
    case WarningKind::Curb: return "curb";
    case WarningKind::LaneMarker: return "lane_marker";
    case WarningKind::Hazard: return "hazard";
  }
  return "vehicle";
}

const char* toString(EventKind k) { return k == EventKind::NearMiss ? "near_miss" : "crossing"; }

const char* toString(Verdict v) {
  switch (v) {
    case Verdict::Unjudged: return "";
    case Verdict::Confirmed: return "confirmed";
    case Verdict::Nuisance: return "nuisance";
  }
  return "";
}

namespace {

// The cells cover the road's features; a network without extent (none, or one point) gets room.
RoadFeatures cellBounds(RoadFeatures f) {
  if (f.bounds.extent().minCoeff() <= 0.0) f.bounds = {f.bounds.min.array() - 100.0, f.bounds.max.array() + 100.0};
  return f;
}

std::vector<std::string> laneIdsOf(const RoadGeometry& road) {
  std::vector<std::string> ids;
  ids.reserve(road.lanes.size());
  for (const Lane& l : road.lanes) ids.push_back(l.id);
  return ids;
}

}  // namespace

// The stages of a tick, each a part of its own (the step below calls them in order):
//   cars    the vehicle table: who is here, their hot state       (vehicle_table.cpp)
//   paths   each car's lane frame and predicted path (road prediction) (lane_prediction.cpp)
//   pairs   who is near whom, and the car-car threats              (cell_pair_search.cpp, all_pairs_search.cpp)
//   road    which road features an ego may reach, and their threats (road_search.cpp)
//   book    threats into episodes, exposure, alerts, warnings      (episode_book.cpp)
//   judge   what happened next: each warning's verdict, near misses (hindsight.cpp)
//   conflicts  SSAM's conflicts, one per pair and encounter below TTC*, whatever the detector (conflict_book.cpp)
struct HighwayMonitor::Impl {
  MonitorConfig cfg;
  MonitorCounters counters;
  detail::VehicleTable cars;
  detail::LanePrediction prediction;
  detail::RoadSearch road;
  CellNetwork cells;
  std::unique_ptr<detail::PairSearch> pairs;
  detail::Hindsight hindsight;
  detail::EpisodeBook book;
  detail::ConflictBook conflicts;
  std::vector<detail::Threat> threats;  // scratch: one ego's
  double lastT = -std::numeric_limits<double>::infinity();
  bool started = false;

  Impl(const RoadGeometry& geometry, const MonitorConfig& config)
      : cfg((checkSettings(config), config)),
        cars(cfg, counters, laneIdsOf(geometry)),
        prediction(geometry, cfg, cars, counters),
        road(geometry, cfg, cars, prediction, counters),
        cells(geometry, cellBounds(road.features()), cfg.cells),
        hindsight(cfg, cars, road, prediction, counters),
        book(cars, prediction, road, hindsight, cfg, counters),
        conflicts(cars, prediction, cfg, counters) {
    const detail::PairTest test{&cfg, &cars, &counters, &prediction};
    pairs = cfg.broadphase == Broadphase::Cells ? detail::makeCellPairSearch(test, cells) : detail::makeAllPairsSearch(test);
  }
};

HighwayMonitor::HighwayMonitor(const RoadGeometry& road, const MonitorConfig& config)
    : impl_(std::make_unique<Impl>(road, config)) {}

HighwayMonitor::~HighwayMonitor() = default;
HighwayMonitor::HighwayMonitor(HighwayMonitor&&) noexcept = default;
HighwayMonitor& HighwayMonitor::operator=(HighwayMonitor&&) noexcept = default;

void HighwayMonitor::step(double t, std::span<const VehicleState> vehicles) {
  Impl& m = *impl_;
  if (!std::isfinite(t)) throw std::invalid_argument("step time must be finite");
  if (m.started && !(t > m.lastT)) throw std::invalid_argument("step times must increase strictly");
  if (m.started) m.book.accumulateExposure(t - m.lastT);
  // who is here; the episodes of the cars that left end at their last tick
  m.cars.update(t, vehicles);
  m.prediction.update(t);
  m.book.beginTick();
  for (int s : m.cars.departed) m.book.close(s, m.lastT);
  ++m.counters.ticks;
  // the analyst's conflicts, apart from the warnings (before the departed slots are freed)
  m.conflicts.observe(t, m.lastT);
  // who is near whom, and which road features
  m.pairs->prepare();
  if (m.cfg.checkRoad) m.road.prepare(m.pairs->groups());
  m.cars.release();
  // each equipped ego's threats into its episodes, in input order
  for (int s : m.cars.active) {
    if (!m.cars.equipped[s]) {
      m.book.close(s, t);
      continue;
    }
    m.threats.clear();
    m.pairs->threatsOf(s, m.threats);
    if (m.cfg.checkRoad) m.road.threatsOf(s, m.pairs->groupOf(s), m.threats);
    m.book.merge(s, t, m.threats);
  }
  m.book.endTick();
  if (m.hindsight.enabled()) {
    m.hindsight.observe(t);
    m.hindsight.release(m.book.finished());
  }
  m.lastT = t;
  m.started = true;
}

void HighwayMonitor::finish(double t) {
  Impl& m = *impl_;
  if (m.started && t > m.lastT) m.book.accumulateExposure(t - m.lastT);
  for (int s : m.cars.active) m.book.close(s, std::max(t, m.lastT));
  m.hindsight.finishAll(m.book.finished());
  m.book.clearAlerts();
  m.conflicts.finish(std::max(t, m.lastT));
}

std::vector<Warning> HighwayMonitor::takeFinished() {
  std::vector<Warning> out;
  takeFinished(out);
  return out;
}
void HighwayMonitor::takeFinished(std::vector<Warning>& out) {
  out.clear();
  out.swap(impl_->book.finished());
}

void HighwayMonitor::takeConflicts(std::vector<Conflict>& out) { impl_->conflicts.take(out); }
void HighwayMonitor::takeEvents(std::vector<HindsightEvent>& out) { impl_->hindsight.takeEvents(out); }
void HighwayMonitor::recordTrajectories(bool on) { impl_->book.recordTrajectories(on); }
void HighwayMonitor::takeTrajectories(std::vector<TrajectoryPoint>& out) { impl_->book.takeTrajectories(out); }

std::vector<Warning> HighwayMonitor::openWarnings() const { return impl_->book.openWarnings(); }
std::span<const Alert> HighwayMonitor::alerts() const { return impl_->book.alerts(); }
const MonitorCounters& HighwayMonitor::counters() const { return impl_->counters; }
const MonitorConfig& HighwayMonitor::config() const { return impl_->cfg; }
const RoadFeatures& HighwayMonitor::features() const { return impl_->road.features(); }
const CellNetwork& HighwayMonitor::cells() const { return impl_->cells; }
double HighwayMonitor::lastTime() const { return impl_->lastT; }

}  // namespace st::highway
