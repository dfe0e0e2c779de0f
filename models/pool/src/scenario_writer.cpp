#include <stpool/scenario_writer.hpp>

#include <ostream>

#include <stio/format.hpp>
#include <stio/settings_table.hpp>
#include <stpool/settings.hpp>

namespace st::pool {

namespace {

// Shortest text that reads back to the same double: the replay starts from the same bits.
std::string num(double x) { return io::number(x); }
// appended piece by piece: GCC 12 flags `"[" + std::string&&` with a false -Wrestrict (PR 105329)
std::string pair(const Vec2& v) {
  std::string s = "[";
  s += num(v.x());
  s += ", ";
  s += num(v.y());
  s += ']';
  return s;
}

// The settings of one section ("table", "space"; "" for the top level's) as the reader takes them,
// from the settings table: a space key of another kind is left out (the reader refuses it).
void writeSettings(std::ostream& os, const Scenario& s, const std::string& section) {
  if (!section.empty()) os << section << ":\n";
  for (const Setting& setting : poolSettings()) {
    if (io::keySection(setting.key) != section || !keyForKind(s, setting.key)) continue;
    os << (section.empty() ? "" : "  ") << io::keyName(setting.key) << ": " << io::exactSettingText(setting.get(s)) << "\n";
  }
}

}  // namespace

void writeScenarioYaml(std::ostream& os, const Scenario& s) {
  // a JSON string literal is a YAML double-quoted scalar with the same escapes
  os << "name: " << io::jsonString(s.name) << "\n";
  writeSettings(os, s, "");
  writeSettings(os, s, "table");
  // every ball listed as it stands (a rack or random layout is written out, not regenerated)
  os << "balls:\n";
  for (const BallSpec& b : s.balls) {
    os << "  - {number: " << b.number << ", position: " << pair(b.position);
    if (b.velocity != Vec2::Zero()) os << ", velocity: " << pair(b.velocity);
    os << ", radius: " << num(b.radius) << ", mass: " << num(b.mass) << ", colour: " << toString(b.colour)
       << ", pattern: " << toString(b.pattern) << "}\n";
  }
  writeSettings(os, s, "space");
  if (s.shots.empty()) return;
  // the velocity the Game was given, not the angle and speed it came from: cos/sin are not redone
  os << "shots:\n";
  for (const Shot& shot : s.shots) {
    os << "  - {ball: " << shot.ball << ", velocity: " << pair(shot.velocity);
    if (shot.until > 0.0) os << ", until: " << num(shot.until);
    os << "}\n";
  }
}

}  // namespace st::pool
