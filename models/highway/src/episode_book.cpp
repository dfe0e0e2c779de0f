#include "episode_book.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace st::highway::detail {

void EpisodeBook::ensure(std::size_t n) {
  if (openBegin_.size() >= n) return;
  openBegin_.resize(n);
  openCount_.resize(n);
  exposure_.resize(n);
}

void EpisodeBook::accumulateExposure(double dt) {
  for (int s : cars_->active)
    for (int k = 0; k < kWarningKindCount; ++k)
      if (exposure_[s].exposed[k]) {
        counters_->tet[k] += dt;
        counters_->tit[k] += dt * exposure_[s].deficit[k];
      }
}

void EpisodeBook::beginTick() {
  ensure(cars_->slots.size());
  for (int s : cars_->arrived) {
    openCount_[s] = 0;
    exposure_[s] = Exposure{};
  }
  alerts_.clear();
  poolNext_.clear();
}

Warning EpisodeBook::warningOf(int e, const Episode& ep, bool open) const {
  const auto& slots = cars_->slots;
  Warning w;
  w.ego = slots[e].id;
  w.foe = ep.kind == WarningKind::Vehicle ? slots[ep.foe].id : road_->groupName(ep.foe);
  w.kind = ep.kind;
  w.zone = ep.zone;
  w.begin = ep.begin;
  w.end = ep.end;
  w.minTtc = ep.minTtc;
  w.minTtcTime = ep.minTtcTime;
  w.safeTimeAtMin = ep.safeTimeAtMin;
  w.open = open;
  const ConflictCapture& c = captures_[ep.capture];
  const bool vehicle = ep.kind == WarningKind::Vehicle;
  const bool pedestrian = vehicle && (cars_->vclass[e] == VehicleClass::Pedestrian ||
                                      cars_->vclass[ep.foe] == VehicleClass::Pedestrian);
  describeConflict(c, ep.kind, cars_->mass[e], vehicle ? cars_->mass[ep.foe] : 0.0, pedestrian, ep.minTtc, ep.safeTimeAtMin,
                   cfg_->detector, road_->features(), cfg_->conflict, w);
  w.lane = cars_->laneId(c.lane);
  if (c.feature >= 0) w.line = road_->features().features[c.feature].name;
  return w;
}


int EpisodeBook::newCapture(int e, const Threat& th) {
  int c;
  if (freeCaptures_.empty()) {
    c = static_cast<int>(captures_.size());
    captures_.emplace_back();
  } else {
    c = freeCaptures_.back();
    freeCaptures_.pop_back();
  }
  capture(*cars_, paths_->reportedLane(e), e, th, captures_[c]);
  beginTrack(*cars_, e, th.kind == WarningKind::Vehicle ? th.foe : -1, captures_[c].track);
  startPetAt(captures_[c], e, th);
  return c;
}

void EpisodeBook::startPetAt(ConflictCapture& c, int e, const Threat& th) const {
  if (th.kind == WarningKind::Vehicle)
    startPet(c.ego, c.foe, paths_->laneWidth(e), paths_->laneWidth(th.foe), tNow_, petAngles_, c.pet);
}

void EpisodeBook::advance(int e, const Episode& ep, double t) {
  ConflictCapture& c = captures_[ep.capture];
  const bool vehicle = ep.kind == WarningKind::Vehicle;
  advanceTrack(*cars_, e, vehicle ? ep.foe : -1, c.track);
  if (vehicle) {
    const bool foeHere = cars_->inputOf[ep.foe] >= 0;
    observePet(cars_->front(e), foeHere ? cars_->front(ep.foe) : Vec2::Constant(std::numeric_limits<double>::quiet_NaN()), t,
               c.pet);
  }
}

void EpisodeBook::record(int e, const Threat& th, double begin, double t) {
  const auto& slots = cars_->slots;
  series_.push_back({slots[e].id, th.kind == WarningKind::Vehicle ? slots[th.foe].id : road_->groupName(th.foe), th.kind, begin,
                     t, th.ttc, tickDrac(*cars_, road_->features(), e, th)});
}

void EpisodeBook::emit(int e, const Episode& ep) {
  Warning w = warningOf(e, ep, false);
  ++counters_->warningsByType[static_cast<int>(w.type)];
  // a crossing or merging conflict whose PET is still to come: hindsight watches on
  const PetWatch& pet = captures_[ep.capture].pet;
  const bool petPending = pet.active && std::isnan(w.pet) && crossesPaths(w.type);
  freeCaptures_.push_back(ep.capture);
  if (ep.window >= 0) hindsight_->finished(std::move(w), ep.window, petPending ? &pet : nullptr);
  else finished_.push_back(std::move(w));
}

