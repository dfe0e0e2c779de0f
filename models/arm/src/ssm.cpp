#include <starm/ssm.hpp>

#include <algorithm>
#include <cmath>

#include <stcore/distance.hpp>
#include <starm/drive.hpp>
#include <starm/monitor.hpp>

namespace st::arm {

const char* toString(SsmResponse r) {
  switch (r) {
    case SsmResponse::Stop: return "stop";
    case SsmResponse::Scaling: return "scaling";
    case SsmResponse::Pfl: return "pfl";
  }
  return "?";
}

const RegionLimits& regionLimits(BodyRegion r) {
  // ISO/TS 15066:2016 Annex A, Table A.2 (maximum permissible quasi-static force per body region;
  // transient contact: force multiplier 2) and Table A.3 (effective spring constant K in N/mm,
  // effective mass m_H in kg), as the standard gives them and as they are widely cited (e.g.
  // skull/forehead 130 N, 150 N/mm, 4.4 kg; hand/fingers 140 N, 75 N/mm, 0.6 kg; chest 140 N,
  // 25 N/mm, 40 kg). The torso capsule covers back, shoulders and chest: it takes the chest's
  // values, the lower speed limit of the two (back/shoulders: 210 N, 35 N/mm, 40 kg). The head
  // (skull, forehead, and the face it carries) and the neck take no transient contact here: the
  // pfl response never plans a contact with them, whatever their numbers allow (our choice, on
  // the safe side).
  static const RegionLimits table[] = {
      {130.0, 150e3, 4.4, false},  // Skull: skull and forehead
      {150.0, 50e3, 1.2, false},   // Neck
      {140.0, 25e3, 40.0, true},   // Chest: back, shoulders, chest (chest's values)
      {180.0, 25e3, 40.0, true},   // Pelvis
      {150.0, 30e3, 3.0, true},    // UpperArm: upper arms and elbow joints
      {160.0, 40e3, 2.0, true},    // LowerArm: lower arms and wrist joints
      {140.0, 75e3, 0.6, true},    // Hand: hands and fingers
      {220.0, 50e3, 75.0, true},   // Thigh: thighs and knees
      {130.0, 60e3, 75.0, true},   // LowerLeg: lower legs
  };
  return table[static_cast<int>(r)];
}

double robotEffectiveMass(double armMass, double payload) { return armMass / 2.0 + payload; }

double reducedMass(double humanMass, double robotMass) { return 1.0 / (1.0 / humanMass + 1.0 / robotMass); }

double transientSpeedLimit(double force, double springK, double mu) { return force / std::sqrt(mu * springK); }

double pflSpeedLimit(const SsmConfig& c, BodyRegion r) { return pflSpeedLimit(c, r, false, 0.0); }

double pflSpeedLimit(const SsmConfig& c, BodyRegion r, bool clamped, double personSpeed) {
  const RegionLimits& l = regionLimits(r);
  if (!l.transient) return 0.0;
  const double mR = robotEffectiveMass(c.armMass, c.payload);
  // clamped: the quasi-static force, and the region backed by the obstacle (mu = m_R)
  const double vRel = clamped ? transientSpeedLimit(l.force, l.springK, mR)
                              : transientSpeedLimit(2.0 * l.force, l.springK, reducedMass(l.mass, mR));
  return std::max(0.0, vRel - personSpeed);
}

double clampGap(const SsmConfig& c) { return protectiveSeparation(c, 0.0, c.robotSpeed).total(); }

double partSpeedInto(const SsmConfig& c, int part, const Capsule& body, const Capsule& arm, bool known,
                     const std::array<Vec3, kSkeletonJoints>& v) {
  const BodyPart& bp = bodyParts()[part];
  if (!known) return bp.hand ? c.handSpeed : c.bodySpeed;
  const Vec3& va = v[bp.a];
  const Vec3& vb = v[bp.b];
  const SegmentPair cp = closestSegmentSegment(body.a, body.b, arm.a, arm.b);
  const Vec3 line = cp.q - cp.p;  // from the part's axis to the arm capsule's
  const double n = line.norm();
  if (!(n > body.radius + arm.radius)) return std::max(va.norm(), vb.norm());  // touching
  const Vec3 u = line / n;
  return std::max({0.0, va.dot(u), vb.dot(u)});
}

const char* SeparationTerms::dominant() const {
  const std::pair<double, const char*> t[] = {{sh, "S_h"}, {sr, "S_r"}, {ss, "S_s"}, {c, "C"}, {zd, "Z_d"}, {zr, "Z_r"}};
  return std::max_element(std::begin(t), std::end(t), [](auto& a, auto& b) { return a.first < b.first; })->second;
}

SeparationTerms protectiveSeparation(const SsmConfig& c, double vh, double vr) {
  SeparationTerms s;
  s.sh = vh * (c.reactionTime + c.stoppingTime);  // (2)
  s.sr = vr * c.reactionTime;                     // (3)
  s.ss = vr * c.stoppingTime / 2.0;               // (4), the drive's linear ramp to rest
  s.c = c.intrusion;
  s.zd = c.personUncertainty;
  s.zr = c.robotUncertainty;
  return s;
}

SeparationTerms protectiveSeparation(const SsmConfig& c, double vh, double vr, double s, double sb) {
  SeparationTerms t = protectiveSeparation(c, vh, 0.0);
  // the arm's speed until it stops: its path may speed up meanwhile (v_r is near 0 at a turn of
  // the path whatever s is), so v_r is no bound, but R per unit of program speed is: s_b R, or
  // v_r + (s_b - s) R where the arm is seen faster than R allows
  const double vb = std::max(sb * c.robotSpeed, vr + std::max(0.0, sb - s) * c.robotSpeed);
  t.sr = vb * c.reactionTime;             // (3) at the speed braking starts from
  t.ss = vb * sb * c.stoppingTime / 2.0;  // (4) with the drive's stopping time s_b T_s
  return t;
}

double allowedDrivenSpeed(const SsmConfig& c, double vh, double d) {
  // the person comes on for T_r before the factor takes effect (a drive heading down from a higher
  // factor is still there); one cycle is not enough, S_p at the drive's speed would break
  const double room = d - vh * c.reactionTime - protectiveSeparation(c, vh, 0.0).total();
  const double b = c.reactionTime + c.cycleTime;
  if (room <= 0.0) return b > 0.0 ? room / b : (room == 0.0 ? 0.0 : -1.0);
  const double r = room / c.robotSpeed;
  // the positive root of (T_s / 2) f^2 + b f - r = 0, in the form without cancellation
  const double f = 2.0 * r / (b + std::sqrt(b * b + 2.0 * c.stoppingTime * r));
  return f * c.robotSpeed;
}

double allowedRobotSpeed(const SsmConfig& c, double vh, double d) {
  const double room = d - vh * c.cycleTime - protectiveSeparation(c, vh, 0.0).total();
  const double perSpeed = c.reactionTime + c.stoppingTime / 2.0 + c.cycleTime;
  if (perSpeed <= 0.0) return room >= 0.0 ? std::numeric_limits<double>::infinity() : -1.0;
  return room / perSpeed;
}

void PersonSet::add(std::string name, std::unique_ptr<PersonTrack> track) {
  names_.push_back(std::move(name));
  tracks_.push_back(std::move(track));
  skeletons_.emplace_back();
  present_.push_back(0);
  velocities_.emplace_back();
  velocitiesKnown_.push_back(0);
}

void PersonSet::pose(double t) {
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    present_[i] = tracks_[i]->at(t, skeletons_[i]) ? 1 : 0;
    velocitiesKnown_[i] = present_[i] && tracks_[i]->velocities(t, velocityWindow_, velocities_[i]) ? 1 : 0;
  }
}

