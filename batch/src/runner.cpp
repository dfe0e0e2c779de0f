#include <stbatch/runner.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <thread>

#include <stio/output.hpp>

#include "files.hpp"

extern char** environ;

namespace st::batch {

namespace fs = std::filesystem;
using namespace detail;

namespace {

// Starts one run: stdout and stderr into `log`, stdin from /dev/null. The run dies with the batch:
// the child asks the kernel for SIGTERM when its parent goes (a batch killed by SIGKILL, or one
// that exits on an error before it could stop its runs), and checks that the parent it asked about
// is still the batch (it may have gone between fork and prctl). PR_SET_PDEATHSIG outlives execve.
// posix_spawn cannot do this, hence fork; after fork the child makes only async-signal-safe calls.
pid_t spawnRun(const std::string& exe, const std::vector<char*>& argv, const std::string& log) {
  int pipeFd[2];  // the exec's errno, if it fails; closed unread (CLOEXEC) when it succeeds
  if (::pipe2(pipeFd, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(pipeFd[0]);
    ::close(pipeFd[1]);
    throw std::runtime_error("cannot start " + exe + ": " + std::strerror(err));
  }
  if (pid == 0) {
    ::close(pipeFd[0]);
    int err = 0;
    if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0) err = errno;
    if (err == 0 && ::getppid() != parent) ::_exit(128 + SIGTERM);  // the batch is already gone
    const int out = err ? -1 : ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (err == 0 && out < 0) err = errno;
    const int in = err ? -1 : ::open("/dev/null", O_RDONLY);
    if (err == 0 && in < 0) err = errno;
    if (err == 0 && (::dup2(out, 1) < 0 || ::dup2(out, 2) < 0 || ::dup2(in, 0) < 0)) err = errno;
    if (err == 0) {
      if (out > 2) ::close(out);
      if (in > 2) ::close(in);
      ::execve(exe.c_str(), argv.data(), environ);
      err = errno;
    }
    [[maybe_unused]] const ssize_t w = ::write(pipeFd[1], &err, sizeof err);
    ::_exit(127);
  }
  ::close(pipeFd[1]);
  int err = 0;
  ssize_t n;
  while ((n = ::read(pipeFd[0], &err, sizeof err)) < 0 && errno == EINTR) {
  }
  ::close(pipeFd[0]);
  if (n == static_cast<ssize_t>(sizeof err)) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    throw std::runtime_error("cannot start " + exe + ": " + std::strerror(err));
  }
  return pid;
}

// Stops the runs still going when the batch leaves executeRuns on an error: SIGTERM (each writes
// what it has and exits), reaped; after 10 s, SIGKILL.
void stopRuns(const std::vector<pid_t>& pids) {
  for (const pid_t pid : pids) ::kill(pid, SIGTERM);
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  for (const pid_t pid : pids) {
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > until) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
}

}  // namespace

FolderLock::FolderLock(const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path file = dir / ".batch.lock";
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(file.string() + ": cannot open: " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char buf[32] = {};
    const ssize_t n = ::pread(fd_, buf, sizeof buf - 1, 0);
    ::close(fd_);
    fd_ = -1;
    if (err != EWOULDBLOCK) throw std::runtime_error(file.string() + ": cannot lock: " + std::strerror(err));
    std::string holder = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
    while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) holder.pop_back();
    throw std::runtime_error(dir.string() + ": folder in use by pid " + (holder.empty() ? "?" : holder) +
                             " (another stsim batch writes it)");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const int err = errno;
    ::close(fd_);
    throw std::runtime_error(file.string() + ": cannot write: " + std::strerror(err));
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);
}

namespace {

// A run in progress: its index in the batch's runs, its folder until it is published, its start.
struct Running {
  std::size_t index;
  fs::path tmp;
  std::chrono::steady_clock::time_point start;
};

// The runs' results as the folder holds them, and the indices of those to run: every one not done,
// and every done one whose scenario this experiment makes differently now (the run id names the
// parameters, not the base's content: an edited base left every old run "done").
std::vector<std::size_t> runsToDo(const Experiment& e, const std::vector<RunSpec>& runs, const BatchOptions& o,
                                  std::vector<RunResult>& results) {
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    results[i] = loadRunResult(o.outDir, runs[i]);
    const fs::path scenario = runDir(o.outDir, runs[i]) / "scenario.yaml";
    if (results[i].status == RunStatus::Done &&
        (!fs::exists(scenario) || readFile(scenario) != runScenarioYaml(e, runs[i]))) {
      if (o.log) o.log(runs[i].id + " stale (its scenario changed since it ran): run again");
      results[i] = RunResult{};
      results[i].spec = runs[i];
    }
    if (results[i].status != RunStatus::Done) todo.push_back(i);  // failed runs are tried again
  }
  return todo;
}

