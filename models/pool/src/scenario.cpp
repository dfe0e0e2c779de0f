#include <stpool/scenario.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <set>

#include <yaml-cpp/yaml.h>

#include <stcore/tolerances.hpp>
#include <stio/format.hpp>
#include <stio/input.hpp>
#include <stio/yaml.hpp>

#include <stpool/rack.hpp>
#include <stpool/settings.hpp>

namespace st::pool {

namespace {

// Where a key sits, for messages: "file:line:col: key"; or that the command line gave it.
struct Where {
  std::string source;
  std::string key;
  YAML::Mark mark;
  bool fromCli = false;
  std::string str() const { return io::place(source, mark, true) + ": " + key; }
};

// A key's problem: at its line, or, when the command line gave the key, a SettingError the front
// end words with its option.
[[noreturn]] void fail(const Where& w, const std::string& problem) {
  if (w.fromCli) throw SettingError(w.key, problem);
  throw ScenarioError(w.str() + ": " + problem);
}

// A setting's check (stpool/settings.hpp), its problem named at the key that gave it.
template <class F>
auto named(const Where& w, F&& f) {
  try {
    return f();
  } catch (const SettingError& e) {
    fail(w, e.problem());
  }
}

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  Where at(const YAML::Node& n, const std::string& key) const { return Where{source_, key, n.Mark()}; }

  // Checks that map node n (named key) has only the allowed keys.
  void onlyKeys(const YAML::Node& n, const std::string& key, std::initializer_list<const char*> allowed) const {
    onlyKeysIf(n, key, [&](const std::string& k) {
      return std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return k == a; });
    });
  }
  void onlyKeysIf(const YAML::Node& n, const std::string& key, const std::function<bool(const std::string&)>& allowed) const {
    if (!n.IsMap()) fail(at(n, key), io::wrongTypeText("a mapping"));
    const io::KeyProblem p = io::checkKeys(n, key, allowed);
    if (!p.key.empty()) fail(at(p.at, p.key), p.what);
  }

  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(at(n, key), io::wrongTypeText("a number"));
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(at(n, key), io::wrongTypeText("a number", n.Scalar()));
    }
    if (!std::isfinite(v)) fail(at(n, key), "must be finite");
    return v;
  }

  double positive(const YAML::Node& n, const std::string& key) const {
    const double v = number(n, key);
    if (!(v > 0.0)) fail(at(n, key), "must be positive, got " + n.Scalar());
    return v;
  }

  long integer(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(at(n, key), io::wrongTypeText("an integer"));
    try {
      return n.as<long>();
    } catch (const YAML::Exception&) {
      fail(at(n, key), io::wrongTypeText("an integer", n.Scalar()));
    }
  }

  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(at(n, key), io::wrongTypeText("a string"));
    return n.Scalar();
  }

  Vec2 vec2(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() != 2) fail(at(n, key), io::wrongTypeText("a pair [x, y]"));
    return Vec2(number(n[0], key + "[0]"), number(n[1], key + "[1]"));
  }

 private:
  std::string source_;
};

std::string indexed(const std::string& key, std::size_t i) { return key + "[" + std::to_string(i) + "]"; }

// Validation shared by the YAML loader (which knows lines) and programmatic scenarios.
using Locate = std::function<Where(const std::string& key, int ball)>;

