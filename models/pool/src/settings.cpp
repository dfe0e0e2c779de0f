#include <stpool/settings.hpp>

#include <vector>

#include <stpool/scenario.hpp>

namespace st::pool {

namespace {

constexpr double kMaxTableSide = 100.0;  // m; a snooker table is 3.6
constexpr double kMaxFriction = 100.0;   // m/s^2; cloth's rolling resistance is about 0.1
constexpr double kMaxUntil = 1e12;       // s; the event limit ends a run long before
constexpr double kMaxSeed = 1e15;        // below 2^53: a seed read as a double is exact

double number(const SettingValue& v) { return std::get<double>(v); }
bool isWord(const SettingValue& v) { return std::holds_alternative<std::string>(v); }
const std::string& word(const SettingValue& v) { return std::get<std::string>(v); }

using T = SettingType;

// A number key of a struct field, with set/get.
#define ST_POOL_NUMBER(KEY, UNIT, MIN, MAX, ABOVE, WHY, DOC, FIELD)                                   \
  Setting {                                                                                           \
    {KEY, T::Number, UNIT, MIN, MAX, ABOVE, "", WHY, DOC}, [](Scenario& s, const SettingValue& v) { s.FIELD = number(v); }, \
        [](const Scenario& s) { return SettingValue(s.FIELD); }                                        \
  }

// A declarative table: one row per key
std::vector<Setting> makeTable() {
  return {
      ST_POOL_NUMBER("table.width", "m", 0.0, kMaxTableSide, true, "any table's (at most 100 m)",
                     "the playing surface along x, cushion to cushion (given in every scenario)", table.width),
      ST_POOL_NUMBER("table.height", "m", 0.0, kMaxTableSide, true, "any table's (at most 100 m)",
                     "the playing surface along y, cushion to cushion (given in every scenario)", table.height),
      {{"table.pockets", T::Boolean, "", 0, 0, false, "", "", "six pockets; false: a closed box"},
       [](Scenario& s, const SettingValue& v) { s.table.pockets = std::get<bool>(v); },
       [](const Scenario& s) { return SettingValue(s.table.pockets); }},
      ST_POOL_NUMBER("table.corner_mouth", "m", 0.0, kMaxTableSide, true, "",
                     "jaw-to-jaw opening of a corner pocket (WPA: 4.5-4.625 in)", table.cornerMouth),
      ST_POOL_NUMBER("table.side_mouth", "m", 0.0, kMaxTableSide, true, "",
                     "jaw-to-jaw opening of a side pocket (WPA: 5-5.125 in)", table.sideMouth),
      ST_POOL_NUMBER("until", "s", 0.0, kMaxUntil, true, "",
                     "time limit of each shot, unless the shot gives its own (stsim pool --until: of every shot)", until),
      ST_POOL_NUMBER("friction", "m/s^2", 0.0, kMaxFriction, false, "any cloth's rolling resistance (at most 100 m/s^2)",
                     "rolling-resistance deceleration; 0: the report's frictionless table", friction),
      {{"seed", T::Integer, "", 0.0, kMaxSeed, false, "", "", "seed of the random layout and of the rack's order"},
       [](Scenario& s, const SettingValue& v) { s.seed = static_cast<std::uint64_t>(number(v)); },
       [](const Scenario& s) { return SettingValue(static_cast<double>(s.seed)); }},
      {{"space.kind", T::Choice, "", 0, 0, false, "quadtree|cells|single|none", "",
        "the broadphase: the report's quadtree, uniform cells, one list, or none (the brute force: every pair)"},
       [](Scenario& s, const SettingValue& v) { parseSpaceKind(word(v), s.space.kind); },
       [](const Scenario& s) {
         return SettingValue(std::string(s.space.kind == SpaceKind::Tree ? "quadtree" : toString(s.space.kind)));
       }},
      {{"space.decomposition_factor", T::Integer, "", 1.0, 1e9, false, "auto", "",
        "quadtree: a region holding more balls than this divides; auto: the space picks it as it runs"},
       [](Scenario& s, const SettingValue& v) {
         s.space.autoFactor = isWord(v);
         if (!isWord(v)) s.space.decompositionFactor = static_cast<int>(number(v));
       },
       [](const Scenario& s) {
         return s.space.autoFactor ? SettingValue(std::string("auto"))
                                   : SettingValue(static_cast<double>(s.space.decompositionFactor));
       }},
      {{"space.divisions", T::Choice, "", 0, 0, false, "2|4", "", "quadtree: a region divides in halves (2) or quarters (4)"},
       [](Scenario& s, const SettingValue& v) { s.space.divisions = word(v) == "2" ? 2 : 4; },
       [](const Scenario& s) { return SettingValue(std::to_string(s.space.divisions)); }},
      {{"space.max_depth", T::Integer, "", -1.0, 30.0, false, "", "",
        "quadtree: deepest division; -1: the deepest whose regions are still one ball across"},
       [](Scenario& s, const SettingValue& v) { s.space.maxDepth = static_cast<int>(number(v)); },
       [](const Scenario& s) { return SettingValue(static_cast<double>(s.space.maxDepth)); }},
      ST_POOL_NUMBER("space.cell_size", "m", 0.0, kMaxTableSide, true, "", "cells: edge of a cell", space.cellSize),
      {{"space.margin", T::Number, "", 0.0, 100.0, true, "auto", "",
        "cells: fat-box margin, a fraction of each ball's radius (a ball is re-filed when it leaves its box grown by "
        "it); auto: 0.5"},
       [](Scenario& s, const SettingValue& v) { s.space.margin = isWord(v) ? -1.0 : number(v); },
       [](const Scenario& s) { return s.space.margin > 0.0 ? SettingValue(s.space.margin) : SettingValue(std::string("auto")); }},
  };
}

#undef ST_POOL_NUMBER

}  // namespace

std::span<const Setting> poolSettings() {
  static const std::vector<Setting> table = makeTable();
  return table;
}

const Setting* findSetting(std::string_view key) { return io::findSetting(poolSettings(), key); }

void applySettingText(Scenario& sc, const Setting& s, std::string_view text) { s.set(sc, io::settingValue(s, text)); }

void checkSettings(const Scenario& sc) {
  for (const Setting& s : poolSettings()) io::checkSetting(s, s.get(sc));
}

namespace {

bool treeKey(std::string_view key) {
  return key == "space.decomposition_factor" || key == "space.divisions" || key == "space.max_depth";
}
bool cellsKey(std::string_view key) { return key == "space.cell_size" || key == "space.margin"; }

}  // namespace

bool keyForKind(const Scenario& sc, std::string_view key) {
  if (treeKey(key)) return sc.space.kind == SpaceKind::Tree;
  if (cellsKey(key)) return sc.space.kind == SpaceKind::Cells;
  return true;
}

void checkKeyForKind(const Scenario& sc, std::string_view key) {
  if (keyForKind(sc, key)) return;
  const bool tree = treeKey(key);
  const SpaceKind kind = sc.space.kind;
  const char* kindName = kind == SpaceKind::Tree ? "quadtree" : toString(kind);
  throw SettingError(std::string(key), std::string("only for kind ") + (tree ? "quadtree" : "cells") + " (this space is " +
                                           kindName + ")");
}

std::string settingsReferenceMarkdown(const Scenario* values, const char* column) {
  const Scenario defaults;
  const Scenario& v = values ? *values : defaults;
  std::string out = io::referenceHeading(column);
  for (const Setting& s : poolSettings()) out += io::referenceRow(s, s.get(v), s.doc);
  return out;
}

}  // namespace st::pool
