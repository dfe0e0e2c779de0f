#include <starm/scenario.hpp>

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <set>

#include <yaml-cpp/yaml.h>

#include <starm/settings.hpp>
#include <starm/urdf.hpp>
#include <stio/format.hpp>
#include <stio/yaml.hpp>

namespace st::arm {

namespace {

// Bounds on the work one scenario may ask for (s; cycles).
constexpr double kMaxLookAhead = 60.0;
constexpr double kMaxCycles = 1e7;
constexpr double kMaxBaseOffset = 100.0;  // m: an arm's base from the workcell's origin, per axis

// Error helpers: every message is "file:line: key: what".
struct Yaml {
  std::string file;

  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& what) const {
    io::Yaml<InputError>(file).fail(n, key, what);
  }
  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsDefined() || !n.IsScalar()) fail(n, key, "expected a number");
    double v;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, key, "'" + n.Scalar() + "' is not a number");
    }
    if (!std::isfinite(v)) fail(n, key, "not a finite number");
    return v;
  }
  bool boolean(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, "expected true or false");
    if (n.Scalar() == "true") return true;
    if (n.Scalar() == "false") return false;
    fail(n, key, "expected true or false, got '" + n.Scalar() + "'");
  }
  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsDefined() || !n.IsScalar()) fail(n, key, "expected a name");
    return n.Scalar();
  }
  // A list node (or an absent one, which holds nothing).
  YAML::Node list(const YAML::Node& n, const std::string& key) const {
    if (n.IsDefined() && !n.IsSequence()) fail(n, key, "expected a list");
    return n;
  }
  int integer(const YAML::Node& n, const std::string& key, int lo, int hi) const {
    const double v = number(n, key);
    if (v != std::floor(v) || v < lo || v > hi)
      fail(n, key, "expected an integer " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<int>(v);
  }
  double number(const YAML::Node& parent, const char* name, const std::string& key, double def) const {
    const YAML::Node n = parent[name];
    return n.IsDefined() ? number(n, key.empty() ? std::string(name) : key + "." + name) : def;
  }
  double positive(const YAML::Node& parent, const char* name, const std::string& key, double def) const {
    const double v = number(parent, name, key, def);
    if (!(v > 0.0)) fail(parent[name], key + "." + name, "must be positive");
    return v;
  }
  Vec3 vec3(const YAML::Node& n, const std::string& key) const {
    if (!n.IsDefined() || !n.IsSequence() || n.size() != 3) fail(n, key, "expected [x, y, z]");
    return {number(n[0], key + "[0]"), number(n[1], key + "[1]"), number(n[2], key + "[2]")};
  }
  std::vector<double> numbers(const YAML::Node& n, const std::string& key) const {
    if (!n.IsDefined() || !n.IsSequence()) fail(n, key, "expected a list of numbers");
    std::vector<double> v;
    for (std::size_t i = 0; i < n.size(); ++i) v.push_back(number(n[i], key + "[" + std::to_string(i) + "]"));
    return v;
  }
  Eigen::Isometry3d pose(const YAML::Node& n, const std::string& key) const {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    if (!n.IsDefined()) return p;
    if (n["xyz"]) p.translation() = vec3(n["xyz"], key + ".xyz");
    if (n["rpy"]) p.linear() = rpy(vec3(n["rpy"], key + ".rpy"));
    return p;
  }
  static Eigen::Matrix3d rpy(const Vec3& a) {
    // URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll)
    return (Eigen::AngleAxisd(a.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(a.y(), Vec3::UnitY()) *
            Eigen::AngleAxisd(a.x(), Vec3::UnitX()))
        .toRotationMatrix();
  }
  bool mapping(const YAML::Node& n, const std::string& key) const {
    if (!n.IsMap()) fail(n, key, "expected a mapping");
    return true;
  }
  void knownKeys(const YAML::Node& n, const std::string& key, std::initializer_list<const char*> keys) const {
    knownKeysIf(n, key, [&](const std::string& k) {
      return std::find_if(keys.begin(), keys.end(), [&](const char* s) { return k == s; }) != keys.end();
    });
  }
  void knownKeysIf(const YAML::Node& n, const std::string& key, const std::function<bool(const std::string&)>& known) const {
    if (!n.IsMap()) fail(n, key, "expected a mapping");
    io::Yaml<InputError>(file).onlyKeys(n, key, known);
  }
};

// One side of an allowed pair: a body index, or a link name (the arm's own, else "obstacle:NAME"
// when obstacles may be named); a body index in `body`, else the obstacle's name in `obstacle`.
struct PairSide {
  int body = -1;
  std::string obstacle;
};

PairSide pairSide(const Yaml& y, const YAML::Node& n, const std::string& key, const ArmModel& m, bool obstacles) {
  const int nb = m.bodies();
  if (!n.IsScalar()) y.fail(n, key, "expected a body (0.." + std::to_string(nb - 1) + ") or a link name");
  const std::string& v = n.Scalar();
  if (!v.empty() && v.find_first_not_of("0123456789+-.eE") == std::string::npos) return {y.integer(n, key, 0, nb - 1), ""};
  if (obstacles && v.rfind("obstacle:", 0) == 0 && v.size() > 9) return {-1, v.substr(9)};
  const int b = m.bodyIndex(v);
  if (b < 0) {
    std::string names;
    for (int k = 0; k < nb; ++k) names += (k ? ", " : "") + bodyName(m, k);
    y.fail(n, key, "unknown link '" + v + "' (bodies: " + names + (obstacles ? "; or obstacle:NAME" : "") + ")");
  }
  return {b, ""};
}

ArmModel parseUrdfModel(const Yaml& y, const YAML::Node& n, const std::string& key, const std::string& name) {
  y.knownKeys(n, key, {"urdf", "srdf", "allow"});
  auto file = [&](const char* k) {
    std::filesystem::path f = y.text(n[k], key + "." + k);
    if (f.is_relative()) f = std::filesystem::path(y.file).parent_path() / f;
    return f.string();
  };
  ArmModel m;
  try {
    m = loadUrdf(file("urdf"), name);
  } catch (const InputError& e) {
    y.fail(n["urdf"], key + ".urdf", e.what());
  }
  if (n["srdf"]) {
    try {
      applySrdf(m, file("srdf"));
    } catch (const InputError& e) {
      y.fail(n["srdf"], key + ".srdf", e.what());
    }
  }
  // the robot's own never-colliding pairs (SRDF's disable_collisions), by link name
  if (const YAML::Node pairs = y.list(n["allow"], key + ".allow"))
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const std::string pk = key + ".allow[" + std::to_string(k) + "]";
      if (!pairs[k].IsSequence() || pairs[k].size() != 2) y.fail(pairs[k], pk, "expected [link, link]");
      m.setAllowed(pairSide(y, pairs[k][0], pk + "[0]", m, false).body, pairSide(y, pairs[k][1], pk + "[1]", m, false).body, true);
    }
  return m;
}

