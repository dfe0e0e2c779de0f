#pragma once
// The core every model's settings table shares (starm/settings.hpp, stpool/settings.hpp): a key's
// type, unit, range and doc; reading a value as text (a YAML scalar, a command-line value), its
// checks and their words, the reference's rows and --set's KEY=VALUE list. A model's table adds
// what a key sets (Setting<Config>'s set and get); this layer knows no model.
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace st::io {

enum class SettingType { Number, Integer, Boolean, Choice };

// A value as read: a number, a bool, or a word (a choice; a word a number key takes instead, as
// "auto" or "never").
using SettingValue = std::variant<double, bool, std::string>;

// What a key takes, whatever it sets.
struct SettingSpec {
  const char* key;    // the YAML's nested name, e.g. "safety.cycle_time"
  SettingType type;
  const char* unit;   // "s", "m", "m/s", "kg", "rad/s^2" or "" (none)
  double min;         // Number, Integer: the range, inclusive of max
  double max;
  bool aboveMin;      // the range excludes min: (min, max]
  const char* words;  // Choice: "stop|scaling|pfl"; Number, Integer: a word taken instead ("never"), or ""
  const char* maxWhy; // what the upper bound is ("the 60 s look-ahead limit"), worded in its error; or ""
  const char* doc;
  // every value outside the range, below or above it or not finite, worded "must be in [min, max]
  // UNIT, got x" (the highway monitor's and the cosim scenario's words since their first release),
  // rather than "must be positive" / "must not be negative" / "must be a finite number"
  bool rangeWords = false;
};

// A key of a model's table: its spec, and how it sets and reads Config's value.
template <class Config>
struct Setting : SettingSpec {
  void (*set)(Config&, const SettingValue&);  // stores a value checkSetting passed
  SettingValue (*get)(const Config&);         // the value it holds
};

// The error of a bad value: what() is "KEY PROBLEM"; problem() without the key, for the front
// ends that name the key their own way ("file:line: KEY: PROBLEM", "--set KEY: PROBLEM").
class SettingError : public std::invalid_argument {
 public:
  SettingError(std::string key, std::string problem)
      : std::invalid_argument(key + " " + problem), key_(std::move(key)), problem_(std::move(problem)) {}
  const std::string& key() const { return key_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string key_, problem_;
};

// What a value of s must be, for a type error: "a number", "a number or never", "one of a, b".
std::string expected(const SettingSpec& s);
// The values s takes, as the reference gives them: "number in (0, 60] s", "one of a, b".
std::string valuesText(const SettingSpec& s);
// A value as the YAML would write it: 0.5, true, never (numbers to 15 digits, for people).
std::string settingText(const SettingValue& v);
// The same with numbers in the shortest text that reads back to the same double (a file written
// to be read again: a recorded game replays from the same bits).
std::string exactSettingText(const SettingValue& v);

// Throws SettingError unless v is a value of s (type, finite, range, whole, word).
void checkSetting(const SettingSpec& s, const SettingValue& v);
// Text as s's type, a command-line value or a YAML scalar alike: a number, true/false or a word;
// checked by checkSetting. Throws SettingError.
SettingValue settingValue(const SettingSpec& s, std::string_view text);

// A nested key's section and name: "space.cell_size" -> "space", "cell_size"; "until" -> "", "until".
std::string_view keySection(std::string_view key);
std::string_view keyName(std::string_view key);

// The setting named key in a table; null if none.
template <class S>
const S* findSetting(std::span<const S> table, std::string_view key) {
  for (const S& s : table)
    if (key == s.key) return &s;
  return nullptr;
}

// Checks v for s and stores it in c.
template <class Config>
void applySetting(Config& c, const Setting<Config>& s, const SettingValue& v) {
  checkSetting(s, v);
  s.set(c, v);
}

// A value given on the command line for a key, as text (stsim arm --set KEY=VALUE), to be read
// over the scenario file's.
struct SettingOverride {
  std::string key;
  std::string text;
  std::string option;  // how the front end names it: "--set safety.cycle_time", "--response"
};

// A key and its value as text, from --set KEY=VALUE[,KEY=VALUE...].
struct Assignment {
  std::string key;
  std::string text;
};
// The assignments of --set's text; throws std::invalid_argument with the problem ("needs
// KEY=VALUE, got 'x'") for a piece without '=' or an empty text.
std::vector<Assignment> splitAssignments(std::string_view text);

// The reference, a Markdown table: the heading (key, value, `column`, what it sets), then one row
// per key (its values, its value v, its doc).
std::string referenceHeading(std::string_view column);
std::string referenceRow(const SettingSpec& s, const SettingValue& v, std::string_view doc);

// The names a model's settings table takes from this core, in one list: a model's settings header
// says `using namespace io::setting_names;` in its namespace, so pool::SettingError is
// io::SettingError (a value's type, its error and the words of both, shared by every table).
namespace setting_names {
using io::expected;
using io::SettingError;
using io::SettingOverride;
using io::settingText;
using io::SettingType;
using io::SettingValue;
using io::valuesText;
}  // namespace setting_names

}  // namespace st::io
