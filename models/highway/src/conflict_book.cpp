#include "conflict_book.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <sthighway/sumo_conversion.hpp>
#include <sthighway/tolerances.hpp>

#include "lane_encounter.hpp"

namespace st::highway::detail {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// added to the sweep's reach (m): the reach bounds a pair that touches within TTC* up to the
// contact slop; this keeps rounding from dropping one at the bound
constexpr double kReachMargin = 1.0;

double halfDiagonal(const Body& b) { return 0.5 * std::hypot(b.length, b.width); }

// The order in which the two fronts reach the contact point p: at or past it now first (the
// further past the earlier; a front within tol::kArrivalTie short of it is at it: a car standing
// with its front on the point is there, whichever way rounding puts it), then by time to get
// there at the speed along the axis.
std::pair<int, double> arrival(const Body& b, const Vec2& p) {
  const double d = (p - b.position).dot(b.axis) - 0.5 * b.length;
  if (d <= tol::kArrivalTie) return {0, d};
  const double s = b.velocity.dot(b.axis);
  return {1, s > 0.0 ? d / s : kInfinity};
}

// SSAM's first of the two at the contact point p: the front that reaches it first; together
// (within tol::kArrivalTie) the one named first (the smaller id), whatever order they came in.
bool aReachesFirst(const Body& a, const Body& b, const Vec2& p, bool aNamedFirst) {
  const auto ta = arrival(a, p), tb = arrival(b, p);
  if (ta.first != tb.first) return ta.first < tb.first;
  if (std::abs(ta.second - tb.second) <= tol::kArrivalTie || ta.second == tb.second) return aNamedFirst;
  return ta.second < tb.second;
}
}  // namespace

void startRearPet(const Body& a, const Body& b, double ttc, double t, bool aNamedFirst, RearPetWatch& w) {
  w = RearPetWatch{};
  if (!std::isfinite(ttc)) return;
  Body at = a, bt = b;
  at.position += ttc * at.velocity;
  bt.position += ttc * bt.velocity;
  startRearPet(a, b, at, bt, t, aNamedFirst, w);
}

void startRearPet(const Body& a, const Body& b, const Body& at, const Body& bt, double t, bool aNamedFirst,
                  RearPetWatch& w) {
  w = RearPetWatch{};
  w.active = true;
  w.p = contactPoint(at.box(), bt.box(), tol::kContactPointTie);
  // the leader as close() names SSAM's first vehicle
  w.first = aReachesFirst(a, b, w.p, aNamedFirst) ? 0 : 1;
  w.dir = {at.axis, bt.axis};
  w.half = {0.5 * a.length, 0.5 * b.length};
  w.lastT = t;
  observeRearPet(a.position, b.position, t, w);
}

void observeRearPet(const Vec2& ca, const Vec2& cb, double t, RearPetWatch& w) {
  if (!w.active) return;
  const Vec2* c[2] = {&ca, &cb};
  const bool first = !(t > w.lastT);  // the watch's own start: no tick before to time from
  for (int i = 0; i < 2; ++i) {
    if (std::isnan(c[i]->x())) continue;
    const bool leader = i == w.first;
    const double along = (*c[i] - w.p).dot(w.dir[i]);
    // leader: its back past p (> 0: left); follower: its front short of p (<= 0: reached)
    const double s = leader ? along - w.half[i] : -along - w.half[i];
    double& when = leader ? w.leave : w.arrive;
    const bool crossed = leader ? s > 0.0 : s <= 0.0;
    if (std::isnan(when) && crossed)
      when = first || s == w.s[i] ? t : w.lastT + (t - w.lastT) * (0.0 - w.s[i]) / (s - w.s[i]);
    w.s[i] = s;
  }
  w.lastT = t;
}

