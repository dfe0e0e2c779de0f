#include <stpool/scenario.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include <stcore/tolerances.hpp>
#include <stio/format.hpp>
#include <stio/input.hpp>
#include <stio/yaml.hpp>

#include <stpool/rack.hpp>

namespace st::pool {

namespace {

constexpr double kMaxTableSide = 100.0;  // m; a snooker table is 3.6
constexpr double kMaxFriction = 100.0;   // m/s^2; cloth's rolling resistance is about 0.1
constexpr long kMaxFactor = 1000000000;  // a factor past any ball count: taken as this

// The whole text as a number (a leading '+' allowed, as YAML and strtod allow it).
template <class T>
bool wholeNumber(const std::string& text, T& out) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, e, out);
  return b != e && ec == std::errc() && ptr == e;
}

}  // namespace

SpaceKind spaceKindSetting(const std::string& text) {
  SpaceKind kind = SpaceKind::Tree;
  if (!parseSpaceKind(text, kind)) throw SettingError("unknown space kind '" + text + "' (none, single, quadtree, cells)");
  return kind;
}

void setDecompositionFactor(SpaceSpec& space, const std::string& text) {
  if (text == "auto") {
    space.autoFactor = true;  // the space picks it as it runs (stcore/factor_tuner.hpp)
    return;
  }
  long df = 0;
  if (!wholeNumber(text, df)) throw SettingError("must be an integer or auto, got '" + text + "'");
  if (df < 1) throw SettingError("must be at least 1 (or auto), got " + text);
  space.decompositionFactor = static_cast<int>(std::min(df, kMaxFactor));
  space.autoFactor = false;
}

void checkKeyForKind(const SpaceSpec& space, const std::string& key) {
  const bool tree = key == "space.decomposition_factor" || key == "space.divisions" || key == "space.max_depth";
  const bool cells = key == "space.cell_size" || key == "space.margin";
  if (!tree && !cells) return;
  if (space.kind == (tree ? SpaceKind::Tree : SpaceKind::Cells)) return;
  const char* kindName = space.kind == SpaceKind::Tree ? "quadtree" : toString(space.kind);
  throw SettingError(std::string("only for kind ") + (tree ? "quadtree" : "cells") + " (this space is " + kindName + ")");
}

double untilSetting(const std::string& text) {
  double v = 0.0;
  if (!wholeNumber(text, v)) {
    std::string low;
    for (const char c : text) low += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    // YAML's own spellings of infinity and NaN
    if (low == ".inf" || low == "+.inf" || low == "-.inf" || low == ".nan") throw SettingError("must be finite");
    throw SettingError("must be a number, got '" + text + "'");
  }
  if (!std::isfinite(v)) throw SettingError("must be finite");
  if (!(v > 0.0)) throw SettingError("must be positive, got " + text);
  return v;
}

namespace {

// Where a key sits, for messages: "file:line:col: key".
struct Where {
  std::string source;
  std::string key;
  YAML::Mark mark;
  std::string str() const { return io::place(source, mark, true) + ": " + key; }
};

[[noreturn]] void fail(const Where& w, const std::string& problem) { throw ScenarioError(w.str() + ": " + problem); }

// One of the settings above, its problem named at the key that gave it.
template <class F>
auto setting(const Where& w, F&& f) {
  try {
    return f();
  } catch (const SettingError& e) {
    fail(w, e.what());
  }
}

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  Where at(const YAML::Node& n, const std::string& key) const { return Where{source_, key, n.Mark()}; }

