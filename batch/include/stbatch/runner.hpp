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

// An output folder held by one batch: an exclusive flock(2) on DIR/.batch.lock (created with the
// folder), which holds the holder's pid. A second batch on the folder gets std::runtime_error
// "DIR: folder in use by pid N" instead of two batches writing one folder's runs. The kernel drops
// the lock when the holder exits, however it exits; the file stays (removing it would let a third
// batch lock a new file while a second holds the old one).
class FolderLock {
 public:
  explicit FolderLock(const std::filesystem::path& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

// Runs (or reuses) every run in `runs`; returns their results in the order given.
std::vector<RunResult> executeRuns(const Experiment& e, const std::vector<RunSpec>& runs, const BatchOptions& o);

}  // namespace st::batch
