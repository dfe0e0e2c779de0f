#include <stbatch/experiment.hpp>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include <stcore/hash.hpp>
#include <stio/yaml.hpp>

namespace st::batch {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const Experiment& e, const std::string& key, const YAML::Node& at, const std::string& what) {
  io::Yaml<ExperimentError>(e.file.string()).fail(at, key, what);
}

std::vector<std::string> splitKey(const std::string& key) {
  // by hand: clang 14 (the fuzz build) cannot compile libstdc++ 12's views::split
  std::vector<std::string> parts(1);
  for (char c : key) {
    if (c == '.') parts.emplace_back();
    else parts.back() += c;
  }
  return parts;
}

bool hasKey(const YAML::Node& root, const std::string& key) {
  YAML::Node n = YAML::Clone(root);
  for (const auto& part : splitKey(key)) {
    if (!n.IsMap() || !n[part]) return false;
    n = n[part];
  }
  return true;
}

void setKey(YAML::Node root, const std::string& key, const std::string& value) {
  const auto parts = splitKey(key);
  YAML::Node n = root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    if (!n[parts[i]] || !n[parts[i]].IsMap()) n[parts[i]] = YAML::Node(YAML::NodeType::Map);
    n.reset(n[parts[i]]);
  }
  n[parts.back()] = YAML::Load(value);
}

std::string scalarText(const YAML::Node& n) {
  YAML::Emitter out;
  out << YAML::Flow << n;
  return out.c_str();
}

std::string slug(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : '_';
  return out;
}

// Relative paths in the base that name existing files become absolute: the run's scenario is
// written into the run's folder, far from the base.
void absolutizePaths(YAML::Node n, const fs::path& baseDir) {
  if (n.IsMap()) {
    for (auto it = n.begin(); it != n.end(); ++it) absolutizePaths(it->second, baseDir);
  } else if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i) absolutizePaths(n[i], baseDir);
  } else if (n.IsScalar()) {
    const std::string v = n.Scalar();
    if (v.empty() || v.size() > 4096 || fs::path(v).is_absolute()) return;
    std::error_code ec;
    if (v.find('/') != std::string::npos || v.find('.') != std::string::npos)
      if (fs::exists(baseDir / v, ec)) n = fs::weakly_canonical(baseDir / v).string();
  }
}

// warmup: and report: (after command:, which they depend on)
void readAnalysis(Experiment& e, const io::Yaml<ExperimentError>& y, const YAML::Node& root) {
  if (const YAML::Node w = root["warmup"]) {
    if (e.command != "highway") fail(e, "warmup", w, "applies to highway experiments (their conflicts.csv) only");
    double v = std::nan("");
    try {
      if (w.IsScalar()) v = w.as<double>();
    } catch (const YAML::Exception&) {
    }
    if (!(v >= 0.0 && v < 1e9)) fail(e, "warmup", w, "must be seconds >= 0 (from each run's start, left out of every statistic)");
    e.warmup = v;
  }
  if (const YAML::Node r = root["report"]) {
    if (e.command != "highway") fail(e, "report", r, "applies to highway experiments only");
    if (!r.IsMap()) y.wrongType(r, "report", "a mapping (report: {headline: conflicts_per_vehicle_km})");
    y.onlyKeys(r, "report", [](const std::string& k) { return k == "headline"; }, "expected headline");
    if (const YAML::Node h = r["headline"]) {
      std::string list;
      for (const char* k : kHeadlines) list.append(list.empty() ? "" : ", ").append(k);
      if (!h.IsScalar()) y.wrongType(h, "report.headline", "one of " + list);
      e.headline = h.as<std::string>();
      if (std::find(std::begin(kHeadlines), std::end(kHeadlines), e.headline) == std::end(kHeadlines))
        fail(e, "report.headline", h, "unknown headline '" + e.headline + "': expected one of " + list);
    }
  }
}

using Reader = io::Yaml<ExperimentError>;