ArmModel parseModel(const Yaml& y, const YAML::Node& n, const std::string& key, const std::string& name) {
  if (n.IsMap() && n["urdf"]) return parseUrdfModel(y, n, key, name);
  y.knownKeys(n, key, {"convention", "joints", "flange", "capsules", "urdf"});
  ArmModel m;
  m.name = name;
  const std::string conv = n["convention"] ? y.text(n["convention"], key + ".convention") : "";
  if (conv == "classic") m.convention = DhConvention::Classic;
  else if (conv == "modified") m.convention = DhConvention::Modified;
  else y.fail(n["convention"], key + ".convention", "expected classic or modified");
  const YAML::Node joints = n["joints"];
  if (!joints.IsSequence() || joints.size() == 0) y.fail(joints, key + ".joints", "expected a list of joints");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const std::string jk = key + ".joints[" + std::to_string(i) + "]";
    y.knownKeys(joints[i], jk, {"a", "alpha", "d", "offset", "limits", "max_rate"});
    Joint j;
    j.a = y.number(joints[i], "a", jk, 0.0);
    j.alpha = y.number(joints[i], "alpha", jk, 0.0);
    j.d = y.number(joints[i], "d", jk, 0.0);
    j.offset = y.number(joints[i], "offset", jk, 0.0);
    if (joints[i]["limits"]) {
      const auto lim = y.numbers(joints[i]["limits"], jk + ".limits");
      if (lim.size() != 2 || !(lim[0] < lim[1])) y.fail(joints[i]["limits"], jk + ".limits", "expected [lower, upper]");
      j.lower = lim[0];
      j.upper = lim[1];
    }
    j.maxRate = y.positive(joints[i], "max_rate", jk, j.maxRate);
    m.joints.push_back(j);
  }
  m.flange = y.pose(n["flange"], key + ".flange");
  const YAML::Node caps = n["capsules"];
  if (!caps.IsSequence() || caps.size() == 0) y.fail(caps, key + ".capsules", "expected a list of capsules");
  for (std::size_t i = 0; i < caps.size(); ++i) {
    const std::string ck = key + ".capsules[" + std::to_string(i) + "]";
    y.knownKeys(caps[i], ck, {"body", "a", "b", "radius"});
    LinkCapsule c;
    c.body = y.integer(caps[i]["body"], ck + ".body", 0, m.dof() + 1);
    c.a = y.vec3(caps[i]["a"], ck + ".a");
    c.b = y.vec3(caps[i]["b"], ck + ".b");
    c.radius = y.positive(caps[i], "radius", ck, 0.0);
    m.capsules.push_back(c);
  }
  m.resetAllowedToAdjacent();
  return m;
}

