#include <starm/ssm.hpp>

#include <algorithm>
#include <cmath>

#include <stcore/distance.hpp>
#include <starm/monitor.hpp>

namespace st::arm {

const char* toString(SsmResponse r) { return r == SsmResponse::Stop ? "stop" : "scaling"; }

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
}

void PersonSet::pose(double t) {
  for (std::size_t i = 0; i < tracks_.size(); ++i) present_[i] = tracks_[i]->at(t, skeletons_[i]) ? 1 : 0;
}

SeparationMonitor::SeparationMonitor(SsmConfig cfg, int arms) : cfg_(cfg), verdicts_(static_cast<std::size_t>(arms)) {}

void SeparationMonitor::cycle(const Monitor& m, const PersonSet& persons) {
  ++counters_.cycles;
  const int nc = m.capsuleCount();
  // the arms' capsules at the cycle time, and each arm's speed: its fastest capsule end point
  std::vector<MovingCapsule> caps(static_cast<std::size_t>(nc));
  std::vector<double> speed(verdicts_.size(), 0.0);
  for (int i = 0; i < nc; ++i) {
    caps[i] = m.movingCapsule(i);
    double& v = speed[m.capsuleArm(i)];
    v = std::max({v, caps[i].va.norm(), caps[i].vb.norm()});
  }
  // every person's capsules once
  std::vector<std::array<Capsule, kBodyParts>> body(static_cast<std::size_t>(persons.size()));
  for (int p = 0; p < persons.size(); ++p)
    if (persons.present(p)) body[p] = bodyCapsules(persons.skeleton(p));

  for (int a = 0; a < static_cast<int>(verdicts_.size()); ++a) {
    SsmVerdict v;
    v.robotSpeed = speed[a];
    // the top speed a binary monitor must assume: declared, or faster if the arm is seen faster
    const double topSpeed = std::max(cfg_.robotSpeed, speed[a]);
    double worstSlack = std::numeric_limits<double>::infinity();
    bool touching = false, stopBinary = false;
    for (int i = 0; i < nc; ++i) {
      if (m.capsuleArm(i) != a) continue;
      for (int p = 0; p < persons.size(); ++p) {
        if (!persons.present(p)) continue;
        for (int k = 0; k < kBodyParts; ++k) {
          const double vh = bodyParts()[k].hand ? cfg_.handSpeed : cfg_.bodySpeed;
          const double d = distance(caps[i].c, body[p][k]);
          const SeparationTerms terms = protectiveSeparation(cfg_, vh, speed[a]);
          const double slack = d - terms.total();
          if (slack < worstSlack) {
            worstSlack = slack;
            v.required = terms.total();
            v.terms = terms;
            v.person = p;
            v.part = k;
            v.armBody = m.capsuleBody(i);
          }
          v.separation = std::min(v.separation, d);
          v.allowedSpeed = std::min(v.allowedSpeed, allowedRobotSpeed(cfg_, vh, d));
          if (d < protectiveSeparation(cfg_, vh, topSpeed).total()) stopBinary = true;
          if (d <= 0.0) touching = true;
        }
      }
    }
    if (v.person >= 0) {
      v.slack = worstSlack;
      v.violated = worstSlack < 0.0;
      if (cfg_.response == SsmResponse::Stop) {
        v.stop = stopBinary;
        v.factor = v.stop ? 0.0 : 1.0;
      } else {
        // the factor heads the drive for rest before S_p breaks; STOP only where it broke anyway
        v.factor = std::clamp(v.allowedSpeed / cfg_.robotSpeed, 0.0, 1.0);
        v.stop = v.violated;
        if (v.stop) v.factor = 0.0;
      }
    }
    if (v.stop) ++counters_.stopCycles;
    else if (v.factor < 1.0) ++counters_.scaledCycles;
    if (v.violated && !v.stop) ++counters_.violations;
    if (touching && speed[a] > 0.0) ++counters_.contacts;
    counters_.minSeparation = std::min(counters_.minSeparation, v.separation);
    verdicts_[a] = v;
  }
}

}  // namespace st::arm
