#include <starm/urdf.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <starm/sensor.hpp>

namespace st::arm {

namespace {

// urdfdom reports through console_bridge and returns null: keep its first error instead of
// letting it print (the library never prints).
class Capture final : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first.empty()) first = text;
  }
  std::string first;
};

std::mutex& parseMutex() {
  static std::mutex m;  // the output handler is process-wide
  return m;
}

bool finite(const urdf::Vector3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Vec3(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  return t;
}

bool finite(const urdf::Pose& p) {
  return finite(p.position) && std::isfinite(p.rotation.x) && std::isfinite(p.rotation.y) &&
         std::isfinite(p.rotation.z) && std::isfinite(p.rotation.w);
}

struct Builder {
  std::string file;
  ArmModel m;

  [[noreturn]] void fail(const std::string& what) const { throw InputError(file + ": " + what); }

  // one collision element of `link` (in the link frame placed by body_link) as a capsule of body
  void addCollision(const urdf::Link& link, const urdf::Collision& c, int body, const Eigen::Isometry3d& body_link) {
    if (!c.geometry) return;
    if (!finite(c.origin)) fail("link '" + link.name + "': collision origin is not finite");
    const Eigen::Isometry3d t = body_link * toIsometry(c.origin);
    Vec3 a = Vec3::Zero(), b = Vec3::Zero();
    double r = 0.0;
    switch (c.geometry->type) {
      case urdf::Geometry::SPHERE: {
        r = static_cast<const urdf::Sphere&>(*c.geometry).radius;
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& cy = static_cast<const urdf::Cylinder&>(*c.geometry);
        if (!(std::isfinite(cy.length) && cy.length >= 0.0)) fail("link '" + link.name + "': cylinder length is not a finite length");
        r = cy.radius;
        a = Vec3(0, 0, -0.5 * cy.length);
        b = -a;
        break;
      }
      case urdf::Geometry::BOX: {
        const auto& bx = static_cast<const urdf::Box&>(*c.geometry);
        Vec3 h(0.5 * bx.dim.x, 0.5 * bx.dim.y, 0.5 * bx.dim.z);
        if (!(h.allFinite() && (h.array() > 0.0).all())) fail("link '" + link.name + "': box size must be finite and positive");
        int axis = 0;
        h.maxCoeff(&axis);
        b[axis] = h[axis];
        a[axis] = -h[axis];
        h[axis] = 0.0;
        r = h.norm();
        break;
      }
      case urdf::Geometry::MESH:
        fail("link '" + link.name + "': collision mesh '" + static_cast<const urdf::Mesh&>(*c.geometry).filename +
             "' is not supported (give a cylinder, sphere or box)");
      default:
        fail("link '" + link.name + "': unknown collision geometry");
    }
    if (!(std::isfinite(r) && r > 0.0)) fail("link '" + link.name + "': collision radius must be finite and positive");
    m.capsules.push_back({body, t * a, t * b, r});
  }

  // link and everything fixed to it onto body; the one moving joint below it, if any, returned
  // with its origin in the body's frame
  const urdf::Joint* gather(const urdf::Link& link, int body, const Eigen::Isometry3d& body_link, Eigen::Isometry3d& moving_origin,
                            bool descend = true) {
    m.links.emplace_back(link.name, body);
    for (const auto& c : link.collision_array)
      if (c) addCollision(link, *c, body, body_link);
    if (link.collision_array.empty() && link.collision) addCollision(link, *link.collision, body, body_link);
    const urdf::Joint* moving = nullptr;
    for (const auto& jp : descend ? link.child_joints : std::vector<urdf::JointSharedPtr>{}) {
      const urdf::Joint& j = *jp;
      if (!finite(j.parent_to_joint_origin_transform)) fail("joint '" + j.name + "': origin is not finite");
      const Eigen::Isometry3d origin = body_link * toIsometry(j.parent_to_joint_origin_transform);
      const urdf::Link* child = findChild(link, j.child_link_name);
      if (!child) fail("joint '" + j.name + "': child link '" + j.child_link_name + "' not found");
      const urdf::Joint* below = nullptr;
      Eigen::Isometry3d belowOrigin;
      switch (j.type) {
        case urdf::Joint::FIXED: below = gather(*child, body, origin, belowOrigin); break;
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS:
        case urdf::Joint::PRISMATIC:
          below = &j;
          belowOrigin = origin;
          break;
        default: fail("joint '" + j.name + "': type not supported (revolute, continuous, prismatic or fixed)");
      }
      if (below && moving)
        fail("joints '" + moving->name + "' and '" + below->name + "' both move below link '" + link.name +
             "': only serial chains (one moving branch)");
      if (below) {
        moving = below;
        moving_origin = belowOrigin;
      }
    }
    return moving;
  }

  // a moving joint anywhere below link
  static bool movesBelow(const urdf::Link& link) {
    for (const auto& j : link.child_joints)
      if (j->type != urdf::Joint::FIXED) return true;
    for (const auto& c : link.child_links)
      if (c && movesBelow(*c)) return true;
    return false;
  }

  static const urdf::Link* findChild(const urdf::Link& link, const std::string& name) {
    for (const auto& c : link.child_links)
      if (c && c->name == name) return c.get();
    return nullptr;
  }

  Joint joint(const urdf::Joint& j, const Eigen::Isometry3d& origin) const {
    Joint out;
    out.name = j.name;
    out.origin = origin;
    out.type = j.type == urdf::Joint::PRISMATIC ? JointType::Prismatic : JointType::Revolute;
    if (!finite(j.axis)) fail("joint '" + j.name + "': axis is not finite");
    const Vec3 axis(j.axis.x, j.axis.y, j.axis.z);
    if (!(axis.norm() > 1e-12)) fail("joint '" + j.name + "': axis is zero");
    out.axis = axis.normalized();
    if (j.type == urdf::Joint::CONTINUOUS) {
      out.lower = -std::numeric_limits<double>::infinity();
      out.upper = std::numeric_limits<double>::infinity();
    } else {
      if (!j.limits) fail("joint '" + j.name + "': no <limit>");
      out.lower = j.limits->lower;
      out.upper = j.limits->upper;
      if (!(std::isfinite(out.lower) && std::isfinite(out.upper) && out.lower <= out.upper))
        fail("joint '" + j.name + "': limits [" + std::to_string(out.lower) + ", " + std::to_string(out.upper) +
             "] are not finite with lower <= upper");
    }
    return out;
  }
};

}  // namespace