void ConflictBook::observe(double t, double lastT) {
  ++tick_;
  const double dt = std::isfinite(lastT) ? t - lastT : 0.0;
  // the pairs below TTC* into their encounters
  const double maxTtc = cfg_->conflict.maxTtc;
  const VehicleTable& c = *cars_;
  sweep_.clear();
  double vmax = 0.0, hmax = 0.0;
  // each body's half diagonal and speed once a tick, not once a pair (std::hypot is slow)
  for (int s : c.active) {
    sweep_.push_back({c.centre[s].x(), s, halfDiagonal(c.body[s]), c.vel[s].norm()});
    vmax = std::max(vmax, sweep_.back().speed);
    hmax = std::max(hmax, sweep_.back().halfDiagonal);
  }
  std::sort(sweep_.begin(), sweep_.end(),
            [](const SweepEntry& p, const SweepEntry& q) { return p.x < q.x || (p.x == q.x && p.slot < q.slot); });
  // two bodies touching within TTC* are at most their half diagonals plus the way both cover apart
  // (along their lanes, at a merge: each path departs from its straight line by its deviation at most)
  double devMax = 0.0;
  if (paths_->alongLanes())
    for (int s : c.active) devMax = std::max(devMax, paths_->deviation(s));
  const double reachX = 2.0 * hmax + 2.0 * vmax * maxTtc + 2.0 * devMax + kReachMargin;
  for (std::size_t i = 0; i < sweep_.size(); ++i) {
    const SweepEntry& ea = sweep_[i];
    const int a = ea.slot;
    for (std::size_t j = i + 1; j < sweep_.size() && sweep_[j].x - ea.x <= reachX; ++j) {
      const SweepEntry& eb = sweep_[j];
      const int b = eb.slot;
      if (!c.equipped[a] && !c.equipped[b]) continue;
      const double dev = paths_->alongLanes() ? paths_->deviation(a) + paths_->deviation(b) : 0.0;
      const double reach = ea.halfDiagonal + eb.halfDiagonal + (ea.speed + eb.speed) * maxTtc + dev + kReachMargin;
      if ((c.centre[b] - c.centre[a]).squaredNorm() > reach * reach) continue;
      // in the order of first appearance, whatever the input order
      const bool ab = c.slots[a].serial < c.slots[b].serial;
      const int lo = ab ? a : b, hi = ab ? b : a;
      Body atLo, atHi;
      const double ttc = pairTtc(lo, hi, maxTtc, atLo, atHi).actTime();
      if (ttc <= maxTtc) touch(lo, hi, ttc, atLo, atHi, t, dt);
    }
  }
  // the encounters not below TTC* this tick end: now, or at the last tick of a car that left
  for (auto it = open_.begin(); it != open_.end();) {
    Encounter& en = it->second;
    if (en.seen == tick_) {
      ++it;
      continue;
    }
    const bool left = c.inputOf[en.a] < 0 || c.inputOf[en.b] < 0;
    close(en, left ? lastT : t, false);
    it = open_.erase(it);
  }
  // the PETs still to come, in the order their encounters ended
  std::size_t kept = 0;
  for (std::size_t i = 0; i < waiting_.size(); ++i) {
    Waiting& w = waiting_[i];
    const bool here = c.inputOf[w.a] >= 0 && c.slots[w.a].serial == w.serialA && c.inputOf[w.b] >= 0 &&
                      c.slots[w.b].serial == w.serialB;
    if (here && t <= w.until) {
      observePet(c.front(w.a), c.front(w.b), t, w.pet);
      observeRearPet(c.centre[w.a], c.centre[w.b], t, w.rearPet);
    }
    if (!here || t > w.until || !std::isnan(w.petNow())) settle(std::move(w.conflict), w.petNow(true));
    else if (kept != i) waiting_[kept++] = std::move(w);
    else ++kept;
  }
  waiting_.resize(kept);
}

Impact ConflictBook::pairTtc(int a, int b, double maxTtc, Body& atA, Body& atB) const {
  const VehicleTable& c = *cars_;
  if (paths_->alongLanes() && (paths_->atMerge(a) || paths_->atMerge(b)))
    return paths_->boxTtcAlong(a, b, maxTtc, atA, atB);
  const Impact hit = boxTtc(c.body[a], c.body[b], MotionModel::ConstantVelocity, maxTtc);
  if (hit.acts()) {
    const double ttc = hit.actTime();
    atA = c.body[a];
    atB = c.body[b];
    atA.position += ttc * atA.velocity;
    atB.position += ttc * atB.velocity;
  }
  return hit;
}

// The lanes each takes as far as it drives until the contact, with its length and a margin: a
// car standing at its line has the junction lane beyond it in reach.
LaneMeeting ConflictBook::encounterOf(int a, int b, double ttc) {
  const VehicleTable& c = *cars_;
  if (c.vclass[a] == VehicleClass::Pedestrian || c.vclass[b] == VehicleClass::Pedestrian)
    return {EncounterType::Pedestrian};
  auto reach = [&](int s) { return c.body[s].velocity.norm() * ttc + c.body[s].length + tol::kEncounterReach; };
  return laneEncounter(*paths_, a, b, reach(a), reach(b), lanesA_, lanesB_);
}