// `ballsKey`: "balls" for a ball list, or the key that generated them ("rack", "random"), which
// is then named instead of a balls[i] key the file does not have.
void validate(const Scenario& s, const Locate& where, const std::string& ballsKey = "balls") {
  // every setting in its range: a scenario built in code is held to the table as a file is
  try {
    checkSettings(s);
  } catch (const SettingError& e) {
    fail(where(e.key(), -1), e.problem());
  }
  const bool listed = ballsKey == "balls";
  auto ballKey = [&](int i, const char* field) {
    return listed ? indexed("balls", static_cast<std::size_t>(i)) + field : ballsKey;
  };
  Table table;
  try {
    table = makeTable(s.table);
  } catch (const std::invalid_argument& e) {
    fail(where("table", -1), e.what());
  }
  std::set<int> numbers;
  for (int i = 0; i < static_cast<int>(s.balls.size()); ++i) {
    const BallSpec& b = s.balls[i];
    const std::string ball = listed ? "" : "ball " + std::to_string(b.number) + ": ";
    if (!(b.radius > 0.0) || !std::isfinite(b.radius)) fail(where(ballKey(i, ".radius"), i), ball + "must be positive");
    if (!(b.mass > 0.0) || !std::isfinite(b.mass)) fail(where(ballKey(i, ".mass"), i), ball + "must be positive");
    if (!b.position.allFinite()) fail(where(ballKey(i, ".position"), i), ball + "must be finite");
    if (!b.velocity.allFinite()) fail(where(ballKey(i, ".velocity"), i), ball + "must be finite");
    if (b.velocity.norm() > kMaxSpeed)
      fail(where(ballKey(i, ".velocity"), i),
           ball + "speed must be at most " + std::to_string(static_cast<int>(kMaxSpeed)) + " m/s");
    if (!numbers.insert(b.number).second)
      fail(where(ballKey(i, ".number"), i), "ball number " + std::to_string(b.number) + " is used twice");
    if (const char* why = placementProblem(table, b.position, b.radius); *why)
      fail(where(ballKey(i, ".position"), i), ball + why);
  }
  // overlaps: sort by x so only near neighbours are compared
  std::vector<int> order(s.balls.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return s.balls[a].position.x() < s.balls[b].position.x(); });
  double rmax = 0.0;
  for (const auto& b : s.balls) rmax = std::max(rmax, b.radius);
  for (std::size_t u = 0; u < order.size(); ++u) {
    const BallSpec& a = s.balls[order[u]];
    for (std::size_t w = u + 1; w < order.size(); ++w) {
      const BallSpec& b = s.balls[order[w]];
      if (b.position.x() - a.position.x() > 2.0 * rmax) break;
      // touching is allowed, and so is roundoff below the simulator's slop (the exact frozen
      // rack puts neighbours 2r apart up to roundoff)
      if ((a.position - b.position).norm() < a.radius + b.radius - tol::kLinearSlop) {
        const int later = std::max(order[u], order[w]), earlier = std::min(order[u], order[w]);
        fail(where(ballKey(later, ".position"), later),
             "ball " + std::to_string(s.balls[later].number) + " overlaps ball " +
                 std::to_string(s.balls[earlier].number));
      }
    }
  }
  for (std::size_t k = 0; k < s.shots.size(); ++k) {
    if (!numbers.count(s.shots[k].ball))
      fail(where(indexed("shots", k) + ".ball", -1), "no ball number " + std::to_string(s.shots[k].ball));
    if (!s.shots[k].velocity.allFinite()) fail(where(indexed("shots", k), -1), "velocity must be finite");
    if (s.shots[k].velocity.norm() > kMaxSpeed)
      fail(where(indexed("shots", k), -1), "speed must be at most " + std::to_string(static_cast<int>(kMaxSpeed)) + " m/s");
  }
  const SpaceSpec& sp = s.space;
  // stcore's cells space holds at most 5e7 cells: say which key asks for more
  if (sp.kind == SpaceKind::Cells && std::isfinite(sp.cellSize) &&
      std::floor(s.table.width / sp.cellSize) * std::floor(s.table.height / sp.cellSize) > 5e7)
    fail(where("space.cell_size", -1), "too small for the table: more than 5e7 cells (the table is " +
                                           std::to_string(s.table.width) + " x " + std::to_string(s.table.height) + " m)");
}

// Where the keys were found, so validation names the line of the one at fault, or the option when
// the command line gave it.
struct Places {
  std::map<std::string, YAML::Mark> marks;
  std::vector<YAML::Mark> balls;  // each ball's (a rack's or random layout's: that key's)
  std::set<std::string> fromCli;
};

