#include "play_session.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include <stcore/tolerances.hpp>
#include <stio/format.hpp>
#include <stio/json.hpp>
#include <stpool/scenario_writer.hpp>
#include <stpool/settings.hpp>

namespace st::pool {

using json = nlohmann::json;

namespace {

// A message the game refuses: the field it names and why. The game goes on.
struct FieldError {
  std::string field, message;
};

// The text as valid UTF-8: a byte that begins no well-formed sequence (overlong, a surrogate,
// past U+10FFFF, cut short) becomes U+FFFD. The JSON library's errors quote the bytes it stopped
// at, whatever they are; a text frame that is not UTF-8 is one a browser refuses.
std::string validUtf8(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool ok = n > 0 && i + n <= s.size();
    if (ok && n > 1) {
      unsigned cp = c & (0x7Fu >> n);
      for (std::size_t k = 1; ok && k < n; ++k) {
        const auto b = static_cast<unsigned char>(s[i + k]);
        ok = (b & 0xC0u) == 0x80u;
        cp = (cp << 6) | (b & 0x3Fu);
      }
      static constexpr unsigned kLeast[] = {0, 0, 0x80, 0x800, 0x10000};
      ok = ok && cp >= kLeast[n] && cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
    }
    if (ok) {
      out.append(s.substr(i, n));
      i += n;
    } else {
      out += "\xEF\xBF\xBD";
      ++i;
    }
  }
  return out;
}

std::string errorMessage(const std::string& field, const std::string& message) {
  io::JsonText j;
  j << "{\"type\":\"error\",\"field\":" << validUtf8(field) << ",\"message\":" << validUtf8(message) << "}";
  return j.str();
}

// Numbers in the messages are the shortest text that reads back to the same double, in
// JavaScript too (the page shows the bits): io::JsonText's default.
io::JsonText pair(const Vec2& v) {
  io::JsonText j;
  j << "[" << v.x() << "," << v.y() << "]";
  return j;
}

// Nesting deeper than any message needs is refused before parsing (bounded work on garbage).
bool nestedDeeperThan(std::string_view text, int limit) {
  int depth = 0;
  bool inString = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (c == '\\') ++i;
      else if (c == '"') inString = false;
    } else if (c == '"') inString = true;
    else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if (c == ']' || c == '}') --depth;
  }
  return false;
}

void onlyFields(const json& j, std::initializer_list<const char*> allowed) {
  for (const auto& item : j.items()) {
    const std::string& key = item.key();  // (clang before 16 cannot capture a structured binding)
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }))
      throw FieldError{key, "unknown field"};
  }
}

double number(const json& j, const char* key) {
  if (!j.contains(key)) throw FieldError{key, "missing"};
  const json& v = j.at(key);
  if (!v.is_number()) throw FieldError{key, "must be a number"};
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw FieldError{key, "must be finite"};
  return x;
}

long integer(const json& j, const char* key) {
  if (!j.contains(key)) throw FieldError{key, "missing"};
  const json& v = j.at(key);
  if (!v.is_number_integer()) throw FieldError{key, "must be an integer"};
  return v.get<long>();
}

// A field that is a key of the pool's settings table (the YAML's and stsim pool's), checked there
// in their words, then against this server's own bound: a shot's work grows with it.
double settingField(double v, const char* field, const char* key, double serverMax) {
  const Setting& s = *findSetting(key);
  try {
    io::checkSetting(s, v);
  } catch (const SettingError& e) {
    throw FieldError{field, e.problem()};
  }
  if (v > serverMax)
    throw FieldError{field, "must be at most " + io::number(serverMax) + (*s.unit ? std::string(" ") + s.unit : "") + " on this server"};
  return v;
}

Vec2 vec2(const json& j, const char* key) {
  if (!j.contains(key)) throw FieldError{key, "missing"};
  const json& v = j.at(key);
  if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    throw FieldError{key, "must be a pair of numbers [x, y]"};
  const Vec2 p(v[0].get<double>(), v[1].get<double>());
  if (!p.allFinite()) throw FieldError{key, "must be finite"};
  return p;
}

