#pragma once
// Executes batch runs, one process per run (libsumo allows one simulation per process), in
// parallel, resumable: a run's results are written into runs/<id>.tmp and renamed to runs/<id>
// when complete, so an interrupted batch never leaves a half-written run behind.
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <stbatch/experiment.hpp>

namespace st::batch {

enum class RunStatus { Done, Failed, Missing };
const char* toString(RunStatus s);

struct RunResult {
  RunSpec spec;
  RunStatus status = RunStatus::Missing;
  std::string error;          // one line, for failed runs
  double wallSeconds = 0.0;
  bool reused = false;        // finished by an earlier invocation
  std::vector<std::pair<std::string, double>> metrics;  // numeric leaves of summary.json, flattened
};

struct BatchOptions {
  std::filesystem::path outDir;
  std::filesystem::path stsim;  // the stsim executable each run invokes
  int jobs = 1;
  // progress(done, total, elapsed seconds) after each run; log(line) for each finished run
  std::function<void(int, int, double)> progress;
  std::function<void(const std::string&)> log;
  // polled between runs: true stops launching new runs (Ctrl-C)
  std::function<bool()> stopRequested;
};

// Runs (or reuses) every run in `runs`; returns their results in the order given.
std::vector<RunResult> executeRuns(const Experiment& e, const std::vector<RunSpec>& runs, const BatchOptions& o);

// Reads the result of one run from outDir/runs/<id>, if there is one.
RunResult loadRunResult(const std::filesystem::path& outDir, const RunSpec& spec);

// Writes runs.csv, summary.csv and paired.csv (atomically) for the given results, in run-index
// order. paired.csv: each swept key's values against its first value, other keys held, as
// differences run by run on the same seed (mean, sd, 95 % CI of the differences). Highway runs
// also get hindsight.csv: per combination, pooled over its seeds, each warning kind's warnings
// per vehicle-km and confirmed share, the near misses' recall and median lead time (empty where
// nothing was counted). A figure a run's summary gives as null is an empty cell in every table.
void writeTables(const Experiment& e, std::vector<RunResult> results, const std::filesystem::path& outDir);

// The experiment as resolved for this batch (absolute base), stored in the output folder so
// shards can be merged and checked to be of the same experiment.
void writeExperimentRecord(const Experiment& e, const std::filesystem::path& outDir);
// Throws ExperimentError if outDir already records a different experiment (resuming it would mix
// the two experiments' runs in one table). Called by writeExperimentRecord.
void checkResumable(const Experiment& e, const std::filesystem::path& outDir);
Experiment readExperimentRecord(const std::filesystem::path& outDir);

// Merges shard output folders into `outDir`: run folders are copied, tables rebuilt.
std::vector<RunResult> mergeShards(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& outDir);

// Plots and report.md via Debian's python3-matplotlib; returns false (with the reason) if unavailable.
bool writePlots(const std::filesystem::path& outDir, std::string& why);

}  // namespace st::batch
