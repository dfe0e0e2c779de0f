#include <sthighway/settings.hpp>

#include <algorithm>
#include <vector>

#include <sthighway/detector.hpp>
#include <stio/format.hpp>

namespace st::highway {

namespace {

double number(const SettingValue& v) { return std::get<double>(v); }
const std::string& text(const SettingValue& v) { return std::get<std::string>(v); }

// A row of the table as it is written below: a key of io's core (the range inclusive at both ends,
// every value outside it worded "must be in [min, max]") with what it sets.
struct Row {
  const char* key;
  SettingType type;
  const char* unit;     // "s", "m", "m/s^2", "N", "deg", "dB", "dBm", or "" (none)
  double min;           // Number, Integer: the range, inclusive
  double max;
  const char* choices;  // Choice: the words, "concentric|five|box"
  const char* doc;
  void (*set)(MonitorConfig&, const SettingValue&);
  SettingValue (*get)(const MonitorConfig&);

  operator Setting() const {
    return Setting{{key, type, unit, min, max, false, choices, "", doc, true}, set, get};
  }
};

template <int C>
void setBrakeForce(MonitorConfig& c, const SettingValue& v) {
  c.safeTime.brakeForce[C] = number(v);
}
template <int C>
SettingValue getBrakeForce(const MonitorConfig& c) {
  return c.safeTime.brakeForce[C];
}

// the class names in VehicleClass order, for the keys safe_time.brake_force.<class>
template <int C>
Row brakeForce(const char* key) {
  return {key, SettingType::Number, "N", 1.0, 1e8, "",
          "braking force of the class (safe time: t_r + m v / (2 F))", setBrakeForce<C>, getBrakeForce<C>};
}

const char* motionWord(MotionModel m) { return m == MotionModel::ConstantAcceleration ? "acceleration" : "velocity"; }
// the word of a layout: "b" for Fig. 11(b), else "a"
const char* layoutWord(const FiveCircleLayout& l) {
  const FiveCircleLayout b = FiveCircleLayout::fig11b();
  for (int z = 0; z < 5; ++z) {
    const ZoneCircle &p = l.zones[z], &q = b.zones[z];
    if (p.x != q.x || p.y != q.y || p.rx != q.rx || p.ry != q.ry || p.margin != q.margin) return "a";
  }
  return "b";
}

std::vector<Setting> makeTable() {
  static_assert(kVehicleClassCount == 8, "one safe_time.brake_force key per VehicleClass");
  using T = SettingType;
  const std::vector<Row> rows = {
      {"detector", T::Choice, "", 0, 0, "concentric|five|box",
       "the collision detector: the report's concentric circles, its five circles (Fig. 11), or the exact box",
       [](MonitorConfig& c, const SettingValue& v) { parseDetectorKind(text(v), c.detector.kind); },
       [](const MonitorConfig& c) { return SettingValue(std::string(toString(c.detector.kind))); }},
      {"layout", T::Choice, "", 0, 0, "a|b", "five-circle zone layout: Fig. 11(a) small or 11(b) large overlaps",
       [](MonitorConfig& c, const SettingValue& v) { parseFiveCircleLayout(text(v), c.detector.five); },
       [](const MonitorConfig& c) { return SettingValue(std::string(layoutWord(c.detector.five))); }},
      {"motion", T::Choice, "", 0, 0, "velocity|acceleration",
       "the detectors' motion: constant velocity, or constant acceleration",
       [](MonitorConfig& c, const SettingValue& v) { parseMotionModel(text(v), c.detector.motion); },
       [](const MonitorConfig& c) { return SettingValue(std::string(motionWord(c.detector.motion))); }},
      {"prediction", T::Choice, "", 0, 0, "road|straight",
       "paths along the lanes (lane-frame road checks), or straight lines",
       [](MonitorConfig& c, const SettingValue& v) { parsePrediction(text(v), c.prediction); },
       [](const MonitorConfig& c) { return SettingValue(std::string(toString(c.prediction))); }},
      {"priority_rules", T::Boolean, "", 0, 0, "",
       "a car gives way where its link is minor (a light's g, a junction's m or =: at its line, or a left turn's "
       "wait point) while it can stop there; false: predicted on at its speed, as SSM and SSAM extrapolate",
       [](MonitorConfig& c, const SettingValue& v) { c.priorityRules = std::get<bool>(v); },
       [](const MonitorConfig& c) { return SettingValue(c.priorityRules); }},
      {"broadphase", T::Choice, "", 0, 0, "cells|all-pairs", "neighbour search: the cell hierarchy, or every pair",
       [](MonitorConfig& c, const SettingValue& v) { parseBroadphase(text(v), c.broadphase); },
       [](const MonitorConfig& c) { return SettingValue(std::string(toString(c.broadphase))); }},
      {"check_road", T::Boolean, "", 0, 0, "", "warn of curbs, lane markers and hazards too",
       [](MonitorConfig& c, const SettingValue& v) { c.checkRoad = std::get<bool>(v); },
       [](const MonitorConfig& c) { return SettingValue(c.checkRoad); }},
      {"body_circles", T::Integer, "", 0, 1000, "",
       "circles covering a foe's body in the five-circle model; 0: ceil(length / width)",
       [](MonitorConfig& c, const SettingValue& v) { c.detector.bodyCircles = static_cast<int>(number(v)); },
       [](const MonitorConfig& c) { return SettingValue(static_cast<double>(c.detector.bodyCircles)); }},
      {"safe_time.vehicle_reaction", T::Number, "s", 0, 60, "", "reaction time before braking for another vehicle",
       [](MonitorConfig& c, const SettingValue& v) { c.safeTime.vehicleReactionTime = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.safeTime.vehicleReactionTime); }},
      {"safe_time.road_reaction", T::Number, "s", 0, 60, "", "reaction time for a curb, lane marker or hazard",
       [](MonitorConfig& c, const SettingValue& v) { c.safeTime.roadReactionTime = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.safeTime.roadReactionTime); }},
      brakeForce<0>("safe_time.brake_force.passenger"),
      brakeForce<1>("safe_time.brake_force.truck"),
      brakeForce<2>("safe_time.brake_force.bus"),
      brakeForce<3>("safe_time.brake_force.motorcycle"),
      brakeForce<4>("safe_time.brake_force.emergency"),
      brakeForce<5>("safe_time.brake_force.other"),
      brakeForce<6>("safe_time.brake_force.bicycle"),
      brakeForce<7>("safe_time.brake_force.pedestrian"),
      {"conflict.rear_end_below", T::Number, "deg", 0, 180, "",
       "a warning is typed rear-end below this heading angle (SSAM's 30)",
       [](MonitorConfig& c, const SettingValue& v) { c.conflict.rearEndBelowDeg = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.conflict.rearEndBelowDeg); }},
      {"conflict.crossing_above", T::Number, "deg", 0, 180, "",
       "crossing above this angle, lane change between (SSAM's 85)",
       [](MonitorConfig& c, const SettingValue& v) { c.conflict.crossingAboveDeg = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.conflict.crossingAboveDeg); }},
      {"conflict.max_ttc", T::Number, "s", 0.01, 60, "",
       "TTC*: a conflict (conflicts.csv) is an encounter whose TTC falls to this (SSAM's 1.5); TET and TIT of conflicts against it",
       [](MonitorConfig& c, const SettingValue& v) { c.conflict.maxTtc = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.conflict.maxTtc); }},
      {"conflict.max_pet", T::Number, "s", 0, 60, "",
       "PET*: a conflict whose PET is measured counts only at or below this (SSAM's 5)",
       [](MonitorConfig& c, const SettingValue& v) { c.conflict.maxPet = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.conflict.maxPet); }},
      {"concentric.inner_margin", T::Number, "m", 0, 100, "", "inner circle radius: half the width plus this",
       [](MonitorConfig& c, const SettingValue& v) { c.detector.concentric.innerMargin = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.detector.concentric.innerMargin); }},
      {"concentric.outer_margin", T::Number, "m", 0, 100, "", "outer circle radius: half the diagonal plus this",
       [](MonitorConfig& c, const SettingValue& v) { c.detector.concentric.outerMargin = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.detector.concentric.outerMargin); }},
      {"cells.length", T::Number, "m", 1, 1e6, "", "distance between cell sites along a road section",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.cellLength = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.cellLength); }},
      {"cells.hysteresis_db", T::Number, "dB", 0, 100, "", "a new site must be this much stronger to take a car",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.hysteresisDb = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.hysteresisDb); }},
      {"cells.tx_power_dbm", T::Number, "dBm", -100, 100, "", "a site's transmit power",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.txPowerDbm = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.txPowerDbm); }},
      {"cells.path_loss_exponent", T::Number, "", 1, 10, "", "log-distance path loss exponent (2 free space)",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.pathLossExponent = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.pathLossExponent); }},
      {"cells.reference_distance", T::Number, "m", 0.01, 1000, "", "path loss is 0 dB at this distance",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.referenceDistance = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.referenceDistance); }},
      {"cells.radio_range", T::Number, "m", 1, 1e6, "", "sites farther than this are not heard",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.radioRange = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.radioRange); }},
      {"cells.fat_margin", T::Number, "m", 0, 1000, "", "a car's box in its cell's space is grown by this",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.fatMargin = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.fatMargin); }},
      {"cells.fat_lookahead", T::Number, "s", 0, 60, "", "and stretched to where its velocity takes it in this",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.fatLookahead = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.cells.fatLookahead); }},
      {"cells.decomposition_factor", T::Integer, "", 1, 1e6, "", "a cell's space subdivides past this many cars",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.decompositionFactor = static_cast<int>(number(v)); },
       [](const MonitorConfig& c) { return SettingValue(static_cast<double>(c.cells.decompositionFactor)); }},
      {"cells.max_depth", T::Integer, "", 0, 32, "", "deepest subdivision of a cell's space",
       [](MonitorConfig& c, const SettingValue& v) { c.cells.maxDepth = static_cast<int>(number(v)); },
       [](const MonitorConfig& c) { return SettingValue(static_cast<double>(c.cells.maxDepth)); }},
      {"hindsight.enabled", T::Boolean, "", 0, 0, "", "judge every warning from what happened after it",
       [](MonitorConfig& c, const SettingValue& v) { c.hindsight.enabled = std::get<bool>(v); },
       [](const MonitorConfig& c) { return SettingValue(c.hindsight.enabled); }},
      {"hindsight.clearance", T::Number, "m", 0, 100, "", "a realized clearance below this confirms a vehicle warning",
       [](MonitorConfig& c, const SettingValue& v) { c.hindsight.clearance = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.hindsight.clearance); }},
      {"hindsight.evasive_deceleration", T::Number, "m/s^2", 0.1, 100, "", "a vehicle of unknown decel braking harder than this confirms it too (else: beyond its own vType decel)",
       [](MonitorConfig& c, const SettingValue& v) { c.hindsight.evasiveDeceleration = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.hindsight.evasiveDeceleration); }},
      {"hindsight.lead", T::Number, "s", 0, 60, "", "a near miss counts as warned if an episode was open this long before",
       [](MonitorConfig& c, const SettingValue& v) { c.hindsight.lead = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.hindsight.lead); }},
      {"hindsight.near_miss_ttc", T::Number, "s", 0, 60, "", "a near miss is on a collision course: its box TTC at most this",
       [](MonitorConfig& c, const SettingValue& v) { c.hindsight.nearMissTtc = number(v); },
       [](const MonitorConfig& c) { return SettingValue(c.hindsight.nearMissTtc); }},
  };
  const std::vector<Setting> t(rows.begin(), rows.end());
  const auto first = std::find_if(t.begin(), t.end(), [](const Setting& s) { return std::string(s.key) == "safe_time.brake_force.passenger"; });
  for (int c = 0; c < kVehicleClassCount; ++c)
    if (first + c >= t.end() || std::string((first + c)->key) != std::string("safe_time.brake_force.") + toString(static_cast<VehicleClass>(c)))
      throw std::logic_error("settings: brake_force keys out of VehicleClass order");
  return t;
}

}  // namespace

