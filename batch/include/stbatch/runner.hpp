#pragma once
// Executes batch runs, one process per run (libsumo allows one simulation per process), in
// parallel, resumable: a run's results are written into runs/<id>.tmp and renamed to runs/<id>
// when complete, so an interrupted batch never leaves a half-written run behind.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <stbatch/experiment.hpp>
#include <stbatch/run_result.hpp>

namespace st::batch {

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

}  // namespace st::batch