ArmModel parseUrdf(const std::string& xml, const std::string& file, const std::string& name) {
  urdf::ModelInterfaceSharedPtr model;
  std::string error;
  {
    const std::lock_guard lock(parseMutex());
    Capture capture;
    console_bridge::useOutputHandler(&capture);
    try {
      model = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      error = e.what();
    }
    console_bridge::restorePreviousOutputHandler();
    if (error.empty()) error = capture.first;
  }
  if (!model) throw InputError(file + ": not a valid URDF" + (error.empty() ? std::string() : ": " + error));
  Builder b{file, {}};
  b.m.name = name.empty() ? model->getName() : name;
  b.m.convention = DhConvention::Urdf;
  const urdf::LinkConstSharedPtr root = model->getRoot();
  if (!root) b.fail("no root link");
  // body 0 the root link; each moving joint starts the next body at its child link
  Eigen::Isometry3d origin;
  const urdf::Joint* j = b.gather(*root, 0, Eigen::Isometry3d::Identity(), origin);
  b.m.bodyNames.push_back(root->name);
  while (j) {
    b.m.joints.push_back(b.joint(*j, origin));
    const int body = b.m.dof();
    const urdf::Link* child = model->getLink(j->child_link_name).get();
    if (!child) b.fail("joint '" + j->name + "': child link '" + j->child_link_name + "' not found");
    b.m.bodyNames.push_back(child->name);
    // the last moving link with one link fixed to it: that link is the flange, body n + 1
    const bool tip = !Builder::movesBelow(*child) && child->child_joints.size() == 1;
    j = b.gather(*child, body, Eigen::Isometry3d::Identity(), origin, !tip);
    if (tip) {
      const urdf::Joint& fj = *child->child_joints.front();
      if (!finite(fj.parent_to_joint_origin_transform)) b.fail("joint '" + fj.name + "': origin is not finite");
      b.m.flange = toIsometry(fj.parent_to_joint_origin_transform);
      const urdf::Link* flange = Builder::findChild(*child, fj.child_link_name);
      if (!flange) b.fail("joint '" + fj.name + "': child link '" + fj.child_link_name + "' not found");
      b.m.bodyNames.push_back(flange->name);
      Eigen::Isometry3d unused;
      b.gather(*flange, body + 1, Eigen::Isometry3d::Identity(), unused);
    }
  }
  if (b.m.joints.empty()) b.fail("no moving joint (revolute, continuous or prismatic) below root link '" + root->name + "'");
  if (static_cast<int>(b.m.bodyNames.size()) == b.m.dof() + 1) b.m.bodyNames.push_back("flange");
  b.m.resetAllowedToAdjacent();
  return b.m;
}

void applySrdfText(ArmModel& m, const std::string& xml, const std::string& file) {
  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  if (doc.Error())
    throw InputError(file + ":" + std::to_string(doc.ErrorRow()) + ": not a valid SRDF: " + doc.ErrorDesc());
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Value()) != "robot") throw InputError(file + ": not a valid SRDF: the root element is not <robot>");
  for (const TiXmlElement* e = robot->FirstChildElement("disable_collisions"); e; e = e->NextSiblingElement("disable_collisions")) {
    const char* l1 = e->Attribute("link1");
    const char* l2 = e->Attribute("link2");
    const std::string at = file + ":" + std::to_string(e->Row());
    if (!l1 || !l2) throw InputError(at + ": disable_collisions needs link1 and link2");
    int b[2] = {-1, -1};
    const char* names[2] = {l1, l2};
    for (int k = 0; k < 2; ++k)
      for (const auto& [link, body] : m.links)
        if (link == names[k]) b[k] = body;
    for (int k = 0; k < 2; ++k)
      if (b[k] < 0) throw InputError(at + ": disable_collisions: robot " + m.name + " has no link '" + names[k] + "'");
    m.setAllowed(b[0], b[1], true);
  }
}

void applySrdf(ArmModel& m, const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the SRDF file");
  std::ostringstream text;
  text << in.rdbuf();
  applySrdfText(m, text.str(), path);
}

ArmModel loadUrdf(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the URDF file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseUrdf(text.str(), path, name);
}

}  // namespace st::arm
