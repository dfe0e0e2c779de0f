#include <starm/arm.hpp>

#include <algorithm>
#include <cmath>

#include <stcore/distance.hpp>

namespace st::arm {

namespace {

constexpr double kPi = 3.141592653589793;

// A capsule as franka_description writes it: centre, axis direction, cylinder length, radius.
LinkCapsule centred(int body, const Vec3& centre, const Vec3& dir, double length, double radius) {
  const Vec3 half = 0.5 * length * dir.normalized();
  return {body, centre - half, centre + half, radius};
}

LinkCapsule rotated(const LinkCapsule& c, const Eigen::Matrix3d& r) { return {c.body, r * c.a, r * c.b, c.radius}; }

// One DH transform, written out (the matrix product is checked against Eigen's in the tests);
// under the Urdf convention the joint's origin followed by its motion.
Eigen::Isometry3d dhTransform(DhConvention conv, const Joint& j, double theta) {
  if (conv == DhConvention::Urdf) {
    if (j.type == JointType::Prismatic) return j.origin * Eigen::Translation3d(theta * j.axis);
    return j.origin * Eigen::AngleAxisd(theta, j.axis);
  }
  const double ct = std::cos(theta), st = std::sin(theta);
  const double ca = std::cos(j.alpha), sa = std::sin(j.alpha);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d rot;
  Vec3 p;
  if (conv == DhConvention::Modified) {
    rot << ct, -st, 0.0, st * ca, ct * ca, -sa, st * sa, ct * sa, ca;
    p << j.a, -sa * j.d, ca * j.d;
  } else {
    rot << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0.0, sa, ca;
    p << j.a * ct, j.a * st, j.d;
  }
  t.linear() = rot;
  t.translation() = p;
  return t;
}

}  // namespace

double jointReach(const Joint& j) {
  double r = std::abs(j.a) + std::abs(j.d) + j.origin.translation().norm();
  if (j.type == JointType::Prismatic) r += std::max(std::abs(j.lower), std::abs(j.upper));
  return r;
}

int ArmModel::bodyIndex(const std::string& wanted) const {
  for (const auto& [link, body] : links)
    if (link == wanted) return body;
  for (int b = 0; b < static_cast<int>(bodyNames.size()); ++b)
    if (bodyNames[b] == wanted) return b;
  if (wanted == "flange") return dof() + 1;
  if (wanted.rfind("link", 0) == 0 && wanted.size() > 4 && wanted.size() < 8 &&
      wanted.find_first_not_of("0123456789", 4) == std::string::npos) {
    const int k = std::stoi(wanted.substr(4));
    if (k <= dof()) return k;
  }
  return -1;
}

void ArmModel::setAllowed(int i, int j, bool allow) {
  allowed[i * bodies() + j] = allow;
  allowed[j * bodies() + i] = allow;
}

void ArmModel::resetAllowedToAdjacent() {
  const int n = bodies();
  allowed.assign(static_cast<std::size_t>(n * n), 0);
  for (int i = 0; i < n; ++i) setAllowed(i, i, true);
  for (int i = 0; i + 1 < n; ++i) setAllowed(i, i + 1, true);
}

ArmModel pandaModel() {
  ArmModel m;
  m.name = "panda";
  m.convention = DhConvention::Modified;
  const double a[7] = {0, 0, 0, 0.0825, -0.0825, 0, 0.088};
  const double d[7] = {0.333, 0, 0.316, 0, 0.384, 0, 0};
  const double alpha[7] = {0, -kPi / 2, kPi / 2, kPi / 2, -kPi / 2, kPi / 2, kPi / 2};
  const double lo[7] = {-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973};
  const double hi[7] = {2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973};
  for (int k = 0; k < 7; ++k) m.joints.push_back({a[k], alpha[k], d[k], 0.0, lo[k], hi[k]});
  m.flange = Eigen::Translation3d(0, 0, 0.107);
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  // franka_arm.xacro self-collision capsules, body k = panda_link<k>
  m.capsules = {
      centred(0, {-0.075, 0, 0.06}, x, 0.03, 0.06),
      centred(1, {0, 0, -0.1915}, z, 0.283, 0.06),
      centred(2, {0, 0, 0}, z, 0.12, 0.06),
      centred(3, {0, 0, -0.145}, z, 0.15, 0.06),
      centred(4, {0, 0, 0}, z, 0.12, 0.06),
      centred(5, {0, 0, -0.26}, z, 0.10, 0.06),
      centred(5, {0, 0.08, -0.13}, z, 0.14, 0.025),
      centred(6, {0, 0, -0.03}, z, 0.08, 0.05),
      centred(7, {0, 0, 0.01}, z, 0.14, 0.04),
      rotated(centred(7, {0.06, 0, 0.082}, x, 0.01, 0.03), Eigen::AngleAxisd(kPi / 4, z).toRotationMatrix()),
  };
  // franka_hand.xacro: the hand sits on the flange turned by -45 degrees about z
  const Eigen::Matrix3d hand = Eigen::AngleAxisd(-kPi / 4, z).toRotationMatrix();
  m.capsules.push_back(rotated(centred(8, {0, 0, 0.04}, y, 0.1, 0.04), hand));
  m.capsules.push_back(rotated(centred(8, {0, 0, 0.10}, y, 0.1, 0.02), hand));
  m.resetAllowedToAdjacent();
  // the capsules of links 1 and 3 overlap across the shoulder in a quarter of all poses; the
  // real links cannot meet (MoveIt's panda SRDF disables the pair as never colliding)
  m.setAllowed(1, 3, true);
  return m;
}

ArmModel iiwa14Model() {
  ArmModel m;
  m.name = "iiwa14";
  m.convention = DhConvention::Classic;
  const double d[7] = {0.36, 0, 0.42, 0, 0.40, 0, 0.126};
  const double alpha[7] = {-kPi / 2, kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, kPi / 2, 0};
  const double deg = kPi / 180.0;
  const double lim[7] = {170 * deg, 120 * deg, 170 * deg, 120 * deg, 170 * deg, 120 * deg, 175 * deg};
  for (int k = 0; k < 7; ++k) m.joints.push_back({0.0, alpha[k], d[k], 0.0, -lim[k], lim[k]});
  // capsules along the (straight-up) zero pose, in world coordinates, moved into body frames below
  struct Seg {
    int body;
    double z0, z1, r;
  };
  const Seg segs[] = {{0, 0.10, 0.12, 0.10}, {1, 0.17, 0.36, 0.08}, {2, 0.36, 0.56, 0.08}, {3, 0.56, 0.78, 0.075},
                      {4, 0.78, 0.98, 0.075}, {5, 0.98, 1.18, 0.07}, {6, 1.15, 1.22, 0.07}, {7, 1.22, 1.306, 0.05}};
  std::vector<double> q0(7, 0.0);
  const auto frames = forwardKinematics(m, Eigen::Isometry3d::Identity(), q0);
  for (const Seg& s : segs) {
    const Eigen::Isometry3d inv = frames[s.body].inverse();
    m.capsules.push_back({s.body, inv * Vec3(0, 0, s.z0), inv * Vec3(0, 0, s.z1), s.r});
  }
  m.resetAllowedToAdjacent();
  // across the wrist the approximating capsules touch in every pose
  m.setAllowed(5, 7, true);
  return m;
}

std::optional<ArmModel> builtinModel(const std::string& name) {
  if (name == "panda") return pandaModel();
  if (name == "iiwa14") return iiwa14Model();
  return std::nullopt;
}

void forwardKinematics(const ArmModel& m, const Eigen::Isometry3d& base, const double* q, Eigen::Isometry3d* frames) {
  frames[0] = base;
  const int n = m.dof();
  for (int k = 0; k < n; ++k) frames[k + 1] = frames[k] * dhTransform(m.convention, m.joints[k], q[k] + m.joints[k].offset);
  frames[n + 1] = frames[n] * m.flange;
}

std::vector<Eigen::Isometry3d> forwardKinematics(const ArmModel& m, const Eigen::Isometry3d& base,
                                                 const std::vector<double>& q) {
  std::vector<Eigen::Isometry3d> frames(m.bodies());
  forwardKinematics(m, base, q.data(), frames.data());
  return frames;
}

std::vector<BodyContact> selfContacts(const ArmModel& m, const std::vector<double>& q, double separation) {
  const auto frames = forwardKinematics(m, Eigen::Isometry3d::Identity(), q);
  std::vector<BodyContact> out;
  for (std::size_t i = 0; i < m.capsules.size(); ++i)
    for (std::size_t j = i + 1; j < m.capsules.size(); ++j) {
      const LinkCapsule &ci = m.capsules[i], &cj = m.capsules[j];
      if (m.isAllowed(ci.body, cj.body)) continue;
      const Capsule a{frames[ci.body] * ci.a, frames[ci.body] * ci.b, ci.radius};
      const Capsule b{frames[cj.body] * cj.a, frames[cj.body] * cj.b, cj.radius};
      const double d = distance(a, b);
      if (d > separation) continue;
      const int lo = std::min(ci.body, cj.body), hi = std::max(ci.body, cj.body);
      const auto it = std::find_if(out.begin(), out.end(), [&](const BodyContact& c) { return c.a == lo && c.b == hi; });
      if (it == out.end()) out.push_back({lo, hi, d});
      else it->distance = std::min(it->distance, d);
    }
  return out;
}

void bodyRates(const ArmModel& m, const Eigen::Isometry3d* frames, const double* qdot, BodyRates& out) {
  const int n = m.dof();
  out.w.resize(n + 2);
  out.c.resize(n + 2);
  out.w[0].setZero();
  out.c[0].setZero();
  for (int k = 1; k <= n; ++k) {
    // joint k turns about z of frame k (modified) or frame k-1 (classic), about or along its
    // axis in frame k (urdf)
    const bool urdf = m.convention == DhConvention::Urdf;
    const Eigen::Isometry3d& f = frames[m.convention == DhConvention::Classic ? k - 1 : k];
    const Vec3 axis = urdf ? Vec3(f.linear() * m.joints[k - 1].axis) : Vec3(f.linear().col(2));
    if (urdf && m.joints[k - 1].type == JointType::Prismatic) {
      // a slide: every point of the body and beyond moves at qdot axis (w x p - c with c = -v)
      out.w[k] = out.w[k - 1];
      out.c[k] = out.c[k - 1] - qdot[k - 1] * axis;
      continue;
    }
    const Vec3 w = qdot[k - 1] * axis;
    out.w[k] = out.w[k - 1] + w;
    out.c[k] = out.c[k - 1] + w.cross(f.translation());
  }
  out.w[n + 1] = out.w[n];
  out.c[n + 1] = out.c[n];
}

}  // namespace st::arm