Obstacle parseObstacle(const Yaml& y, const YAML::Node& n, const std::string& key, int index) {
  y.knownKeys(n, key, {"name", "sphere", "capsule", "box", "velocity", "tracked"});
  Obstacle o;
  o.name = n["name"] ? y.text(n["name"], key + ".name") : "o" + std::to_string(index);
  if ((n["sphere"] ? 1 : 0) + (n["capsule"] ? 1 : 0) + (n["box"] ? 1 : 0) > 1)
    y.fail(n, key, "give one of sphere, capsule, box (an obstacle has one shape)");
  if (n["sphere"]) {
    o.kind = ShapeKind::Sphere;
    y.knownKeys(n["sphere"], key + ".sphere", {"center", "radius"});
    o.sphere = {y.vec3(n["sphere"]["center"], key + ".sphere.center"), y.positive(n["sphere"], "radius", key + ".sphere", 0)};
  } else if (n["capsule"]) {
    o.kind = ShapeKind::Capsule;
    y.knownKeys(n["capsule"], key + ".capsule", {"a", "b", "radius"});
    o.capsule = {y.vec3(n["capsule"]["a"], key + ".capsule.a"), y.vec3(n["capsule"]["b"], key + ".capsule.b"),
                 y.positive(n["capsule"], "radius", key + ".capsule", 0)};
  } else if (n["box"]) {
    o.kind = ShapeKind::Box;
    y.knownKeys(n["box"], key + ".box", {"center", "half_extents", "rpy"});
    o.box.center = y.vec3(n["box"]["center"], key + ".box.center");
    o.box.halfExtents = y.vec3(n["box"]["half_extents"], key + ".box.half_extents");
    if ((o.box.halfExtents.array() <= 0.0).any()) y.fail(n["box"]["half_extents"], key + ".box.half_extents", "must be positive");
    if (n["box"]["rpy"]) o.box.rotation = Yaml::rpy(y.vec3(n["box"]["rpy"], key + ".box.rpy"));
  } else {
    y.fail(n, key, "expected one of sphere, capsule, box");
  }
  if (n["velocity"]) o.velocity = y.vec3(n["velocity"], key + ".velocity");
  if (n["tracked"]) o.tracked = y.boolean(n["tracked"], key + ".tracked");
  return o;
}

// Random obstacles, deterministic for a seed (own uniform mapping: not implementation-defined).
void randomObstacles(const Yaml& y, const YAML::Node& n, Scenario& s) {
  const std::string key = "random_obstacles";
  y.knownKeys(n, key, {"count", "seed", "min", "max", "radius", "keep_out"});
  const double count = y.number(n["count"], key + ".count");
  if (count < 0 || count != std::floor(count) || count > 1e6) y.fail(n["count"], key + ".count", "expected a count");
  std::mt19937_64 gen(static_cast<std::uint64_t>(y.number(n, "seed", key, 1.0)));
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(gen() >> 11) * 0x1.0p-53); };
  const Vec3 lo = y.vec3(n["min"], key + ".min"), hi = y.vec3(n["max"], key + ".max");
  const auto r = n["radius"] ? y.numbers(n["radius"], key + ".radius") : std::vector<double>{0.01, 0.04};
  if (r.size() != 2 || !(0 < r[0] && r[0] <= r[1])) y.fail(n["radius"], key + ".radius", "expected [lo, hi]");
  std::vector<Sphere> keepOut;
  if (const YAML::Node ko = y.list(n["keep_out"], key + ".keep_out"))
    for (std::size_t i = 0; i < ko.size(); ++i) {
      const std::string kk = key + ".keep_out[" + std::to_string(i) + "]";
      y.knownKeys(ko[i], kk, {"center", "radius"});
      keepOut.push_back({y.vec3(n["keep_out"][i]["center"], kk + ".center"), y.positive(n["keep_out"][i], "radius", kk, 0)});
    }
  int made = 0;
  for (long tries = 0; made < static_cast<int>(count) && tries < 1000 * static_cast<long>(count) + 1000; ++tries) {
    Obstacle o;
    const Vec3 c(uniform(lo.x(), hi.x()), uniform(lo.y(), hi.y()), uniform(lo.z(), hi.z()));
    const double rad = uniform(r[0], r[1]);
    bool ok = true;
    for (const Sphere& k : keepOut) ok = ok && (c - k.center).norm() > k.radius + 2 * rad;
    if (!ok) continue;
    o.name = "rand" + std::to_string(made);
    switch (gen() % 3) {
      case 0: o.kind = ShapeKind::Sphere; o.sphere = {c, rad}; break;
      case 1: {
        o.kind = ShapeKind::Capsule;
        Vec3 d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        d = d.normalized() * rad;
        o.capsule = {c - d, c + d, 0.5 * rad};
        break;
      }
      default: {
        o.kind = ShapeKind::Box;
        o.box.center = c;
        o.box.halfExtents = Vec3(uniform(0.5, 1), uniform(0.5, 1), uniform(0.5, 1)) * rad;
        o.box.rotation = Yaml::rpy(Vec3(uniform(-3.14, 3.14), uniform(-3.14, 3.14), uniform(-3.14, 3.14)));
      }
    }
    s.obstacles.push_back(o);
    ++made;
  }
  if (made < static_cast<int>(count)) y.fail(n, key, "could not place all obstacles outside the keep-out zones");
}

}  // namespace

