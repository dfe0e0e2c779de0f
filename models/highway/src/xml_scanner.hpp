#pragma once
// The SUMO file readers' XML scanner (sumo_files.cpp, sumo_signals.cpp) and its number parsing:
// errors name the file and line (InputError).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <stio/input.hpp>
#include <sthighway/sumo_files.hpp>

namespace st::highway::detail {

// A small streaming XML tag scanner: enough for SUMO's machine-written files (elements and
// attributes; text content, CDATA and DOCTYPE are skipped). Tracks the line for error messages.
class XmlScanner {
 public:
  struct Tag {
    std::string name;
    bool closing = false;
    bool selfClosing = false;
    long line = 0;
    std::vector<std::pair<std::string, std::string>> attrs;
    const std::string* attr(const char* key) const {
      for (const auto& [k, v] : attrs)
        if (k == key) return &v;
      return nullptr;
    }
  };

  explicit XmlScanner(const std::filesystem::path& path) : path_(path.string()) {
    std::error_code ec;
    // an ifstream opens a directory and reads it as an empty file, and waits for ever on a FIFO
    if (std::filesystem::exists(path, ec))
      if (const std::string why = io::notReadableReason(path); !why.empty()) throw InputError(why);
    in_.open(path, std::ios::binary);
    if (!in_) throw InputError(path_ + ": cannot open file");
  }

  [[noreturn]] void fail(long line, const std::string& msg) const {
    throw InputError(path_ + ":" + std::to_string(line) + ": " + msg);
  }
  const std::string& path() const { return path_; }

  bool next(Tag& tag) {
    while (true) {
      int c;
      do {
        c = get();
      } while (c != EOF && c != '<');
      if (c == EOF) return false;
      const long start = line_;
      c = get();
      if (c == '?') {
        skipPast("?>", start);
        continue;
      }
      if (c == '!') {
        const int c1 = get(), c2 = get();
        if (c1 == '-' && c2 == '-') skipPast("-->", start);
        else skipPast(">", start);
        continue;
      }
      tag.name.clear();
      tag.attrs.clear();
      tag.closing = tag.selfClosing = false;
      tag.line = start;
      if (c == '/') {
        tag.closing = true;
        c = get();
      }
      while (c != EOF && !std::isspace(c) && c != '>' && c != '/') {
        tag.name += static_cast<char>(c);
        c = get();
      }
      if (tag.name.empty()) fail(start, "malformed tag");
      while (true) {
        while (c != EOF && std::isspace(c)) c = get();
        if (c == EOF) fail(start, "unexpected end of file inside <" + tag.name + ">");
        if (c == '>') return true;
        if (c == '/') {
          if (get() != '>') fail(line_, "expected '>' after '/' in <" + tag.name + ">");
          tag.selfClosing = true;
          return true;
        }
        std::string key;
        while (c != EOF && c != '=' && !std::isspace(c) && c != '>' && c != '/') {
          key += static_cast<char>(c);
          c = get();
        }
        while (c != EOF && std::isspace(c)) c = get();
        if (c != '=') fail(line_, "attribute '" + key + "' of <" + tag.name + "> has no value");
        c = get();
        while (c != EOF && std::isspace(c)) c = get();
        if (c != '"' && c != '\'') fail(line_, "attribute '" + key + "' of <" + tag.name + "> is not quoted");
        const int quote = c;
        std::string value;
        while ((c = get()) != quote) {
          if (c == EOF) fail(start, "unexpected end of file in attribute '" + key + "'");
          value += static_cast<char>(c);
        }
        // XML allows an attribute once; which of two would count is a guess
        if (tag.attr(key.c_str())) fail(line_, "attribute '" + key + "' of <" + tag.name + "> given twice");
        tag.attrs.emplace_back(std::move(key), decode(value));
        c = get();
      }
    }
  }

 private:
  int get() {
    const int c = in_.get();
    if (c == '\n') ++line_;
    // no XML holds a NUL: /dev/zero was read for ever, one NUL at a time, looking for a '<'
    if (c == 0) fail(line_, "a NUL byte: not an XML text file");
    return c;
  }
  void skipPast(const char* end, long start) {
    const std::string e(end);
    std::string window;
    int c;
    while ((c = get()) != EOF) {
      window += static_cast<char>(c);
      if (window.size() > e.size()) window.erase(0, 1);
      if (window == e) return;
    }
    fail(start, "unterminated markup");
  }
  static std::string decode(const std::string& s) {
    if (s.find('&') == std::string::npos) return s;
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] != '&') {
        out += s[i];
        continue;
      }
      const std::size_t semi = s.find(';', i);
      const std::string ent = semi == std::string::npos ? "" : s.substr(i + 1, semi - i - 1);
      if (ent == "amp") out += '&';
      else if (ent == "lt") out += '<';
      else if (ent == "gt") out += '>';
      else if (ent == "quot") out += '"';
      else if (ent == "apos") out += '\'';
      else {
        out += '&';
        continue;
      }
      i = semi;
    }
    return out;
  }

  std::string path_;
  std::ifstream in_;
  long line_ = 1;
};

inline double number(const XmlScanner& x, const XmlScanner::Tag& t, const char* key, const std::string& text) {
  const char* b = text.c_str();
  char* e = nullptr;
  // decimal only: strtod also reads hex floats ("0x1p3"), inf and nan, which SUMO never writes
  const bool decimal = text.find_first_not_of("0123456789+-.eE") == std::string::npos;
  const double v = decimal ? std::strtod(b, &e) : 0.0;
  if (!decimal || e == b || *e != '\0' || !std::isfinite(v))
    x.fail(t.line, "<" + t.name + "> attribute '" + key + "' is not a finite number: '" + text + "'");
  return v;
}

inline double required(const XmlScanner& x, const XmlScanner::Tag& t, const char* key) {
  const std::string* s = t.attr(key);
  if (!s) x.fail(t.line, "<" + t.name + "> lacks attribute '" + key + "'");
  return number(x, t, key, *s);
}

inline double optionalNumber(const XmlScanner& x, const XmlScanner::Tag& t, const char* key, double def) {
  const std::string* s = t.attr(key);
  return s ? number(x, t, key, *s) : def;
}

}  // namespace st::highway::detail
