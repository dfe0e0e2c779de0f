#pragma once
// Persons in the cell: a person is a chain of capsules (head, torso, upper and lower arms, hands,
// thighs, lower legs) posed from a skeleton, the joint positions in the cell frame a camera
// skeleton tracker gives. Each capsule names its ISO/TS 15066 body region (Annex A, Table A.2)
// and the approach speed of ISO 13855 that bounds its motion: 2.0 m/s for a hand, 1.6 m/s for
// the rest of the body. A skeleton comes from a script in the scenario (walk to a point, reach
// into a volume, wait) or from a CSV trace; both are PersonTracks.
#include <algorithm>
#include <array>
#include <fstream>
#include <string>
#include <vector>

#include <stcore/shapes.hpp>

namespace st::arm {

// ISO/TS 15066:2016 Annex A, Table A.2 body regions (the ones our capsules cover).
enum class BodyRegion {
  Skull,          // skull and forehead
  Neck,
  Chest,          // back, shoulders, chest: the torso capsule
  Pelvis,         // pelvis and abdomen (the torso's lower half is not split off)
  UpperArm,       // upper arms and elbow joints
  LowerArm,       // lower arms and wrist joints
  Hand,           // hands and fingers
  Thigh,          // thighs and knees
  LowerLeg,       // lower legs
};
const char* toString(BodyRegion r);

// Skeleton joints, in the order of a CSV trace's columns.
enum SkeletonJoint : int {
  kHead, kNeck, kPelvis,
  kLeftShoulder, kLeftElbow, kLeftWrist, kLeftHand,
  kRightShoulder, kRightElbow, kRightWrist, kRightHand,
  kLeftHip, kLeftKnee, kLeftAnkle,
  kRightHip, kRightKnee, kRightAnkle,
  kSkeletonJoints
};
const char* jointName(int j);

struct Skeleton {
  std::array<Vec3, kSkeletonJoints> p;  // m, cell frame
};

// One body capsule: between two skeleton joints, its radius, region and name.
struct BodyPart {
  const char* name;
  int a, b;           // skeleton joints
  double radius;      // m
  BodyRegion region;
  bool hand;          // approaches at the hand speed
};
inline constexpr int kBodyParts = 12;
const std::array<BodyPart, kBodyParts>& bodyParts();

// The capsules of a posed skeleton, in bodyParts() order.
std::array<Capsule, kBodyParts> bodyCapsules(const Skeleton& s);

// A standing person (1.75 m) with the feet's midpoint at `feet` (z the floor), facing `heading`
// (rad about z from +x), arms hanging.
Skeleton standingSkeleton(const Vec3& feet, double heading);

// The reachable set of a capsule over time t at speed v: every point within v t of it (the
// capsule grown by v t), what ISO/TS 15066's S_h stands for.
inline Capsule reachable(const Capsule& c, double v, double t) { return {c.a, c.b, c.radius + v * t}; }

// Where a person is at time t.
class PersonTrack {
 public:
  virtual ~PersonTrack() = default;
  // The skeleton at time t; false when the track has no reading for t (before its first).
  virtual bool at(double t, Skeleton& s) = 0;
  // Each joint's velocity at t (m/s, cell frame), by default over the last h seconds:
  // (p(t) - p(t - h)) / h. False where the track cannot tell (no pose h before t): then the
  // person is taken at the standard's approach speeds.
  virtual bool velocities(double t, double h, std::array<Vec3, kSkeletonJoints>& v);
};

// A scripted person: from a standing start, a list of actions done one after the other.
struct PersonAction {
  enum Kind { Walk, Reach, Wait } kind = Wait;
  Vec3 to = Vec3::Zero();  // walk: the feet's goal (z ignored); reach: the hand's goal
  double speed = 0.0;      // m/s (walk: the feet; reach: the hand)
  double duration = 0.0;   // s, wait
  bool rightHand = true;   // reach
};
struct PersonScript {
  std::string name;
  Vec3 start = Vec3::Zero();  // feet
  double heading = 0.0;       // rad
  std::vector<PersonAction> actions;
};

class ScriptedPerson final : public PersonTrack {
 public:
  explicit ScriptedPerson(PersonScript script);
  bool at(double t, Skeleton& s) override;
  double end() const { return segments_.empty() ? 0.0 : segments_.back().t1; }

 private:
  // one action laid out in time: feet and hand goal interpolated linearly over [t0, t1]
  struct Segment {
    double t0, t1;
    Vec3 feet0, feet1;
    double heading;
    bool reaching;         // a hand is out (reaching or holding)
    bool rightHand;
    Vec3 hand0, hand1;     // the reaching hand's tip
  };
  PersonScript script_;
  std::vector<Segment> segments_;
};

// CSV lines `t, person, x y z of the 17 joints` (jointName order; 51 numbers), person by name;
// '#' comments and a header line allowed. The skeleton between two lines is interpolated
// linearly; after the last, it stays. Bad lines are InputErrors naming file:line.
class CsvPersonTrace {
 public:
  CsvPersonTrace(const std::string& path, std::vector<std::string> names);
  // All rows of person `index` (read at construction).
  struct Row {
    double t;
    Skeleton s;
  };
  const std::vector<Row>& rows(int index) const { return rows_[index]; }

 private:
  std::vector<std::vector<Row>> rows_;
};

class TracedPerson final : public PersonTrack {
 public:
  explicit TracedPerson(std::vector<CsvPersonTrace::Row> rows) : rows_(std::move(rows)) {}
  bool at(double t, Skeleton& s) override;

 private:
  std::vector<CsvPersonTrace::Row> rows_;
  std::size_t i_ = 0;
};

// A person whose skeleton is set from outside (a tracker over the network): there from its first
// pose on, where it was last set.
// Its joints' velocities are those between its last two stamped poses (a tracker's successive
// frames); a pose set without a time leaves them unknown.
class HeldPerson final : public PersonTrack {
 public:
  void set(const Skeleton& s) {
    s_ = s;
    seen_ = true;
    stamped_ = 0;
  }
  // a pose at time t (s), from kSkeletonJoints positions in SkeletonJoint order (a decoded
  // SKELETONS' pose); a later time than the last moves the last to the previous
  void set(const Vec3* joints, double t) {
    if (stamped_ > 0 && t > t_) prev_ = s_, prevT_ = t_, stamped_ = 2;
    else if (stamped_ == 0) stamped_ = 1;
    std::copy(joints, joints + kSkeletonJoints, s_.p.begin());
    t_ = t;
    seen_ = true;
  }
  bool at(double, Skeleton& s) override {
    if (seen_) s = s_;
    return seen_;
  }
  bool velocities(double, double, std::array<Vec3, kSkeletonJoints>& v) override {
    if (stamped_ < 2 || !(t_ > prevT_)) return false;
    for (int j = 0; j < kSkeletonJoints; ++j) v[j] = (s_.p[j] - prev_.p[j]) / (t_ - prevT_);
    return true;
  }

 private:
  Skeleton s_, prev_;
  double t_ = 0.0, prevT_ = 0.0;
  int stamped_ = 0;  // stamped poses held (0, 1 or 2)
  bool seen_ = false;
};

}  // namespace st::arm
