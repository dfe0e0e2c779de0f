#include <stcosim/scenario_settings.hpp>

#include <optional>
#include <vector>

#include <sthighway/run_settings.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {

namespace {

using io::SettingType;
using io::SettingValue;

double number(const SettingValue& v) { return std::get<double>(v); }
bool isWord(const SettingValue& v) { return std::holds_alternative<std::string>(v); }
const std::string& word(const SettingValue& v) { return std::get<std::string>(v); }

// a value SUMO takes from the sumocfg unless given: the word of its default, or the number
SettingValue optional(const std::optional<double>& x, const char* none) {
  return x ? SettingValue(*x) : SettingValue(std::string(none));
}
std::optional<double> optional(const SettingValue& v) {
  return isWord(v) ? std::nullopt : std::optional<double>(number(v));
}

// A key of the table: every value out of range worded "must be in [min, max], got x", as the
// scenario reader always worded it.
ScenarioSetting row(const io::SettingSpec& spec, void (*set)(Scenario&, const SettingValue&),
                    SettingValue (*get)(const Scenario&)) {
  return ScenarioSetting{spec, set, get};
}
io::SettingSpec spec(const char* key, SettingType type, const char* unit, double min, double max,
                     const char* words, const char* doc) {
  return {key, type, unit, min, max, false, words, "", doc, true};
}

#define ST_COSIM_NUMBER(KEY, UNIT, MIN, MAX, DOC, FIELD)                                    \
  row(spec(KEY, SettingType::Number, UNIT, MIN, MAX, "", DOC),                              \
      [](Scenario& s, const SettingValue& v) { s.FIELD = number(v); },                      \
      [](const Scenario& s) { return SettingValue(s.FIELD); })

std::vector<ScenarioSetting> makeTable() {
  using T = SettingType;
  return {
      row(highway::kSeedSetting,
          [](Scenario& s, const SettingValue& v) {
            s.seed = static_cast<std::uint64_t>(number(v));
            s.passSeed = true;
            s.plugin.smart.seed = s.seed;
          },
          [](const Scenario& s) { return SettingValue(static_cast<double>(s.seed)); }),
      row(highway::kEndSetting, [](Scenario& s, const SettingValue& v) { s.end = optional(v); },
          [](const Scenario& s) { return optional(s.end, "sumocfg"); }),
      row(spec("demand_scale", T::Number, "", 0.0, 1000.0, "sumo",
               "SUMO's --scale: multiplies the routes' demand; sumo: the sumocfg's (else 1)"),
          [](Scenario& s, const SettingValue& v) { s.demandScale = optional(v); },
          [](const Scenario& s) { return optional(s.demandScale, "sumo"); }),
      row(spec("validate_ssm", T::Boolean, "", 0, 0, "", "also run SUMO's SSM device and write validation.json"),
          [](Scenario& s, const SettingValue& v) { s.validateSsm = std::get<bool>(v); },
          [](const Scenario& s) { return SettingValue(s.validateSsm); }),
      row(highway::kPenetrationSetting, [](Scenario& s, const SettingValue& v) { s.plugin.smart.penetration = number(v); },
          [](const Scenario& s) { return SettingValue(s.plugin.smart.penetration); }),
      row(spec("action", T::Choice, "", 0, 0, "none|color|brake",
               "on a warning: nothing, colour the car (yellow, red below half the safe time), or colour and brake"),
          [](Scenario& s, const SettingValue& v) { parseAction(word(v), s.plugin.actions.action); },
          [](const Scenario& s) { return SettingValue(std::string(toString(s.plugin.actions.action))); }),
      ST_COSIM_NUMBER("brake.deceleration", "m/s^2", 0.1, 20.0,
                      "action brake: a car brakes when matching its foe's speed needs at least this",
                      plugin.actions.brake.deceleration),
      ST_COSIM_NUMBER("brake.max_deceleration", "m/s^2", 0.1, 50.0,
                      "action brake: the hardest it brakes (at least brake.deceleration)",
                      plugin.actions.brake.maxDeceleration),
      ST_COSIM_NUMBER("brake.standstill_gap", "m", 0.0, 100.0, "action brake: the gap it keeps to its foe",
                      plugin.actions.brake.standstillGap),
      row(spec("collision_action", T::Choice, "", 0, 0, "none|warn|teleport|remove",
               "SUMO's --collision.action: what SUMO does with a collision it registers"),
          [](Scenario& s, const SettingValue& v) { s.collisionAction = word(v); },
          [](const Scenario& s) { return SettingValue(s.collisionAction); }),
      row(spec("collision_mingap_factor", T::Number, "", 0.0, 10.0, "sumo",
               "SUMO's --collision.mingap-factor: a gap below this times the follower's minGap is a collision "
               "(0: contact only); sumo: the sumocfg's (else 1)"),
          [](Scenario& s, const SettingValue& v) { s.collisionMinGapFactor = optional(v); },
          [](const Scenario& s) { return optional(s.collisionMinGapFactor, "sumo"); }),
  };
}

#undef ST_COSIM_NUMBER

}  // namespace

std::span<const ScenarioSetting> scenarioSettings() {
  static const std::vector<ScenarioSetting> table = makeTable();
  return table;
}

const ScenarioSetting* findScenarioSetting(std::string_view key) { return io::findSetting(scenarioSettings(), key); }

void applyScenarioSettingText(Scenario& s, const ScenarioSetting& setting, std::string_view text) {
  setting.set(s, io::settingValue(setting, text));
}

void checkScenarioSettings(const Scenario& s) {
  const ActionConfig& a = s.plugin.actions;
  if (a.brake.maxDeceleration < a.brake.deceleration)
    throw io::SettingError("brake.max_deceleration", "must be at least brake.deceleration");
}

std::string scenarioSettingsMarkdown(const Scenario& values, const char* column) {
  std::string out = io::referenceHeading(column);
  for (const ScenarioSetting& s : scenarioSettings()) out += io::referenceRow(s, s.get(values), s.doc);
  return out;
}

std::string scenarioSettingsMarkdown() { return scenarioSettingsMarkdown(Scenario{}); }

}  // namespace st::cosim
