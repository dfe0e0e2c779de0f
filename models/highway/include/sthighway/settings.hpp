#pragma once
// The monitor's settings (MonitorConfig), each named once with its type, unit, range and one line
// of doc. Every front end sets MonitorConfig through this table: the YAML scenario (the nested
// keys, "safe_time.vehicle_reaction", are the reference names), stsim highway's options (--set
// KEY=VALUE for any of them, and short options for the common ones) and Python's
// Monitor(**settings) (the same key with '.' spelt '_', or nested dicts). applySetting checks a
// value and words its error once, whichever front end read it; the defaults are MonitorConfig's.
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include <sthighway/monitor.hpp>

namespace st::highway {

enum class SettingType { Number, Integer, Boolean, Choice };

// A value as a front end read it: a number (YAML/Python int or float), a bool, or text.
using SettingValue = std::variant<double, bool, std::string>;

struct Setting {
  const char* key;      // the YAML's nested name, e.g. "safe_time.vehicle_reaction"
  SettingType type;
  const char* unit;     // "s", "m", "m/s^2", "N", "deg", "dB", "dBm", or "" (none)
  double min = 0.0;     // Number, Integer: the range, inclusive
  double max = 0.0;
  const char* choices;  // Choice: the words, "concentric|five|box"
  const char* doc;
  void (*set)(MonitorConfig&, const SettingValue&);   // stores a value applySetting checked
  SettingValue (*get)(const MonitorConfig&);          // the value it holds
};

// The error of a bad value: what() is "KEY PROBLEM" ("safe_time.vehicle_reaction must be in
// [0, 60] s, got 99"); problem() without the key, for readers that name the key their own way.
class SettingError : public std::invalid_argument {
 public:
  SettingError(std::string key, std::string problem)
      : std::invalid_argument(key + " " + problem), key_(std::move(key)), problem_(std::move(problem)) {}
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string key_, problem_;
};

// Every setting, in the order the reference lists them.
std::span<const Setting> monitorSettings();
// The setting named key (the nested name, or its flat spelling with '_' for '.'); null if none.
const Setting* findSetting(std::string_view key);
// "safe_time.vehicle_reaction" -> "safe_time_vehicle_reaction"
std::string flatName(std::string_view key);
// What a value of s must be, for a type error: "a number", "true or false", "one of a, b".
std::string expected(const Setting& s);

// Checks v against s (type, finite, range, choice) and stores it; throws SettingError.
void applySetting(MonitorConfig& cfg, const Setting& s, const SettingValue& v);
// The same from text (a command-line value, a YAML scalar): a number, true/false or a choice.
void applySettingText(MonitorConfig& cfg, const Setting& s, std::string_view text);
// The values s takes, as the reference gives them: "number in [0, 60] s", "one of a, b".
std::string valuesText(const Setting& s);
// A value as the YAML would write it: 0.5, true, five.
std::string settingText(const SettingValue& v);
// Every value in its range, and what no single setting can check: conflict.rear_end_below <= conflict.crossing_above, a
// five-circle layout that covers the car. Throws SettingError naming the key to change.
void checkSettings(const MonitorConfig& cfg);

// The reference: one Markdown table row per setting (key, type and range, its value in `values`
// under the heading `column`, doc).
std::string settingsReferenceMarkdown(const MonitorConfig& values = MonitorConfig{}, const char* column = "default");

}  // namespace st::highway
