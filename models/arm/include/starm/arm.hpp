#pragma once
// Serial arms from Denavit-Hartenberg parameters or a URDF joint chain (starm/urdf.hpp), their
// links as capsules, and forward kinematics. Bodies are numbered by the frame they ride on: 0 the
// base, k the frame after joint k (k = 1..n), n + 1 the flange (tool). Lengths in metres, angles
// in radians.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <stcore/shapes.hpp>

namespace st::arm {

enum class DhConvention {
  Classic,   // T_k = Rz(theta_k) Tz(d_k) Tx(a_k) Rx(alpha_k); joint k turns about z of frame k-1
  Modified,  // T_k = Rx(alpha_{k-1}) Tx(a_{k-1}) Rz(theta_k) Tz(d_k) (Craig); joint k turns about z of frame k
  Urdf,      // T_k = origin_k * motion_k(q_k): turn about (revolute) or slide along (prismatic) axis_k of frame k
};

enum class JointType { Revolute, Prismatic };

// One joint. For the modified convention a and alpha are those applied before the joint. Under
// the Urdf convention a, alpha, d and offset are unused: origin and axis place it, and it may be
// prismatic (q in metres, limits in metres, rates in m/s).
struct Joint {
  double a = 0.0;
  double alpha = 0.0;
  double d = 0.0;
  double offset = 0.0;  // theta_k = q_k + offset
  double lower = -3.141592653589793;
  double upper = 3.141592653589793;
  // Largest believable |qdot| (rad/s). A sanity bound on sensor readings, not the arm's rated
  // speed (Panda 2.6, iiwa 2.4 rad/s at most): a reading beyond it is a fault (a unit mix-up,
  // a corrupt value) and extrapolating from it would make every time to collision zero.
  double maxRate = 100.0;
  JointType type = JointType::Revolute;  // Prismatic only under the Urdf convention
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // Urdf: parent body frame -> joint frame at q = 0
  Vec3 axis = Vec3::UnitZ();                                  // Urdf: unit, in the joint frame
  std::string name{};                                         // Urdf: the joint's name
};

// Upper bound on how far a joint moves its child frame from its parent's origin (m): the
// space's default bounds add these up.
double jointReach(const Joint& j);

// A capsule fixed in body `body`'s frame.
struct LinkCapsule {
  int body = 0;
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  double radius = 0.0;
};

struct ArmModel {
  std::string name;
  DhConvention convention = DhConvention::Modified;
  std::vector<Joint> joints;
  Eigen::Isometry3d flange = Eigen::Isometry3d::Identity();  // last joint frame -> flange
  std::vector<LinkCapsule> capsules;
  // allowed[i * bodies + j]: never test bodies i and j against each other (allowed-collision matrix)
  std::vector<char> allowed;
  // Names of the bodies (URDF: the link each body is, 0..n+1); empty: link0..link<n>, flange.
  std::vector<std::string> bodyNames;
  // Every named link and the body it rides on (URDF links joined by fixed joints share a body).
  std::vector<std::pair<std::string, int>> links;

  int dof() const { return static_cast<int>(joints.size()); }
  int bodies() const { return dof() + 2; }
  bool isAllowed(int i, int j) const { return allowed[i * bodies() + j] != 0; }
  void setAllowed(int i, int j, bool allow);
  // Adjacent bodies (k, k+1) allowed, everything else checked.
  void resetAllowedToAdjacent();
  // The body a name refers to: a link name of `links`, a body name, or link<k> / flange; -1 if none.
  int bodyIndex(const std::string& name) const;
};

// Franka Emika Panda: modified DH, flange 0.107 m, self-collision capsules of franka_description
// (franka_arm.xacro, franka_hand.xacro) with the hand on the flange.
ArmModel pandaModel();
// KUKA LBR iiwa 14 R820: classic DH; capsules approximate the link housings (axial, radii from
// the data sheet outline).
ArmModel iiwa14Model();
std::optional<ArmModel> builtinModel(const std::string& name);

// Forward kinematics: frames[k] for k = 0..n+1 (base, joint frames, flange) in the world.
void forwardKinematics(const ArmModel& m, const Eigen::Isometry3d& base, const double* q, Eigen::Isometry3d* frames);
std::vector<Eigen::Isometry3d> forwardKinematics(const ArmModel& m, const Eigen::Isometry3d& base,
                                                 const std::vector<double>& q);

// Body pairs the allowed-collision matrix checks whose capsules are within `separation` (m) of
// each other at pose q: each (i < j) once, with the smallest distance (negative: overlap depth).
struct BodyContact {
  int a = -1, b = -1;
  double distance = 0.0;
};
std::vector<BodyContact> selfContacts(const ArmModel& m, const std::vector<double>& q, double separation);

// Joint axes in the world: the body-k twist is the sum over joints j <= k of qdot_j about
// (axis_j through point_j). Velocity of a point p on body k: w_k x p - c_k with
// w_k = sum qdot_j axis_j and c_k = sum qdot_j axis_j x point_j.
struct BodyRates {
  std::vector<Vec3> w;  // per body
  std::vector<Vec3> c;  // per body
  Vec3 velocity(int body, const Vec3& p) const { return w[body].cross(p) - c[body]; }
};
void bodyRates(const ArmModel& m, const Eigen::Isometry3d* frames, const double* qdot, BodyRates& out);

}  // namespace st::arm
