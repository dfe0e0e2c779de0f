#include <stpool/scenario_writer.hpp>

#include <ostream>

#include <stio/format.hpp>

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

}  // namespace

void writeScenarioYaml(std::ostream& os, const Scenario& s) {
  // a JSON string literal is a YAML double-quoted scalar with the same escapes
  os << "name: " << io::jsonString(s.name) << "\n";
  os << "seed: " << s.seed << "\n";
  os << "table:\n";
  os << "  width: " << num(s.table.width) << "\n";
  os << "  height: " << num(s.table.height) << "\n";
  os << "  pockets: " << (s.table.pockets ? "true" : "false") << "\n";
  os << "  corner_mouth: " << num(s.table.cornerMouth) << "\n";
  os << "  side_mouth: " << num(s.table.sideMouth) << "\n";
  // every ball listed as it stands (a rack or random layout is written out, not regenerated)
  os << "balls:\n";
  for (const BallSpec& b : s.balls) {
    os << "  - {number: " << b.number << ", position: " << pair(b.position);
    if (b.velocity != Vec2::Zero()) os << ", velocity: " << pair(b.velocity);
    os << ", radius: " << num(b.radius) << ", mass: " << num(b.mass) << ", colour: " << toString(b.colour)
       << ", pattern: " << toString(b.pattern) << "}\n";
  }
  os << "space:\n";
  os << "  kind: " << (s.space.kind == SpaceKind::Tree ? "quadtree" : toString(s.space.kind)) << "\n";
  // only the keys of its kind (the reader refuses the others)
  if (s.space.kind == SpaceKind::Tree) {
    if (s.space.autoFactor) os << "  decomposition_factor: auto\n";
    else os << "  decomposition_factor: " << s.space.decompositionFactor << "\n";
    os << "  divisions: " << s.space.divisions << "\n";
    os << "  max_depth: " << s.space.maxDepth << "\n";
  } else if (s.space.kind == SpaceKind::Cells) {
    os << "  cell_size: " << num(s.space.cellSize) << "\n";
    if (s.space.margin > 0.0) os << "  margin: " << num(s.space.margin) << "\n";
  }
  os << "until: " << num(s.until) << "\n";
  os << "friction: " << num(s.friction) << "\n";
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
