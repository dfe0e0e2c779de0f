#pragma once
// YAML input errors, worded once for every reader: "file:line: key: message" (pool adds the column:
// "file:line:col: key: message"). A reader keeps its own exception type E (constructible from a
// std::string) and reports through Yaml<E>, so its callers catch what they always caught.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

#include <yaml-cpp/yaml.h>

namespace st::io {

// "file:line" ("file:line:col" with column) of a mark or node; "file" alone where there is no
// place (a null mark, an absent or built node).
std::string place(std::string_view file, const YAML::Mark& mark, bool column = false);
std::string place(std::string_view file, const YAML::Node& node, bool column = false);

// The problems every reader meets, in one wording each. A hint, when given, follows in parentheses.
std::string unknownKeyText(std::string_view hint = {});   // "unknown key"
std::string missingKeyText(std::string_view hint = {});   // "missing key"
// "must be <expected>", and ", got '<got>'" when the text given is known: every reader's and the
// settings tables' one wording of a value of the wrong type ("must be a mapping", "must be a
// number, got 'lots'")
std::string wrongTypeText(std::string_view expected);
std::string wrongTypeText(std::string_view expected, std::string_view got);
std::string repeatedKeyText(const YAML::Node& first);     // "repeated key (first given at line N)"

// The first key of a mapping that is not a scalar, not allowed or given twice, with what is wrong;
// key is "" when all is well. `where` prefixes the keys named ("brake" names "brake.x").
struct KeyProblem {
  YAML::Node at;
  std::string key;
  std::string what;
};
KeyProblem checkKeys(const YAML::Node& map, std::string_view where,
                     const std::function<bool(const std::string&)>& allowed, std::string_view unknownHint = {});

// Parses text holding one YAML document. A second document (after a "---") would be ignored
// without a word: it throws YAML::ParserException at its start instead ("a second YAML document
// ..."), as a syntax error does. An empty document after "---" is no document.
YAML::Node loadOneDocument(const std::string& text);

// Reads and parses a YAML file. Problems come back as one line in `error` (an empty Node):
// "file: no such file", "file: is a directory, not a YAML file", "file: cannot read the file",
// "file:line: malformed YAML: msg".
YAML::Node loadFile(const std::filesystem::path& file, std::string& error);
// The same for text already read; `file` names it in messages.
YAML::Node loadText(const std::string& text, std::string_view file, std::string& error, bool column = false);

// One file's error reporting; every failure throws E("file:line: key: what").
template <class E>
class Yaml {
 public:
  explicit Yaml(std::string file, bool column = false) : file_(std::move(file)), column_(column) {}

  const std::string& file() const { return file_; }
  std::string at(const YAML::Node& n) const { return place(file_, n, column_); }
  std::string message(const YAML::Node& n, std::string_view key, std::string_view what) const {
    return join(at(n), key, what);
  }
  std::string message(const YAML::Mark& m, std::string_view key, std::string_view what) const {
    return join(place(file_, m, column_), key, what);
  }

  [[noreturn]] void fail(const YAML::Node& n, std::string_view key, std::string_view what) const {
    throw E(message(n, key, what));
  }
  [[noreturn]] void fail(const YAML::Mark& m, std::string_view key, std::string_view what) const {
    throw E(message(m, key, what));
  }
  [[noreturn]] void unknownKey(const YAML::Node& n, std::string_view key, std::string_view hint = {}) const {
    fail(n, key, unknownKeyText(hint));
  }
  [[noreturn]] void missingKey(const YAML::Node& n, std::string_view key, std::string_view hint = {}) const {
    fail(n, key, missingKeyText(hint));
  }
  [[noreturn]] void wrongType(const YAML::Node& n, std::string_view key, std::string_view expected) const {
    fail(n, key, wrongTypeText(expected));
  }
  [[noreturn]] void repeatedKey(const YAML::Node& n, std::string_view key, const YAML::Node& first) const {
    fail(n, key, repeatedKeyText(first));
  }
  // Throws on the first key of `map` that is not allowed or is repeated (see checkKeys above).
  void onlyKeys(const YAML::Node& map, std::string_view where, const std::function<bool(const std::string&)>& allowed,
                std::string_view unknownHint = {}) const {
    const KeyProblem p = checkKeys(map, where, allowed, unknownHint);
    if (!p.key.empty()) fail(p.at, p.key, p.what);
  }
  // Loads the file, throwing E with loadFile's message.
  YAML::Node load(const std::filesystem::path& path) const {
    std::string error;
    YAML::Node n = loadFile(path, error);
    if (!error.empty()) throw E(error);
    return n;
  }

 private:
  static std::string join(std::string where, std::string_view key, std::string_view what) {
    if (!key.empty()) where.append(": ").append(key);
    return where.append(": ").append(what);
  }
  std::string file_;
  bool column_;
};

}  // namespace st::io
