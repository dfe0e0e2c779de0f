#pragma once
// The one XML reader: a small streaming tag scanner, enough for SUMO's machine-written files
// (elements and attributes; text content, CDATA and DOCTYPE are skipped), with errors that name
// the file and line ("file:line: message"). Every XML file stsim reads (SUMO networks, traces,
// routes, light states, configurations, collision outputs) goes through it.
//
// A reader keeps its own exception type E: the scanner is made with io::raiseAs<E>, so its
// callers catch what they always caught (as Yaml<E> does for YAML).
#include <filesystem>
#include <fstream>
#include <istream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace st::io {

// The scanner's own error, for readers that keep no type of their own.
struct XmlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// How a scanner throws: a function that throws its argument as the reader's exception type.
using XmlRaise = void (*)(const std::string& message);
template <class E>
void raiseAs(const std::string& message) {
  throw E(message);
}

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

  // A file, streamed: refused with io's notReadableReason (a directory, a FIFO), or "cannot open
  // file".
  explicit XmlScanner(const std::filesystem::path& path, XmlRaise raise = raiseAs<XmlError>);
  // Text already read; `name` names it in messages.
  XmlScanner(std::string text, std::string name, XmlRaise raise = raiseAs<XmlError>);

  // The next start, end or empty-element tag (declarations, comments, DOCTYPE skipped); false at
  // the end of the input. Malformed markup throws "name:line: ...".
  bool next(Tag& tag);
  // From now on every element must be closed, by its own end tag: a file cut short (a SUMO run
  // killed before it closed its output) is an error at its end rather than read as whole.
  void requireBalanced() { balanced_ = true; }
  // The elements around the last tag next() gave, itself not counted (with requireBalanced),
  // outermost first: a <seed/> in <configuration><random_number> has depth 2.
  std::size_t depth() const { return around_; }
  const std::string& openElement(std::size_t k) const { return open_[k].first; }

  // Throws "name:line: msg" as the reader's exception.
  [[noreturn]] void fail(long line, const std::string& msg) const;
  const std::string& path() const { return path_; }

 private:
  int get();
  void skipPast(const char* end, long start);
  void readAttribute(Tag& tag, int& c, long start);
  void balance(const Tag& tag);

  std::string path_;
  XmlRaise raise_;
  std::unique_ptr<std::istream> in_;
  long line_ = 1;
  bool balanced_ = false;
  std::vector<std::pair<std::string, long>> open_;  // the open elements and their lines
  std::size_t around_ = 0;
};

// An attribute's number: decimal text only (no hex floats, inf or nan, which SUMO never writes),
// finite; else "<tag> attribute 'key' is not a finite number: 'text'" at the tag's line.
double number(const XmlScanner& x, const XmlScanner::Tag& t, const char* key, const std::string& text);
// The attribute's number; "<tag> lacks attribute 'key'" if it has none.
double required(const XmlScanner& x, const XmlScanner::Tag& t, const char* key);
// The attribute's number, or def if it has none.
double optionalNumber(const XmlScanner& x, const XmlScanner::Tag& t, const char* key, double def);

}  // namespace st::io
