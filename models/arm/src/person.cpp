#include <starm/person.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <starm/sensor.hpp>

namespace st::arm {

namespace {

// segment lengths of an arm (m): shoulder-elbow, elbow-wrist, wrist-hand tip
constexpr double kUpperArm = 0.30, kLowerArm = 0.26, kHandLength = 0.10;
constexpr double kArmReach = kUpperArm + kLowerArm + kHandLength;

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// An arm held straight from the shoulder towards `target` (clamped to its reach).
void poseArm(Skeleton& s, int shoulder, const Vec3& target) {
  const Vec3 sh = s.p[shoulder];
  Vec3 d = target - sh;
  const double n = d.norm();
  if (n < 1e-9) return;  // a hand at the shoulder: leave the hanging pose
  d /= n;
  const double reach = std::min(n, kArmReach);
  const double k = reach / kArmReach;  // a bent arm shortens each segment alike
  s.p[shoulder + 1] = sh + d * (kUpperArm * k);
  s.p[shoulder + 2] = sh + d * ((kUpperArm + kLowerArm) * k);
  s.p[shoulder + 3] = sh + d * reach;
}

}  // namespace

const char* toString(BodyRegion r) {
  switch (r) {
    case BodyRegion::Skull: return "skull_forehead";
    case BodyRegion::Neck: return "neck";
    case BodyRegion::Chest: return "back_shoulders_chest";
    case BodyRegion::Pelvis: return "pelvis_abdomen";
    case BodyRegion::UpperArm: return "upper_arm_elbow";
    case BodyRegion::LowerArm: return "lower_arm_wrist";
    case BodyRegion::Hand: return "hand_fingers";
    case BodyRegion::Thigh: return "thigh_knee";
    case BodyRegion::LowerLeg: return "lower_leg";
  }
  return "?";
}

const char* jointName(int j) {
  static const char* const names[kSkeletonJoints] = {
      "head", "neck", "pelvis", "l_shoulder", "l_elbow", "l_wrist", "l_hand", "r_shoulder", "r_elbow",
      "r_wrist", "r_hand", "l_hip", "l_knee", "l_ankle", "r_hip", "r_knee", "r_ankle"};
  return j >= 0 && j < kSkeletonJoints ? names[j] : "?";
}

const std::array<BodyPart, kBodyParts>& bodyParts() {
  // radii: adult 50th percentile girths (head 0.11, torso 0.17 half-depth-and-width envelope)
  static const std::array<BodyPart, kBodyParts> parts{{
      {"head", kNeck, kHead, 0.11, BodyRegion::Skull, false},
      {"torso", kPelvis, kNeck, 0.17, BodyRegion::Chest, false},
      {"l_upper_arm", kLeftShoulder, kLeftElbow, 0.05, BodyRegion::UpperArm, false},
      {"l_lower_arm", kLeftElbow, kLeftWrist, 0.04, BodyRegion::LowerArm, false},
      {"l_hand", kLeftWrist, kLeftHand, 0.05, BodyRegion::Hand, true},
      {"r_upper_arm", kRightShoulder, kRightElbow, 0.05, BodyRegion::UpperArm, false},
      {"r_lower_arm", kRightElbow, kRightWrist, 0.04, BodyRegion::LowerArm, false},
      {"r_hand", kRightWrist, kRightHand, 0.05, BodyRegion::Hand, true},
      {"l_thigh", kLeftHip, kLeftKnee, 0.08, BodyRegion::Thigh, false},
      {"l_lower_leg", kLeftKnee, kLeftAnkle, 0.06, BodyRegion::LowerLeg, false},
      {"r_thigh", kRightHip, kRightKnee, 0.08, BodyRegion::Thigh, false},
      {"r_lower_leg", kRightKnee, kRightAnkle, 0.06, BodyRegion::LowerLeg, false},
  }};
  return parts;
}

std::array<Capsule, kBodyParts> bodyCapsules(const Skeleton& s) {
  std::array<Capsule, kBodyParts> c;
  for (int i = 0; i < kBodyParts; ++i) {
    const BodyPart& b = bodyParts()[i];
    c[i] = {s.p[b.a], s.p[b.b], b.radius};
  }
  return c;
}

Skeleton standingSkeleton(const Vec3& feet, double heading) {
  const Vec3 left(-std::sin(heading), std::cos(heading), 0.0);
  const Vec3 base(feet.x(), feet.y(), feet.z());
  auto at = [&](double side, double z) { return Vec3(base + side * left + Vec3(0, 0, z)); };
  Skeleton s;
  s.p[kHead] = at(0.0, 1.62);
  s.p[kNeck] = at(0.0, 1.45);
  s.p[kPelvis] = at(0.0, 0.95);
  s.p[kLeftShoulder] = at(0.20, 1.42);
  s.p[kLeftElbow] = at(0.22, 1.12);
  s.p[kLeftWrist] = at(0.22, 0.86);
  s.p[kLeftHand] = at(0.22, 0.76);
  s.p[kRightShoulder] = at(-0.20, 1.42);
  s.p[kRightElbow] = at(-0.22, 1.12);
  s.p[kRightWrist] = at(-0.22, 0.86);
  s.p[kRightHand] = at(-0.22, 0.76);
  s.p[kLeftHip] = at(0.10, 0.92);
  s.p[kLeftKnee] = at(0.10, 0.50);
  s.p[kLeftAnkle] = at(0.10, 0.08);
  s.p[kRightHip] = at(-0.10, 0.92);
  s.p[kRightKnee] = at(-0.10, 0.50);
  s.p[kRightAnkle] = at(-0.10, 0.08);
  return s;
}

ScriptedPerson::ScriptedPerson(PersonScript script) : script_(std::move(script)) {
  // lay the actions out in time; a walk after a reach first lowers the hand at the hand's speed
  double t = 0.0;
  Vec3 feet = script_.start;
  double heading = script_.heading;
  bool reaching = false, right = true;
  Vec3 hand = Vec3::Zero();
  double handSpeed = 2.0;
  auto hanging = [&](bool r) { return standingSkeleton(feet, heading).p[r ? kRightHand : kLeftHand]; };
  for (const PersonAction& a : script_.actions) {
    if (a.kind == PersonAction::Wait) {
      segments_.push_back({t, t + a.duration, feet, feet, heading, reaching, right, hand, hand});
      t += a.duration;
    } else if (a.kind == PersonAction::Walk) {
      if (reaching) {
        const Vec3 down = hanging(right);
        const double dt = (down - hand).norm() / handSpeed;
        segments_.push_back({t, t + dt, feet, feet, heading, true, right, hand, down});
        t += dt;
        reaching = false;
      }
      Vec3 goal(a.to.x(), a.to.y(), feet.z());
      const Vec3 d = goal - feet;
      if (d.norm() > 0.0) heading = std::atan2(d.y(), d.x());
      const double dt = d.norm() / a.speed;
      segments_.push_back({t, t + dt, feet, goal, heading, false, right, hand, hand});
      t += dt;
      feet = goal;
    } else {  // reach
      const bool r = a.rightHand;
      const Vec3 from = reaching && r == right ? hand : hanging(r);
      if (reaching && r != right) {
        // the other hand first comes down
        const Vec3 down = hanging(right);
        const double dt = (down - hand).norm() / handSpeed;
        segments_.push_back({t, t + dt, feet, feet, heading, true, right, hand, down});
        t += dt;
      }
      const double dt = (a.to - from).norm() / a.speed;
      segments_.push_back({t, t + dt, feet, feet, heading, true, r, from, a.to});
      t += dt;
      reaching = true;
      right = r;
      hand = a.to;
      handSpeed = a.speed;
    }
  }
}

bool PersonTrack::velocities(double t, double h, std::array<Vec3, kSkeletonJoints>& v) {
  Skeleton now, before;
  if (!(h > 0.0) || !at(t - h, before) || !at(t, now)) return false;
  for (int j = 0; j < kSkeletonJoints; ++j) v[j] = (now.p[j] - before.p[j]) / h;
  return true;
}

bool ScriptedPerson::at(double t, Skeleton& s) {
  if (segments_.empty()) {
    s = standingSkeleton(script_.start, script_.heading);
    return true;
  }
  // the segment holding t (before the first: its start; after the last: its end)
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t, [](double x, const Segment& g) { return x < g.t1; });
  const Segment& g = it == segments_.end() ? segments_.back() : *it;
  const double u = g.t1 > g.t0 ? std::clamp((t - g.t0) / (g.t1 - g.t0), 0.0, 1.0) : 1.0;
  s = standingSkeleton(g.feet0 + u * (g.feet1 - g.feet0), g.heading);
  if (g.reaching) poseArm(s, g.rightHand ? kRightShoulder : kLeftShoulder, g.hand0 + u * (g.hand1 - g.hand0));
  return true;
}