  // Checks that map node n (named key) has only the allowed keys.
  void onlyKeys(const YAML::Node& n, const std::string& key, std::initializer_list<const char*> allowed) const {
    if (!n.IsMap()) fail(at(n, key), "must be a map");
    const io::KeyProblem p = io::checkKeys(n, key, [&](const std::string& k) {
      return std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return k == a; });
    });
    if (!p.key.empty()) fail(at(p.at, p.key), p.what);
  }

  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(at(n, key), "must be a number");
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(at(n, key), "must be a number, got '" + n.Scalar() + "'");
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
    if (!n.IsScalar()) fail(at(n, key), "must be an integer");
    try {
      return n.as<long>();
    } catch (const YAML::Exception&) {
      fail(at(n, key), "must be an integer, got '" + n.Scalar() + "'");
    }
  }

  bool boolean(const YAML::Node& n, const std::string& key) const {
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      fail(at(n, key), "must be true or false");
    }
  }

  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(at(n, key), "must be a string");
    return n.Scalar();
  }

  Vec2 vec2(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() != 2) fail(at(n, key), "must be a pair [x, y]");
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
  if (s.table.width > kMaxTableSide) fail(where("table.width", -1), "must be at most " + io::number(kMaxTableSide) + " m");
  if (s.table.height > kMaxTableSide) fail(where("table.height", -1), "must be at most " + io::number(kMaxTableSide) + " m");
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
  if (!(s.until > 0.0)) fail(where("until", -1), "must be positive");
  if (!(s.friction >= 0.0) || !std::isfinite(s.friction)) fail(where("friction", -1), "must be zero or positive");
  // a deceleration beyond any cloth's: 1e308 was blamed on until (the event limit)
  if (s.friction > kMaxFriction)
    fail(where("friction", -1), io::number(s.friction) + " m/s^2 is more than any cloth's rolling resistance (at most " +
                                    io::number(kMaxFriction) + " m/s^2)");
  const SpaceSpec& sp = s.space;
  if (sp.decompositionFactor < 1) fail(where("space.decomposition_factor", -1), "must be at least 1");
  if (sp.divisions != 2 && sp.divisions != 4) fail(where("space.divisions", -1), "must be 2 or 4");
  if (sp.maxDepth < -1 || sp.maxDepth > 30) fail(where("space.max_depth", -1), "must be between 0 and 30 (or -1: automatic)");
  if (sp.kind == SpaceKind::Cells && !(sp.cellSize > 0.0)) fail(where("space.cell_size", -1), "must be positive");
  // stcore's cells space holds at most 5e7 cells: say which key asks for more
  if (sp.kind == SpaceKind::Cells && std::isfinite(sp.cellSize) &&
      std::floor(s.table.width / sp.cellSize) * std::floor(s.table.height / sp.cellSize) > 5e7)
    fail(where("space.cell_size", -1), "too small for the table: more than 5e7 cells (the table is " +
                                           std::to_string(s.table.width) + " x " + std::to_string(s.table.height) + " m)");
  if (!(sp.marginFactor() > 0.0) || !std::isfinite(sp.marginFactor())) fail(where("space.margin", -1), "must be positive");
}