namespace {

// ssm: and persons: (after braking:, whose times are the drive's T_r and T_s)
// A sensor's rate (an arm's joint sensor, a person's tracker: sensor: {period, jitter, drift}): a
// reading older than period + jitter is stale (STOP). `what` names the sensor in a missing period.
struct SensorRate {
  double period = 0.0, jitter = 0.0, drift = 0.0;
};
SensorRate readSensorRate(const Yaml& y, const YAML::Node& sn, const std::string& key, const char* what) {
  SensorRate r;
  y.knownKeys(sn, key + ".sensor", {"period", "jitter", "drift"});
  if (!sn["period"]) y.fail(sn, key + ".sensor.period", std::string("missing: the ") + what + "'s period (s)");
  r.period = y.positive(sn, "period", key + ".sensor", 0.0);
  r.jitter = y.number(sn, "jitter", key + ".sensor", 0.0);
  if (!(r.jitter >= 0.0 && r.jitter < r.period))
    y.fail(sn["jitter"] ? sn["jitter"] : sn, key + ".sensor.jitter", "must be at least 0 and less than the period");
  if (r.period > kMaxLookAhead) y.fail(sn["period"], key + ".sensor.period", "must be at most 60 s");
  // how far its clock may run from the monitor's (a ratio: 0.02 is 2 %)
  r.drift = y.number(sn, "drift", key + ".sensor", 0.0);
  if (!(r.drift >= 0.0 && r.drift < 0.5))
    y.fail(sn["drift"], key + ".sensor.drift", "must be at least 0 and less than 0.5 (a ratio: 0.02 is 2 %)");
  return r;
}

// One action of a person's script: walk, reach or wait; a speed within the one S_h assumes.
PersonAction readAction(const Yaml& y, const YAML::Node& a, const std::string& ak, const SsmConfig& c) {
  y.knownKeys(a, ak, {"walk", "reach", "wait"});
  if (a.size() != 1) y.fail(a, ak, "expected one of walk, reach, wait");
  PersonAction act;
  if (const YAML::Node wait = a["wait"]) {
    act.kind = PersonAction::Wait;
    act.duration = y.number(wait, ak + ".wait");
    if (!(act.duration >= 0.0 && act.duration <= 3600.0)) y.fail(wait, ak + ".wait", "expected a time in 0..3600 s");
    return act;
  }
  const bool walk = static_cast<bool>(a["walk"]);
  const YAML::Node w = walk ? a["walk"] : a["reach"];
  const std::string wk = ak + (walk ? ".walk" : ".reach");
  y.knownKeys(w, wk, walk ? std::initializer_list<const char*>{"to", "speed"}
                          : std::initializer_list<const char*>{"to", "speed", "hand"});
  act.kind = walk ? PersonAction::Walk : PersonAction::Reach;
  const double limit = walk ? c.bodySpeed : c.handSpeed;
  if (!w["speed"]) y.fail(w, wk + ".speed", "missing (m/s)");
  act.speed = y.positive(w, "speed", wk, 0.0);
  // S_h bounds the person by these speeds: a script faster than them breaks the bound
  if (act.speed > limit)
    y.fail(w["speed"], wk + ".speed",
           io::number(act.speed) + " m/s is beyond " + (walk ? "ssm.body_speed " : "ssm.hand_speed ") +
               io::number(limit) + " m/s, the speed S_h assumes");
  if (walk) {
    const std::vector<double> to = y.numbers(w["to"], wk + ".to");
    if (to.size() != 2) y.fail(w["to"], wk + ".to", "expected [x, y]");
    act.to = Vec3(to[0], to[1], 0.0);
  } else {
    act.to = y.vec3(w["to"], wk + ".to");
    const std::string hand = w["hand"] ? y.text(w["hand"], wk + ".hand") : "right";
    if (hand != "right" && hand != "left") y.fail(w["hand"], wk + ".hand", "expected right or left, got '" + hand + "'");
    act.rightHand = hand == "right";
  }
  if (!(act.to.cwiseAbs().maxCoeff() <= kMaxBaseOffset))
    y.fail(w["to"], wk + ".to", "farther than " + io::number(kMaxBaseOffset) + " m from the workcell's origin");
  return act;
}

// A person's script: where it stands first, then its actions.
void readPersonScript(const Yaml& y, const YAML::Node& p, const std::string& key, const SsmConfig& c, PersonScript& sc) {
  if (const YAML::Node st = p["start"]) {
    y.knownKeys(st, key + ".start", {"xy", "heading"});
    const std::vector<double> xy = y.numbers(st["xy"], key + ".start.xy");
    if (xy.size() != 2) y.fail(st["xy"], key + ".start.xy", "expected [x, y]");
    sc.start = Vec3(xy[0], xy[1], 0.0);
    sc.heading = y.number(st, "heading", key + ".start", 0.0);
  } else {
    y.fail(p, key + ".start", "missing: where the person stands first ({xy: [x, y], heading})");
  }
  const YAML::Node script = y.list(p["script"], key + ".script");
  for (std::size_t k = 0; script && k < script.size(); ++k)
    sc.actions.push_back(readAction(y, script[k], key + ".script[" + std::to_string(k) + "]", c));
}

// persons[i]: a name, its tracker's rate, and a trace or a script.
Scenario::Person readPerson(const Yaml& y, const YAML::Node& p, const std::string& key, const Scenario& s) {
  y.knownKeys(p, key, {"name", "start", "script", "trace", "sensor"});
  Scenario::Person person;
  person.name = p["name"] ? y.text(p["name"], key + ".name") : "person" + std::to_string(s.persons.size());
  for (const Scenario::Person& other : s.persons)
    if (other.name == person.name) y.fail(p["name"], key + ".name", "duplicate person name '" + person.name + "'");
  if (p["trace"] && (p["script"] || p["start"])) y.fail(p["trace"], key + ".trace", "give either a trace or start and script, not both");
  if (const YAML::Node sn = p["sensor"]) {
    // its tracker's rate over the service
    const SensorRate r = readSensorRate(y, sn, key, "tracker");
    person.sensorPeriod = r.period;
    person.sensorJitter = r.jitter;
    person.sensorDrift = r.drift;
  }
  if (p["trace"]) {
    std::filesystem::path f = y.text(p["trace"], key + ".trace");
    if (f.is_relative()) f = std::filesystem::path(s.file).parent_path() / f;
    person.trace = f.string();
    return person;
  }
  person.script.name = person.name;
  readPersonScript(y, p, key, s.ssm, person.script);
  return person;
}

void parseSsm(const Yaml& y, const YAML::Node& root, Scenario& s) {
  SsmConfig& c = s.ssm;
  c.cycleTime = s.safety.cycleTime;
  c.reactionTime = s.safety.cycleTime + s.braking.delay;
  c.stoppingTime = s.braking.stoppingTime;
  const YAML::Node persons = y.list(root["persons"], "persons");
  if (!persons) return;
  if (s.braking.deceleration > 0.0)
    y.fail(root["braking"] ? root["braking"]["deceleration"] : root, "braking.deceleration",
           "persons need the drive's stopping time (braking.stopping_time) for S_s, not a deceleration");
  for (std::size_t i = 0; i < persons.size(); ++i)
    s.persons.push_back(readPerson(y, persons[i], "persons[" + std::to_string(i) + "]", s));
}

// The node of a nested key ("safety.cycle_time") under root; an undefined node if absent.
YAML::Node settingNode(const YAML::Node& root, const std::string& key) {
  const auto dot = key.find('.');
  const YAML::Node section = root[key.substr(0, dot)];
  if (!section || !section.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  return section[key.substr(dot + 1)];
}

// The settings of the table (starm/settings.hpp): the YAML's, then the command line's over them,
// each checked and worded by the table; then the keys that follow another, then what no single
// key can check. A YAML value's error names its file, line and key; a command-line value's is a
// SettingError the front end words with its option.
void applySettings(const Yaml& y, const YAML::Node& root, const std::vector<SettingOverride>& overrides, Scenario& s) {
  // the sections hold the table's keys (and octree's bounds, a box, read apart)
  for (const char* section : {"safety", "braking", "octree", "ssm"}) {
    const YAML::Node n = root[section];
    if (!n) continue;
    const std::string prefix = std::string(section) + ".";
    y.knownKeysIf(n, section, [&](const std::string& k) {
      return findSetting(prefix + k) != nullptr || prefix + k == "octree.bounds";
    });
  }
  std::map<std::string, YAML::Node> fromYaml;
  for (const Setting& setting : armSettings()) {
    const YAML::Node n = settingNode(root, setting.key);
    if (!n) continue;
    if (!n.IsScalar()) y.fail(n, setting.key, "must be " + expected(setting));
    try {
      applySettingText(s, setting, n.Scalar());
    } catch (const SettingError& e) {
      y.fail(n, e.key(), e.problem());
    }
    fromYaml[setting.key] = n;
  }
  std::set<std::string> fromCli;
  for (const SettingOverride& o : overrides) {
    const Setting* setting = findSetting(o.key);
    if (!setting) throw SettingError(o.key, "is not a setting (stsim arm --settings lists them)");
    applySettingText(s, *setting, o.text);
    fromCli.insert(setting->key);
  }
  auto given = [&](std::string_view k) { return fromYaml.count(std::string(k)) > 0 || fromCli.count(std::string(k)) > 0; };
  // a problem of key k: the option's if the command line gave it, else the YAML line's
  auto fail = [&](const std::string& k, const std::string& problem) {
    if (fromCli.count(k)) throw SettingError(k, problem);
    const auto it = fromYaml.find(k);
    const YAML::Node section = root[k.substr(0, k.find('.'))];
    y.fail(it != fromYaml.end() ? it->second : section ? section : root, k, problem);
  };
  if (given("braking.stopping_time") && given("braking.deceleration"))
    fail("braking.deceleration", "give either stopping_time or deceleration, not both");
  followDefaults(s, given);
  try {
    checkSettings(s);
  } catch (const SettingError& e) {
    fail(e.key(), e.problem());
  }
}

// Where an arm allows or checks a pair with an obstacle by name: checked once the obstacles are read.
struct ObstacleAllow {
  YAML::Node node;
  std::string key, name;
};

// allow / check: pairs of an arm's bodies (or a body and an obstacle by name) never / always checked.
void readPairs(const Yaml& y, const YAML::Node& a, const std::string& key, ArmInstance& inst,
               std::vector<ObstacleAllow>& obstacleAllows) {
  for (const char* which : {"allow", "check"}) {
    const YAML::Node pairs = y.list(a[which], key + "." + which);
    if (!pairs) continue;
    const bool allow = std::string(which) == "allow";
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const std::string pk = key + "." + which + "[" + std::to_string(k) + "]";
      const int nb = inst.model.bodies();
      if (!pairs[k].IsSequence() || pairs[k].size() != 2)
        y.fail(pairs[k], pk, "expected [body, body] with bodies 0.." + std::to_string(nb - 1) + " or link names");
      const PairSide s0 = pairSide(y, pairs[k][0], pk + "[0]", inst.model, allow);
      const PairSide s1 = pairSide(y, pairs[k][1], pk + "[1]", inst.model, allow);
      if (s0.body < 0 && s1.body < 0) y.fail(pairs[k], pk, "expected a link of the arm and an obstacle");
      if (s0.body >= 0 && s1.body >= 0) {
        inst.model.setAllowed(s0.body, s1.body, allow);
      } else {
        // arm vs a named obstacle (checked against the obstacles below)
        inst.allowedObstacles.emplace_back(s0.body >= 0 ? s0.body : s1.body, s0.body >= 0 ? s1.obstacle : s0.obstacle);
        obstacleAllows.push_back({pairs[k], pk, inst.allowedObstacles.back().second});
      }
    }
  }
}

// An arm's waypoints: {t, q} at increasing times, each a valid reading of the arm.
Script readWaypoints(const Yaml& y, const YAML::Node& w, const std::string& path, const std::string& key, int arm,
                     const ArmModel& model) {
  Script sc;
  sc.arm = arm;
  sc.where = path + ": " + key + ".waypoints";
  if (!w.IsSequence() || w.size() == 0) y.fail(w, key + ".waypoints", "expected a list of {t, q}");
  for (std::size_t k = 0; k < w.size(); ++k) {
    const std::string wk = key + ".waypoints[" + std::to_string(k) + "]";
    y.knownKeys(w[k], wk, {"t", "q"});
    Waypoint wp;
    wp.t = y.number(w[k]["t"], wk + ".t");
    wp.q = y.numbers(w[k]["q"], wk + ".q");
    if (!sc.waypoints.empty() && !(wp.t > sc.waypoints.back().t)) y.fail(w[k]["t"], wk + ".t", "times must increase");
    // every interpolated angle lies between two checked waypoints; the rate is the slope
    // of the piece that ends here
    Reading r{wp.t, sc.arm, wp.q, std::vector<double>(wp.q.size(), 0.0), ""};
    if (!sc.waypoints.empty() && sc.waypoints.back().q.size() == wp.q.size())
      for (std::size_t j = 0; j < wp.q.size(); ++j)
        r.qdot[j] = (wp.q[j] - sc.waypoints.back().q[j]) / (wp.t - sc.waypoints.back().t);
    try {
      validateReading(model, r);
    } catch (const InputError& e) {
      y.fail(w[k]["q"], wk + ".q", std::string(e.what()).substr(2));
    }
    sc.waypoints.push_back(wp);
  }
  return sc;
}

// arms[i]: its model, base, sensor, pairs and waypoints.
ArmInstance readArm(const Yaml& y, const YAML::Node& root, const YAML::Node& a, const std::string& key,
                    const Scenario& s, std::vector<ObstacleAllow>& obstacleAllows) {
  ArmInstance inst;
  inst.name = a["name"] ? y.text(a["name"], key + ".name") : "arm" + std::to_string(s.arms.size());
  for (const ArmInstance& other : s.arms)
    if (other.name == inst.name) y.fail(a["name"], key + ".name", "duplicate arm name '" + inst.name + "'");
  if (!a["model"] || !a["model"].IsScalar()) y.fail(a, key + ".model", "expected an arm model name");
  const std::string model = a["model"].Scalar();
  if (auto b = builtinModel(model)) {
    inst.model = *b;
  } else if (root["models"] && y.mapping(root["models"], "models") && root["models"][model]) {
    inst.model = parseModel(y, root["models"][model], "models." + model, model);
  } else {
    y.fail(a["model"], key + ".model", "unknown arm model '" + model + "' (built in: panda, iiwa14)");
  }
  inst.base = y.pose(a["base"], key + ".base");
  if (const YAML::Node sn = a["sensor"]) {
    const SensorRate r = readSensorRate(y, sn, key, "sensor");
    inst.sensorPeriod = r.period;
    inst.sensorJitter = r.jitter;
    inst.sensorDrift = r.drift;
  }
  // a base kilometres away is no workcell: 1e300 was accepted ("first contact at 0 s")
  if (const Vec3 at = inst.base.translation(); !(at.cwiseAbs().maxCoeff() <= kMaxBaseOffset))
    y.fail(a["base"]["xyz"], key + ".base.xyz",
           "[" + io::number(at.x()) + ", " + io::number(at.y()) + ", " + io::number(at.z()) + "] is farther than " +
               io::number(kMaxBaseOffset) + " m from the workcell's origin");
  readPairs(y, a, key, inst, obstacleAllows);
  return inst;
}

// A trace or waypoints, and the duration (the waypoints' end unless given).
void readTiming(const Yaml& y, const YAML::Node& root, const std::string& path, bool anyWaypoints, Scenario& s) {
  if (root["trace"]) {
    if (anyWaypoints) y.fail(root["trace"], "trace", "give either a trace or waypoints, not both");
    std::filesystem::path p = y.text(root["trace"], "trace");
    if (p.is_relative()) p = std::filesystem::path(path).parent_path() / p;
    std::error_code ec;
    if (std::filesystem::is_directory(p, ec)) y.fail(root["trace"], "trace", "is a directory, not a sensor trace: " + p.string());
    s.tracePath = p.string();
  } else if (!anyWaypoints) {
    y.fail(root, "trace", "expected a sensor trace or waypoints for at least one arm");
  }
  const double waypointsEnd = s.duration;
  s.duration = y.number(root, "duration", "", s.duration);
  if (s.duration < 0.0) y.fail(root["duration"], "duration", "must not be negative");
  // waypoints are sampled every cycle: cycle_time 1e-12 asked for 1e12 cycles; the key blamed
  // is the one out of the ordinary (a cycle shorter than a microsecond, else a duration given
  // beyond the waypoints: 1e300 blamed the cycle time)
  if (s.tracePath.empty() && s.duration / s.safety.cycleTime > kMaxCycles) {
    if (root["duration"] && s.duration > waypointsEnd && s.safety.cycleTime >= 1e-6)
      y.fail(root["duration"], "duration",
             io::number(s.duration) + " s would take more than 1e7 cycles at the cycle time of " +
                 io::number(s.safety.cycleTime) + " s");
    y.fail(root["safety"] && root["safety"]["cycle_time"] ? root["safety"]["cycle_time"] : root, "safety.cycle_time",
           "the waypoints' " + io::number(s.duration) + " s would take more than 1e7 cycles at this cycle time");
  }
}

// obstacles and random_obstacles, each name once; the arms' pairs with an obstacle name one.
void readObstacles(const Yaml& y, const YAML::Node& root, const std::vector<ObstacleAllow>& obstacleAllows, Scenario& s) {
  if (const YAML::Node obs = y.list(root["obstacles"], "obstacles")) {
    for (std::size_t i = 0; i < obs.size(); ++i) {
      const std::string key = "obstacles[" + std::to_string(i) + "]";
      s.obstacles.push_back(parseObstacle(y, obs[i], key, static_cast<int>(i)));
      // a name names one obstacle (in the logs, the verdicts), as an arm's does
      for (std::size_t j = 0; j + 1 < s.obstacles.size(); ++j)
        if (s.obstacles[j].name == s.obstacles.back().name)
          y.fail(obs[i]["name"] ? obs[i]["name"] : obs[i], key + ".name",
                 "duplicate obstacle name '" + s.obstacles.back().name + "' (also obstacles[" + std::to_string(j) + "])");
    }
  }
  if (const YAML::Node n = root["random_obstacles"]) randomObstacles(y, n, s);
  for (const ObstacleAllow& oa : obstacleAllows)
    if (std::none_of(s.obstacles.begin(), s.obstacles.end(), [&](const Obstacle& o) { return o.name == oa.name; }))
      y.fail(oa.node, oa.key, "no obstacle named '" + oa.name + "'");
}

Scenario parseScenario(const std::string& path, const YAML::Node& root, const std::vector<SettingOverride>& overrides) {
  const Yaml y{path};
  y.knownKeys(root, "", {"safety", "octree", "models", "arms", "trace", "duration", "obstacles", "random_obstacles", "name",
                         "description", "braking", "persons", "ssm"});
  Scenario s;
  s.file = path;
  applySettings(y, root, overrides, s);
  if (const YAML::Node n = root["octree"]) {
    if (const YAML::Node b = n["bounds"]) {
      y.knownKeys(b, "octree.bounds", {"min", "max"});
      s.broad.bounds = Aabb3{y.vec3(b["min"], "octree.bounds.min"), y.vec3(b["max"], "octree.bounds.max")};
      if (!(s.broad.bounds->min.array() < s.broad.bounds->max.array()).all())
        y.fail(b["max"], "octree.bounds.max", "must exceed octree.bounds.min on every axis");
    }
  }
  const YAML::Node arms = root["arms"];
  // an absent key of a const node is invalid: IsSequence() would throw yaml-cpp's "invalid node"
  if (!arms.IsDefined()) y.fail(root, "arms", "missing key (the list of arms)");
  if (!arms.IsSequence() || arms.size() == 0) y.fail(arms, "arms", "expected a list of arms");
  bool anyWaypoints = false;
  std::vector<ObstacleAllow> obstacleAllows;
  for (std::size_t i = 0; i < arms.size(); ++i) {
    const std::string key = "arms[" + std::to_string(i) + "]";
    const YAML::Node a = arms[i];
    y.knownKeys(a, key, {"name", "model", "base", "allow", "check", "waypoints", "sensor"});
    s.arms.push_back(readArm(y, root, a, key, s, obstacleAllows));
    if (const YAML::Node w = a["waypoints"]) {
      anyWaypoints = true;
      s.scripts.push_back(readWaypoints(y, w, path, key, static_cast<int>(i), s.arms.back().model));
      s.duration = std::max(s.duration, s.scripts.back().waypoints.back().t);
    }
  }
  readTiming(y, root, path, anyWaypoints, s);
  readObstacles(y, root, obstacleAllows, s);
  parseSsm(y, root, s);
  return s;
}

}  // namespace