SeparationMonitor::SeparationMonitor(SsmConfig cfg, int arms)
    : cfg_(cfg), verdicts_(static_cast<std::size_t>(arms)), drives_(static_cast<std::size_t>(arms), nullptr) {}

// What one arm's scan over the persons' parts carries from part to part: its fixed inputs (the
// S_p terms per kind of part, the drive) and what it has found so far.
struct SeparationMonitor::ArmScan {
  // S_p depends on the part only through v_h (hand or body): its terms once per kind
  SeparationTerms terms[2];
  double binary[2];  // S_p at the top speed a binary monitor must assume
  const ArmDrive* drive = nullptr;
  double worstSlack = std::numeric_limits<double>::infinity();
  int worstCap = 0;  // the arm capsule of the binding pair (ties: the lowest, as pair by pair)
  bool touching = false, stopBinary = false;
  // pfl: the allowed speed per pair is the larger of S_p's and the region's contact limit
  double pflAllowed = std::numeric_limits<double>::infinity();
  bool pflBreak = false;  // a pair below S_p at the present speed, faster than its region's limit
  double touchLimit = std::numeric_limits<double>::infinity();  // smallest limit of a touched region
};

void SeparationMonitor::cycle(const Monitor& m, const PersonSet& persons) {
  ++counters_.cycles;
  placeArms(m);
  placePersons(m, persons);
  for (int a = 0; a < static_cast<int>(verdicts_.size()); ++a) {
    ArmScan scan;
    const SsmVerdict v = armVerdict(m, persons, a, scan);
    count(v, scan, speed_[a]);
    verdicts_[a] = v;
  }
}