// The edge a road user on `lane` came into its junction from: the lane's own edge, or for a lane
// inside a junction the edge of the lane before its junction lanes; "" if unknown.
std::string ConflictBook::approachOf(int lane) const {
  if (lane < 0) return "";
  lane = paths_->junctionEntry(lane);
  if (paths_->internalLane(lane)) {
    const std::span<const int> before = paths_->predecessors(lane);
    if (before.empty() || paths_->internalLane(before.front())) return "";
    lane = before.front();
  }
  return paths_->laneEdgeId(lane);
}

void ConflictBook::touch(int a, int b, double ttc, const Body& atA, const Body& atB, double t, double dt) {
  const VehicleTable& c = *cars_;
  auto [it, fresh] = open_.try_emplace(Key{c.slots[a].serial, c.slots[b].serial});
  Encounter& en = it->second;
  if (fresh) {
    en.a = a;
    en.b = b;
    en.begin = t;
    en.minTtc = kInfinity;
    beginTrack(c, a, b, en.trackA);
    beginTrack(c, b, a, en.trackB);
  } else {
    advanceTrack(c, a, b, en.trackA);
    advanceTrack(c, b, a, en.trackB);
  }
  en.seen = tick_;
  const double maxTtc = cfg_->conflict.maxTtc;
  en.tet += dt;
  en.tit += dt * (maxTtc - ttc);
  if (ttc < en.minTtc) {
    en.minTtc = ttc;
    en.minTtcTime = t;
    en.bodyA = c.body[a];
    en.bodyB = c.body[b];
    en.contactA = atA;
    en.contactB = atB;
    en.laneA = paths_->reportedLane(a);
    en.laneB = paths_->reportedLane(b);
    en.meeting = encounterOf(a, b, ttc);
    startPet(en.bodyA, en.bodyB, paths_->laneWidth(a), paths_->laneWidth(b), t, petAngles_, en.pet);
    startRearPet(en.bodyA, en.bodyB, atA, atB, t, c.slots[a].id < c.slots[b].id, en.rearPet);
  } else {
    observePet(c.front(a), c.front(b), t, en.pet);
    observeRearPet(c.centre[a], c.centre[b], t, en.rearPet);
  }
}

