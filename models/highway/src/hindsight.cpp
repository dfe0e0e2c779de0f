#include "hindsight.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <stcore/box2.hpp>
#include <stcore/toi.hpp>
#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

int Hindsight::open(int e, int foe, WarningKind kind, double t, double safe) {
  int id;
  if (!freeWindows_.empty()) {
    id = freeWindows_.back();
    freeWindows_.pop_back();
  } else {
    id = static_cast<int>(windows_.size());
    windows_.emplace_back();
  }
  Window& w = windows_[id];
  w = Window{};
  w.ego = e;
  w.foe = foe;
  w.kind = kind;
  w.egoSerial = cars_->slots[e].serial;
  w.begin = t;
  // a vehicle warning's conflict may come a little after its safe time (the margin of the report's
  // prediction): one more second is watched
  w.end = t + safe + (kind == WarningKind::Vehicle ? 1.0 : 0.0);
  if (kind == WarningKind::Vehicle) {
    w.foeSerial = cars_->slots[foe].serial;
    const int track = trackFor(e, foe, pairKey(w.egoSerial, w.foeSerial));
    liveVehicles_.push_back({id, track, e, foe, w.end});
    addEpisode(e, w.foeSerial, t, track);
    return id;
  }
  if (kind != WarningKind::Hazard) addEpisode(e, kLineBit | static_cast<std::uint32_t>(foe), t, -1);
  live_.push_back(id);
  return id;
}

void Hindsight::finished(Warning&& w, int window, const PetWatch* pet) {
  Window& win = windows_[window];
  if (pet) {
    win.petLive = true;
    livePets_.push_back({window, w.end + kPetHorizon, *pet});
  }
  if (win.kind == WarningKind::Vehicle) endEpisodes(win.ego, win.egoSerial, win.foeSerial, w.end);
  else if (win.kind != WarningKind::Hazard)
    endEpisodes(win.ego, win.egoSerial, kLineBit | static_cast<std::uint32_t>(win.foe), w.end);
  pending_.push_back({std::move(w), window, tick_});
}

// The track of the pair (slots e and foe, serials' key), shared by every live window on it: the
// live track an episode of either car against the other names, else a new one.
int Hindsight::trackFor(int e, int foe, std::uint64_t key) {
  const std::uint64_t serialE = cars_->slots[e].serial, serialF = cars_->slots[foe].serial;
  auto find = [&](int head, std::uint64_t other) {
    for (int i = head; i >= 0; i = episodes_[i].next) {
      const PastEpisode& pe = episodes_[i];
      if (pe.foe == other && pe.track >= 0 && tracks_[pe.track].windows > 0 && tracks_[pe.track].key == key) return pe.track;
    }
    return -1;
  };
  int id = find(firstOf(e), serialF);
  if (id < 0) id = find(firstOf(foe), serialE);
  if (id < 0) {
    if (!freeTracks_.empty()) {
      id = freeTracks_.back();
      freeTracks_.pop_back();
    } else {
      id = static_cast<int>(tracks_.size());
      tracks_.emplace_back();
    }
    Track& tr = tracks_[id];
    tr = Track{};
    tr.key = key;
    tr.a = e;
    tr.b = foe;
    tr.serialA = serialE;
    tr.serialB = serialF;
  }
  ++tracks_[id].windows;
  return id;
}

int& Hindsight::listOf(int s) {
  if (listHead_.size() <= static_cast<std::size_t>(s)) {
    listHead_.resize(cars_->slots.size(), -1);
    listOwner_.resize(cars_->slots.size(), 0);
  }
  const std::uint64_t serial = cars_->slots[s].serial;
  if (listOwner_[s] != serial) {
    while (listHead_[s] >= 0) listHead_[s] = freeEpisode(listHead_[s]);
    listOwner_[s] = serial;
  }
  return listHead_[s];
}

// Frees episode i; returns the one after it in its list.
int Hindsight::freeEpisode(int i) {
  const int next = episodes_[i].next;
  episodes_[i].next = freeEpisode_;
  freeEpisode_ = i;
  return next;
}