Scenario loadScenario(const std::string& path, const std::vector<SettingOverride>& overrides) {
  const YAML::Node root = io::Yaml<InputError>(path).load(path);
  try {
    return parseScenario(path, root, overrides);
  } catch (const YAML::Exception& e) {
    // a shape the checks above did not foresee: still one line naming the file and line
    throw InputError(io::place(path, e.mark) + ": " + e.msg);
  }
}

std::unique_ptr<SensorSource> makeSensor(const Scenario& s) {
  if (!s.tracePath.empty()) {
    std::vector<std::string> names;
    std::vector<int> dofs;
    for (const ArmInstance& a : s.arms) {
      names.push_back(a.name);
      dofs.push_back(a.model.dof());
    }
    return std::make_unique<CsvSensor>(s.tracePath, names, dofs);
  }
  return std::make_unique<WaypointSensor>(s.scripts, s.safety.cycleTime, s.duration);
}

Monitor makeMonitor(const Scenario& s) { return Monitor(s.arms, s.obstacles, s.safety, s.broad); }

PersonSet makePersons(const Scenario& s) {
  PersonSet set;
  for (const Scenario::Person& p : s.persons) {
    if (p.trace.empty()) {
      set.add(p.name, std::make_unique<ScriptedPerson>(p.script));
    } else {
      const CsvPersonTrace trace(p.trace, {p.name});
      set.add(p.name, std::make_unique<TracedPerson>(trace.rows(0)));
    }
  }
  return set;
}