// Starts run i in its .tmp folder: its scenario written there, `stsim COMMAND scenario.yaml`.
std::pair<pid_t, Running> launchRun(const Experiment& e, const std::vector<RunSpec>& runs, std::size_t i,
                                    const BatchOptions& o) {
  const RunSpec& spec = runs[i];
  const fs::path tmp = o.outDir / "runs" / (spec.id + ".tmp");
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  io::writeFileAtomically(tmp / "scenario.yaml", runScenarioYaml(e, spec));
  const std::string exe = o.stsim.string(), scen = (tmp / "scenario.yaml").string(), out = tmp.string();
  std::vector<std::string> args = {exe, e.command, scen, "--out", out};
  // the report draws one conflict map per parameter combination, all seeds together (plots.py)
  if (e.command == "highway") args.emplace_back("--no-map");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = spawnRun(exe, argv, (tmp / "log.txt").string());
  return {pid, Running{i, tmp, std::chrono::steady_clock::now()}};
}

// A run that ended with `status`: its result.yaml written, its folder published in one rename
// (a previous failed attempt replaced), its summary read when it is done.
RunResult finishRun(const Running& run, const RunSpec& spec, int status, const BatchOptions& o) {
  RunResult r;
  r.spec = spec;
  r.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - run.start).count();
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(run.tmp / "summary.json")) {
    r.status = RunStatus::Done;
  } else {
    r.status = RunStatus::Failed;
    if (WIFSIGNALED(status)) r.error = "crashed with signal " + std::to_string(WTERMSIG(status));
    else r.error = "exit " + std::to_string(WEXITSTATUS(status));
    if (std::string l = lastLogLine(run.tmp / "log.txt"); !l.empty()) {
      // the run's folder is renamed below: name its files where they will be
      const std::string from = run.tmp.string(), to = runDir(o.outDir, r.spec).string();
      for (std::size_t at = l.find(from); at != std::string::npos; at = l.find(from, at + to.size()))
        l.replace(at, from.size(), to);
      r.error += ": " + l;
    }
  }
  YAML::Emitter em;
  em << YAML::BeginMap << YAML::Key << "status" << YAML::Value << toString(r.status) << YAML::Key << "error"
     << YAML::Value << r.error << YAML::Key << "wall_seconds" << YAML::Value << r.wallSeconds << YAML::EndMap;
  io::writeFileAtomically(run.tmp / "result.yaml", std::string(em.c_str()) + "\n");
  const fs::path dir = runDir(o.outDir, r.spec);
  fs::remove_all(dir);
  fs::rename(run.tmp, dir);
  if (r.status == RunStatus::Done) {
    const RunResult loaded = loadRunResult(o.outDir, r.spec);
    r.metrics = loaded.metrics;
    if (loaded.status != RunStatus::Done) {
      r.status = loaded.status;
      r.error = loaded.error;
    }
    r.reused = false;
  }
  return r;
}

// an error in the loop (a file that cannot be written, a callback that throws) leaves with the runs stopped
struct StopOnError {
  std::map<pid_t, Running>& running;
  ~StopOnError() {
    if (running.empty()) return;
    std::vector<pid_t> pids;
    for (const auto& kv : running) pids.push_back(kv.first);
    stopRuns(pids);
  }
};

}  // namespace

std::vector<RunResult> executeRuns(const Experiment& e, const std::vector<RunSpec>& runs, const BatchOptions& o) {
  fs::create_directories(o.outDir / "runs");
  std::vector<RunResult> results(runs.size());
  const std::vector<std::size_t> todo = runsToDo(e, runs, o, results);
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  int finished = static_cast<int>(runs.size() - todo.size());
  const int total = static_cast<int>(runs.size());
  if (o.progress) o.progress(finished, total, 0.0);

  std::map<pid_t, Running> running;
  std::size_t next = 0;
  const int jobs = std::max(1, o.jobs);
  auto finish = [&](pid_t pid, int status) {
    const Running run = running.at(pid);
    running.erase(pid);
    RunResult& r = results[run.index];
    r = finishRun(run, runs[run.index], status, o);
    ++finished;
    if (o.log) o.log(r.spec.id + " " + toString(r.status) + (r.error.empty() ? "" : " (" + r.error + ")"));
    if (o.progress) o.progress(finished, total, elapsed());
  };
  const StopOnError stopOnError{running};

  bool forwarded = false;
  while (next < todo.size() || !running.empty()) {
    const bool stopping = o.stopRequested && o.stopRequested();
    if (stopping && !forwarded) {
      // a SIGTERM sent to the batch alone reaches its runs too (Ctrl-C already reached the group):
      // each writes what it has and stops, instead of the batch waiting for them to finish
      for (const auto& kv : running) ::kill(kv.first, SIGTERM);
      forwarded = true;
    }
    while (!stopping && next < todo.size() && static_cast<int>(running.size()) < jobs)
      running.insert(launchRun(e, runs, todo[next++], o));
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    }
    if (running.count(pid)) finish(pid, status);
  }
  return results;
}

}  // namespace st::batch