void Hindsight::addEpisode(int e, std::uint64_t foe, double t, int track) {
  int& head = listOf(e);
  // on the way: the car's episodes over before the earliest time a lead can reach back to (an
  // event at t or later asks of none of them), so its list stays as short as its recent past
  const double before = t - cfg_->hindsight.lead;
  for (int* link = &head; *link >= 0;) {
    if (episodes_[*link].end < before) *link = freeEpisode(*link);
    else link = &episodes_[*link].next;
  }
  int i = freeEpisode_;
  if (i >= 0) {
    freeEpisode_ = episodes_[i].next;
  } else {
    i = static_cast<int>(episodes_.size());
    episodes_.emplace_back();
  }
  episodes_[i] = {foe, t, kInf, track, head};
  head = i;
}

void Hindsight::endEpisodes(int e, std::uint64_t egoSerial, std::uint64_t foe, double end) {
  if (e >= static_cast<int>(listHead_.size()) || listOwner_[e] != egoSerial) return;
  for (int i = listHead_[e]; i >= 0; i = episodes_[i].next)
    if (episodes_[i].foe == foe && episodes_[i].end == kInf) episodes_[i].end = end;
}

void Hindsight::pruneEpisodes(double before) {
  const auto& slots = cars_->slots;
  for (std::size_t s = 0; s < listHead_.size(); ++s) {
    // a list of a car gone is of no use: no event can name it again
    const bool gone = !slots[s].present || listOwner_[s] != slots[s].serial;
    for (int* link = &listHead_[s]; *link >= 0;) {
      if (gone || episodes_[*link].end < before) *link = freeEpisode(*link);
      else link = &episodes_[*link].next;
    }
  }
}

// Each track's state at this tick, in one pass over the tracks: both cars here (the slot still
// holds the car it held), their boxes and the gap bound.
void Hindsight::measureTracks() {
  const VehicleTable& c = *cars_;
  if (serialOf_.size() < c.slots.size()) serialOf_.resize(c.slots.size(), 0);
  for (int s : c.arrived) serialOf_[s] = c.slots[s].serial;
  auto here = [&](int s, std::uint64_t serial) { return c.inputOf[s] >= 0 && serialOf_[s] == serial; };
  for (Track& tr : tracks_) {
    if (tr.windows == 0) continue;
    tr.here = here(tr.a, tr.serialA) && here(tr.b, tr.serialB);
    tr.hasDist = false;
    if (!tr.here) continue;
    tr.boxA = c.body[tr.a].box();
    tr.boxB = c.body[tr.b].box();
    tr.sep = separation(tr.boxA, tr.boxB);
  }
}

// The vehicle windows: the smallest clearance so far, when, and the hardest braking. The gap
// along a separating axis bounds the distance from below: most ticks it cannot beat the smallest
// clearance so far (a car alongside in the next lane).
void Hindsight::measureVehicles(double t) {
  const std::vector<double>& braking = cars_->braking;
  for (std::size_t i = 0; i < liveVehicles_.size();) {
    LiveVehicle& v = liveVehicles_[i];
    Track& tr = tracks_[v.track];
    if (t > v.end || !tr.here) {
      closeVehicle(i);
      continue;
    }
    if (!v.measured || tr.sep < v.clearance) {
      if (!tr.hasDist) tr.dist = tr.sep <= 0.0 ? 0.0 : distanceApart(tr.boxA, tr.boxB), tr.hasDist = true;
      if (!v.measured || tr.dist < v.clearance) {
        v.clearance = tr.dist;
        v.clearanceTime = t;
      }
    }
    v.deceleration = std::max({v.deceleration, braking[v.ego], braking[v.foe]});
    v.evasive = v.evasive || braking[v.ego] > evasiveThreshold(v.ego) || braking[v.foe] > evasiveThreshold(v.foe);
    v.measured = true;
    ++i;
  }
}