// A shot's velocity as the scenario reader derives it: speed and angle, a cue vector, or given.
Vec2 shotVelocity(const json& j) {
  const int ways = (j.contains("angle") || j.contains("speed") ? 1 : 0) + (j.contains("cue") ? 1 : 0) +
                   (j.contains("velocity") ? 1 : 0);
  if (ways != 1) throw FieldError{"speed", "give one of angle and speed, cue, or velocity"};
  Vec2 v = Vec2::Zero();
  if (j.contains("cue")) {
    const json& c = j["cue"];
    if (!c.is_object()) throw FieldError{"cue", "must be an object {from, to, scale}"};
    try {
      onlyFields(c, {"from", "to", "scale"});
      const double scale = c.contains("scale") ? number(c, "scale") : 1.0;
      if (!(scale > 0.0)) throw FieldError{"scale", "must be positive"};
      v = scale * (vec2(c, "to") - vec2(c, "from"));
    } catch (const FieldError& e) {
      throw FieldError{"cue." + e.field, e.message};
    }
  } else if (j.contains("velocity")) {
    v = vec2(j, "velocity");
  } else {
    const double speed = number(j, "speed");
    const double rad = number(j, "angle") * std::numbers::pi / 180.0;
    v = speed * Vec2(std::cos(rad), std::sin(rad));
  }
  if (!v.allFinite()) throw FieldError{"speed", "must be finite"};
  if (!(v.norm() > 0.0)) throw FieldError{"speed", "must be positive"};
  if (v.norm() > kMaxSpeed) throw FieldError{"speed", "must be at most " + std::to_string(static_cast<int>(kMaxSpeed)) + " m/s"};
  return v;
}

// The game's counts as a shot began: the shot_end message reports what the shot added.
struct ShotStart {
  std::uint64_t checks, obstacleChecks;
  std::size_t pocketed;
};

// The shot_end message: how the shot ended, its work and energy, the balls it pocketed.
std::string shotEndMessage(const Game& game, int index, const ShotSummary& summary, const ShotStart& at) {
  const SimulatorCounters& c = game.simulator().counters();
  io::JsonText end;
  end << "{\"type\":\"shot_end\",\"index\":" << index << ",\"ending\":" << toString(summary.ending)
      << ",\"end\":" << summary.end << ",\"events\":" << summary.events << ",\"checks\":" << c.pairChecks - at.checks
      << ",\"obstacle_checks\":" << c.staticChecks - at.obstacleChecks << ",\"ke_start\":" << summary.keStart
      << ",\"ke_end\":" << summary.keEnd << ",\"ke_pocketed\":" << summary.kePocketed
      << ",\"energy_drift\":" << summary.energyDrift() << ",\"pocketed\":[";
  for (std::size_t k = at.pocketed; k < game.pocketed().size(); ++k) {
    const Pocketing& p = game.pocketed()[k];
    if (k > at.pocketed) end << ",";
    end << "{\"number\":" << p.number << ",\"pocket\":" << p.pocket << ",\"t\":" << p.t << "}";
  }
  end << "]}";
  return end.str();
}

// each leaf as [x0,y0,x1,y1]
io::JsonText regionsJson(const Simulator<2>& sim) {
  io::JsonText out;
  out << "[";
  // (none, the brute force, has no regions to draw)
  if (const Space<2>* sp = sim.space(); sp->kind() != SpaceKind::None) {
    bool first = true;
    for (int leaf : sp->leaves()) {
      const Rect b = sp->leafBounds(leaf);
      if (!first) out << ",";
      first = false;
      out << "[" << b.min.x() << "," << b.min.y() << "," << b.max.x() << "," << b.max.y() << "]";
    }
  }
  out << "]";
  return out;
}

