#include <stbatch/run_result.hpp>

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>

#include "files.hpp"

namespace st::batch {

namespace fs = std::filesystem;
using detail::runDir;

const char* toString(RunStatus s) {
  switch (s) {
    case RunStatus::Done: return "done";
    case RunStatus::Failed: return "failed";
    case RunStatus::Missing: return "missing";
  }
  return "?";
}

namespace {

using Json = nlohmann::ordered_json;  // the document's order is the columns' order

// A JSON file parsed, or an exception naming it.
Json readJson(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot open");
  try {
    return Json::parse(in);
  } catch (const Json::exception& ex) {
    throw std::runtime_error(file.string() + ": " + ex.what());
  }
}

// A leaf as a number: numbers as they are, true/false as 1/0, null as NaN (a figure with nothing
// to count, a share of nothing, no lead time: the column is there and its cell empty, never 0 or
// 1), a string that is a whole number as that number (the arm's infinite times, "inf"); none for
// other strings.
std::optional<double> leafNumber(const Json& v) {
  if (v.is_number()) return v.get<double>();
  if (v.is_boolean()) return v.get<bool>() ? 1.0 : 0.0;
  if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v.is_string()) return std::nullopt;
  const std::string& text = v.get_ref<const std::string&>();
  char* end = nullptr;
  const double d = std::strtod(text.c_str(), &end);
  if (!text.empty() && end && *end == '\0') return d;
  return std::nullopt;
}

// Numeric leaves of a JSON document as (dotted.key, value). An array element that is an object
// naming itself ("detector" or "name", as validation.json's per-detector entries do) is reached
// by that name; other array elements are skipped.
void flatten(const Json& t, const std::string& prefix, std::vector<std::pair<std::string, double>>& out) {
  const auto visit = [&](const std::string& label, const Json& child) {
    const std::string name = prefix.empty() ? label : prefix + "." + label;
    if (child.is_structured()) {
      flatten(child, name, out);
    } else if (const auto x = leafNumber(child)) {
      out.emplace_back(name, *x);
    }
  };
  if (t.is_object()) {
    for (auto it = t.begin(); it != t.end(); ++it) visit(it.key(), it.value());
    return;
  }
  for (const Json& child : t) {  // array elements
    if (!child.is_object()) continue;
    std::string label;
    for (const char* k : {"detector", "name"}) {
      const auto n = child.find(k);
      if (label.empty() && n != child.end() && n->is_string()) label = n->get<std::string>();
    }
    if (!label.empty()) visit(label, child);
  }
}

// summary.json writes the events' lead times as null when none was warned: that null
// stands for the distribution's three figures, so their columns are there, empty
void nullLeadTimes(std::vector<std::pair<std::string, double>>& metrics) {
  for (const std::string lead : {"hindsight.near_misses.lead_s", "hindsight.crossings.lead_s", "collisions.lead_s"}) {
    const auto at = std::find_if(metrics.begin(), metrics.end(), [&](const auto& m) { return m.first == lead; });
    if (at == metrics.end() || !std::isnan(at->second)) continue;
    const double none = at->second;
    const auto next = metrics.erase(at);
    metrics.insert(next, {{lead + ".min", none}, {lead + ".median", none}, {lead + ".p90", none}});
  }
}

}  // namespace

RunResult loadRunResult(const fs::path& outDir, const RunSpec& spec) {
  RunResult r;
  r.spec = spec;
  const fs::path dir = runDir(outDir, spec);
  if (!fs::exists(dir / "result.yaml")) return r;
  try {
    const YAML::Node res = YAML::LoadFile((dir / "result.yaml").string());
    r.status = res["status"].as<std::string>() == "done" ? RunStatus::Done : RunStatus::Failed;
    r.error = res["error"] ? res["error"].as<std::string>() : "";
    r.wallSeconds = res["wall_seconds"] ? res["wall_seconds"].as<double>() : 0.0;
  } catch (const YAML::Exception&) {
    return r;  // unreadable result: the run is redone
  }
  if (r.status == RunStatus::Done) {
    try {
      flatten(readJson(dir / "summary.json"), "", r.metrics);
      nullLeadTimes(r.metrics);
      // --validate-ssm / validate_ssm: the agreement with SUMO's SSM device, as ssm.*
      if (fs::exists(dir / "validation.json")) {
        flatten(readJson(dir / "validation.json"), "ssm", r.metrics);
      }
    } catch (const std::exception& ex) {
      r.status = RunStatus::Failed;
      r.error = std::string("summary.json unreadable: ") + ex.what();
    }
  }
  r.reused = true;
  return r;
}

}  // namespace st::batch