// A vehicle window stops measuring: what it saw into its Window; the last window on a track frees it.
void Hindsight::closeVehicle(std::size_t i) {
  const LiveVehicle& v = liveVehicles_[i];
  Window& w = windows_[v.id];
  w.clearance = v.clearance;
  w.clearanceTime = v.clearanceTime;
  w.deceleration = v.deceleration;
  w.evasive = v.evasive;
  w.measured = v.measured;
  w.closed = true;
  Track& tr = tracks_[v.track];
  if (--tr.windows == 0) freeTracks_.push_back(v.track);
  liveVehicles_[i] = liveVehicles_.back();
  liveVehicles_.pop_back();
}

bool Hindsight::alive(const Window& w) const {
  const auto& slots = cars_->slots;
  auto here = [&](int s, std::uint64_t serial) { return slots[s].present && slots[s].serial == serial; };
  return here(w.ego, w.egoSerial) && (w.kind != WarningKind::Vehicle || here(w.foe, w.foeSerial));
}

void Hindsight::measure(Window& w, double t) {
  const Body& a = cars_->body[w.ego];
  w.measured = true;
  if (w.crossed) return;
  const LanePrediction* lp = frames_;
  if (lp->frame(w.ego).lane >= 0 && w.kind != WarningKind::Hazard) {
    if (!lp->alongside(w.ego)) return;
    // in the lane frame: the body reaches across the line on one side of the lane it is on (the
    // one it left, or the one it entered, after a crossing)
    const int lane = lp->frame(w.ego).lane;
    for (int side = 0; side < 2; ++side) {
      if (road_->lineOf(lane, side) != w.foe || lp->beyondLine(w.ego, side, false) < 0.0) continue;
      w.crossed = true;
      w.clearanceTime = t;
      w.signalled = (cars_->signals[w.ego] & (side == 1 ? kSignalLeft : kSignalRight)) != 0;
    }
    return;
  }
  const RoadFeatures& rf = road_->features();
  for (int fi : road_->groupFeatures(w.foe)) {
    const RoadFeature& f = rf.features[fi];
    const bool touches =
        f.kind == FeatureKind::Hazard ? distance(f.segment.a, a.box()) <= f.radius : overlaps(f.segment, a.box());
    if (!touches) continue;
    w.crossed = true;
    w.clearanceTime = t;
    // the signal of the side the line is on (as the monitor's exemption reads it)
    double side = cross(a.axis, closestPointOnSegment(f.segment, a.position) - a.position);
    if (std::abs(side) < 1e-9) side = cross(a.axis, a.velocity);
    w.signalled = (cars_->signals[w.ego] & (side > 0.0 ? kSignalLeft : kSignalRight)) != 0;
    return;
  }
}

// The PETs still to come: both vehicles' positions on their paths, until both are known, the
// horizon passes or a vehicle leaves.
void Hindsight::watchPets(double t) {
  for (std::size_t i = 0; i < livePets_.size();) {
    LivePet& p = livePets_[i];
    Window& w = windows_[p.window];
    if (t <= p.until && alive(w)) observePet(cars_->front(w.ego), cars_->front(w.foe), t, p.watch);
    if (t > p.until || !alive(w) || !std::isnan(p.watch.pet())) {
      w.pet = p.watch.pet(true);
      w.petLive = false;
      livePets_[i] = livePets_.back();
      livePets_.pop_back();
      continue;
    }
    ++i;
  }
}

void Hindsight::judge(Warning& w, const Window& win) {
  if (std::isnan(w.pet)) w.pet = win.pet;
  const HindsightConfig& h = cfg_->hindsight;
  bool confirmed = false;
  if (win.kind == WarningKind::Vehicle) {
    w.clearance = win.measured ? win.clearance : std::numeric_limits<double>::quiet_NaN();
    w.clearanceTime = win.measured ? win.clearanceTime : std::numeric_limits<double>::quiet_NaN();
    w.deceleration = win.deceleration;
    confirmed = (win.measured && win.clearance < h.clearance) || win.evasive;
  } else {
    w.crossed = win.crossed;
    w.signalled = win.signalled;
    w.clearanceTime = win.crossed ? win.clearanceTime : std::numeric_limits<double>::quiet_NaN();
    confirmed = win.crossed && (win.kind != WarningKind::LaneMarker || !win.signalled);
  }
  w.verdict = confirmed ? Verdict::Confirmed : Verdict::Nuisance;
  const int k = static_cast<int>(win.kind);
  ++counters_->judged[k];
  counters_->confirmed[k] += confirmed ? 1 : 0;
}