std::span<const Setting> monitorSettings() {
  static const std::vector<Setting> table = makeTable();
  return table;
}

std::string flatName(std::string_view key) {
  std::string out(key);
  for (char& c : out)
    if (c == '.') c = '_';
  return out;
}

const Setting* findSetting(std::string_view key) {
  for (const Setting& s : monitorSettings())
    if (key == s.key || key == flatName(s.key)) return &s;
  return nullptr;
}

void applySetting(MonitorConfig& cfg, const Setting& s, const SettingValue& v) { io::applySetting(cfg, s, v); }

void applySettingText(MonitorConfig& cfg, const Setting& s, std::string_view text) {
  s.set(cfg, io::settingValue(s, text));
}

void checkSettings(const MonitorConfig& cfg) {
  // each value in its range (a caller may have built cfg without the table)
  MonitorConfig copy = cfg;
  for (const Setting& s : monitorSettings()) applySetting(copy, s, s.get(cfg));
  const ConflictConfig& cc = cfg.conflict;
  if (!(cc.rearEndBelowDeg <= cc.crossingAboveDeg))
    throw SettingError("conflict.crossing_above", "must be at least conflict.rear_end_below");
  if (cfg.detector.kind == DetectorKind::FiveCircle) {
    // the zones must cover the car or the five-circle TTC is not a conservative envelope
    for (double aspect : {1.0, 2.0, 2.78, 4.7, 8.0})
      if (!layoutCoversBody(cfg.detector.five, aspect, 1.0))
        throw SettingError("layout", "does not cover the car with its front, rear, left and right zones");
  }
}

std::string settingsReferenceMarkdown(const MonitorConfig& values, const char* column) {
  std::string out = io::referenceHeading(column);
  for (const Setting& s : monitorSettings()) out += io::referenceRow(s, s.get(values), s.doc);
  return out;
}

}  // namespace st::highway