void run(Monitor& m, SensorSource& src, RunStats& stats, const std::function<void(const Monitor&)>& onCycle,
         const std::function<bool()>& stopRequested) {
  using Clock = std::chrono::steady_clock;
  stats.firstStop.assign(m.armCount(), std::numeric_limits<double>::quiet_NaN());
  stats.interrupted = false;
  Reading r;
  bool have = src.next(r);
  double last = -std::numeric_limits<double>::infinity();
  std::vector<Reading> batch;
  while (have) {
    if (stopRequested && stopRequested()) {
      stats.interrupted = true;
      return;
    }
    // one cycle: every reading stamped with the same time
    const double t = r.t;
    if (t < last) throw InputError(r.where + ": time " + std::to_string(t) + " s goes backwards");
    batch.clear();
    std::exception_ptr bad;  // a malformed next reading: finish this cycle first, then report it
    while (have && r.t == t) {
      validateReading(m.arm(r.arm).model, r);
      batch.push_back(r);
      try {
        have = src.next(r);
      } catch (const InputError&) {
        bad = std::current_exception();
        have = false;
      }
    }
    const auto start = Clock::now();
    for (const Reading& b : batch) m.setJointState(b.arm, b.t, b.q.data(), b.qdot.data());
    m.cycle(t);
    const auto stop = Clock::now();
    stats.latencyUs.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
    ++stats.cycles;
    for (int a = 0; a < m.armCount(); ++a)
      if (m.stopped(a) && std::isnan(stats.firstStop[a])) stats.firstStop[a] = t;
    onCycle(m);
    last = t;
    if (bad) std::rethrow_exception(bad);
  }
}

void DeadlineWatch::see(double t, double us) {
  ++cycles;
  if (us > worstUs) worstUs = us, worstT = t;
  if (!(us > budgetUs)) return;
  ++missed;
  if (misses.size() < kMaxKept) misses.emplace_back(t, us);
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  // nearest rank
  const double rank = std::ceil(p / 100.0 * static_cast<double>(v.size()));
  const std::size_t idx = static_cast<std::size_t>(std::clamp(rank, 1.0, static_cast<double>(v.size()))) - 1;
  return v[idx];
}

}  // namespace st::arm