CsvPersonTrace::CsvPersonTrace(const std::string& path, std::vector<std::string> names) : rows_(names.size()) {
  if (std::filesystem::is_directory(path)) throw InputError(path + ": is a directory, not a person trace");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the person trace");
  std::string line;
  int n = 0;
  constexpr std::size_t kFields = 2 + 3 * kSkeletonJoints;
  while (std::getline(in, line)) {
    ++n;
    const std::string where = path + ":" + std::to_string(n);
    if (line.size() > 64 * 1024) throw InputError(where + ": a line longer than 64 KiB: not a person trace");
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(trim(c));
    if (n == 1 && !cells.empty() && cells[0] == "t") continue;  // header
    if (cells.size() != kFields)
      throw InputError(where + ": expected t, person and x, y, z of " + std::to_string(kSkeletonJoints) + " joints (" +
                       std::to_string(kFields) + " fields), got " + std::to_string(cells.size()));
    auto number = [&](std::size_t i, const std::string& what) {
      char* end = nullptr;
      const double v = std::strtod(cells[i].c_str(), &end);
      if (cells[i].empty() || *end != '\0') throw InputError(where + ": " + what + " '" + cells[i] + "' is not a number");
      if (!std::isfinite(v)) throw InputError(where + ": " + what + " is not finite");
      return v;
    };
    CsvPersonTrace::Row row;
    row.t = number(0, "t");
    const auto who = std::find(names.begin(), names.end(), cells[1]);
    if (who == names.end()) throw InputError(where + ": unknown person '" + cells[1] + "'");
    for (int j = 0; j < kSkeletonJoints; ++j)
      for (int k = 0; k < 3; ++k) {
        const double v = number(2 + 3 * j + k, std::string(jointName(j)) + "." + "xyz"[k]);
        // a cell is some metres across: a joint 1 km away is a corrupt reading
        if (std::abs(v) > 1000.0) throw InputError(where + ": " + jointName(j) + " is more than 1 km from the cell's origin");
        row.s.p[j][k] = v;
      }
    auto& rows = rows_[who - names.begin()];
    if (!rows.empty() && row.t <= rows.back().t)
      throw InputError(where + ": time " + cells[0] + " s is not after the person's previous line");
    rows.push_back(row);
  }
}

bool TracedPerson::at(double t, Skeleton& s) {
  if (rows_.empty() || t < rows_.front().t) return false;
  while (i_ + 1 < rows_.size() && rows_[i_ + 1].t <= t) ++i_;
  while (i_ > 0 && rows_[i_].t > t) --i_;
  if (i_ + 1 >= rows_.size()) {
    s = rows_[i_].s;
    return true;
  }
  const CsvPersonTrace::Row& a = rows_[i_];
  const CsvPersonTrace::Row& b = rows_[i_ + 1];
  const double u = (t - a.t) / (b.t - a.t);
  for (int j = 0; j < kSkeletonJoints; ++j) s.p[j] = a.s.p[j] + u * (b.s.p[j] - a.s.p[j]);
  return true;
}

}  // namespace st::arm
