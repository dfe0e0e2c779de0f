// Forward kinematics: the Panda's published zero pose, an independent DH product, and joint
// rates against finite differences of the kinematics.
#include <gtest/gtest.h>

#include <random>

#include <starm/arm.hpp>

namespace st::arm {
namespace {

// T_k written as a product of elementary motions, straight from the convention's definition.
Eigen::Isometry3d dhProduct(const ArmModel& m, const Eigen::Isometry3d& base, const std::vector<double>& q, int upto) {
  Eigen::Isometry3d t = base;
  for (int k = 0; k < upto; ++k) {
    const Joint& j = m.joints[k];
    const double theta = q[k] + j.offset;
    if (m.convention == DhConvention::Modified)
      t = t * Eigen::AngleAxisd(j.alpha, Vec3::UnitX()) * Eigen::Translation3d(j.a, 0, 0) *
          Eigen::AngleAxisd(theta, Vec3::UnitZ()) * Eigen::Translation3d(0, 0, j.d);
    else
      t = t * Eigen::AngleAxisd(theta, Vec3::UnitZ()) * Eigen::Translation3d(0, 0, j.d) *
          Eigen::Translation3d(j.a, 0, 0) * Eigen::AngleAxisd(j.alpha, Vec3::UnitX());
  }
  return t;
}

std::vector<double> randomQ(const ArmModel& m, std::mt19937_64& g) {
  std::vector<double> q;
  for (const Joint& j : m.joints) q.push_back(std::uniform_real_distribution<double>(j.lower, j.upper)(g));
  return q;
}

ArmModel customClassic() {
  // an arm with every parameter non-zero, to exercise each term of the classic matrix
  ArmModel m;
  m.name = "custom";
  m.convention = DhConvention::Classic;
  m.joints = {{0.1, 0.3, 0.2, 0.1, -3, 3}, {0.25, -1.2, 0.05, -0.4, -3, 3}, {0.15, 0.7, -0.1, 0.2, -3, 3},
              {0.05, 1.5, 0.3, 0.0, -3, 3}};
  m.flange = Eigen::Translation3d(0.01, 0.02, 0.1) * Eigen::AngleAxisd(0.3, Vec3::UnitY());
  m.capsules = {{2, {0, 0, 0}, {0.1, 0, 0}, 0.05}, {4, {0, 0.05, 0}, {0, 0, 0.1}, 0.03}};
  m.resetAllowedToAdjacent();
  return m;
}

TEST(Kinematics, PandaFlangeAtZero) {
  const ArmModel m = pandaModel();
  const auto f = forwardKinematics(m, Eigen::Isometry3d::Identity(), std::vector<double>(7, 0.0));
  const Vec3 p = f.back().translation();
  EXPECT_NEAR(p.x(), 0.088, 1e-12);
  EXPECT_NEAR(p.y(), 0.0, 1e-12);
  EXPECT_NEAR(p.z(), 0.926, 1e-12);
}

TEST(Kinematics, Iiwa14StraightUpAtZero) {
  const auto f = forwardKinematics(iiwa14Model(), Eigen::Isometry3d::Identity(), std::vector<double>(7, 0.0));
  EXPECT_NEAR((f.back().translation() - Vec3(0, 0, 0.36 + 0.42 + 0.40 + 0.126)).norm(), 0.0, 1e-12);
}

TEST(Kinematics, MatchesDhProductAtRandomQ) {
  std::mt19937_64 g(11);
  for (const ArmModel& m : {pandaModel(), iiwa14Model(), customClassic()}) {
    const Eigen::Isometry3d base = Eigen::Translation3d(0.3, -0.2, 0.1) * Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized());
    for (int trial = 0; trial < 1000; ++trial) {
      const auto q = randomQ(m, g);
      const auto f = forwardKinematics(m, base, q);
      for (int k = 0; k <= m.dof(); ++k) {
        const Eigen::Isometry3d ref = dhProduct(m, base, q, k);
        ASSERT_LT((f[k].matrix() - ref.matrix()).cwiseAbs().maxCoeff(), 1e-12) << m.name << " frame " << k;
      }
      const Eigen::Isometry3d flange = dhProduct(m, base, q, m.dof()) * m.flange;
      ASSERT_LT((f.back().matrix() - flange.matrix()).cwiseAbs().maxCoeff(), 1e-12) << m.name;
    }
  }
}

TEST(Kinematics, PointVelocitiesMatchFiniteDifferences) {
  std::mt19937_64 g(12);
  for (const ArmModel& m : {pandaModel(), iiwa14Model(), customClassic()}) {
    const Eigen::Isometry3d base = Eigen::Translation3d(0.5, 0.1, 0) * Eigen::AngleAxisd(1.0, Vec3::UnitZ());
    for (int trial = 0; trial < 200; ++trial) {
      auto q = randomQ(m, g);
      std::vector<double> qd;
      for (int k = 0; k < m.dof(); ++k) qd.push_back(std::uniform_real_distribution<double>(-2, 2)(g));
      const auto f = forwardKinematics(m, base, q);
      BodyRates rates;
      bodyRates(m, f.data(), qd.data(), rates);
      // central difference of the world position of each capsule end point
      const double h = 1e-6;
      std::vector<double> qp = q, qm = q;
      for (int k = 0; k < m.dof(); ++k) qp[k] += h * qd[k], qm[k] -= h * qd[k];
      const auto fp = forwardKinematics(m, base, qp), fm = forwardKinematics(m, base, qm);
      for (const LinkCapsule& c : m.capsules)
        for (const Vec3& local : {c.a, c.b}) {
          const Vec3 numeric = (fp[c.body] * local - fm[c.body] * local) / (2 * h);
          const Vec3 analytic = rates.velocity(c.body, f[c.body] * local);
          ASSERT_LT((numeric - analytic).norm(), 1e-7) << m.name << " body " << c.body;
        }
    }
  }
}

TEST(Kinematics, AllowedCollisionMatrixIsEditableAndSymmetric) {
  ArmModel m = pandaModel();
  EXPECT_TRUE(m.isAllowed(2, 3));
  EXPECT_FALSE(m.isAllowed(2, 5));
  m.setAllowed(5, 2, true);
  EXPECT_TRUE(m.isAllowed(2, 5));
  m.setAllowed(2, 3, false);
  EXPECT_FALSE(m.isAllowed(3, 2));
}

}  // namespace
}  // namespace st::arm