// Subdivisions plus reunions: changes when the regions change.
std::uint64_t regionChanges(const Simulator<2>& sim) {
  const Space<2>* sp = sim.space();
  return sp->counters().subdivisions + sp->counters().reunions;
}

int version(SpaceKind k) { return k == SpaceKind::Tree ? 2 : 1; }

}  // namespace

// The message handlers, on the JSON library (kept out of the public header).
struct SessionMessages {
  static void shoot(PlaySession& s, const json& j, std::vector<std::string>& out);
  static void edit(PlaySession& s, const json& j, const std::string& type, std::vector<std::string>& out);
  static void checkPlace(const PlaySession& s, const Scenario& layout, int skip, const Vec2& p, double radius);
};

PlaySession::PlaySession(const Scenario& initial, SessionLimits limits) : initial_(initial), limits_(limits) {
  initial_.shots.clear();
  if (static_cast<int>(initial_.balls.size()) > limits_.maxBalls)
    throw ScenarioError(initial_.name + ": balls: " + std::to_string(initial_.balls.size()) +
                        " balls, more than a served game takes (" + std::to_string(limits_.maxBalls) + ")");
  initial_.until = std::min(initial_.until, limits_.maxUntil);
  rebuild(initial_);
}

PlaySession::~PlaySession() = default;

void PlaySession::rebuild(Scenario layout) {
  layout.shots.clear();
  auto game = std::make_unique<Game>(layout, simulatorConfig(layout));  // validates; throws before anything changes
  layout_ = std::move(layout);
  game_ = std::move(game);
}

Scenario PlaySession::restingLayout() const {
  if (layout_.shots.empty()) return layout_;
  Scenario next = layout_;
  next.shots.clear();
  next.balls.clear();
  const Simulator<2>& sim = game_->simulator();
  for (int i = 0; i < static_cast<int>(game_->specs().size()); ++i) {
    if (!sim.ball(i).active) continue;
    BallSpec b = game_->specs()[i];
    b.position = sim.ball(i).positionAt(sim.now());
    b.velocity = sim.ball(i).velocityAt(sim.now());
    next.balls.push_back(b);
  }
  return next;
}

std::vector<std::string> PlaySession::handle(std::string_view message) {
  std::vector<std::string> out;
  try {
    if (nestedDeeperThan(message, 8)) throw FieldError{"(message)", "nested deeper than 8 levels"};
    json j;
    std::string lastKey;  // the key being read: a number JSON cannot hold (1e999) is its field's error
    try {
      j = json::parse(message, [&](int, json::parse_event_t event, json& parsed) {
        if (event == json::parse_event_t::key && parsed.is_string()) lastKey = parsed.get<std::string>();
        return true;
      });
    } catch (const json::parse_error& e) {
      std::string what = e.what();
      if (const auto p = what.find("] "); p != std::string::npos) what.erase(0, p + 2);
      throw FieldError{"(message)", "malformed JSON: " + what};
    } catch (const json::out_of_range& e) {
      if (e.id == 406) throw FieldError{lastKey.empty() ? "(message)" : lastKey, "must be finite"};
      throw FieldError{"(message)", e.what()};
    }
    if (!j.is_object()) throw FieldError{"(message)", "must be a JSON object"};
    if (!j.contains("type") || !j["type"].is_string()) throw FieldError{"type", "missing (a string)"};
    const std::string type = j["type"].get<std::string>();
    if (type == "state") {
      onlyFields(j, {"type"});
      out.push_back(stateMessage());
    } else if (type == "download") {
      onlyFields(j, {"type"});
      out.push_back("{\"type\":\"download\",\"name\":\"pool-game.yaml\",\"yaml\":" + io::jsonString(downloadYaml()) + "}");
    } else if (type == "shoot") {
      SessionMessages::shoot(*this, j, out);
    } else if (type == "move" || type == "add" || type == "remove" || type == "restart" || type == "settings") {
      SessionMessages::edit(*this, j, type, out);
    } else {
      throw FieldError{"type", "unknown message type '" + type + "' (shoot, move, add, remove, restart, settings, state, download)"};
    }
  } catch (const FieldError& e) {
    out.push_back(errorMessage(e.field, e.message));
  } catch (const json::exception& e) {
    // a shape the checks did not foresee
    out.push_back(errorMessage("(message)", e.what()));
  }
  return out;
}