// name:, command: and seed_key:
void readHeader(Experiment& e, const Reader& y, const YAML::Node& root) {
  if (root["name"] && !root["name"].IsScalar()) fail(e, "name", root["name"], "must be a plain folder name, got a list or map");
  e.name = root["name"] ? root["name"].as<std::string>() : e.file.stem().string();
  // the name is the default output folder out/<name>: one plain folder name, never a path
  if (e.name.empty() || e.name == "." || e.name == ".." || e.name.find_first_of("/\\") != std::string::npos)
    fail(e, "name", root["name"] ? root["name"] : root,
         "must be a plain folder name (no '/', not '.' or '..'), got '" + e.name + "'");
  if (root["command"]) {
    if (!root["command"].IsScalar()) y.wrongType(root["command"], "command", "a command name");
    e.command = root["command"].as<std::string>();
    if (e.command != "highway" && e.command != "pool" && e.command != "arm")
      fail(e, "command", root["command"], "must be highway, pool or arm");
  }
  if (root["seed_key"]) {
    if (!root["seed_key"].IsScalar()) y.wrongType(root["seed_key"], "seed_key", "a key name");
    e.seedKey = root["seed_key"].as<std::string>();
  }
}

// A base scenario file named at `at`, relative to the experiment's folder, made absolute.
fs::path baseFile(const Experiment& e, const Reader& y, const YAML::Node& at, const std::string& key) {
  if (!at.IsScalar()) y.wrongType(at, key, "a scenario file");
  fs::path p = at.as<std::string>();
  if (p.is_relative()) p = e.file.parent_path() / p;
  if (!fs::exists(p)) fail(e, key, at, "no such file: " + p.string());
  return fs::weakly_canonical(p);
}

// One entry of a base map: a file, or {scenario: FILE, fixed: {key: value}}.
NamedBase namedBase(const Experiment& e, const Reader& y, const std::string& name, const YAML::Node& n) {
  NamedBase b{name, {}, {}};
  const std::string where = "base." + name;
  if (!n.IsMap()) {
    b.file = baseFile(e, y, n, where);
    return b;
  }
  y.onlyKeys(n, where, [](const std::string& k) { return k == "scenario" || k == "fixed"; },
             "expected scenario (the file) and fixed (this base's overrides)");
  if (!n["scenario"]) y.missingKey(n, where + ".scenario", "the base scenario file");
  b.file = baseFile(e, y, n["scenario"], where + ".scenario");
  if (const YAML::Node fixed = n["fixed"]) {
    if (!fixed.IsMap()) y.wrongType(fixed, where + ".fixed", "a mapping of scenario keys to values");
    y.onlyKeys(fixed, where + ".fixed", [](const std::string&) { return true; });
    for (auto f = fixed.begin(); f != fixed.end(); ++f) {
      if (!f->second.IsScalar()) y.wrongType(f->second, where + ".fixed." + f->first.Scalar(), "a scalar");
      b.fixed[f->first.Scalar()] = scalarText(f->second);
    }
  }
  return b;
}

// base: one scenario file, or a map name -> file (several bases: a sweep axis over the names)
void readBases(Experiment& e, const Reader& y, const YAML::Node& root) {
  const YAML::Node baseNode = root["base"];
  if (!baseNode) y.missingKey(root, "base", "the base scenario file");
  if (!baseNode.IsScalar() && !baseNode.IsMap())
    y.wrongType(baseNode, "base", "a scenario file, or a map of names to scenario files");
  if (baseNode.IsScalar()) {
    e.base = baseFile(e, y, baseNode, "base");
    return;
  }
  if (baseNode.size() == 0) fail(e, "base", baseNode, "empty map: name at least one base scenario");
  y.onlyKeys(baseNode, "base", [](const std::string&) { return true; });
  SweepAxis axis{kBaseAxis, {}};
  for (auto it = baseNode.begin(); it != baseNode.end(); ++it) {
    const std::string name = it->first.as<std::string>();
    if (name.empty()) fail(e, "base", it->first, "a base's name must not be empty");
    e.bases.push_back(namedBase(e, y, name, it->second));
    axis.values.push_back(name);
  }
  e.base = e.bases.front().file;
  e.sweep.push_back(std::move(axis));
}