void ConflictBook::close(Encounter& en, double end, bool open) {
  const VehicleTable& c = *cars_;
  // the predicted contact: the rectangles moved on to the minimum TTC (in straight lines, or along
  // the lanes at a merge), where SSAM's angle classes are taken
  const Body &at = en.contactA, &bt = en.contactB;
  const Vec2 p = contactPoint(at.box(), bt.box(), tol::kContactPointTie);
  // SSAM's first vehicle: its front at the contact point first (together: the smaller id)
  const bool aFirst = aReachesFirst(en.bodyA, en.bodyB, p, c.slots[en.a].id < c.slots[en.b].id);
  const int f = aFirst ? en.a : en.b, s = aFirst ? en.b : en.a;
  const Body &bf = aFirst ? en.bodyA : en.bodyB, &bs = aFirst ? en.bodyB : en.bodyA;
  const EpisodeTrack &tf = aFirst ? en.trackA : en.trackB, &ts = aFirst ? en.trackB : en.trackA;
  const double mf = c.mass[f], ms = c.mass[s];

  Conflict k;
  k.first = c.slots[f].id;
  k.second = c.slots[s].id;
  const Body &cf = aFirst ? at : bt, &cs = aFirst ? bt : at;
  k.type = conflictType(toDegrees(std::atan2(std::abs(cross(cf.axis, cs.axis)), cf.axis.dot(cs.axis))), c.vclass[f],
                        c.vclass[s], cfg_->conflict);
  k.encounter = en.meeting.type;
  k.begin = en.begin;
  k.end = end;
  k.minTtc = en.minTtc;
  k.minTtcTime = en.minTtcTime;
  // the rate the centre distance shrinks, as the warnings' DRAC has it
  const Vec2 rel = bs.position - bf.position, vrel = bs.velocity - bf.velocity;
  const double dist = rel.norm();
  k.drac = decelerationToAvoid(dist > 0.0 ? -rel.dot(vrel) / dist : vrel.norm(), en.minTtc);
  k.maxSpeed = std::max(en.trackA.maxSpeed, en.trackB.maxSpeed);
  k.deltaSpeed = (bf.velocity - bs.velocity).norm();
  k.dr = ts.dr;
  k.maxD = ts.maxD;
  k.maxDeltaV = maxDeltaV(mf, bf.velocity, ms, bs.velocity);
  k.firstDeltaV = deltaV(mf, bf.velocity, ms, bs.velocity);
  k.secondDeltaV = deltaV(ms, bs.velocity, mf, bf.velocity);
  k.conflictAngle = conflictAngleDeg(cf.axis, cs.axis);
  k.clockAngle = clockPosition(k.conflictAngle);
  const Vec2 v = postCrashVelocity(mf, bf.velocity, ms, bs.velocity);
  k.postCrashSpeed = v.norm();
  k.postCrashHeading = v.squaredNorm() > 0.0 ? toDegrees(std::atan2(v.y(), v.x())) : kNaN;
  k.conflictX = p.x();
  k.conflictY = p.y();
  k.pathsMeetX = en.meeting.point.x();
  k.pathsMeetY = en.meeting.point.y();
  k.firstAlong = aFirst ? en.meeting.alongA : en.meeting.alongB;
  k.secondAlong = aFirst ? en.meeting.alongB : en.meeting.alongA;
  k.firstX = bf.position.x();
  k.firstY = bf.position.y();
  k.secondX = bs.position.x();
  k.secondY = bs.position.y();
  k.firstSpeed = bf.velocity.norm();
  k.secondSpeed = bs.velocity.norm();
  k.firstStartX = tf.start.x();
  k.firstStartY = tf.start.y();
  k.firstEndX = tf.last.x();
  k.firstEndY = tf.last.y();
  k.secondStartX = ts.start.x();
  k.secondStartY = ts.start.y();
  k.secondEndX = ts.last.x();
  k.secondEndY = ts.last.y();
  k.firstLane = c.laneId(aFirst ? en.laneA : en.laneB);
  k.secondLane = c.laneId(aFirst ? en.laneB : en.laneA);
  k.junction = junctionOfLane(k.firstLane);
  if (k.junction.empty()) k.junction = junctionOfLane(k.secondLane);
  // neither on a junction lane yet (a merge onto a roundabout's ring): where their paths meet
  if (k.junction.empty() && en.meeting.lane >= 0) k.junction = junctionOfLane(c.laneId(en.meeting.lane));
  if (!k.junction.empty()) {
    k.firstApproach = approachOf(aFirst ? en.laneA : en.laneB);
    k.secondApproach = approachOf(aFirst ? en.laneB : en.laneA);
  }
  k.firstClass = c.vclass[f];
  k.secondClass = c.vclass[s];
  k.firstLength = bf.length;
  k.secondLength = bs.length;
  k.firstWidth = bf.width;
  k.secondWidth = bs.width;
  k.tet = en.tet;
  k.tit = en.tit;
  k.open = open;
  // PET: once the first has left and the second arrived, or watched on for a while; of crossing
  // and merging paths across the area their bodies sweep, of a rear-end at the conflict point
  const bool rearEnd = k.type == ConflictType::RearEnd;
  const double pet = rearEnd ? en.rearPet.pet() : en.pet.pet(open);
  if (open || !(rearEnd ? en.rearPet.active : en.pet.active) || !std::isnan(pet)) return settle(std::move(k), pet);
  waiting_.push_back({std::move(k), en.a, en.b, c.slots[en.a].serial, c.slots[en.b].serial, end + kPetHorizon, en.pet,
                      en.rearPet, rearEnd});
}

void ConflictBook::settle(Conflict&& k, double pet) {
  k.pet = pet;
  if (!std::isnan(pet) && pet > cfg_->conflict.maxPet) {
    ++counters_->conflictsOverMaxPet;
    return;
  }
  ++counters_->conflictsByType[static_cast<int>(k.type)];
  ++counters_->conflictsByEncounter[static_cast<int>(k.encounter)];
  if (!k.junction.empty()) {
    ++counters_->conflictsByJunction[k.junction][static_cast<int>(k.type)];
    auto& approaches = counters_->conflictsByApproach[k.junction];
    if (!k.firstApproach.empty()) ++approaches[k.firstApproach];
    if (!k.secondApproach.empty() && k.secondApproach != k.firstApproach) ++approaches[k.secondApproach];
  }
  const bool firstBicycle = k.firstClass == VehicleClass::Bicycle, secondBicycle = k.secondClass == VehicleClass::Bicycle;
  if (firstBicycle || secondBicycle) ++counters_->conflictsWithBicycle[static_cast<int>(k.type)];
  if (firstBicycle && secondBicycle) ++counters_->conflictsBetweenBicycles;
  counters_->conflictTet += k.tet;
  counters_->conflictTit += k.tit;
  settled_.push_back(std::move(k));
}

void ConflictBook::finish(double t) {
  for (auto& [key, en] : open_) close(en, t, true);
  open_.clear();
  for (Waiting& w : waiting_) settle(std::move(w.conflict), w.petNow(true));
  waiting_.clear();
}

}  // namespace st::highway::detail