namespace {
// a sphere holding a capsule (its segment's midpoint; half its length plus its radius): the
// distance of two capsules is at least that of their spheres, so a pair whose spheres are no
// nearer than the nearest pair found so far cannot be nearer and is not measured
template <class Bound>
Bound boundOf(const Capsule& c) {
  return Bound{0.5 * (c.a + c.b), 0.5 * (c.b - c.a).norm() + c.radius};
}
}  // namespace

void SeparationMonitor::placeArms(const Monitor& m) {
  const int nc = m.capsuleCount();
  const int arms = static_cast<int>(verdicts_.size());
  // the arms' capsules at the cycle time, by arm, and each arm's speed: its fastest capsule end
  // point (the buffers are kept from cycle to cycle: no allocation once they have grown)
  caps_.resize(static_cast<std::size_t>(nc));
  capBound_.resize(static_cast<std::size_t>(nc));
  speed_.assign(verdicts_.size(), 0.0);
  armFirst_.assign(verdicts_.size() + 1, 0);
  for (int i = 0; i < nc; ++i) ++armFirst_[m.capsuleArm(i) + 1];
  for (int a = 0; a < arms; ++a) armFirst_[a + 1] += armFirst_[a];
  armCaps_.resize(static_cast<std::size_t>(nc));
  fill_.assign(armFirst_.begin(), armFirst_.end() - 1);
  for (int i = 0; i < nc; ++i) {
    caps_[i] = m.movingCapsule(i);
    capBound_[i] = boundOf<Bound>(caps_[i].c);
    double& v = speed_[m.capsuleArm(i)];
    v = std::max({v, caps_[i].va.norm(), caps_[i].vb.norm()});
    armCaps_[fill_[m.capsuleArm(i)]++] = i;  // in index order within each arm
  }
}

void SeparationMonitor::placePersons(const Monitor& m, const PersonSet& persons) {
  // the fixed obstacles a body region can be pinned against (pfl: clamping), and how near
  fixed_.clear();
  for (const Obstacle& o : m.obstacles())
    if (!o.tracked && !o.moving()) fixed_.push_back(&o);
  gap_ = clampGap(cfg_);
  // every person's capsules once
  body_.resize(static_cast<std::size_t>(persons.size()));
  bodyBound_.resize(static_cast<std::size_t>(persons.size()));
  for (int p = 0; p < persons.size(); ++p)
    if (persons.present(p)) {
      body_[p] = bodyCapsules(persons.skeleton(p));
      for (int k = 0; k < kBodyParts; ++k) bodyBound_[p][k] = boundOf<Bound>(body_[p][k]);
    }
}

double SeparationMonitor::partLimit(const PersonSet& persons, int p, int k, int armCapsule, bool& clamped) const {
  // a part's power-and-force limit (pfl, and the contact counters): clamped or not, less its
  // speed (made only where needed: a response without pfl asks only for a touched part's)
  const BodyPart& part = bodyParts()[k];
  clamped = false;
  for (const Obstacle* o : fixed_) {
    const Capsule& c = body_[p][k];
    const double d = o->kind == ShapeKind::Sphere    ? distance(c, o->sphere)
                     : o->kind == ShapeKind::Capsule ? distance(c, o->capsule)
                                                     : distance(c, o->box);
    if (d <= gap_) {
      clamped = true;
      break;
    }
  }
  const double vPart = partSpeedInto(cfg_, k, body_[p][k], caps_[armCapsule].c, persons.velocitiesKnown(p), persons.velocities(p));
  return pflSpeedLimit(cfg_, part.region, clamped, vPart);
}