// Which scenario keys an experiment may set: a key every base has (a run of a base without it
// would fail), or one the command documents as optional.
struct ScenarioKeys {
  std::vector<std::pair<fs::path, YAML::Node>> bases;  // every base, loaded
  std::vector<std::string> optionalKeys;

  bool optional(const std::string& k) const {
    return std::any_of(optionalKeys.begin(), optionalKeys.end(), [&](const std::string& o) { return o == k || o == "*"; });
  }
  // the first base that lacks k (and k not optional), or null
  const fs::path* lackingBase(const std::string& k) const {
    if (optional(k)) return nullptr;
    for (const auto& b : bases)
      if (!hasKey(b.second, k)) return &b.first;
    return nullptr;
  }
  void check(const Experiment& e, const std::string& k, const YAML::Node& at) const {
    if (const fs::path* lacking = lackingBase(k))
      fail(e, k, at, "unknown key: not in the base scenario " + lacking->filename().string());
  }
};

// seeds: a count (1..n) or an explicit list of integers
void readSeeds(Experiment& e, const Reader& y, const YAML::Node& seeds) {
  if (!seeds) {
    e.seeds = {1};
  } else if (seeds.IsScalar()) {
    long n = 0;
    try {
      n = seeds.as<long>();
    } catch (const YAML::Exception&) {
      y.wrongType(seeds, "seeds", "a count or a list of integers");
    }
    if (n < 1 || n > 100000) fail(e, "seeds", seeds, "count must be between 1 and 100000");
    for (long s = 1; s <= n; ++s) e.seeds.push_back(s);
  } else if (seeds.IsSequence()) {
    if (seeds.size() == 0) fail(e, "seeds", seeds, "empty list");
    for (const auto& s : seeds) {
      try {
        e.seeds.push_back(s.as<std::int64_t>());
      } catch (const YAML::Exception&) {
        y.wrongType(s, "seeds", "a list of integers");
      }
      // two equal seeds would be one run id twice: the same run, written twice at once
      if (std::count(e.seeds.begin(), e.seeds.end(), e.seeds.back()) > 1)
        fail(e, "seeds", s, "seed " + std::to_string(e.seeds.back()) + " is given twice");
    }
  } else {
    y.wrongType(seeds, "seeds", "a count or a list of integers");
  }
}

// One swept key's values: a value, or a list of distinct scalars.
SweepAxis sweepAxis(const Experiment& e, const Reader& y, const std::string& k, const YAML::Node& n) {
  SweepAxis axis{k, {}};
  if (n.IsScalar()) {
    axis.values.push_back(scalarText(n));
  } else if (n.IsSequence()) {
    if (n.size() == 0) fail(e, "sweep." + k, n, "empty sweep: give at least one value");
    for (const auto& v : n) {
      if (!v.IsScalar()) y.wrongType(v, "sweep." + k, "a list of scalars");
      axis.values.push_back(scalarText(v));
      if (std::count(axis.values.begin(), axis.values.end(), axis.values.back()) > 1)
        fail(e, "sweep." + k, v, "value " + axis.values.back() + " is given twice");
    }
  } else {
    y.wrongType(n, "sweep." + k, "a value or a list of values");
  }
  return axis;
}

void readSweep(Experiment& e, const Reader& y, const YAML::Node& sweep, const ScenarioKeys& keys) {
  if (!sweep) return;
  if (!sweep.IsMap()) y.wrongType(sweep, "sweep", "a mapping of scenario keys to lists of values");
  if (sweep.size() == 0) fail(e, "sweep", sweep, "empty: give at least one key, or leave sweep out");
  y.onlyKeys(sweep, "sweep", [](const std::string&) { return true; });
  for (auto it = sweep.begin(); it != sweep.end(); ++it) {
    const std::string k = it->first.as<std::string>();
    if (k == kBaseAxis && !e.bases.empty())
      fail(e, "sweep." + k, it->first, "the bases are swept by base: itself (a map of names to scenario files)");
    keys.check(e, k, it->first);
    if (k == e.seedKey) fail(e, k, it->first, "sweep seeds with the top-level 'seeds' key");
    const YAML::Node values = it->second;  // a range-for over a temporary's member would dangle
    e.sweep.push_back(sweepAxis(e, y, k, values));
  }
}