std::optional<std::string> PlaySession::nextPart() {
  if (parts_.empty()) return std::nullopt;
  std::string p = std::move(parts_.front());
  parts_.pop_front();
  return p;
}

void SessionMessages::shoot(PlaySession& s, const json& j, std::vector<std::string>& out) {
  onlyFields(j, {"type", "ball", "angle", "speed", "cue", "velocity", "until"});
  if (s.streaming()) throw FieldError{"type", "a shot is still playing (wait for its shot_end)"};
  if (s.shotsTaken_ >= s.limits_.maxShots)
    throw FieldError{"type", "this game has taken its " + std::to_string(s.limits_.maxShots) + " shots"};
  const int cueBall = j.contains("ball") ? static_cast<int>(std::clamp(integer(j, "ball"), -1L, 1L << 30)) : 0;
  const int h = s.game_->handleOf(cueBall);
  if (h < 0) throw FieldError{"ball", "no ball number " + std::to_string(cueBall)};
  if (!s.game_->simulator().ball(h).active) throw FieldError{"ball", "ball " + std::to_string(cueBall) + " was pocketed"};
  Shot shot{cueBall, shotVelocity(j), -1.0};
  const Vec2 v = shot.velocity;
  if (j.contains("until")) {
    shot.until = settingField(number(j, "until"), "until", "until", s.limits_.maxUntil);
  }
  const double limit = shot.until > 0.0 ? shot.until : s.layout_.until;

  // play it now (the served break: about 4 ms; bench/pool_serve), in parts of bounded size
  const Simulator<2>& sim = s.game_->simulator();
  const int index = s.shotsTaken_;
  const std::uint64_t checks0 = sim.counters().pairChecks, obstacle0 = sim.counters().staticChecks;
  const std::size_t pocketed0 = s.game_->pocketed().size();
  std::uint64_t regions = regionChanges(sim);
  std::deque<std::string> parts;
  io::JsonText head;
  head << "{\"type\":\"shot\",\"index\":" << index << ",\"ball\":" << cueBall << ",\"velocity\":" << pair(v)
       << ",\"start\":" << sim.now() << ",\"until\":" << limit << "}";
  parts.push_back(head.str());
  io::JsonText part;
  std::size_t count = 0;
  auto close = [&] {
    if (part.empty()) return;
    io::JsonText events;
    events << "{\"type\":\"events\",\"index\":" << index << ",\"events\":[" << part << "]}";
    parts.push_back(events.str());
    part = io::JsonText();
  };
  ShotSummary summary;
  try {
    summary = s.game_->play(shot, limit, [&](const PoolEvent& e) {
      if (++count > s.limits_.maxShotEvents)
        throw std::runtime_error("the shot needs more than " + std::to_string(s.limits_.maxShotEvents) +
                                 " events (lower until or raise friction)");
      if (!part.empty()) part << ",";
      part << "{\"t\":" << e.t << ",\"k\":" << toString(e.kind) << ",\"b\":" << e.ball << ",\"o\":" << e.other
           << ",\"p\":" << pair(e.p) << ",\"v\":" << pair(e.v);
      if (e.kind == PoolEventKind::Ball) part << ",\"op\":" << pair(e.otherP) << ",\"ov\":" << pair(e.otherV);
      part << ",\"c\":" << sim.counters().pairChecks - checks0;
      // version II: the regions after every event that subdivided or reunited them
      if (const std::uint64_t r = regionChanges(sim); r != regions) {
        regions = r;
        part << ",\"r\":" << regionsJson(sim);
      }
      part << "}";
      if (part.str().size() > s.limits_.partBytes) close();
    });
  } catch (const std::runtime_error& e) {
    // undo: the game as it was before the shot (replayed: the same bits)
    Scenario layout = s.layout_;
    const std::vector<Shot> shots = layout.shots;
    s.rebuild(layout);
    for (const Shot& k : shots) s.game_->play(k, k.until > 0.0 ? k.until : s.layout_.until);
    s.layout_.shots = shots;
    throw FieldError{"until", std::string(e.what()) + "; the shot was undone"};
  }
  close();
  s.layout_.shots.push_back(shot);
  ++s.shotsTaken_;
  parts.push_back(shotEndMessage(*s.game_, index, summary, {checks0, obstacle0, pocketed0}));
  parts.push_back(s.stateMessage());
  s.parts_ = std::move(parts);
  (void)out;  // the parts go out through nextPart, paced by the socket
}

