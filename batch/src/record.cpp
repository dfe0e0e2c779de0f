#include <stbatch/record.hpp>

#include <yaml-cpp/yaml.h>

#include <limits>

#include <stbatch/tables.hpp>
#include <stio/output.hpp>

#include "files.hpp"

namespace st::batch {

namespace fs = std::filesystem;
using namespace detail;

namespace {

std::string experimentRecord(const Experiment& e) {
  YAML::Emitter em;
  em << YAML::BeginMap;
  em << YAML::Key << "name" << YAML::Value << e.name;
  em << YAML::Key << "command" << YAML::Value << e.command;
  if (e.bases.empty()) {
    em << YAML::Key << "base" << YAML::Value << e.base.string();
  } else {
    em << YAML::Key << "base" << YAML::Value << YAML::BeginMap;
    for (const auto& b : e.bases) {
      em << YAML::Key << b.name << YAML::Value;
      if (b.fixed.empty()) {
        em << b.file.string();
        continue;
      }
      em << YAML::BeginMap << YAML::Key << "scenario" << YAML::Value << b.file.string() << YAML::Key << "fixed"
         << YAML::Value << YAML::BeginMap;
      for (const auto& [k, v] : b.fixed) em << YAML::Key << k << YAML::Value << YAML::Load(v);
      em << YAML::EndMap << YAML::EndMap;
    }
    em << YAML::EndMap;
  }
  em << YAML::Key << "seed_key" << YAML::Value << e.seedKey;
  em << YAML::Key << "seeds" << YAML::Value << YAML::Flow << e.seeds;
  // the bases' axis is base: itself
  const bool onlyBases = e.sweep.size() == 1 && !e.bases.empty();
  if (!e.sweep.empty() && !onlyBases) {
    em << YAML::Key << "sweep" << YAML::Value << YAML::BeginMap;
    for (const auto& a : e.sweep) {
      if (!e.bases.empty() && a.key == kBaseAxis) continue;
      em << YAML::Key << a.key << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const auto& v : a.values) em << YAML::Load(v);
      em << YAML::EndSeq;
    }
    em << YAML::EndMap;
  }
  if (!e.fixed.empty()) {
    em << YAML::Key << "fixed" << YAML::Value << YAML::BeginMap;
    for (const auto& [k, v] : e.fixed) em << YAML::Key << k << YAML::Value << YAML::Load(v);
    em << YAML::EndMap;
  }
  em << YAML::EndMap;
  return std::string(em.c_str()) + "\n";
}

// The analysis keys, after the runs' record: a batch resumed with another warm-up or headline
// reuses its runs and analyses them anew.
std::string analysisRecord(const Experiment& e) {
  std::string a;
  if (e.warmup != 0.0) a += "warmup: " + number(e.warmup) + "\n";
  if (e.headline != Experiment{}.headline) a += "report: {headline: " + e.headline + "}\n";
  return a;
}

// A run's folder, every file through io's checked writer: a full disk names the file.
void copyRunDir(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(from)) {
    const fs::path dst = to / fs::relative(entry.path(), from);
    if (entry.is_directory()) fs::create_directories(dst);
    else if (entry.is_regular_file()) io::copyFile(entry.path(), dst);
  }
}

}  // namespace

void checkResumable(const Experiment& e, const fs::path& outDir) {
  const fs::path p = outDir / "experiment.yaml";
  if (!fs::exists(p)) return;
  const std::string runs = experimentRecord(e), held = readFile(p);
  if (held.rfind(runs, 0) != 0)
    throw ExperimentError(p.string() + ": this folder holds the runs of another experiment (its base, sweep, fixed or "
                          "seeds differ from " + e.file.string() + "); give another --out or remove the folder");
}

void writeExperimentRecord(const Experiment& e, const fs::path& outDir) {
  checkResumable(e, outDir);
  fs::create_directories(outDir);
  io::writeFileAtomically(outDir / "experiment.yaml", experimentRecord(e) + analysisRecord(e));
}

Experiment readExperimentRecord(const fs::path& outDir) {
  const fs::path p = outDir / "experiment.yaml";
  if (!fs::exists(p)) throw ExperimentError(outDir.string() + ": not a stsim batch output folder (no experiment.yaml)");
  // keys were validated when the batch ran; accept them all again
  Experiment e = loadExperiment(p, std::vector<std::string>{"*"});
  return e;
}

std::vector<RunResult> mergeShards(const std::vector<fs::path>& dirs, const fs::path& outDir) {
  if (dirs.empty()) throw std::invalid_argument("merge needs at least one batch output folder");
  const Experiment e = readExperimentRecord(dirs.front());
  const std::string record = readFile(dirs.front() / "experiment.yaml");
  for (const auto& d : dirs)
    if (readFile(d / "experiment.yaml") != record)
      throw ExperimentError(d.string() + ": experiment.yaml differs from " + dirs.front().string() + ": not shards of one experiment");
  fs::create_directories(outDir / "runs");
  // the shards ran this experiment: the limit their --max-runs set admitted it
  const auto runs = expandRuns(e, std::numeric_limits<std::uint64_t>::max());
  std::vector<RunResult> results;
  for (const auto& spec : runs) {
    RunResult best;
    best.spec = spec;
    for (const auto& d : dirs) {
      RunResult r = loadRunResult(d, spec);
      if (r.status == RunStatus::Missing) continue;
      if (best.status == RunStatus::Missing || (best.status == RunStatus::Failed && r.status == RunStatus::Done)) {
        best = r;
        const fs::path dst = runDir(outDir, spec);
        if (fs::weakly_canonical(runDir(d, spec)) != fs::weakly_canonical(dst)) {
          fs::remove_all(dst);
          copyRunDir(runDir(d, spec), dst);
        }
      }
    }
    results.push_back(best);
  }
  if (fs::weakly_canonical(dirs.front()) != fs::weakly_canonical(outDir)) writeExperimentRecord(e, outDir);
  writeTables(e, results, outDir);
  return results;
}

}  // namespace st::batch