void SeparationMonitor::boundParts(int a, const PersonSet& persons) {
  const int first = armFirst_[a], n = armFirst_[a + 1] - first;
  lows_.resize(static_cast<std::size_t>(persons.size()) * kBodyParts * static_cast<std::size_t>(n));
  partLow_.assign(static_cast<std::size_t>(persons.size()) * kBodyParts, std::numeric_limits<double>::infinity());
  for (int p = 0; p < persons.size(); ++p) {
    if (!persons.present(p)) continue;
    for (int k = 0; k < kBodyParts; ++k) {
      const Bound& bb = bodyBound_[p][k];
      const std::size_t pk = static_cast<std::size_t>(p) * kBodyParts + static_cast<std::size_t>(k);
      double* low = &lows_[pk * static_cast<std::size_t>(n)];
      for (int j = 0; j < n; ++j) {
        const Bound& cb = capBound_[armCaps_[first + j]];
        low[j] = (cb.centre - bb.centre).norm() - cb.reach - bb.reach;
        partLow_[pk] = std::min(partLow_[pk], low[j]);
      }
    }
  }
}

SeparationMonitor::Nearest SeparationMonitor::nearestCapsule(int a, int p, int k) {
  // the part's nearest capsule of the arm: every verdict is monotone in the distance (S_p and the
  // part's limit do not depend on which arm capsule), so the nearest decides what every pair of
  // the part would (the first nearest in index order, as pair by pair)
  // (the arm's capsules by their spheres' distance, nearest first, the lower index on a tie:
  // measured until the next sphere is farther than the nearest capsule found, which then no
  // capsule left can beat; picked one by one, not sorted: only the first few are measured)
  const int first = armFirst_[a], n = armFirst_[a + 1] - first;
  double* low = &lows_[(static_cast<std::size_t>(p) * kBodyParts + static_cast<std::size_t>(k)) * static_cast<std::size_t>(n)];
  Nearest best{std::numeric_limits<double>::infinity(), -1};
  while (true) {
    int next = -1;
    double lowest = std::numeric_limits<double>::infinity();
    for (int j = 0; j < n; ++j)
      if (low[j] < lowest) lowest = low[j], next = j;
    if (next < 0 || lowest > best.d) break;
    low[next] = std::numeric_limits<double>::infinity();  // measured
    const int i = armCaps_[first + next];
    const double dij = distance(caps_[i].c, body_[p][k]);
    if (dij < best.d || (dij == best.d && i < best.capsule)) best = {dij, i};
  }
  return best;
}