// a base's own overrides: keys of that base, and not swept (the sweep would override them)
void checkBaseOverrides(const Experiment& e, const YAML::Node& baseNode, const ScenarioKeys& keys) {
  for (std::size_t i = 0; i < e.bases.size(); ++i)
    for (const auto& kv : e.bases[i].fixed) {
      const std::string& k = kv.first;
      const YAML::Node at = baseNode[e.bases[i].name]["fixed"];
      const std::string where = "base." + e.bases[i].name + ".fixed." + k;
      if (!hasKey(keys.bases[i].second, k) && !keys.optional(k))
        fail(e, where, at, "unknown key: not in the base scenario " + e.bases[i].file.filename().string());
      for (const auto& axis : e.sweep)
        if (axis.key == k) fail(e, where, at, "is swept: a base cannot fix it");
      if (k == e.seedKey) fail(e, where, at, "the seeds are the top-level 'seeds' key");
    }
}

void readFixed(Experiment& e, const Reader& y, const YAML::Node& fixed, const ScenarioKeys& keys) {
  if (!fixed) return;
  if (!fixed.IsMap()) y.wrongType(fixed, "fixed", "a mapping of scenario keys to values");
  y.onlyKeys(fixed, "fixed", [](const std::string&) { return true; });
  for (auto it = fixed.begin(); it != fixed.end(); ++it) {
    const std::string k = it->first.as<std::string>();
    keys.check(e, k, it->first);
    if (!it->second.IsScalar()) y.wrongType(it->second, "fixed." + k, "a scalar");
    e.fixed[k] = scalarText(it->second);
  }
}

}  // namespace

Experiment loadExperiment(const fs::path& file, const std::vector<std::string>& optionalKeys) {
  return loadExperiment(file, [&](const std::string&) { return optionalKeys; });
}

Experiment loadExperiment(const fs::path& file,
                          const std::function<std::vector<std::string>(const std::string&)>& optionalKeysFor) {
  Experiment e;
  e.file = file;
  const Reader y(file.string());
  const YAML::Node root = y.load(file);
  if (!root.IsMap()) throw ExperimentError(file.string() + ": an experiment is a YAML map (base, sweep, seeds, ...)");
  static const std::set<std::string> known = {"name", "command", "base",     "sweep", "fixed",
                                              "seeds", "seed_key", "warmup", "report"};
  y.onlyKeys(root, "", [](const std::string& k) { return known.count(k) > 0; },
             "expected one of name, command, base, sweep, fixed, seeds, seed_key, warmup, report");
  readHeader(e, y, root);
  readAnalysis(e, y, root);
  readBases(e, y, root);

  ScenarioKeys keys;
  if (e.bases.empty()) keys.bases.emplace_back(e.base, y.load(e.base));
  for (const auto& b : e.bases) keys.bases.emplace_back(b.file, y.load(b.file));
  keys.optionalKeys = optionalKeysFor(e.command);
  // every run sets the seed key: a key the scenarios do not have fails every run, so say it once here
  if (const fs::path* lacking = keys.lackingBase(e.seedKey))
    fail(e, "seed_key", root["seed_key"] ? root["seed_key"] : root,
         "'" + e.seedKey + "' is not a key of the base scenario " + lacking->filename().string() +
             " (seed_key names the key each run's seed goes to)");

  readSeeds(e, y, root["seeds"]);
  readSweep(e, y, root["sweep"], keys);
  checkBaseOverrides(e, root["base"], keys);
  readFixed(e, y, root["fixed"], keys);
  return e;
}