// The node of a setting's key ("space.cell_size", "until") under root; an undefined node if absent.
YAML::Node settingNode(const YAML::Node& root, std::string_view key) {
  const std::string name(io::keyName(key));
  if (io::keySection(key).empty()) return root[name];
  const YAML::Node section = root[std::string(io::keySection(key))];
  if (!section || !section.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  return section[name];
}

// The sections' keys: those of the settings table. The table and its size are given in every
// scenario (a table's size is no default to forget).
void checkSections(const Reader& rd, const YAML::Node& root, const std::string& source) {
  rd.onlyKeys(root, "", {"name", "table", "balls", "rack", "random", "shots", "space", "until", "friction", "seed"});
  const YAML::Node table = root["table"];
  if (!table) fail(Where{source, "table", root.Mark()}, io::missingKeyText());
  for (const char* section : {"table", "space"}) {
    const YAML::Node n = root[section];
    if (!n) continue;
    const std::string prefix = std::string(section) + ".";
    rd.onlyKeysIf(n, section, [&](const std::string& k) { return findSetting(prefix + k) != nullptr; });
  }
  if (!table["width"]) fail(rd.at(table, "table.width"), io::missingKeyText());
  if (!table["height"]) fail(rd.at(table, "table.height"), io::missingKeyText());
}

// The settings (stpool/settings.hpp): the file's, then the command line's over them, each checked
// and worded by the table. A space key of another kind is refused against the kind of the front
// end that gave it: the file's against the file's kind (--space sets them aside), an option's
// against the kind in effect (`--space cells --df 7` as `kind: cells` with a decomposition_factor).
void readSettings(const Reader& rd, const YAML::Node& root, const std::vector<SettingOverride>& overrides, Scenario& s,
                  Places& at) {
  for (const Setting& setting : poolSettings()) {
    const YAML::Node n = settingNode(root, setting.key);
    if (!n) continue;
    const Where w = rd.at(n, setting.key);
    if (!n.IsScalar()) fail(w, "must be " + expected(setting));
    // space.kind comes first in its section: the file's kind is known here
    named(w, [&] {
      checkKeyForKind(s, setting.key);
      applySettingText(s, setting, n.Scalar());
    });
    at.marks[setting.key] = n.Mark();
  }
  for (const SettingOverride& o : overrides) {
    const Setting* setting = findSetting(o.key);
    if (!setting) throw SettingError(o.key, "is not a setting (stsim pool --settings lists them)");
    applySettingText(s, *setting, o.text);
    at.fromCli.insert(setting->key);
  }
  for (const std::string& key : at.fromCli) checkKeyForKind(s, key);
}

// rack: the standard triangle (a scalar "standard", or its keys)
std::vector<BallSpec> readRack(const Reader& rd, const YAML::Node& rack, const Table& built, Rng& rng) {
  RackSpec spec;
  if (rack.IsScalar()) {
    if (rack.Scalar() != "standard") fail(rd.at(rack, "rack"), "unknown rack '" + rack.Scalar() + "' (standard)");
    return standardRack(built, spec, rng);
  }
  rd.onlyKeys(rack, "rack", {"kind", "gap", "apex", "cue_ball", "radius", "mass"});
  if (rack["kind"] && rd.text(rack["kind"], "rack.kind") != "standard")
    fail(rd.at(rack["kind"], "rack.kind"), "unknown rack '" + rack["kind"].Scalar() + "' (standard)");
  if (rack["gap"]) {
    spec.gap = rd.number(rack["gap"], "rack.gap");
    if (spec.gap < 0.0) fail(rd.at(rack["gap"], "rack.gap"), "must be zero or positive");
  }
  if (rack["apex"]) spec.apex = rd.vec2(rack["apex"], "rack.apex");
  if (rack["cue_ball"]) spec.cueBall = rd.vec2(rack["cue_ball"], "rack.cue_ball");
  if (rack["radius"]) spec.radius = rd.positive(rack["radius"], "rack.radius");
  if (rack["mass"]) spec.mass = rd.positive(rack["mass"], "rack.mass");
  return standardRack(built, spec, rng);
}

// random: seeded non-overlapping balls
std::vector<BallSpec> readRandom(const Reader& rd, const YAML::Node& rnd, const Table& built, Rng& rng) {
  rd.onlyKeys(rnd, "random", {"count", "speed", "radius", "mass", "clearance"});
  if (!rnd["count"]) fail(rd.at(rnd, "random.count"), io::missingKeyText());
  const long count = rd.integer(rnd["count"], "random.count");
  if (count < 1 || count > 1000000) fail(rd.at(rnd["count"], "random.count"), "must be between 1 and 1000000");
  const double speed = rnd["speed"] ? rd.number(rnd["speed"], "random.speed") : 1.0;
  if (speed < 0.0 || speed > kMaxSpeed)
    fail(rd.at(rnd["speed"], "random.speed"), "must be between 0 and " + std::to_string(static_cast<int>(kMaxSpeed)) + " m/s");
  const double radius = rnd["radius"] ? rd.positive(rnd["radius"], "random.radius") : kBallRadius;
  const double mass = rnd["mass"] ? rd.positive(rnd["mass"], "random.mass") : kBallMass;
  const double clearance = rnd["clearance"] ? rd.number(rnd["clearance"], "random.clearance") : 0.0;
  if (clearance < 0.0) fail(rd.at(rnd["clearance"], "random.clearance"), "must be zero or positive");
  try {
    return randomBalls(built, static_cast<int>(count), speed, radius, mass, clearance, rng);
  } catch (const std::invalid_argument& e) {
    fail(rd.at(rnd, "random"), e.what());
  }
}

// balls: a list, each ball by its number and position
BallSpec readBall(const Reader& rd, const YAML::Node& b, const std::string& key) {
  rd.onlyKeys(b, key, {"number", "position", "velocity", "radius", "mass", "colour", "color", "pattern"});
  if (!b["number"]) fail(rd.at(b, key + ".number"), io::missingKeyText());
  if (!b["position"]) fail(rd.at(b, key + ".position"), io::missingKeyText());
  const long number = rd.integer(b["number"], key + ".number");
  if (number < 0 || number > 1000000) fail(rd.at(b["number"], key + ".number"), "must be between 0 and 1000000");
  BallSpec spec = makeBall(static_cast<int>(number), rd.vec2(b["position"], key + ".position"));
  if (b["velocity"]) spec.velocity = rd.vec2(b["velocity"], key + ".velocity");
  if (b["radius"]) spec.radius = rd.positive(b["radius"], key + ".radius");
  if (b["mass"]) spec.mass = rd.positive(b["mass"], key + ".mass");
  for (const char* ck : {"colour", "color"}) {
    if (!b[ck]) continue;
    const auto c = parseColour(rd.text(b[ck], key + "." + ck));
    if (!c) fail(rd.at(b[ck], key + "." + ck), "unknown colour '" + b[ck].Scalar() + "'");
    spec.colour = *c;
  }
  if (b["pattern"]) {
    const auto p = parsePattern(rd.text(b["pattern"], key + ".pattern"));
    if (!p) fail(rd.at(b["pattern"], key + ".pattern"), "unknown pattern '" + b["pattern"].Scalar() + "' (solid, striped)");
    spec.pattern = *p;
  }
  return spec;
}

// The balls: exactly one of balls / rack / random. Returns the key that gave them.
std::string readBalls(const Reader& rd, const YAML::Node& root, const std::string& source, Scenario& s, Places& at) {
  const int sources = (root["balls"] ? 1 : 0) + (root["rack"] ? 1 : 0) + (root["random"] ? 1 : 0);
  if (sources == 0) fail(Where{source, "balls", root.Mark()}, io::missingKeyText("give balls, rack or random"));
  if (sources > 1) fail(Where{source, "balls", root.Mark()}, "give only one of balls, rack and random");
  Table built;
  try {
    built = makeTable(s.table);
  } catch (const std::invalid_argument& e) {
    fail(Where{source, "table", root["table"].Mark()}, e.what());
  }
  Rng rng(s.seed);
  for (const char* key : {"rack", "random"}) {
    const YAML::Node n = root[key];
    if (!n) continue;
    s.balls = key == std::string("rack") ? readRack(rd, n, built, rng) : readRandom(rd, n, built, rng);
    at.balls.assign(s.balls.size(), n.Mark());
    return key;
  }
  const YAML::Node balls = root["balls"];
  if (!balls.IsSequence() || balls.size() == 0) fail(rd.at(balls, "balls"), io::wrongTypeText("a non-empty list"));
  for (std::size_t i = 0; i < balls.size(); ++i) {
    s.balls.push_back(readBall(rd, balls[i], indexed("balls", i)));
    // point validation messages at the position (the usual culprit)
    at.balls.push_back(balls[i]["position"].Mark());
  }
  return "balls";
}

// A shot's velocity: from a cue vector, a speed and angle, or given as it is.
Vec2 shotVelocity(const Reader& rd, const YAML::Node& n, const std::string& key) {
  const bool cue = static_cast<bool>(n["cue"]);
  const bool polar = n["speed"] || n["angle"];
  const bool direct = static_cast<bool>(n["velocity"]);
  if ((cue ? 1 : 0) + (polar ? 1 : 0) + (direct ? 1 : 0) != 1) fail(rd.at(n, key), "give one of cue, speed and angle, or velocity");
  // the velocity as the Game takes it: what a recorded game (writeScenarioYaml) replays bit for bit
  if (direct) return rd.vec2(n["velocity"], key + ".velocity");
  if (cue) {
    const YAML::Node c = n["cue"];
    rd.onlyKeys(c, key + ".cue", {"from", "to", "scale"});
    if (!c["from"]) fail(rd.at(c, key + ".cue.from"), io::missingKeyText());
    if (!c["to"]) fail(rd.at(c, key + ".cue.to"), io::missingKeyText());
    const Vec2 from = rd.vec2(c["from"], key + ".cue.from");
    const Vec2 to = rd.vec2(c["to"], key + ".cue.to");
    // the report: velocity proportional to the cue vector, in its direction (§2.3)
    const double scale = c["scale"] ? rd.positive(c["scale"], key + ".cue.scale") : 1.0;
    return scale * (to - from);
  }
  if (!n["speed"]) fail(rd.at(n, key + ".speed"), io::missingKeyText());
  if (!n["angle"]) fail(rd.at(n, key + ".angle"), io::missingKeyText());
  const double speed = rd.number(n["speed"], key + ".speed");
  if (speed < 0.0) fail(rd.at(n["speed"], key + ".speed"), "must be zero or positive");
  const double deg = rd.number(n["angle"], key + ".angle");
  // 1e308 made the direction NaN, blamed on the speed
  if (!(std::abs(deg) <= 360.0)) fail(rd.at(n["angle"], key + ".angle"), "must be between -360 and 360 degrees");
  const double rad = deg * std::numbers::pi / 180.0;
  return speed * Vec2(std::cos(rad), std::sin(rad));
}

void readShots(const Reader& rd, const YAML::Node& shots, Scenario& s, Places& at) {
  if (!shots.IsSequence()) fail(rd.at(shots, "shots"), io::wrongTypeText("a list"));
  const Setting& until = *findSetting("until");
  for (std::size_t k = 0; k < shots.size(); ++k) {
    const YAML::Node n = shots[k];
    const std::string key = indexed("shots", k);
    rd.onlyKeys(n, key, {"ball", "cue", "speed", "angle", "velocity", "until"});
    Shot shot;
    at.marks[key] = n.Mark();
    if (n["ball"]) shot.ball = static_cast<int>(rd.integer(n["ball"], key + ".ball"));
    at.marks[key + ".ball"] = (n["ball"] ? n["ball"] : n).Mark();
    shot.velocity = shotVelocity(rd, n, key);
    // a shot's own limit, checked as the scenario's until is
    if (const YAML::Node u = n["until"]) {
      const Where w = rd.at(u, key + ".until");
      if (!u.IsScalar()) fail(w, "must be " + expected(until));
      shot.until = named(w, [&] { return std::get<double>(io::settingValue(until, u.Scalar())); });
    }
    s.shots.push_back(shot);
  }
}

Scenario parse(const YAML::Node& root, const std::string& source, const std::vector<SettingOverride>& overrides) {
  const Reader rd(source);
  Scenario s;
  s.name = source;
  if (!root.IsMap()) fail(Where{source, "(top level)", root.Mark()}, "a scenario must be a YAML map");
  checkSections(rd, root, source);
  if (root["name"]) s.name = rd.text(root["name"], "name");
  Places at;
  at.marks["table"] = root["table"].Mark();
  readSettings(rd, root, overrides, s, at);
  const std::string ballsKey = readBalls(rd, root, source, s, at);
  if (const YAML::Node shots = root["shots"]) readShots(rd, shots, s, at);
  validate(s, [&](const std::string& key, int ball) {
    if (ball >= 0 && ball < static_cast<int>(at.balls.size())) return Where{source, key, at.balls[ball]};
    const auto it = at.marks.find(key);
    return Where{source, key, it != at.marks.end() ? it->second : root.Mark(), at.fromCli.count(key) > 0};
  }, ballsKey);
  return s;
}

}  // namespace

void validateScenario(const Scenario& s, const std::string& source) {
  validate(s, [&](const std::string& key, int) { return Where{source, key, YAML::Mark::null_mark()}; });
}

Scenario parseScenario(const std::string& yamlText, const std::string& source, const std::vector<SettingOverride>& overrides) {
  YAML::Node root;
  try {
    root = io::loadOneDocument(yamlText);
  } catch (const YAML::ParserException& e) {
    fail(Where{source, "(syntax)", e.mark}, e.msg);
  }
  try {
    return parse(root, source, overrides);
  } catch (const YAML::Exception& e) {
    // a shape the checks in parse() did not foresee: still one line naming the file and place
    fail(Where{source, "(scenario)", e.mark}, e.msg);
  }
}

Scenario loadScenario(const std::string& path, const std::vector<SettingOverride>& overrides) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ScenarioError(path + ": is a directory, not a YAML file");
  if (!std::filesystem::exists(path, ec)) throw ScenarioError(path + ": cannot open the scenario file");
  std::string text, error;
  if (!io::readTextFile(path, text, error)) throw ScenarioError(error);
  return parseScenario(text, path, overrides);
}

}  // namespace st::pool
