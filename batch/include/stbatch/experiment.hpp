#pragma once
// A batch experiment: a base scenario, a sweep over scenario keys, and seeds. The runs are the
// cross product; each has a stable id derived from its parameters, so a re-run finds its results.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace st::batch {

// A malformed experiment: the message names the file, the key and (where known) the line.
struct ExperimentError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SweepAxis {
  std::string key;                  // dotted scenario key, e.g. "detector" or "safe_time.reaction"
  std::vector<std::string> values;  // YAML scalars, in the order given
};

// The sweep axis that a map of base scenarios makes: its values are the bases' names.
inline constexpr const char* kBaseAxis = "base";

// One of several bases: a name (its value in the tables), the scenario file and overrides for
// this base's runs only (`base: {name: {scenario: FILE, fixed: {key: value}}}`), applied after
// the experiment's `fixed`.
struct NamedBase {
  std::string name;
  std::filesystem::path file;  // absolute
  std::map<std::string, std::string> fixed;
  bool operator==(const NamedBase&) const = default;
};

struct Experiment {
  std::filesystem::path file;       // the experiment file
  std::filesystem::path base;       // base scenario (absolute); with several, the first
  // `base:` as a map of name -> scenario file (networks with settings of their own in one
  // experiment): the bases, in file order, and the first sweep axis is kBaseAxis over their names.
  // Empty for a single base.
  std::vector<NamedBase> bases;
  std::string command = "highway";  // the stsim subcommand each run executes
  std::string name;
  std::vector<SweepAxis> sweep;     // in file order; the cross product varies the last fastest
  std::map<std::string, std::string> fixed;  // overrides applied to every run
  std::vector<std::int64_t> seeds;
  std::string seedKey = "seed";
  // The analysis (highway experiments; changing it re-analyses the runs, it reruns none):
  // `warmup:` seconds from each run's start left out of every conflict count, rate and exposure;
  // `report: {headline: H}` the rate report.md leads with, by conflict type (kHeadlines).
  double warmup = 0.0;  // s
  std::string headline = "conflicts_per_vehicle_km";
};

// report.headline's values: conflicts (conflicts.csv, counted once) per vehicle-km driven, per
// hour simulated, per vehicle entering the network, each after the warm-up.
inline constexpr const char* kHeadlines[] = {"conflicts_per_vehicle_km", "conflicts_per_hour",
                                             "conflicts_per_entering_vehicle"};

struct RunSpec {
  int index = 0;  // position in the cross product
  std::string id; // stable: derived from parameters and seed only
  std::vector<std::pair<std::string, std::string>> params;  // sweep key -> value, in sweep order
  std::int64_t seed = 0;
};

// Reads and validates an experiment file. Sweep and fixed keys must name keys of the base
// scenario (or keys the command documents as optional, listed in `optionalKeys`; "*" accepts any).
Experiment loadExperiment(const std::filesystem::path& file,
                          const std::vector<std::string>& optionalKeys = {});
// The same, the optional keys depending on the experiment's command.
Experiment loadExperiment(const std::filesystem::path& file,
                          const std::function<std::vector<std::string>(const std::string& command)>& optionalKeys);

// Runs the experiment makes: the product of its sweep's value counts and its seeds (saturating
// at UINT64_MAX), counted without making them.
std::uint64_t runCount(const Experiment& e);
constexpr std::uint64_t kDefaultMaxRuns = 100000;
// Every run, in index order. Throws ExperimentError naming the count when it exceeds maxRuns
// (before making any: a sweep of 1e8 runs was 8 GB of --list in 20 s).
std::vector<RunSpec> expandRuns(const Experiment& e, std::uint64_t maxRuns = kDefaultMaxRuns);

// The base scenario a run starts from: its `base` value's file with several bases, else e.base.
std::filesystem::path baseOf(const Experiment& e, const RunSpec& run);

// The run's scenario: its base with the run's overrides applied, relative file references made
// absolute (the run scenario is written elsewhere). Returned as YAML text.
std::string runScenarioYaml(const Experiment& e, const RunSpec& run);

// Disjoint slice `shard` (1-based) of `count` for schedulers (Slurm arrays): every count-th run.
std::vector<RunSpec> shardRuns(const std::vector<RunSpec>& runs, int shard, int count);

}  // namespace st::batch
