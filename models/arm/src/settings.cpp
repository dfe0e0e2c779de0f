#include <starm/settings.hpp>

#include <algorithm>
#include <limits>

#include <starm/scenario.hpp>
#include <stio/format.hpp>

namespace st::arm {

namespace {

// the bound of a look-ahead term (s): the work of a cycle grows with the look-ahead
constexpr double kMaxLookAhead = 60.0;
constexpr const char* kLookAheadWhy = "the 60 s look-ahead limit";

double number(const SettingValue& v) { return std::get<double>(v); }
bool isWord(const SettingValue& v) { return std::holds_alternative<std::string>(v); }
const std::string& word(const SettingValue& v) { return std::get<std::string>(v); }

using SetFn = void (*)(Scenario&, const SettingValue&);
using GetFn = SettingValue (*)(const Scenario&);

// A row of the table: the key's spec, how it is stored, the key it follows ("" for none).
Setting row(const io::SettingSpec& spec, SetFn set, GetFn get, const char* follows = "") {
  return Setting{{spec, set, get}, follows};
}

// A plain number key of a struct field, with set/get.
#define ST_ARM_NUMBER(KEY, UNIT, MIN, MAX, ABOVE, WHY, FOLLOWS, DOC, FIELD)                           \
  row({KEY, SettingType::Number, UNIT, MIN, MAX, ABOVE, "", WHY, DOC},                                \
      [](Scenario& s, const SettingValue& v) { s.FIELD = number(v); },                                 \
      [](const Scenario& s) { return SettingValue(s.FIELD); }, FOLLOWS)

std::vector<Setting> makeTable() {
  using T = SettingType;
  return {
      ST_ARM_NUMBER("safety.cycle_time", "s", 0.0, kMaxLookAhead, true, kLookAheadWhy, "",
                    "the sensor period: one cycle of the monitor (a term of the safe time)", safety.cycleTime),
      ST_ARM_NUMBER("safety.reaction_time", "s", 0.0, kMaxLookAhead, false, kLookAheadWhy, "",
                    "from a warning to the start of braking (a term of the safe time)", safety.reactionTime),
      ST_ARM_NUMBER("safety.stopping_time", "s", 0.0, kMaxLookAhead, false, kLookAheadWhy, "",
                    "braking to rest, as the monitor assumes it (a term of the safe time)", safety.stoppingTime),
      ST_ARM_NUMBER("safety.min_separation", "m", 0.0, 10.0, false, "10 m (a workcell's size)", "",
                    "every object is grown by half of it: a pair closer than this is a contact", safety.minSeparation),
      ST_ARM_NUMBER("safety.horizon", "s", 0.0, kMaxLookAhead, false, kLookAheadWhy, "",
                    "look-ahead of the time-to-collision search, at least the safe time; 0: the safe time "
                    "(cycle + reaction + stopping)",
                    safety.horizon),
      row({"safety.latch_stale", T::Boolean, "", 0, 0, false, "", "",
       "a STOP because an arm's sensor fell silent holds until reset (a deliberate restart); false: it clears itself"},
       [](Scenario& s, const SettingValue& v) { s.safety.latchStale = std::get<bool>(v); },
       [](const Scenario& s) { return SettingValue(s.safety.latchStale); }),
      ST_ARM_NUMBER("braking.stopping_time", "s", 0.0, kMaxLookAhead, false, kLookAheadWhy, "safety.stopping_time",
                    "closed loop: how long a STOPped arm takes to rest (the drive's own, T_s of the persons' "
                    "separation)",
                    braking.stoppingTime),
      row({"braking.deceleration", T::Number, "rad/s^2", 0.0, 1e6, true, "", "",
       "closed loop, instead of braking.stopping_time: the fastest joint brakes at this (0: not given)"},
       [](Scenario& s, const SettingValue& v) { s.braking.deceleration = number(v); },
       [](const Scenario& s) { return SettingValue(s.braking.deceleration); }),
      ST_ARM_NUMBER("braking.delay", "s", 0.0, kMaxLookAhead, false, kLookAheadWhy, "safety.reaction_time",
                    "closed loop: from a STOP cycle to the start of braking", braking.delay),
      row({"braking.resume", T::Number, "s", 0.0, 3600.0, false, "never", "",
       "closed loop: a STOPped arm resumes once no warning for this long; never: it stays stopped"},
       [](Scenario& s, const SettingValue& v) {
         s.braking.resumeAfter = isWord(v) ? std::numeric_limits<double>::infinity() : number(v);
       },
       [](const Scenario& s) {
         return s.braking.resumes() ? SettingValue(s.braking.resumeAfter) : SettingValue(std::string("never"));
       }),
      row({"octree.kind", T::Choice, "", 0, 0, false, "tree|octree|quadtree|cells|single|none", "",
       "the broadphase: the dynamic octree (tree, octree, quadtree), uniform cells, one list, or none (the brute force: every pair)"},
       [](Scenario& s, const SettingValue& v) { parseSpaceKind(word(v), s.broad.kind); },
       [](const Scenario& s) { return SettingValue(std::string(toString(s.broad.kind))); }),
      row({"octree.decomposition_factor", T::Integer, "", 1.0, 1e6, false, "auto", "",
       "a leaf holding more objects than this divides; auto: the space picks it as it runs"},
       [](Scenario& s, const SettingValue& v) {
         s.broad.rule.autoFactor = isWord(v);
         if (!isWord(v)) s.broad.rule.decompositionFactor = static_cast<int>(number(v));
       },
       [](const Scenario& s) {
         return s.broad.rule.autoFactor ? SettingValue(std::string("auto"))
                                        : SettingValue(static_cast<double>(s.broad.rule.decompositionFactor));
       }),
      row({"octree.max_depth", T::Integer, "", 0.0, 20.0, false, "scene", "",
       "deepest division of the octree; scene: from the moving objects' sizes and the bounds"},
       [](Scenario& s, const SettingValue& v) {
         s.broad.depthFromScene = isWord(v);
         if (!isWord(v)) s.broad.rule.maxDepth = static_cast<int>(number(v));
       },
       [](const Scenario& s) {
         return s.broad.depthFromScene ? SettingValue(std::string("scene"))
                                       : SettingValue(static_cast<double>(s.broad.rule.maxDepth));
       }),
      ST_ARM_NUMBER("octree.margin", "m", 0.0, 10.0, false, "", "",
                    "fat-box margin: a capsule is re-filed in the space only when it leaves its box grown by this",
                    broad.margin),
      ST_ARM_NUMBER("octree.cell_size", "m", 0.0, 10.0, true, "", "", "edge of a cell (kind cells)",
                    broad.rule.cellSize),
      row({"ssm.response", T::Choice, "", 0, 0, false, "stop|scaling|pfl", "",
       "persons: binary STOP, speed scaling, or scaling with contact within ISO/TS 15066 Annex A's limits (pfl)"},
       [](Scenario& s, const SettingValue& v) {
         const std::string& r = word(v);
         s.ssm.response = r == "stop" ? SsmResponse::Stop : r == "pfl" ? SsmResponse::Pfl : SsmResponse::Scaling;
       },
       [](const Scenario& s) { return SettingValue(std::string(toString(s.ssm.response))); }),
      ST_ARM_NUMBER("ssm.body_speed", "m/s", 0.0, 100.0, true, "", "", "v_h of a person's body (ISO 13855: walking)",
                    ssm.bodySpeed),
      ST_ARM_NUMBER("ssm.hand_speed", "m/s", 0.0, 100.0, true, "", "", "v_h of a hand (ISO 13855: hand and arm approach)",
                    ssm.handSpeed),
      ST_ARM_NUMBER("ssm.robot_speed", "m/s", 0.0, 100.0, true, "", "", "the arm's top speed: speed factor 1",
                    ssm.robotSpeed),
      ST_ARM_NUMBER("ssm.arm_mass", "kg", 0.0, 10000.0, true, "", "", "M: the arm's moving mass (ISO/TS 15066 A.4)",
                    ssm.armMass),
      ST_ARM_NUMBER("ssm.payload", "kg", 0.0, 1000.0, false, "", "", "m_L: what the arm carries (gripper and part)",
                    ssm.payload),
      ST_ARM_NUMBER("ssm.intrusion", "m", 0.0, 10.0, false, "", "", "C: how far a person reaches unseen beyond the body capsules",
                    ssm.intrusion),
      ST_ARM_NUMBER("ssm.person_uncertainty", "m", 0.0, 10.0, false, "", "", "Z_d: the skeleton tracker's error",
                    ssm.personUncertainty),
      ST_ARM_NUMBER("ssm.robot_uncertainty", "m", 0.0, 10.0, false, "", "", "Z_r: joint encoders and capsule fit",
                    ssm.robotUncertainty),
  };
}

#undef ST_ARM_NUMBER

}  // namespace

std::span<const Setting> armSettings() {
  static const std::vector<Setting> table = makeTable();
  return table;
}

const Setting* findSetting(std::string_view key) { return io::findSetting(armSettings(), key); }

void applySetting(Scenario& sc, const Setting& s, const SettingValue& v) { io::applySetting<Scenario>(sc, s, v); }

void applySettingText(Scenario& sc, const Setting& s, std::string_view text) { s.set(sc, io::settingValue(s, text)); }

void followDefaults(Scenario& sc, const std::function<bool(std::string_view)>& given) {
  for (const Setting& s : armSettings()) {
    if (!*s.follows || (given && given(s.key))) continue;
    s.set(sc, findSetting(s.follows)->get(sc));
  }
}

void checkSettings(const Scenario& sc) {
  const SafetyConfig& safety = sc.safety;
  if (safety.horizon != 0.0 && safety.horizon < safety.safeTime())
    throw SettingError("safety.horizon", "must be at least the safe time (cycle + reaction + stopping)");
  // each term within the bound on its own (the table's ranges); their sum too, blamed on the
  // horizon if given, else on the longest term
  if (safety.lookAhead() > kMaxLookAhead) {
    const char* key = safety.horizon != 0.0 ? "safety.horizon"
                      : safety.stoppingTime >= std::max(safety.cycleTime, safety.reactionTime) ? "safety.stopping_time"
                      : safety.reactionTime >= safety.cycleTime ? "safety.reaction_time"
                                                                 : "safety.cycle_time";
    throw SettingError(key, "the look-ahead (horizon, or cycle + reaction + stopping) must be at most " +
                                io::number(kMaxLookAhead, 15) + " s");
  }
}

std::string defaultText(std::string_view key) {
  Scenario sc;
  followDefaults(sc);
  return settingText(findSetting(key)->get(sc));
}

std::string settingsReferenceMarkdown(const Scenario* values, const char* column) {
  Scenario defaults;
  followDefaults(defaults);
  const Scenario& v = values ? *values : defaults;
  std::string out = io::referenceHeading(column);
  for (const Setting& s : armSettings()) {
    std::string doc = s.doc;
    if (*s.follows) doc += " (default: " + std::string(s.follows) + ")";
    out += io::referenceRow(s, s.get(v), doc);
  }
  return out;
}

}  // namespace st::arm
