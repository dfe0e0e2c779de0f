#include <stbatch/run_result.hpp>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

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

// Numeric leaves of a JSON document as (dotted.key, value). An array element that is an object
// naming itself ("detector" or "name", as validation.json's per-detector entries do) is reached
// by that name; other array elements are skipped.
void flatten(const boost::property_tree::ptree& t, const std::string& prefix,
             std::vector<std::pair<std::string, double>>& out) {
  for (const auto& [key, child] : t) {
    std::string label = key;
    if (label.empty()) {  // array element
      for (const char* k : {"detector", "name"})
        if (auto n = child.get_optional<std::string>(k); n && !n->empty() && label.empty()) label = *n;
      if (label.empty()) continue;
    }
    const std::string name = prefix.empty() ? label : prefix + "." + label;
    if (child.empty()) {
      const std::string v = child.data();
      char* end = nullptr;
      const double d = std::strtod(v.c_str(), &end);
      if (!v.empty() && end && *end == '\0') out.emplace_back(name, d);
      else if (v == "true" || v == "false") out.emplace_back(name, v == "true" ? 1.0 : 0.0);
      // null: a figure with nothing to count (a share of nothing, no lead time): kept as NaN, so
      // the column is there and its cell empty, never 0 or 1
      else if (v == "null") out.emplace_back(name, std::numeric_limits<double>::quiet_NaN());
    } else {
      flatten(child, name, out);
    }
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
      boost::property_tree::ptree tree;
      boost::property_tree::read_json((dir / "summary.json").string(), tree);
      flatten(tree, "", r.metrics);
      nullLeadTimes(r.metrics);
      // --validate-ssm / validate_ssm: the agreement with SUMO's SSM device, as ssm.*
      if (fs::exists(dir / "validation.json")) {
        boost::property_tree::ptree validation;
        boost::property_tree::read_json((dir / "validation.json").string(), validation);
        flatten(validation, "ssm", r.metrics);
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