void EpisodeBook::close(int s, double endTime) {
  Episode* open = pool_.data() + openBegin_[s];
  for (int k = 0; k < openCount_[s]; ++k) {
    open[k].end = endTime;
    emit(s, open[k]);
  }
  openCount_[s] = 0;
  exposure_[s].exposed.fill(false);
}

void EpisodeBook::merge(int e, double t, std::vector<Threat>& threats) {
  tNow_ = t;
  Episode* open = pool_.data() + openBegin_[e];
  const int nOpen = openCount_[e];
  openBegin_[e] = static_cast<int>(poolNext_.size());
  Exposure& x = exposure_[e];
  x.exposed.fill(false);
  x.deficit.fill(0.0);
  if (threats.empty() && nOpen == 0) return;  // the common case: nothing now, nothing before
  // the worst threat per key, keys ascending: the smallest TTC, on a tie the longer safe time
  // (the larger deficit), then the zone. A total order, so the episodes and the alert do not
  // depend on the order the searches found the threats in.
  if (threats.size() > 1) std::sort(threats.begin(), threats.end(), [](const Threat& a, const Threat& b) {
    if (a.key != b.key) return a.key < b.key;
    if (a.ttc != b.ttc) return a.ttc < b.ttc;
    if (a.safe != b.safe) return a.safe > b.safe;
    return a.zone < b.zone;
  });
  threats.erase(std::unique(threats.begin(), threats.end(), [](const Threat& a, const Threat& b) { return a.key == b.key; }),
                threats.end());
  // episodes without a threat end, those with one go on, new keys begin
  const int nThreats = static_cast<int>(threats.size());
  int i = 0, j = 0;
  while (i < nOpen || j < nThreats) {
    if (j == nThreats || (i < nOpen && open[i].key < threats[j].key)) {
      Episode& ep = open[i++];
      ep.end = t;
      // the ego is here at its end: the track's last tick (the foe counted if still here)
      advance(e, ep, t);
      emit(e, ep);
      continue;
    }
    const Threat& th = threats[j++];
    if (i < nOpen && open[i].key == th.key) {
      // copied whole, then updated in the copy (updating the old one first stalls the copy's
      // loads on the stores just made)
      Episode& ep = poolNext_.emplace_back(open[i++]);
      ep.end = t;
      advance(e, ep, t);
      if (th.ttc < ep.minTtc) {
        ep.minTtc = th.ttc;
        ep.minTtcTime = t;
        ep.safeTimeAtMin = th.safe;
        capture(*cars_, paths_->reportedLane(e), e, th, captures_[ep.capture]);
        startPetAt(captures_[ep.capture], e, th);
      }
      if (recordSeries_) record(e, th, ep.begin, t);
      continue;
    }
    const int window = hindsight_->enabled() ? hindsight_->open(e, th.foe, th.kind, t, th.safe) : -1;
    poolNext_.push_back({th.key, th.foe, th.kind, th.zone, newCapture(e, th), t, t, th.ttc, t, th.safe, window});
    ++counters_->warningsBegun;
    if (recordSeries_) record(e, th, t, t);
    ++counters_->warningsByKind[static_cast<int>(th.kind)];
    ++counters_->warningsByZone[static_cast<int>(th.zone)];
  }
  openCount_[e] = static_cast<int>(poolNext_.size()) - openBegin_[e];
  // exposure and the alert
  const Threat* worst = nullptr;
  for (const Threat& th : threats) {
    const int k = static_cast<int>(th.kind);
    x.exposed[k] = true;
    x.deficit[k] = std::max(x.deficit[k], th.safe - th.ttc);
    if (!worst || th.ttc * worst->safe < worst->ttc * th.safe) worst = &th;
  }
  const std::vector<int>& inputOf = cars_->inputOf;
  if (worst)
    alerts_.push_back({inputOf[e], worst->kind, worst->zone, worst->ttc, worst->safe,
                       worst->kind == WarningKind::Vehicle ? inputOf[worst->foe] : -1});
}

std::vector<Warning> EpisodeBook::openWarnings() const {
  std::vector<Warning> out;
  for (int s : cars_->active)
    for (int k = 0; k < openCount_[s]; ++k) out.push_back(warningOf(s, pool_[openBegin_[s] + k], true));
  return out;
}

}  // namespace st::highway::detail