void SessionMessages::checkPlace(const PlaySession& s, const Scenario& layout, int skip, const Vec2& p, double radius) {
  if (const char* why = placementProblem(s.game_->table(), p, radius); *why) throw FieldError{"position", why};
  for (int i = 0; i < static_cast<int>(layout.balls.size()); ++i) {
    if (i == skip) continue;
    const BallSpec& b = layout.balls[i];
    if ((b.position - p).norm() < b.radius + radius - tol::kLinearSlop)
      throw FieldError{"position", "overlaps ball " + std::to_string(b.number)};
  }
}

void SessionMessages::edit(PlaySession& s, const json& j, const std::string& type, std::vector<std::string>& out) {
  if (s.streaming()) throw FieldError{"type", "a shot is still playing (wait for its shot_end)"};
  // an edit after shots starts a new layout from where the balls rest (the download holds it)
  Scenario next = s.restingLayout();
  auto find = [&](const char* key) {
    const long number = integer(j, key);
    for (int i = 0; i < static_cast<int>(next.balls.size()); ++i)
      if (next.balls[i].number == number) return i;
    throw FieldError{key, "no ball number " + std::to_string(number) + " on the table"};
  };
  if (type == "move") {
    onlyFields(j, {"type", "ball", "position"});
    const int i = find("ball");
    const Vec2 p = vec2(j, "position");
    checkPlace(s, next, i, p, next.balls[i].radius);
    next.balls[i].position = p;
    next.balls[i].velocity = Vec2::Zero();
  } else if (type == "add") {
    onlyFields(j, {"type", "position", "number"});
    if (static_cast<int>(next.balls.size()) >= s.limits_.maxBalls)
      throw FieldError{"type", "the table holds at most " + std::to_string(s.limits_.maxBalls) + " balls"};
    std::set<int> used;
    for (const BallSpec& b : next.balls) used.insert(b.number);
    int number = 1;
    if (j.contains("number")) {
      const long n = integer(j, "number");
      if (n < 0 || n > 1000000) throw FieldError{"number", "must be between 0 and 1000000"};
      number = static_cast<int>(n);
      if (used.count(number)) throw FieldError{"number", "ball " + std::to_string(number) + " is on the table"};
    } else {
      while (used.count(number)) ++number;
    }
    const Vec2 p = vec2(j, "position");
    checkPlace(s, next, -1, p, kBallRadius);
    next.balls.push_back(makeBall(number, p));
  } else if (type == "remove") {
    onlyFields(j, {"type", "ball"});
    const int i = find("ball");
    if (next.balls.size() == 1) throw FieldError{"ball", "the last ball stays on the table"};
    next.balls.erase(next.balls.begin() + i);
  } else if (type == "restart") {
    onlyFields(j, {"type"});
    Scenario again = s.initial_;
    again.space = next.space;
    again.friction = next.friction;
    again.until = next.until;
    next = again;
  } else {  // settings
    onlyFields(j, {"type", "version", "df", "friction", "until"});
    if (j.contains("version")) {
      const long v = integer(j, "version");
      if (v != 1 && v != 2) throw FieldError{"version", "must be 1 (one space) or 2 (the quadtree)"};
      next.space.kind = v == 1 ? SpaceKind::Single : SpaceKind::Tree;
    }
    if (j.contains("df")) {
      const double df = static_cast<double>(integer(j, "df"));
      next.space.decompositionFactor =
          static_cast<int>(settingField(df, "df", "space.decomposition_factor", s.limits_.maxDecompositionFactor));
    }
    if (j.contains("friction")) {
      next.friction = settingField(number(j, "friction"), "friction", "friction", s.limits_.maxFriction);
    }
    if (j.contains("until")) {
      next.until = settingField(number(j, "until"), "until", "until", s.limits_.maxUntil);
    }
  }
  try {
    s.rebuild(next);
  } catch (const std::exception& e) {
    throw FieldError{"(layout)", e.what()};
  }
  out.push_back(s.stateMessage());
}

