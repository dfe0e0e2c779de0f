// URDF robots against independent truth: the UR5 written as URDF and as modified DH gives the
// same frames and the same warnings; converted collision shapes bound the true shapes (brute-force
// sampling); a prismatic joint's frames and rates by hand; bad URDFs as one line naming the file.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <tuple>
#include <sstream>

#include <tinyxml.h>

#include <stcore/distance.hpp>
#include <starm/scenario.hpp>
#include <starm/urdf.hpp>

namespace st::arm {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.141592653589793;

std::string shipped(const std::string& f) { return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + f; }

// Universal Robots' UR5 DH parameters (classic: d1 0.089159, a2 -0.425, a3 -0.39225, d4 0.10915,
// d5 0.09465, d6 0.0823) in the modified convention, tool0 1 cm out along the last z.
ArmModel ur5Dh() {
  ArmModel m;
  m.name = "ur5_dh";
  m.convention = DhConvention::Modified;
  const double a[6] = {0, 0, -0.425, -0.39225, 0, 0};
  const double alpha[6] = {0, kPi / 2, 0, 0, kPi / 2, -kPi / 2};
  const double d[6] = {0.089159, 0, 0, 0.10915, 0.09465, 0.0823};
  for (int k = 0; k < 6; ++k) {
    Joint j;
    j.a = a[k];
    j.alpha = alpha[k];
    j.d = d[k];
    j.lower = -2 * kPi;
    j.upper = 2 * kPi;
    m.joints.push_back(j);
  }
  m.flange = Eigen::Translation3d(0, 0, 0.01);
  m.resetAllowedToAdjacent();
  return m;
}

TEST(Urdf, Ur5FramesEqualTheDhModel) {
  const ArmModel u = loadUrdf(shipped("ur5.urdf"));
  const ArmModel dh = ur5Dh();
  ASSERT_EQ(u.dof(), 6);
  ASSERT_EQ(u.bodies(), dh.bodies());
  EXPECT_EQ(u.bodyNames.front(), "base_link");
  EXPECT_EQ(u.bodyNames.back(), "tool0");
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> angle(-2 * kPi, 2 * kPi);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translate(Vec3(0.3, -0.2, 0.75)).rotate(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  double worst = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    std::vector<double> q(6);
    for (double& v : q) v = angle(gen);
    const auto fu = forwardKinematics(u, base, q);
    const auto fd = forwardKinematics(dh, base, q);
    for (int b = 0; b < u.bodies(); ++b) worst = std::max(worst, (fu[b].matrix() - fd[b].matrix()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-12);  // 6.7e-16 measured
  RecordProperty("worst", std::to_string(worst));
}

// The URDF's joint chain composed here from the file's own numbers (read with tinyxml, not
// urdfdom): origin xyz, then Rz(yaw) Ry(pitch) Rx(roll), then the turn about the axis; the
// model's frames equal it within 1e-12 at 1 000 random configurations.
TEST(Urdf, Ur5FramesEqualTheChainComposedIndependently) {
  TiXmlDocument doc(shipped("ur5.urdf"));
  ASSERT_TRUE(doc.LoadFile());
  auto numbers = [](const char* text) {
    std::istringstream in(text ? text : "0 0 0");
    Vec3 v;
    in >> v.x() >> v.y() >> v.z();
    return v;
  };
  struct RawJoint {
    Eigen::Isometry3d origin;
    Vec3 axis;
    bool moving;
  };
  std::vector<RawJoint> chain;  // in file order, which is chain order for ur5.urdf
  for (const TiXmlElement* j = doc.RootElement()->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const TiXmlElement* o = j->FirstChildElement("origin");
    const Vec3 xyz = numbers(o ? o->Attribute("xyz") : nullptr), rpy = numbers(o ? o->Attribute("rpy") : nullptr);
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translation() = xyz;
    t.linear() = (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Vec3::UnitX())).toRotationMatrix();
    const TiXmlElement* ax = j->FirstChildElement("axis");
    chain.push_back({t, numbers(ax ? ax->Attribute("xyz") : "1 0 0").normalized(), std::string(j->Attribute("type")) != "fixed"});
  }
  const ArmModel u = loadUrdf(shipped("ur5.urdf"));
  ASSERT_EQ(chain.size(), 7u);
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> angle(-2 * kPi, 2 * kPi);
  double worst = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    std::vector<double> q(6);
    for (double& v : q) v = angle(gen);
    const auto f = forwardKinematics(u, Eigen::Isometry3d::Identity(), q);
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    int k = 0;
    for (const RawJoint& j : chain) {
      t = t * j.origin;
      if (j.moving) t = t * Eigen::AngleAxisd(q[k++], j.axis);
      worst = std::max(worst, (t.matrix() - f[j.moving ? k : k + 1].matrix()).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_LE(worst, 1e-12);
}

// Body velocities from the URDF axes equal those of the DH model (and a finite difference).
TEST(Urdf, Ur5RatesEqualTheDhModel) {
  const ArmModel u = loadUrdf(shipped("ur5.urdf"));
  const ArmModel dh = ur5Dh();
  const std::vector<double> q = {0.3, -1.1, 0.9, -0.4, 1.2, 0.5}, qd = {0.5, -0.3, 0.8, 1.1, -0.7, 0.9};
  const auto fu = forwardKinematics(u, Eigen::Isometry3d::Identity(), q);
  const auto fd = forwardKinematics(dh, Eigen::Isometry3d::Identity(), q);
  BodyRates ru, rd;
  bodyRates(u, fu.data(), qd.data(), ru);
  bodyRates(dh, fd.data(), qd.data(), rd);
  for (int b = 0; b < u.bodies(); ++b) {
    const Vec3 p = fu[b] * Vec3(0.05, -0.02, 0.1);
    EXPECT_LT((ru.velocity(b, p) - rd.velocity(b, p)).norm(), 1e-12) << b;
  }
}

// The shipped cell with each URDF arm replaced by the DH UR5 carrying the same capsules: the same
// warnings, cycle by cycle.
TEST(Urdf, CellFromUrdfAndFromDhWarnsAlike) {
  const Scenario s = loadScenario(shipped("two_ur5_cell.yaml"));
  Scenario d = s;
  for (ArmInstance& a : d.arms) {
    ArmModel dh = ur5Dh();
    dh.capsules = a.model.capsules;
    dh.allowed = a.model.allowed;
    a.model = dh;
  }
  Monitor mu = makeMonitor(s), md = makeMonitor(d);
  auto su = makeSensor(s), sd = makeSensor(d);
  RunStats stu, std_;
  std::vector<Warning> wu, wd;
  run(mu, *su, stu, [&](const Monitor& m) { wu.insert(wu.end(), m.warnings().begin(), m.warnings().end()); });
  run(md, *sd, std_, [&](const Monitor& m) { wd.insert(wd.end(), m.warnings().begin(), m.warnings().end()); });
  ASSERT_GT(wu.size(), 0u);
  ASSERT_EQ(wu.size(), wd.size());
  // within a cycle the order follows the space's traversal: compare as sets
  auto key = [](const Warning& w) { return std::make_tuple(w.t, w.arm, w.capsule, w.otherArm, w.otherCapsule, w.obstacle); };
  auto byKey = [&](const Warning& a, const Warning& b) { return key(a) < key(b); };
  std::sort(wu.begin(), wu.end(), byKey);
  std::sort(wd.begin(), wd.end(), byKey);
  for (std::size_t i = 0; i < wu.size(); ++i) {
    EXPECT_EQ(wu[i].t, wd[i].t);
    EXPECT_EQ(wu[i].body, wd[i].body);
    EXPECT_EQ(wu[i].otherBody, wd[i].otherBody);
    EXPECT_NEAR(wu[i].distance, wd[i].distance, 1e-9);
  }
  // bodies by link name in what the monitor reports
  EXPECT_EQ(bodyName(s.arms[0].model, 4), "wrist_1_link");
  EXPECT_EQ(bodyName(s.arms[0].model, 7), "tool0");
}

// One link with a sphere, a cylinder and a box at non-trivial origins on a revolute joint.
const char* kShapes = R"(<robot name="shapes">
  <link name="base"/>
  <link name="l1">
    <collision><origin xyz="0.1 0.2 0.3" rpy="0 0 0"/><geometry><sphere radius="0.05"/></geometry></collision>
    <collision><origin xyz="0.3 -0.1 0.2" rpy="0.4 -0.7 1.1"/><geometry><cylinder radius="0.04" length="0.3"/></geometry></collision>
    <collision><origin xyz="-0.2 0.1 0.5" rpy="-0.3 0.5 0.2"/><geometry><box size="0.1 0.3 0.06"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1" rpy="0 0.2 0"/>
    <axis xyz="0 1 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>)";

// Points on the surface of each true shape (link frame), sampled densely.
std::vector<std::vector<Vec3>> trueSurfaces() {
  auto place = [](const Vec3& xyz, const Vec3& rpy) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translation() = xyz;
    t.linear() = (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Vec3::UnitX())).toRotationMatrix();
    return t;
  };
  std::vector<std::vector<Vec3>> out(3);
  const int n = 60;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
      const double th = 2 * kPi * u, ph = kPi * v;
      out[0].push_back(place({0.1, 0.2, 0.3}, {0, 0, 0}) * Vec3(0.05 * std::sin(ph) * std::cos(th), 0.05 * std::sin(ph) * std::sin(th), 0.05 * std::cos(ph)));
      // cylinder: side and both flat ends
      const Eigen::Isometry3d c = place({0.3, -0.1, 0.2}, {0.4, -0.7, 1.1});
      out[1].push_back(c * Vec3(0.04 * std::cos(th), 0.04 * std::sin(th), -0.15 + 0.3 * v));
      out[1].push_back(c * Vec3(0.04 * v * std::cos(th), 0.04 * v * std::sin(th), 0.15));
      out[1].push_back(c * Vec3(0.04 * v * std::cos(th), 0.04 * v * std::sin(th), -0.15));
      // box: its six faces
      const Eigen::Isometry3d b = place({-0.2, 0.1, 0.5}, {-0.3, 0.5, 0.2});
      const Vec3 h(0.05, 0.15, 0.03);
      for (int f = 0; f < 3; ++f)
        for (double side : {-1.0, 1.0}) {
          Vec3 p;
          p[f] = side * h[f];
          p[(f + 1) % 3] = (2 * u - 1) * h[(f + 1) % 3];
          p[(f + 2) % 3] = (2 * v - 1) * h[(f + 2) % 3];
          out[2].push_back(b * p);
        }
    }
  return out;
}

TEST(Urdf, ConvertedShapesBoundTheTrueShapes) {
  const ArmModel m = parseUrdf(kShapes, "shapes.urdf");
  ASSERT_EQ(m.capsules.size(), 3u);
  const auto surfaces = trueSurfaces();
  const std::vector<double> q = {0.8};
  const auto frames = forwardKinematics(m, Eigen::Isometry3d::Identity(), q);
  const Eigen::Isometry3d link = frames[1];
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double expectedSlack[3] = {0.0, 0.04, 0.0};  // sphere exact; cylinder caps; box see below
  for (int s = 0; s < 3; ++s) {
    const LinkCapsule& lc = m.capsules[s];
    ASSERT_EQ(lc.body, 1);
    const Capsule cap{link * lc.a, link * lc.b, lc.radius};
    // every sampled point of the true shape lies in the capsule, and the farthest is on its skin
    double farthest = 0.0;
    for (const Vec3& p_link : surfaces[s]) {
      const Vec3 p = link * p_link;
      farthest = std::max(farthest, std::sqrt(pointSegmentDistanceSq(p, cap.a, cap.b)));
    }
    EXPECT_LE(farthest, cap.radius + 1e-12) << s;
    EXPECT_NEAR(farthest, cap.radius, 1e-3) << s;  // tight: the sampled surface reaches the capsule's skin
    // distances from random points: the capsule's (stcore) never exceeds the brute-force distance
    // to the true shape, and exceeds it by at most the stated slack of the approximation
    for (int k = 0; k < 200; ++k) {
      const Vec3 x = link * Vec3(0.6 * u(gen), 0.6 * u(gen), 0.6 * u(gen) + 0.3);
      double brute = 1e9;
      for (const Vec3& p_link : surfaces[s]) brute = std::min(brute, (link * p_link - x).norm());
      const double d = std::max(0.0, distance(cap, Sphere{x, 0.0}));
      if (brute < 1e-9) continue;
      EXPECT_LE(d, brute + 1e-12) << s;
      if (s < 2) {
        EXPECT_GE(d, brute - expectedSlack[s] - 2e-3) << s;  // sampling resolution 2 mm
      }
    }
  }
  // the box: segment along its longest axis (y, 0.15), radius the hypotenuse of 0.05 and 0.03
  EXPECT_NEAR(m.capsules[2].radius, std::hypot(0.05, 0.03), 1e-15);
  EXPECT_NEAR((m.capsules[2].b - m.capsules[2].a).norm(), 0.3, 1e-12);
  EXPECT_NEAR((m.capsules[1].b - m.capsules[1].a).norm(), 0.3, 1e-12);
}

// A prismatic joint along a tilted axis after a fixed offset, then a revolute one: frames and
// velocities by hand.
TEST(Urdf, PrismaticJointAnalytic) {
  const ArmModel m = parseUrdf(R"(<robot name="slide">
    <link name="rail"/><link name="carriage"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
    <link name="arm"/>
    <joint name="slide" type="prismatic"><parent link="rail"/><child link="carriage"/><origin xyz="1 2 3" rpy="0 0 1.5707963267948966"/>
      <axis xyz="1 0 0"/><limit lower="-0.5" upper="1.5" effort="1" velocity="1"/></joint>
    <joint name="turn" type="continuous"><parent link="carriage"/><child link="arm"/><origin xyz="0 0 0.5"/><axis xyz="0 0 1"/></joint>
  </robot>)", "slide.urdf");
  ASSERT_EQ(m.dof(), 2);
  EXPECT_EQ(m.joints[0].type, JointType::Prismatic);
  EXPECT_EQ(m.joints[0].lower, -0.5);
  EXPECT_EQ(m.joints[0].upper, 1.5);
  EXPECT_TRUE(std::isinf(m.joints[1].upper));
  EXPECT_EQ(m.bodyNames, (std::vector<std::string>{"rail", "carriage", "arm", "flange"}));
  const std::vector<double> q = {0.7, 0.3}, qd = {0.4, 2.0};
  const auto f = forwardKinematics(m, Eigen::Isometry3d::Identity(), q);
  // the rail's x is turned onto world y: the carriage slides 0.7 along y from (1, 2, 3)
  EXPECT_LT((f[1].translation() - Vec3(1, 2.7, 3)).norm(), 1e-15);
  EXPECT_LT((f[2].translation() - Vec3(1, 2.7, 3.5)).norm(), 1e-15);
  EXPECT_NEAR(std::atan2(f[2].linear()(1, 0), f[2].linear()(0, 0)), kPi / 2 + 0.3, 1e-12);
  BodyRates r;
  bodyRates(m, f.data(), qd.data(), r);
  // the carriage translates at 0.4 m/s along y; a point 0.2 m out along the arm's x also turns
  EXPECT_LT((r.velocity(1, Vec3(5, 5, 5)) - Vec3(0, 0.4, 0)).norm(), 1e-12);
  const Vec3 p = f[2] * Vec3(0.2, 0, 0);
  const Vec3 expect = Vec3(0, 0.4, 0) + Vec3(0, 0, 2.0).cross(p - f[2].translation());
  EXPECT_LT((r.velocity(2, p) - expect).norm(), 1e-12);
  // a reading beyond the slide's travel is refused
  Reading bad{0.0, 0, {1.6, 0.0}, {0.0, 0.0}, ""};
  EXPECT_THROW(validateReading(m, bad), InputError);
}

std::string oneError(const std::string& xml, const std::string& file = "bad.urdf") {
  try {
    parseUrdf(xml, file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Urdf, BadInputIsOneLineNamingTheFile) {
  const std::string joint = R"(<joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>)";
  struct Case {
    std::string xml, says;
  } cases[] = {
      {"<robot name=\"r\"><link name=\"a\"/>", "not a valid URDF"},
      {"<robot name=\"r\"><link name=\"b\"/>" + joint + "</robot>", "not a valid URDF"},  // parent link a unknown
      {"<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>"
       "<origin xyz=\"nan 0 0\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>",
       ""},
      {"<robot name=\"r\"><link name=\"a\"/><link name=\"b\"><collision><geometry><mesh filename=\"b.stl\"/></geometry></collision></link>" +
           joint + "</robot>",
       "collision mesh 'b.stl'"},
      {"<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>",
       "no moving joint"},
      {"<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>" + joint +
           "<joint name=\"k\" type=\"prismatic\"><parent link=\"a\"/><child link=\"c\"/><axis xyz=\"1 0 0\"/><limit lower=\"0\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>",
       "only serial chains"},
  };
  for (const Case& c : cases) {
    const std::string e = oneError(c.xml);
    EXPECT_EQ(e.rfind("bad.urdf: ", 0), 0u) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_NE(e.find(c.says), std::string::npos) << e;
  }
  // the parser's own reason is kept: the unknown parent link named
  EXPECT_NE(oneError(cases[1].xml).find("a"), std::string::npos);
  try {
    loadUrdf("/nonexistent/robot.urdf");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/robot.urdf: cannot open the URDF file");
  }
}

TEST(Urdf, SrdfDisablesPairsByLinkName) {
  ArmModel m = loadUrdf(shipped("ur5.urdf"));
  EXPECT_FALSE(m.isAllowed(4, 6));
  applySrdf(m, shipped("ur5.srdf"));
  EXPECT_TRUE(m.isAllowed(4, 6));  // wrist_1_link, wrist_3_link
  EXPECT_TRUE(m.isAllowed(5, 7));  // wrist_2_link, tool0
  EXPECT_FALSE(m.isAllowed(2, 4));
  auto error = [&](const std::string& xml) {
    try {
      applySrdfText(m, xml, "r.srdf");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(error("<robot name=\"ur5\">\n<disable_collisions link1=\"wrist_1_link\" link2=\"hand\"/></robot>"),
            "r.srdf:2: disable_collisions: robot ur5 has no link 'hand'");
  EXPECT_EQ(error("<robot><disable_collisions link1=\"a\"").rfind("r.srdf:", 0), 0u);
  EXPECT_EQ(error("<robot><disable_collisions link1=\"a\"").find('\n'), std::string::npos);
}

struct Result {
  int code;
  std::string out, err;
};

Result stsim(const std::string& args) {
  const fs::path d = fs::temp_directory_path() / ("stsim_urdf_" + std::to_string(::getpid()));
  fs::create_directories(d);
  const std::string cmd = std::string(STSIM_BINARY) + " arm " + args + " > " + (d / "out").string() + " 2> " + (d / "err").string();
  const int status = std::system(cmd.c_str());
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  Result r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(d / "out"), slurp(d / "err")};
  fs::remove_all(d);
  return r;
}

TEST(UrdfCli, DescribesARobotAndRunsTheCell) {
  const Result r = stsim(shipped("ur5.urdf"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("robot ur5, 6 moving joints, 8 bodies"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("body 7 tool0"), std::string::npos) << r.out;
  const fs::path out = fs::temp_directory_path() / ("stsim_urdf_cell_" + std::to_string(::getpid()));
  const Result c = stsim(shipped("two_ur5_cell.yaml") + " --out " + out.string());
  ASSERT_EQ(c.code, 0) << c.err;
  std::ifstream in(out / "warnings.csv");
  std::stringstream ss;
  ss << in.rdbuf();
  // the STOP names the links: ur_b's tool onto ur_a's wrist
  EXPECT_NE(ss.str().find("ur_a,wrist_1_link,5,ur_b/tool0"), std::string::npos) << ss.str().substr(0, 400);
  EXPECT_EQ(ss.str().find("table"), std::string::npos);  // base_link vs table allowed
  fs::remove_all(out);
}

TEST(UrdfCli, BadUrdfIsOneLineAndNonZero) {
  const fs::path f = fs::temp_directory_path() / ("stsim_bad_" + std::to_string(::getpid()) + ".urdf");
  std::ofstream(f) << "<robot name=\"r\"><link name=\"a\"/>";
  const Result r = stsim(f.string());
  EXPECT_NE(r.code, 0);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(f.string() + ": not a valid URDF"), std::string::npos) << r.err;
  fs::remove(f);
  // from a scenario: the YAML key and the URDF file, one line
  const fs::path y = fs::temp_directory_path() / ("stsim_bad_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(y) << "models:\n  r: {urdf: missing.urdf}\narms: [{name: a, model: r, waypoints: [{t: 0, q: [0]}]}]\n";
  const Result s = stsim(y.string());
  EXPECT_NE(s.code, 0);
  EXPECT_EQ(std::count(s.err.begin(), s.err.end(), '\n'), 1) << s.err;
  EXPECT_NE(s.err.find("models.r.urdf"), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("missing.urdf: cannot open the URDF file"), std::string::npos) << s.err;
  fs::remove(y);
}

}  // namespace
}  // namespace st::arm