void Hindsight::observe(double t) {
  ++tick_;
  measureTracks();
  measureVehicles(t);
  for (std::size_t i = 0; i < live_.size();) {
    Window& w = windows_[live_[i]];
    if (t > w.end || !alive(w)) {
      w.closed = true;
      live_[i] = live_.back();
      live_.pop_back();
      continue;
    }
    measure(w, t);
    ++i;
  }
  watchPets(t);
  findNearMisses(t);
  findCrossings(t);
  if (t - lastPrune_ > 10.0) {
    // episodes long over no longer decide an event's recall
    pruneEpisodes(t - 10.0);
    lastPrune_ = t;
  }
}

// The pairs closer than the clearance while closing, by a sweep along the axis the cars spread
// along most: the cars sorted along it, their state loaded contiguous, the sweep.
void Hindsight::findNearMisses(double t) {
  const VehicleTable& c = *cars_;
  if (c.active.size() < 2) return;
  const SweepSpread spread = spreadOf(c);
  sortAlong(spread.axis);
  const double hmax = loadSweep();
  sweepNearMisses(t, spread.axis, 2.0 * spread.rmax + cfg_->hindsight.clearance, hmax);
  std::swap(nearBefore_, nearNow_);
}

Hindsight::SweepSpread Hindsight::spreadOf(const VehicleTable& c) {
  Vec2 lo = Vec2::Constant(kInf), hi = Vec2::Constant(-kInf);
  double rmax = 0.0;  // the envelopes hold the bodies
  for (int s : c.active) {
    lo = lo.cwiseMin(c.centre[s]);
    hi = hi.cwiseMax(c.centre[s]);
    rmax = std::max(rmax, c.ownEnv[s]);
  }
  return {hi.y() - lo.y() > hi.x() - lo.x() ? 1 : 0, rmax};
}

// last tick's order, the cars still here first, then the new ones; cars keep their order along
// the road, so an insertion sort finds it nearly sorted
void Hindsight::sortAlong(int axis) {
  const VehicleTable& c = *cars_;
  ++stamp_;
  if (seen_.size() < c.slots.size()) seen_.resize(c.slots.size(), 0);
  std::size_t n = 0;
  for (const auto& [key, s] : order_)
    if (c.inputOf[s] >= 0 && seen_[s] != stamp_) seen_[s] = stamp_, order_[n++] = {c.centre[s][axis], s};
  order_.resize(n);
  for (int s : c.active)
    if (seen_[s] != stamp_) seen_[s] = stamp_, order_.push_back({c.centre[s][axis], s});
  if (n < order_.size() / 2) {
    std::sort(order_.begin(), order_.end());  // mostly new cars (the first tick)
  } else {
    for (std::size_t i = 1; i < order_.size(); ++i) {
      const std::pair<double, int> x = order_[i];
      std::size_t j = i;
      for (; j > 0 && x < order_[j - 1]; --j) order_[j] = order_[j - 1];
      order_[j] = x;
    }
  }
}

// the sorted cars' state, contiguous; the largest half diagonal
double Hindsight::loadSweep() {
  const VehicleTable& c = *cars_;
  const std::size_t n = order_.size();
  sweepCentre_.resize(n);
  sweepVel_.resize(n);
  sweepHalfDiag_.resize(n);
  sweepEquipped_.resize(n);
  double hmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const int s = order_[i].second;
    const Body& b = c.body[s];
    sweepCentre_[i] = c.centre[s];
    sweepVel_[i] = c.vel[s];
    sweepHalfDiag_[i] = 0.5 * std::sqrt(b.length * b.length + b.width * b.width);
    sweepEquipped_[i] = c.equipped[s];
    hmax = std::max(hmax, sweepHalfDiag_[i]);
  }
  return hmax;
}