std::string PlaySession::stateMessage() const {
  const Table& t = game_->table();
  const Simulator<2>& sim = game_->simulator();
  io::JsonText os;
  os << "{\"type\":\"state\",\"table\":{\"width\":" << t.spec.width << ",\"height\":" << t.spec.height
     << ",\"bounds\":[" << t.bounds().min.x() << "," << t.bounds().min.y() << "," << t.bounds().max.x() << ","
     << t.bounds().max.y() << "],\"cushions\":[";
  for (std::size_t i = 0; i < t.cushions.size(); ++i) {
    if (i) os << ",";
    os << "[" << t.cushions[i].a.x() << "," << t.cushions[i].a.y() << "," << t.cushions[i].b.x() << ","
       << t.cushions[i].b.y() << "]";
  }
  os << "],\"pockets\":[";
  for (std::size_t i = 0; i < t.pockets.size(); ++i) {
    if (i) os << ",";
    os << "[" << t.pockets[i].center.x() << "," << t.pockets[i].center.y() << "," << t.pockets[i].radius << "]";
  }
  os << "]},\"t\":" << sim.now() << ",\"balls\":[";
  bool first = true;
  for (int i = 0; i < static_cast<int>(game_->specs().size()); ++i) {
    const BallSpec& b = game_->specs()[i];
    const BallState<2>& ball = sim.ball(i);
    if (!ball.active) continue;
    if (!first) os << ",";
    os << "{\"h\":" << i << ",\"n\":" << b.number << ",\"p\":" << pair(ball.positionAt(sim.now()))
       << ",\"v\":" << pair(ball.velocityAt(sim.now())) << ",\"r\":" << b.radius << ",\"m\":" << b.mass
       << ",\"colour\":" << hexOf(b.colour) << ",\"striped\":" << io::jsonBool(b.pattern == Pattern::Striped) << "}";
    first = false;
  }
  os << "],\"regions\":" << regionsJson(sim) << ",\"settings\":{\"version\":" << version(layout_.space.kind)
     << ",\"space\":" << toString(layout_.space.kind) << ",\"df\":" << layout_.space.decompositionFactor
     << ",\"friction\":" << layout_.friction << ",\"until\":" << layout_.until << "},\"shots\":" << shotsTaken_
     << ",\"layout_shots\":" << layout_.shots.size() << ",\"pocketed\":[";
  for (std::size_t k = 0; k < game_->pocketed().size(); ++k) {
    if (k) os << ",";
    os << game_->pocketed()[k].number;
  }
  os << "],\"limits\":{\"balls\":" << limits_.maxBalls << ",\"shots\":" << limits_.maxShots << "}}";
  return os.str();
}

std::string PlaySession::downloadYaml() const {
  std::ostringstream os;
  os << "# A game played with stsim pool serve: the layout since its last edit and the shots taken since.\n"
        "# `stsim pool THIS.yaml --out DIR` replays it to the same events.\n";
  writeScenarioYaml(os, layout_);
  return os.str();
}

}  // namespace st::pool
