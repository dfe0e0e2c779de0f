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
std::string repeatedKeyText(const YAML::Node& first) {
  if (!first.IsDefined() || first.Mark().is_null()) return "repeated key";
  return "repeated key (first given at line " + std::to_string(first.Mark().line + 1) + ")";
}

KeyProblem checkKeys(const YAML::Node& map, std::string_view where,
                     const std::function<bool(const std::string&)>& allowed, std::string_view unknownHint) {
  const std::string prefix = where.empty() ? std::string() : std::string(where) + ".";
  if (!map.IsMap()) return {map, where.empty() ? std::string("(top level)") : std::string(where), "must be a mapping"};
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

YAML::Node loadOneDocument(const std::string& text) {
  std::vector<YAML::Node> docs = YAML::LoadAll(text);
  for (std::size_t i = 1; i < docs.size(); ++i)
    if (!docs[i].IsNull())
      throw YAML::ParserException(docs[i].Mark(), "a second YAML document (after ---): the file must hold one");
  return docs.empty() ? YAML::Node() : docs.front();
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