Scenario parse(const YAML::Node& root, const std::string& source) {
  Reader rd(source);
  Scenario s;
  s.name = source;
  if (!root.IsMap()) fail(Where{source, "(top level)", root.Mark()}, "a scenario must be a YAML map");
  rd.onlyKeys(root, "", {"name", "table", "balls", "rack", "random", "shots", "space", "until", "friction", "seed"});
  // where each key was found, so validation can name its line
  std::map<std::string, YAML::Mark> marks;
  std::vector<YAML::Mark> ballMarks;
  auto mark = [&](const std::string& key, const YAML::Node& n) { marks[key] = n.Mark(); };

  if (root["name"]) s.name = rd.text(root["name"], "name");
  if (root["seed"]) {
    const long seed = rd.integer(root["seed"], "seed");
    if (seed < 0) fail(rd.at(root["seed"], "seed"), "must not be negative");
    s.seed = static_cast<std::uint64_t>(seed);
  }
  if (const YAML::Node n = root["until"]) {
    if (!n.IsScalar()) fail(rd.at(n, "until"), "must be a number");
    s.until = setting(rd.at(n, "until"), [&] { return untilSetting(n.Scalar()); });
  }
  if (root["friction"]) {
    mark("friction", root["friction"]);
    s.friction = rd.number(root["friction"], "friction");
    if (s.friction < 0.0) fail(rd.at(root["friction"], "friction"), "must be zero or positive");
  }

  // table
  const YAML::Node table = root["table"];
  if (!table) fail(Where{source, "table", root.Mark()}, io::missingKeyText());
  mark("table", table);
  rd.onlyKeys(table, "table", {"width", "height", "pockets", "corner_mouth", "side_mouth"});
  if (!table["width"]) fail(rd.at(table, "table.width"), io::missingKeyText());
  if (!table["height"]) fail(rd.at(table, "table.height"), io::missingKeyText());
  s.table.width = rd.positive(table["width"], "table.width");
  s.table.height = rd.positive(table["height"], "table.height");
  // named here, before a rack is placed on it (1e300 was reported as the rack's overlap)
  for (const auto& [key, v] : {std::pair{"table.width", s.table.width}, std::pair{"table.height", s.table.height}})
    if (v > kMaxTableSide)
      fail(rd.at(table[std::string(key).substr(6)], key), io::number(v) + " m is more than any table's (at most " +
                                                               io::number(kMaxTableSide) + " m)");
  if (table["pockets"]) s.table.pockets = rd.boolean(table["pockets"], "table.pockets");
  if (table["corner_mouth"]) s.table.cornerMouth = rd.positive(table["corner_mouth"], "table.corner_mouth");
  if (table["side_mouth"]) s.table.sideMouth = rd.positive(table["side_mouth"], "table.side_mouth");
  Table built;
  try {
    built = makeTable(s.table);
  } catch (const std::invalid_argument& e) {
    fail(rd.at(table, "table"), e.what());
  }

  // balls: exactly one of balls / rack / random
  const int sources = (root["balls"] ? 1 : 0) + (root["rack"] ? 1 : 0) + (root["random"] ? 1 : 0);
  if (sources == 0) fail(Where{source, "balls", root.Mark()}, io::missingKeyText("give balls, rack or random"));
  if (sources > 1) fail(Where{source, "balls", root.Mark()}, "give only one of balls, rack and random");
  Rng rng(s.seed);
  if (const YAML::Node rack = root["rack"]) {
    RackSpec spec;
    if (rack.IsScalar()) {
      if (rack.Scalar() != "standard") fail(rd.at(rack, "rack"), "unknown rack '" + rack.Scalar() + "' (standard)");
    } else {
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
    }
    s.balls = standardRack(built, spec, rng);
    ballMarks.assign(s.balls.size(), rack.Mark());
  } else if (const YAML::Node rnd = root["random"]) {
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
      s.balls = randomBalls(built, static_cast<int>(count), speed, radius, mass, clearance, rng);
    } catch (const std::invalid_argument& e) {
      fail(rd.at(rnd, "random"), e.what());
    }
    ballMarks.assign(s.balls.size(), rnd.Mark());
  } else {
    const YAML::Node balls = root["balls"];
    if (!balls.IsSequence() || balls.size() == 0) fail(rd.at(balls, "balls"), "must be a non-empty list");
    for (std::size_t i = 0; i < balls.size(); ++i) {
      const YAML::Node b = balls[i];
      const std::string key = indexed("balls", i);
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
      s.balls.push_back(spec);
      // point validation messages at the position (the usual culprit)
      ballMarks.push_back(b["position"].Mark());
    }
  }

  // shots
  if (const YAML::Node shots = root["shots"]) {
    if (!shots.IsSequence()) fail(rd.at(shots, "shots"), "must be a list");
    for (std::size_t k = 0; k < shots.size(); ++k) {
      const YAML::Node n = shots[k];
      const std::string key = indexed("shots", k);
      rd.onlyKeys(n, key, {"ball", "cue", "speed", "angle", "velocity", "until"});
      Shot shot;
      mark(key, n);
      if (n["ball"]) shot.ball = static_cast<int>(rd.integer(n["ball"], key + ".ball"));
      mark(key + ".ball", n["ball"] ? n["ball"] : n);
      const bool cue = static_cast<bool>(n["cue"]);
      const bool polar = n["speed"] || n["angle"];
      const bool direct = static_cast<bool>(n["velocity"]);
      if ((cue ? 1 : 0) + (polar ? 1 : 0) + (direct ? 1 : 0) != 1)
        fail(rd.at(n, key), "give one of cue, speed and angle, or velocity");
      if (direct) {
        // the velocity as the Game takes it: what a recorded game (writeScenarioYaml) replays bit for bit
        shot.velocity = rd.vec2(n["velocity"], key + ".velocity");
      } else if (cue) {
        const YAML::Node c = n["cue"];
        rd.onlyKeys(c, key + ".cue", {"from", "to", "scale"});
        if (!c["from"]) fail(rd.at(c, key + ".cue.from"), io::missingKeyText());
        if (!c["to"]) fail(rd.at(c, key + ".cue.to"), io::missingKeyText());
        const Vec2 from = rd.vec2(c["from"], key + ".cue.from");
        const Vec2 to = rd.vec2(c["to"], key + ".cue.to");
        // the report: velocity proportional to the cue vector, in its direction (§2.3)
        const double scale = c["scale"] ? rd.positive(c["scale"], key + ".cue.scale") : 1.0;
        shot.velocity = scale * (to - from);
      } else {
        if (!n["speed"]) fail(rd.at(n, key + ".speed"), io::missingKeyText());
        if (!n["angle"]) fail(rd.at(n, key + ".angle"), io::missingKeyText());
        const double speed = rd.number(n["speed"], key + ".speed");
        if (speed < 0.0) fail(rd.at(n["speed"], key + ".speed"), "must be zero or positive");
        const double deg = rd.number(n["angle"], key + ".angle");
        // 1e308 made the direction NaN, blamed on the speed
        if (!(std::abs(deg) <= 360.0)) fail(rd.at(n["angle"], key + ".angle"), "must be between -360 and 360 degrees");
        const double rad = deg * std::numbers::pi / 180.0;
        shot.velocity = speed * Vec2(std::cos(rad), std::sin(rad));
      }
      if (const YAML::Node u = n["until"]) {
        if (!u.IsScalar()) fail(rd.at(u, key + ".until"), "must be a number");
        shot.until = setting(rd.at(u, key + ".until"), [&] { return untilSetting(u.Scalar()); });
      }
      s.shots.push_back(shot);
    }
  }

  // space
  if (const YAML::Node sp = root["space"]) {
    mark("space", sp);
    rd.onlyKeys(sp, "space", {"kind", "decomposition_factor", "divisions", "max_depth", "cell_size", "margin"});
    if (sp["kind"]) {
      const std::string k = rd.text(sp["kind"], "space.kind");
      s.space.kind = setting(rd.at(sp["kind"], "space.kind"), [&] { return spaceKindSetting(k); });
    }
    // a key of another kind would be taken and do nothing: refused, naming the kind it is for
    for (const char* k : {"decomposition_factor", "divisions", "max_depth", "cell_size", "margin"})
      if (sp[k]) setting(rd.at(sp[k], std::string("space.") + k), [&] { checkKeyForKind(s.space, std::string("space.") + k); });
    auto intKey = [&](const char* k, int& out) {
      if (!sp[k]) return;
      const std::string key = std::string("space.") + k;
      mark(key, sp[k]);
      out = static_cast<int>(std::clamp(rd.integer(sp[k], key), -1L, 1000000000L));
    };
    if (const YAML::Node df = sp["decomposition_factor"]) {
      mark("space.decomposition_factor", df);
      const Where w = rd.at(df, "space.decomposition_factor");
      if (!df.IsScalar()) fail(w, "must be an integer or auto");
      setting(w, [&] { setDecompositionFactor(s.space, df.Scalar()); });
    }
    intKey("divisions", s.space.divisions);
    intKey("max_depth", s.space.maxDepth);
    if (sp["cell_size"]) {
      mark("space.cell_size", sp["cell_size"]);
      s.space.cellSize = rd.number(sp["cell_size"], "space.cell_size");
    }
    if (sp["margin"]) {
      mark("space.margin", sp["margin"]);
      s.space.margin = rd.number(sp["margin"], "space.margin");
      if (!(s.space.margin > 0.0)) fail(rd.at(sp["margin"], "space.margin"), "must be positive");
    }
  }

  validate(s, [&](const std::string& key, int ball) {
    if (ball >= 0 && ball < static_cast<int>(ballMarks.size())) return Where{source, key, ballMarks[ball]};
    auto it = marks.find(key);
    return Where{source, key, it != marks.end() ? it->second : root.Mark()};
  }, root["rack"] ? "rack" : root["random"] ? "random" : "balls");
  return s;
}

}  // namespace

void validateScenario(const Scenario& s, const std::string& source) {
  validate(s, [&](const std::string& key, int) { return Where{source, key, YAML::Mark::null_mark()}; });
}

Scenario parseScenario(const std::string& yamlText, const std::string& source) {
  YAML::Node root;
  try {
    root = io::loadOneDocument(yamlText);
  } catch (const YAML::ParserException& e) {
    fail(Where{source, "(syntax)", e.mark}, e.msg);
  }
  try {
    return parse(root, source);
  } catch (const YAML::Exception& e) {
    // a shape the checks in parse() did not foresee: still one line naming the file and place
    fail(Where{source, "(scenario)", e.mark}, e.msg);
  }
}

Scenario loadScenario(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ScenarioError(path + ": is a directory, not a YAML file");
  if (!std::filesystem::exists(path, ec)) throw ScenarioError(path + ": cannot open the scenario file");
  std::string text, error;
  if (!io::readTextFile(path, text, error)) throw ScenarioError(error);
  return parseScenario(text, path);
}

}  // namespace st::pool
