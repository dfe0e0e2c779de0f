// The runner's process rules: a batch's runs die with it, on an error and on SIGKILL,
// and one output folder holds one batch. The runs are a stand-in script (no stsim, no SUMO).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <stbatch/experiment.hpp>
#include <stbatch/runner.hpp>
#include <stdexcept>
#include <thread>

#include "files.hpp"

namespace st::batch {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

fs::path freshDir(const std::string& name) { return st::test::freshDir("batch_runner", name); }

// An experiment of two runs whose "stsim" is `script` (called as: script COMMAND SCENARIO --out DIR).
struct Batch {
  Experiment e;
  std::vector<RunSpec> runs;
  BatchOptions o;
};
Batch makeBatch(const fs::path& dir, const std::string& script) {
  fs::copy_file(fs::path(STSIM_SOURCE_DIR) / "tests/batch/data/base.yaml", dir / "base.yaml");
  std::ofstream(dir / "exp.yaml") << "name: runner\nbase: base.yaml\nseeds: 2\n";
  std::ofstream(dir / "run.sh") << "#!/bin/sh\n" << script;
  fs::permissions(dir / "run.sh", fs::perms::owner_all);
  Batch s;
  s.e = loadExperiment(dir / "exp.yaml");
  s.runs = expandRuns(s.e);
  s.o.outDir = dir / "out";
  s.o.stsim = dir / "run.sh";
  s.o.jobs = 2;
  return s;
}

// The pids the runs wrote into their folders (runs/<id>.tmp/pid), once `count` have.
std::vector<pid_t> runPids(const fs::path& outDir, std::size_t count, double seconds = 10) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
    std::vector<pid_t> pids;
    std::error_code ec;
    for (const auto& d : fs::directory_iterator(outDir / "runs", ec)) {
      std::ifstream in(d.path() / "pid");
      pid_t pid = 0;
      if (in >> pid && pid > 0) pids.push_back(pid);
    }
    if (pids.size() >= count) return pids;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return {};
}

// Alive: exists and is not a zombie.
bool alive(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(in, text)) return false;
  const auto paren = text.rfind(')');
  return paren != std::string::npos && paren + 2 < text.size() && text[paren + 2] != 'Z';
}

bool goneWithin(pid_t pid, double seconds) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (alive(pid)) {
    if (Clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

TEST(BatchRunner, RunsDieWithABatchKilledBySigkill) {
  const fs::path dir = freshDir("sigkill");
  Batch s = makeBatch(dir, "echo $$ > \"$4/pid\"\nexec sleep 60\n");
  const pid_t batch = ::fork();
  ASSERT_GE(batch, 0);
  if (batch == 0) {
    try {
      executeRuns(s.e, s.runs, s.o);
    } catch (...) {
    }
    ::_exit(0);
  }
  const std::vector<pid_t> pids = runPids(s.o.outDir, 2);
  ::kill(batch, SIGKILL);
  ::waitpid(batch, nullptr, 0);
  ASSERT_EQ(pids.size(), 2u) << "the runs did not start";
  for (const pid_t pid : pids) {
    EXPECT_TRUE(goneWithin(pid, 5)) << "run " << pid << " outlived its batch (kill -9)";
    if (alive(pid)) ::kill(pid, SIGKILL);
  }
}

TEST(BatchRunner, AnErrorStopsTheRunsBeforeItLeaves) {
  const fs::path dir = freshDir("error");
  // the first run to start ends at once (and fails: no summary.json); the other keeps going
  Batch s = makeBatch(dir, "if mkdir \"$4/../../first\" 2>/dev/null; then exit 0; fi\necho $$ > \"$4/pid\"\nexec sleep 60\n");
  std::vector<pid_t> pids;
  // the first run's line fails the batch (as a result.yaml that cannot be written does)
  s.o.log = [&](const std::string&) {
    pids = runPids(s.o.outDir, 1);
    throw std::runtime_error("cannot write");
  };
  EXPECT_THROW(executeRuns(s.e, s.runs, s.o), std::runtime_error);
  ASSERT_EQ(pids.size(), 1u) << "the second run did not start";
  EXPECT_FALSE(alive(pids[0])) << "run " << pids[0] << " outlived the batch's error";
  if (alive(pids[0])) ::kill(pids[0], SIGKILL);
}

TEST(BatchRunner, AFolderHoldsOneBatch) {
  const fs::path dir = freshDir("lock");
  int ready[2], done[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(done), 0);
  const pid_t holder = ::fork();
  ASSERT_GE(holder, 0);
  if (holder == 0) {
    const FolderLock lock(dir / "out");
    char c = 1;
    [[maybe_unused]] auto w = ::write(ready[1], &c, 1);
    [[maybe_unused]] auto r = ::read(done[0], &c, 1);  // until the test is done
    ::_exit(0);
  }
  char c = 0;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  std::string what;
  try {
    const FolderLock second(dir / "out");
  } catch (const std::runtime_error& e) {
    what = e.what();
  }
  EXPECT_EQ(what, (dir / "out").string() + ": folder in use by pid " + std::to_string(holder) +
                      " (another stsim batch writes it)");
  [[maybe_unused]] auto w = ::write(done[1], &c, 1);
  ::waitpid(holder, nullptr, 0);
  // the holder gone, the folder is free again
  EXPECT_NO_THROW(FolderLock(dir / "out"));
}

}  // namespace
}  // namespace st::batch