SsmVerdict SeparationMonitor::armVerdict(const Monitor& m, const PersonSet& persons, int a, ArmScan& s) {
  SsmVerdict v;
  v.robotSpeed = speed_[a];
  // the top speed a binary monitor must assume: declared, or faster if the arm is seen faster
  const double topSpeed = std::max(cfg_.robotSpeed, speed_[a]);
  // the graded responses with the drive known: its program speed now and the one it would brake from
  s.drive = cfg_.response == SsmResponse::Stop ? nullptr : drives_[a];
  const double sNow = s.drive ? s.drive->speed() : 1.0, sBrake = s.drive ? s.drive->brakingSpeed() : 1.0;
  for (int hand = 0; hand < 2; ++hand) {
    const double vh = hand ? cfg_.handSpeed : cfg_.bodySpeed;
    // without the drive, (3) and (4) as written at the speed seen
    s.terms[hand] = s.drive ? protectiveSeparation(cfg_, vh, speed_[a], sNow, sBrake)
                            : protectiveSeparation(cfg_, vh, speed_[a]);
    s.binary[hand] = protectiveSeparation(cfg_, vh, topSpeed).total();
  }
  s.worstCap = m.capsuleCount();
  boundParts(a, persons);
  // the nearest part of each kind (hand, body) decides the verdict: within a kind S_p, the allowed
  // speed, the binary stop and a contact are each monotone in the distance, so a part whose bound
  // is beyond the nearest of its kind measured so far cannot change a field and is not measured
  // (the part with the smallest bound of each kind is measured first); under pfl every region's
  // own contact limit counts: every part is
  const bool skip = cfg_.response != SsmResponse::Pfl;
  double nearest[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  int firstPart[2] = {-1, -1};
  Nearest firstNearest[2] = {};
  if (skip) {
    for (int pk = 0; pk < static_cast<int>(partLow_.size()); ++pk) {
      const int kind = bodyParts()[pk % kBodyParts].hand ? 1 : 0;
      if (persons.present(pk / kBodyParts) && (firstPart[kind] < 0 || partLow_[pk] < partLow_[firstPart[kind]]))
        firstPart[kind] = pk;
    }
    for (int kind = 0; kind < 2; ++kind)
      if (firstPart[kind] >= 0) {
        firstNearest[kind] = nearestCapsule(a, firstPart[kind] / kBodyParts, firstPart[kind] % kBodyParts);
        nearest[kind] = firstNearest[kind].d;
      }
  }
  for (int p = 0; p < persons.size(); ++p) {
    if (!persons.present(p)) continue;
    for (int k = 0; k < kBodyParts; ++k) {
      const int pk = p * kBodyParts + k, kind = bodyParts()[k].hand ? 1 : 0;
      if (skip && partLow_[pk] > nearest[kind]) continue;
      const Nearest n = pk == firstPart[kind] ? firstNearest[kind] : nearestCapsule(a, p, k);
      nearest[kind] = std::min(nearest[kind], n.d);
      if (n.capsule >= 0) judgePart(m, persons, a, p, k, n, v, s);
    }
  }
  if (v.person >= 0) respond(v, s);
  return v;
}

void SeparationMonitor::judgePart(const Monitor& m, const PersonSet& persons, int a, int p, int k, Nearest n,
                                  SsmVerdict& v, ArmScan& s) const {
  const double d = n.d;
  const int hand = bodyParts()[k].hand ? 1 : 0;
  const double vh = hand ? cfg_.handSpeed : cfg_.bodySpeed;
  const double slack = d - s.terms[hand].total();
  if (slack < s.worstSlack || (slack == s.worstSlack && n.capsule < s.worstCap)) {
    s.worstSlack = slack;
    s.worstCap = n.capsule;
    v.required = s.terms[hand].total();
    v.terms = s.terms[hand];
    v.person = p;
    v.part = k;
    v.armBody = m.capsuleBody(n.capsule);
  }
  v.separation = std::min(v.separation, d);
  const double allowed = s.drive ? allowedDrivenSpeed(cfg_, vh, d) : allowedRobotSpeed(cfg_, vh, d);
  v.allowedSpeed = std::min(v.allowedSpeed, allowed);
  bool clamped = false;
  const double limit = cfg_.response == SsmResponse::Pfl || d <= 0.0 ? partLimit(persons, p, k, n.capsule, clamped) : 0.0;
  if (cfg_.response == SsmResponse::Pfl) {
    s.pflAllowed = std::min(s.pflAllowed, std::max(allowed, limit));
    if (slack < 0.0) {
      v.pflLimit = std::min(v.pflLimit, limit);
      v.clamped = v.clamped || clamped;
      if (speed_[a] > limit) s.pflBreak = true;
    }
  }
  if (d < s.binary[hand]) s.stopBinary = true;
  if (d <= 0.0) {
    s.touching = true;
    s.touchLimit = std::min(s.touchLimit, limit);
  }
}

void SeparationMonitor::respond(SsmVerdict& v, const ArmScan& s) const {
  v.slack = s.worstSlack;
  v.violated = s.worstSlack < 0.0;
  if (cfg_.response == SsmResponse::Stop) {
    v.stop = s.stopBinary;
    v.factor = v.stop ? 0.0 : 1.0;
  } else if (cfg_.response == SsmResponse::Pfl) {
    // below S_p is allowed where the arm is no faster than every such region's contact limit;
    // the factor heads for the larger of S_p's speed and the limit, pair by pair
    v.pflAllowed = v.violated && !s.pflBreak;
    v.violated = s.pflBreak;
    v.allowedSpeed = s.pflAllowed;
    v.factor = std::clamp(s.pflAllowed / cfg_.robotSpeed, 0.0, 1.0);
    v.stop = v.violated;
    if (v.stop) v.factor = 0.0;
  } else {
    // the factor heads the drive for rest before S_p breaks; STOP only where it broke anyway
    v.factor = std::clamp(v.allowedSpeed / cfg_.robotSpeed, 0.0, 1.0);
    v.stop = v.violated;
    if (v.stop) v.factor = 0.0;
  }
}

void SeparationMonitor::count(const SsmVerdict& v, const ArmScan& s, double speed) {
  if (v.stop) ++counters_.stopCycles;
  else if (v.factor < 1.0) ++counters_.scaledCycles;
  if (v.violated && !v.stop) ++counters_.violations;
  if (v.pflAllowed) ++counters_.pflCycles;
  if (s.touching && speed > 0.0) {
    ++counters_.contacts;
    if (speed <= s.touchLimit) ++counters_.contactsWithinLimit;
    else ++counters_.contactsAboveLimit;
  }
  counters_.minSeparation = std::min(counters_.minSeparation, v.separation);
}

}  // namespace st::arm
