#pragma once
// The one JSON writer: JSON assembled in each file's own layout (keys one a line, small objects
// inline), with every value written by io's rules in one place. What goes in decides how it is
// written, so a value cannot slip through unescaped:
//   - a string literal ("{\"scenario\": ") is structure: braces, keys, commas, layout, as given;
//   - any other text (std::string, string_view, a const char* from toString) is a value: a JSON
//     string literal (jsonString: escaped, valid UTF-8);
//   - a double is jsonNumber's at this writer's digits (NaN and infinities as null; infinities as
//     the strings "inf" and "-inf" where a writer says so: the arm's infinite times);
//   - an integer is its decimal digits; jsonBool(b) is true or false;
//   - JSON already written (another JsonText, jsonRaw(text)) goes in as it is.
// Reading JSON is nlohmann::json's job everywhere (one library for each direction).
#include <cmath>
#include <concepts>
#include <string>
#include <string_view>

#include <stio/format.hpp>

namespace st::io {

// A piece of JSON already written (a nested document, "null"): placed as it is.
struct JsonRaw {
  std::string text;
};
inline JsonRaw jsonRaw(std::string text) { return {std::move(text)}; }
inline JsonRaw jsonBool(bool b) { return {b ? "true" : "false"}; }

// How a writer writes an infinite double: null (JSON has no infinity) or the string "inf"/"-inf".
enum class Infinity { Null, Text };

class JsonText {
 public:
  // digits: as jsonNumber's (0: the shortest text that reads back to the same double)
  explicit JsonText(int digits = 0, Infinity infinity = Infinity::Null) : digits_(digits), infinity_(infinity) {}

  template <std::size_t N>
  JsonText& operator<<(const char (&structure)[N]) {
    text_.append(structure, N - 1);
    return *this;
  }
  JsonText& operator<<(std::string_view value) {
    text_ += jsonString(value);
    return *this;
  }
  JsonText& operator<<(double x) {
    text_ += infinity_ == Infinity::Text && std::isinf(x) ? jsonString(number(x)) : jsonNumber(x, digits_);
    return *this;
  }
  template <std::integral I>
    requires(!std::same_as<I, bool> && !std::same_as<I, char>)
  JsonText& operator<<(I n) {
    text_ += std::to_string(n);
    return *this;
  }
  // a char or a bool would pass as a number (',' as 44, true as 1): neither is written this way
  template <std::same_as<char> C>
  JsonText& operator<<(C) = delete;
  template <std::same_as<bool> B>
  JsonText& operator<<(B) = delete;
  JsonText& operator<<(const JsonRaw& json) {
    text_ += json.text;
    return *this;
  }
  JsonText& operator<<(const JsonText& json) {
    text_ += json.text_;
    return *this;
  }

  const std::string& str() const { return text_; }
  bool empty() const { return text_.empty(); }

 private:
  std::string text_;
  int digits_;
  Infinity infinity_;
};

}  // namespace st::io