// A body lies within its half diagonal of its centre, so two bodies whose centres are farther
// apart than the half diagonals and the clearance (and a micrometre for rounding) cannot come
// closer than the clearance: the pair is skipped as nearMissGap would skip it. Pairs found go to
// nearNow_, the new ones are recorded.
void Hindsight::sweepNearMisses(double t, int axis, double reach, double hmax) {
  const double clearance = cfg_->hindsight.clearance;
  const std::size_t n = order_.size();
  nearNow_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 ca = sweepCentre_[i], va = sweepVel_[i];
    const double ha = sweepHalfDiag_[i];
    const double reachI = std::min(reach, ha + hmax + clearance + tol::kNearMissMargin);
    for (std::size_t j = i + 1; j < n && order_[j].first - order_[i].first <= reachI; ++j) {
      if (!sweepEquipped_[i] && !sweepEquipped_[j]) continue;
      const Vec2 p = sweepCentre_[j] - ca;
      if (std::abs(p[1 - axis]) > reachI) continue;
      if (p.dot(sweepVel_[j] - va) >= 0.0) continue;  // not closing
      const double near = ha + sweepHalfDiag_[j] + clearance + tol::kNearMissMargin;
      if (p.squaredNorm() >= near * near) continue;
      const int a = order_[i].second, b = order_[j].second;
      if (const std::optional<double> gap = nearMissGap(a, b, p)) noteNearMiss(a, b, *gap, t);
    }
  }
}

// The gap between slots a and b (centre offset p) if they are on a collision course (SSAM's
// conflict): touching, or the rectangles meet within near_miss_ttc at their velocities now; two
// cars passing side by side are not. None when not closer than the clearance or not on a course.
std::optional<double> Hindsight::nearMissGap(int a, int b, const Vec2& p) const {
  const VehicleTable& c = *cars_;
  const HindsightConfig& h = cfg_->hindsight;
  const double far = c.ownEnv[a] + c.ownEnv[b] + h.clearance;
  if (p.squaredNorm() >= far * far) return std::nullopt;  // the envelopes hold the bodies
  const double gap = distance(c.body[a].box(), c.body[b].box());
  if (gap >= h.clearance) return std::nullopt;
  if (gap > 0.0 && !(boxTtc(c.body[a], c.body[b], MotionModel::ConstantVelocity, h.nearMissTtc).actTime() <= h.nearMissTtc))
    return std::nullopt;
  return gap;
}

// Slots a and b near now (nearNow_); a new approach is recorded with whether an episode between
// the two was open `lead` seconds before.
void Hindsight::noteNearMiss(int a, int b, double gap, double t) {
  const VehicleTable& c = *cars_;
  const std::uint64_t key = pairKey(c.slots[a].serial, c.slots[b].serial);
  nearNow_.insert(key);
  if (nearBefore_.count(key)) return;
  const int e = c.equipped[a] ? a : b, f = e == a ? b : a;
  HindsightEvent ev;
  ev.kind = EventKind::NearMiss;
  ev.foe = c.slots[f].id;
  ev.gap = gap;
  record(std::move(ev), e, t, leadOf(a, c.slots[b].serial, b, c.slots[a].serial, t));
}

void Hindsight::release(std::vector<Warning>& out) {
  while (!pending_.empty()) {
    // the oldest tick's warnings, once every one of them is judged
    const std::uint64_t tick = pending_.front().tick;
    std::size_t n = 0;
    for (; n < pending_.size() && pending_[n].tick == tick; ++n)
      if (!windows_[pending_[n].window].closed || windows_[pending_[n].window].petLive) return;
    for (std::size_t i = 0; i < n; ++i) {
      Pending& p = pending_.front();
      judge(p.warning, windows_[p.window]);
      out.push_back(std::move(p.warning));
      freeWindows_.push_back(p.window);
      pending_.pop_front();
    }
  }
}

void Hindsight::finishAll(std::vector<Warning>& out) {
  while (!liveVehicles_.empty()) closeVehicle(liveVehicles_.size() - 1);
  for (int id : live_) windows_[id].closed = true;
  live_.clear();
  for (const LivePet& p : livePets_) {
    windows_[p.window].pet = p.watch.pet(true);
    windows_[p.window].petLive = false;
  }
  livePets_.clear();
  release(out);
}

