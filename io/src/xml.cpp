#include <stio/xml.hpp>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <stio/input.hpp>

namespace st::io {

namespace {

// the five predefined entities; any other '&' is kept as it is
std::string decodeEntities(const std::string& s) {
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

}  // namespace

XmlScanner::XmlScanner(const std::filesystem::path& path, XmlRaise raise) : path_(path.string()), raise_(raise) {
  std::error_code ec;
  // an ifstream opens a directory and reads it as an empty file, and waits for ever on a FIFO
  if (std::filesystem::exists(path, ec))
    if (const std::string why = notReadableReason(path); !why.empty()) raise_(why);
  auto file = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*file) raise_(path_ + ": cannot open file");
  in_ = std::move(file);
}

XmlScanner::XmlScanner(std::string text, std::string name, XmlRaise raise)
    : path_(std::move(name)), raise_(raise), in_(std::make_unique<std::istringstream>(std::move(text))) {}

void XmlScanner::fail(long line, const std::string& msg) const {
  raise_(path_ + ":" + std::to_string(line) + ": " + msg);
  throw XmlError(path_ + ":" + std::to_string(line) + ": " + msg);  // (a raise that returned)
}

bool XmlScanner::next(Tag& tag) {
  while (true) {
    int c;
    do {
      c = get();
    } while (c != EOF && c != '<');
    if (c == EOF) {
      if (balanced_ && !open_.empty())
        fail(line_, "unexpected end of file: <" + open_.back().first + "> (line " + std::to_string(open_.back().second) +
                        ") is not closed");
      return false;
    }
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
      if (c == '>') {
        balance(tag);
        return true;
      }
      if (c == '/') {
        if (get() != '>') fail(line_, "expected '>' after '/' in <" + tag.name + ">");
        tag.selfClosing = true;
        around_ = open_.size();
        return true;
      }
      readAttribute(tag, c, start);
    }
  }
}

// key="value" from c on; c is then the character after the closing quote
void XmlScanner::readAttribute(Tag& tag, int& c, long start) {
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
  tag.attrs.emplace_back(std::move(key), decodeEntities(value));
  c = get();
}

// with requireBalanced: a start tag opens an element, an end tag must close the innermost one
void XmlScanner::balance(const Tag& tag) {
  if (!balanced_) return;
  around_ = open_.size();
  if (!tag.closing) {
    open_.emplace_back(tag.name, tag.line);
    return;
  }
  if (open_.empty()) fail(tag.line, "</" + tag.name + "> closes no open element");
  if (open_.back().first != tag.name)
    fail(tag.line, "</" + tag.name + "> does not close <" + open_.back().first + "> (line " +
                       std::to_string(open_.back().second) + ")");
  open_.pop_back();
  around_ = open_.size();
}

int XmlScanner::get() {
  const int c = in_->get();
  if (c == '\n') ++line_;
  // no XML holds a NUL: /dev/zero was read for ever, one NUL at a time, looking for a '<'
  if (c == 0) fail(line_, "a NUL byte: not an XML text file");
  return c;
}

void XmlScanner::skipPast(const char* end, long start) {
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

double number(const XmlScanner& x, const XmlScanner::Tag& t, const char* key, const std::string& text) {
  const char* b = text.c_str();
  char* e = nullptr;
  // decimal only: strtod also reads hex floats ("0x1p3"), inf and nan, which SUMO never writes
  const bool decimal = text.find_first_not_of("0123456789+-.eE") == std::string::npos;
  const double v = decimal ? std::strtod(b, &e) : 0.0;
  if (!decimal || e == b || *e != '\0' || !std::isfinite(v))
    x.fail(t.line, "<" + t.name + "> attribute '" + key + "' is not a finite number: '" + text + "'");
  return v;
}

double required(const XmlScanner& x, const XmlScanner::Tag& t, const char* key) {
  const std::string* s = t.attr(key);
  if (!s) x.fail(t.line, "<" + t.name + "> lacks attribute '" + key + "'");
  return number(x, t, key, *s);
}

double optionalNumber(const XmlScanner& x, const XmlScanner::Tag& t, const char* key, double def) {
  const std::string* s = t.attr(key);
  return s ? number(x, t, key, *s) : def;
}

}  // namespace st::io