std::uint64_t runCount(const Experiment& e) {
  std::uint64_t n = e.seeds.size();
  for (const SweepAxis& a : e.sweep) {
    const std::uint64_t k = a.values.size();
    n = k != 0 && n > std::numeric_limits<std::uint64_t>::max() / k ? std::numeric_limits<std::uint64_t>::max() : n * k;
  }
  return n;
}

std::vector<RunSpec> expandRuns(const Experiment& e, std::uint64_t maxRuns) {
  if (const std::uint64_t n = runCount(e); n > maxRuns) {
    std::string shape;
    for (const SweepAxis& a : e.sweep) shape += std::to_string(a.values.size()) + " " + a.key + " x ";
    throw ExperimentError(e.file.string() + ": the experiment makes " + std::to_string(n) + " runs (" + shape +
                          std::to_string(e.seeds.size()) + " seeds), more than the limit of " + std::to_string(maxRuns) +
                          " (raise it with --max-runs N)");
  }
  std::vector<RunSpec> runs;
  std::vector<std::size_t> idx(e.sweep.size(), 0);
  while (true) {
    for (std::int64_t seed : e.seeds) {
      RunSpec r;
      r.index = static_cast<int>(runs.size());
      r.seed = seed;
      for (std::size_t a = 0; a < e.sweep.size(); ++a) r.params.emplace_back(e.sweep[a].key, e.sweep[a].values[idx[a]]);
      // id: readable values plus a hash of the sorted key=value list, independent of sweep order
      auto sorted = r.params;
      std::sort(sorted.begin(), sorted.end());
      std::string canon, readable;
      for (const auto& [k, v] : sorted) canon.append(k).append("=").append(v).append(";");
      canon.append(e.seedKey).append("=").append(std::to_string(seed));
      for (const auto& [k, v] : sorted) readable.append(slug(v).substr(0, 16)).append("_");
      readable.append("s").append(std::to_string(seed));
      const std::uint64_t h = st::fnv1a(canon);
      char hex[9];
      std::snprintf(hex, sizeof hex, "%08x", static_cast<unsigned>((h ^ (h >> 32)) & 0xffffffffu));
      r.id = readable + "-" + hex;
      runs.push_back(std::move(r));
    }
    // odometer over the sweep axes, last axis fastest
    int a = static_cast<int>(e.sweep.size()) - 1;
    for (; a >= 0; --a) {
      if (++idx[a] < e.sweep[a].values.size()) break;
      idx[a] = 0;
    }
    if (a < 0) break;
  }
  return runs;
}

namespace {

const NamedBase* namedBaseOf(const Experiment& e, const RunSpec& run) {
  if (e.bases.empty()) return nullptr;
  for (const auto& [k, v] : run.params)
    if (k == kBaseAxis)
      for (const auto& b : e.bases)
        if (b.name == v) return &b;
  throw std::invalid_argument("run " + run.id + " names no base of the experiment");
}

}  // namespace

fs::path baseOf(const Experiment& e, const RunSpec& run) {
  if (const NamedBase* b = namedBaseOf(e, run)) return b->file;
  return e.base;
}

std::string runScenarioYaml(const Experiment& e, const RunSpec& run) {
  const fs::path base = baseOf(e, run);
  YAML::Node root = YAML::LoadFile(base.string());
  absolutizePaths(root, base.parent_path());
  for (const auto& [k, v] : e.fixed) setKey(root, k, v);
  if (const NamedBase* b = namedBaseOf(e, run))
    for (const auto& [k, v] : b->fixed) setKey(root, k, v);
  for (const auto& [k, v] : run.params)
    if (e.bases.empty() || k != kBaseAxis) setKey(root, k, v);
  setKey(root, e.seedKey, std::to_string(run.seed));
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

std::vector<RunSpec> shardRuns(const std::vector<RunSpec>& runs, int shard, int count) {
  if (count < 1 || shard < 1 || shard > count)
    throw std::invalid_argument("--shard I/N needs 1 <= I <= N");
  std::vector<RunSpec> out;
  for (const auto& r : runs)
    if (r.index % count == shard - 1) out.push_back(r);
  return out;
}

}  // namespace st::batch
