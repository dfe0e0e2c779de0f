#include <stio/settings_table.hpp>

#include <cctype>
#include <cmath>

#include <stio/format.hpp>
#include <stio/yaml.hpp>

namespace st::io {

namespace {

bool isWord(const SettingValue& v) { return std::holds_alternative<std::string>(v); }
const std::string& word(const SettingValue& v) { return std::get<std::string>(v); }

std::string rangeText(const SettingSpec& s) {
  std::string out = s.aboveMin ? "(" : "[";
  out += number(s.min, 15) + ", " + number(s.max, 15) + "]";
  if (*s.unit) out.append(" ").append(s.unit);
  return out;
}

void checkNumber(const SettingSpec& s, const SettingValue& v) {
  if (isWord(v)) {
    if (!*s.words || word(v) != s.words) throw SettingError(s.key, wrongTypeText(expected(s), word(v)));
    return;
  }
  if (!std::holds_alternative<double>(v)) throw SettingError(s.key, wrongTypeText(expected(s)));
  const double x = std::get<double>(v);
  const std::string got = ", got " + number(x, 15);
  if (s.rangeWords && !(x >= s.min && x <= s.max && (!s.aboveMin || x > s.min)))
    throw SettingError(s.key, "must be in " + rangeText(s) + got);
  if (!std::isfinite(x)) throw SettingError(s.key, "must be a finite number" + got);
  // below the range: "must not be negative" / "must be positive" where the range starts at 0
  if (x < s.min || (s.aboveMin && x == s.min)) {
    if (s.min == 0.0) throw SettingError(s.key, (s.aboveMin ? "must be positive" : "must not be negative") + got);
    throw SettingError(s.key, "must be in " + rangeText(s) + got);
  }
  if (x > s.max) {
    if (*s.maxWhy) throw SettingError(s.key, number(x, 15) + (*s.unit ? std::string(" ") + s.unit : "") + " is more than " + s.maxWhy);
    throw SettingError(s.key, "must be in " + rangeText(s) + got);
  }
  if (s.type == SettingType::Integer && x != std::floor(x)) throw SettingError(s.key, "must be a whole number" + got);
}

}  // namespace

std::string expected(const SettingSpec& s) {
  switch (s.type) {
    case SettingType::Number: return *s.words ? std::string("a number or ") + s.words : "a number";
    case SettingType::Integer: return *s.words ? std::string("a whole number or ") + s.words : "a whole number";
    case SettingType::Boolean: return "true or false";
    case SettingType::Choice: {
      std::string out = "one of ";
      const auto w = split(s.words, '|');
      for (std::size_t i = 0; i < w.size(); ++i) out.append(i ? ", " : "").append(w[i]);
      return out;
    }
  }
  return "";
}

std::string valuesText(const SettingSpec& s) {
  switch (s.type) {
    case SettingType::Number:
    case SettingType::Integer: {
      std::string out = (s.type == SettingType::Number ? "number in " : "whole number in ") + rangeText(s);
      if (*s.words) out.append(", or ").append(s.words);
      return out;
    }
    case SettingType::Boolean: return "true or false";
    case SettingType::Choice: return expected(s);
  }
  return "";
}

std::string settingText(const SettingValue& v) {
  if (const double* x = std::get_if<double>(&v)) return number(*x, 15);
  if (const bool* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  return std::get<std::string>(v);
}

std::string_view keySection(std::string_view key) {
  const auto dot = key.find('.');
  return dot == std::string_view::npos ? std::string_view() : key.substr(0, dot);
}

std::string_view keyName(std::string_view key) {
  const auto dot = key.find('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

std::string exactSettingText(const SettingValue& v) {
  if (const double* x = std::get_if<double>(&v)) return number(*x);
  return settingText(v);
}

void checkSetting(const SettingSpec& s, const SettingValue& v) {
  switch (s.type) {
    case SettingType::Number:
    case SettingType::Integer: return checkNumber(s, v);
    case SettingType::Boolean:
      if (!std::holds_alternative<bool>(v)) throw SettingError(s.key, wrongTypeText("true or false"));
      return;
    case SettingType::Choice: {
      if (!isWord(v)) throw SettingError(s.key, wrongTypeText(expected(s)));
      bool known = false;
      for (std::string_view w : split(s.words, '|')) known = known || w == word(v);
      if (!known) throw SettingError(s.key, wrongTypeText(expected(s), word(v)));
      return;
    }
  }
}

SettingValue settingValue(const SettingSpec& s, std::string_view text) {
  const std::string t(text);
  SettingValue v = t;
  if ((s.type == SettingType::Number || s.type == SettingType::Integer) && !(*s.words && t == s.words)) {
    std::size_t used = 0;
    double x = 0.0;
    try {
      x = std::stod(t, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    // stod skips leading blanks: " 1" is no number here, as in YAML
    if (t.empty() || used != t.size() || std::isspace(static_cast<unsigned char>(t.front())))
      throw SettingError(s.key, wrongTypeText(expected(s), t));
    v = x;
  } else if (s.type == SettingType::Boolean) {
    if (t != "true" && t != "false") throw SettingError(s.key, wrongTypeText("true or false", t));
    v = t == "true";
  }
  checkSetting(s, v);
  return v;
}

std::vector<Assignment> splitAssignments(std::string_view text) {
  if (text.empty()) throw std::invalid_argument("needs KEY=VALUE[,...], got nothing");
  std::vector<Assignment> out;
  // split() drops a trailing empty piece: "a=1," names its empty item as "a=1,,b=2" does
  if (text.back() == ',') throw std::invalid_argument("needs KEY=VALUE, got ''");
  for (const std::string_view item : split(text, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string_view::npos) throw std::invalid_argument("needs KEY=VALUE, got '" + std::string(item) + "'");
    out.push_back({std::string(item.substr(0, eq)), std::string(item.substr(eq + 1))});
  }
  return out;
}

std::string referenceHeading(std::string_view column) {
  return "| key | value | " + std::string(column) + " | what it sets |\n| --- | --- | --- | --- |\n";
}

std::string referenceRow(const SettingSpec& s, const SettingValue& v, std::string_view doc) {
  return "| `" + std::string(s.key) + "` | " + valuesText(s) + " | " + settingText(v) + " | " + std::string(doc) + " |\n";
}

}  // namespace st::io