Hindsight::Lead Hindsight::leadOf(int a, std::uint64_t foe, int b, std::uint64_t fromB, double t) const {
  Lead out{std::numeric_limits<double>::quiet_NaN(), false};
  leadIn(firstOf(a), foe, t, out);
  if (b >= 0) leadIn(firstOf(b), fromB, t, out);
  return out;
}

// the earliest begin is taken whatever the order the episodes come in
void Hindsight::leadIn(int head, std::uint64_t foe, double t, Lead& out) const {
  const double at = t - cfg_->hindsight.lead;
  for (int i = head; i >= 0; i = episodes_[i].next) {
    const PastEpisode& pe = episodes_[i];
    if (pe.foe == foe && pe.end >= at && pe.begin <= t) {
      if (!(t - pe.begin <= out.lead)) out.lead = t - pe.begin;
      out.warned = out.warned || pe.begin <= at;
    }
  }
}

void Hindsight::record(HindsightEvent&& ev, int e, double t, const Lead& lead) {
  const VehicleTable& c = *cars_;
  MonitorCounters& k = *counters_;
  const bool near = ev.kind == EventKind::NearMiss;
  ++(near ? k.nearMisses : k.crossings);
  if (lead.warned) {
    ++(near ? k.nearMissesWarned : k.crossingsWarned);
    (near ? k.nearMissLeads : k.crossingLeads).push_back(lead.lead);
  }
  ev.time = t;
  ev.ego = c.slots[e].id;
  ev.x = c.centre[e].x();
  ev.y = c.centre[e].y();
  ev.lane = c.laneId(frames_->reportedLane(e));
  ev.speed = c.body[e].velocity.norm();
  ev.warned = lead.warned;
  ev.lead = lead.lead;
  events_.push_back(std::move(ev));
}

// Equipped cars whose body begins to reach across a line of their lane (in the lane frame): a
// curb, or a marker without that side's signal, while the lines apply (the car alongside its
// lane at this tick and the last: a body that comes out of a junction or onto a lane already
// reaching across a line did not cross it). Was a warning about that line open `lead` before?
void Hindsight::findCrossings(double t) {
  const VehicleTable& c = *cars_;
  if (touching_.size() < c.slots.size()) touching_.resize(c.slots.size(), {-1, -1});
  if (along_.size() < c.slots.size()) along_.resize(c.slots.size(), 0);
  for (int s : c.arrived) touching_[s] = {-1, -1}, along_[s] = 0;
  for (int s : c.active) {
    std::array<int, 2> now = {-1, -1};
    const int lane = frames_->frame(s).lane;
    const bool along = lane >= 0 && frames_->along(s);
    const bool was = along_[s] != 0;
    along_[s] = along;
    // most bodies reach across neither line (the nearer side's is the larger reach)
    if (along && !(frames_->beyondNearerLine(s) < 0.0))
      for (int side = 0; side < 2; ++side) {
        const int g = road_->lineOf(lane, side);
        if (g < 0 || frames_->beyondLine(s, side, false) < 0.0) continue;
        now[side] = g;
        if (!was || !c.equipped[s] || g == touching_[s][0] || g == touching_[s][1]) continue;
        const bool marker = road_->features().features[road_->groupFeatures(g).front()].kind == FeatureKind::LaneMarker;
        if (marker && (c.signals[s] & (side == 1 ? kSignalLeft : kSignalRight))) continue;
        HindsightEvent ev;
        ev.kind = EventKind::Crossing;
        ev.foe = road_->features().features[road_->groupFeatures(g).front()].name;
        ev.lateralSpeed = (side == 1 ? 1.0 : -1.0) * frames_->frame(s).lateral;
        record(std::move(ev), s, t, leadOf(s, kLineBit | static_cast<std::uint32_t>(g), -1, 0, t));
      }
    touching_[s] = now;
  }
}

}  // namespace st::highway::detail
