#include <stio/yaml.hpp>

#include <stio/input.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace st::io {

namespace fs = std::filesystem;

std::string place(std::string_view file, const YAML::Mark& mark, bool column) {
  std::string out(file);
  if (mark.is_null() || mark.line < 0) return out;
  out += ':';
  out += std::to_string(mark.line + 1);
  if (column) {
    out += ':';
    out += std::to_string(mark.column + 1);
  }
  return out;
}

std::string place(std::string_view file, const YAML::Node& node, bool column) {
  // Mark() throws on an invalid node (the result of indexing a scalar)
  if (!node.IsDefined()) return std::string(file);
  return place(file, node.Mark(), column);
}

namespace {
std::string withHint(std::string text, std::string_view hint) {
  if (!hint.empty()) text.append(" (").append(hint).append(")");
  return text;
}
}  // namespace

std::string unknownKeyText(std::string_view hint) { return withHint("unknown key", hint); }
std::string missingKeyText(std::string_view hint) { return withHint("missing key", hint); }
std::string wrongTypeText(std::string_view expected) { return "must be " + std::string(expected); }
std::string wrongTypeText(std::string_view expected, std::string_view got) {
  return wrongTypeText(expected).append(", got '").append(got).append("'");
}
std::string repeatedKeyText(const YAML::Node& first) {
  if (!first.IsDefined() || first.Mark().is_null()) return "repeated key";
  return "repeated key (first given at line " + std::to_string(first.Mark().line + 1) + ")";
}

KeyProblem checkKeys(const YAML::Node& map, std::string_view where,
                     const std::function<bool(const std::string&)>& allowed, std::string_view unknownHint) {
  const std::string prefix = where.empty() ? std::string() : std::string(where) + ".";
  if (!map.IsMap()) return {map, where.empty() ? std::string("(top level)") : std::string(where), wrongTypeText("a mapping")};
  std::map<std::string, YAML::Node> seen;
  for (const auto& kv : map) {
    if (!kv.first.IsScalar())
      return {kv.first, where.empty() ? std::string("(key)") : std::string(where), "keys must be names"};
    const std::string k = kv.first.Scalar();
    if (!allowed(k)) return {kv.first, prefix + k, unknownKeyText(unknownHint)};
    // yaml-cpp keeps both entries of a repeated key and answers map[k] with the first: the second
    // would be ignored without a word
    if (auto [it, fresh] = seen.emplace(k, kv.first); !fresh) return {kv.first, prefix + k, repeatedKeyText(it->second)};
  }
  return {};
}

// yaml-cpp 0.7's LoadAll never returns on some malformed input (fuzz_pool_yaml found one that
// YAML::Load parses at once), so the first document is loaded alone and a second one is found by
// its marker: a line "---" (alone or before a space) at column 0 after the first document's
// content began, followed by more content. A marker at column 0 always starts a document (it
// ends even a block scalar), so no text of the first document is taken for one.
YAML::Node loadOneDocument(const std::string& text) {
  YAML::Node doc = YAML::Load(text);
  bool content = false, marker = false;
  int line = 0;
  for (std::size_t at = 0; at < text.size(); ++line) {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    const std::string_view l(text.data() + at, end - at);
    at = end + 1;
    const std::size_t first = l.find_first_not_of(" \t\r");
    if (first == std::string_view::npos || l[first] == '#') continue;  // blank or a comment
    // what follows a 3-character marker on its line: nothing, a comment, or content ("--- value")
    const std::size_t rest = l.size() > 3 ? l.find_first_not_of(" \t\r", 3) : std::string_view::npos;
    const bool bare = rest == std::string_view::npos || l[rest] == '#';
    const bool isMarker = l.substr(0, 3) == "---" && (l.size() == 3 || l[3] == ' ' || l[3] == '\t' || l[3] == '\r');
    if (l.substr(0, 3) == "..." && bare) continue;  // a document's end
    if (isMarker) {
      if (content) marker = true;
      if (bare) continue;
    }
    if (marker) {
      YAML::Mark m;
      m.line = line;
      m.pos = static_cast<int>(at - l.size() - 1);
      throw YAML::ParserException(m, "a second YAML document (after ---): the file must hold one");
    }
    content = true;
  }
  return doc;
}

YAML::Node loadText(const std::string& text, std::string_view file, std::string& error, bool column) {
  error.clear();
  try {
    return loadOneDocument(text);
  } catch (const YAML::Exception& e) {
    error = place(file, e.mark, column) + ": malformed YAML: " + e.msg;
  }
  return YAML::Node();
}

YAML::Node loadFile(const fs::path& file, std::string& error) {
  error.clear();
  std::error_code ec;
  if (fs::is_directory(file, ec)) {
    error = file.string() + ": is a directory, not a YAML file";
    return YAML::Node();
  }
  std::string text;
  if (!readTextFile(file, text, error)) return YAML::Node();
  return loadText(text, file.string(), error);
}

}  // namespace st::io
