#include <stbatch/runner.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>

#include "files.hpp"

extern char** environ;

namespace st::batch {

namespace fs = std::filesystem;
using namespace detail;

std::vector<RunResult> executeRuns(const Experiment& e, const std::vector<RunSpec>& runs, const BatchOptions& o) {
  fs::create_directories(o.outDir / "runs");
  std::vector<RunResult> results(runs.size());
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    results[i] = loadRunResult(o.outDir, runs[i]);
    // a finished run is reused only if it ran the scenario this experiment makes of it now: the
    // run id names the parameters, not the base's content (an edited base left every old run "done")
    if (results[i].status == RunStatus::Done &&
        readFile(runDir(o.outDir, runs[i]) / "scenario.yaml") != runScenarioYaml(e, runs[i])) {
      if (o.log) o.log(runs[i].id + " stale (its scenario changed since it ran): run again");
      results[i] = RunResult{};
      results[i].spec = runs[i];
    }
    if (results[i].status != RunStatus::Done) todo.push_back(i);  // failed runs are tried again
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  int finished = static_cast<int>(runs.size() - todo.size());
  const int total = static_cast<int>(runs.size());
  if (o.progress) o.progress(finished, total, 0.0);

  struct Running {
    std::size_t index;
    fs::path tmp;
    std::chrono::steady_clock::time_point start;
  };
  std::map<pid_t, Running> running;
  std::size_t next = 0;
  const int jobs = std::max(1, o.jobs);

  auto launch = [&](std::size_t i) {
    const RunSpec& spec = runs[i];
    const fs::path tmp = o.outDir / "runs" / (spec.id + ".tmp");
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    writeFileAtomically(tmp / "scenario.yaml", runScenarioYaml(e, spec));
    const std::string exe = o.stsim.string(), scen = (tmp / "scenario.yaml").string(), out = tmp.string();
    std::vector<std::string> args = {exe, e.command, scen, "--out", out};
    // the report draws one conflict map per parameter combination, all seeds together (plots.py)
    if (e.command == "highway") args.emplace_back("--no-map");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    const std::string log = (tmp / "log.txt").string();
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) throw std::runtime_error("cannot start " + exe + ": " + std::strerror(rc));
    running[pid] = Running{i, tmp, std::chrono::steady_clock::now()};
  };

  auto finish = [&](pid_t pid, int status) {
    const Running run = running.at(pid);
    running.erase(pid);
    RunResult& r = results[run.index];
    r = RunResult{};
    r.spec = runs[run.index];
    r.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - run.start).count();
    const std::string log = readFile(run.tmp / "log.txt");
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(run.tmp / "summary.json")) {
      r.status = RunStatus::Done;
    } else {
      r.status = RunStatus::Failed;
      if (WIFSIGNALED(status)) r.error = "crashed with signal " + std::to_string(WTERMSIG(status));
      else r.error = "exit " + std::to_string(WEXITSTATUS(status));
      if (std::string l = lastLine(log); !l.empty()) {
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
    writeFileAtomically(run.tmp / "result.yaml", std::string(em.c_str()) + "\n");
    // publish the finished run in one rename; a previous failed attempt is replaced
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
    ++finished;
    if (o.log) o.log(r.spec.id + " " + toString(r.status) + (r.error.empty() ? "" : " (" + r.error + ")"));
    if (o.progress) o.progress(finished, total, elapsed());
  };

  bool forwarded = false;
  while (next < todo.size() || !running.empty()) {
    const bool stopping = o.stopRequested && o.stopRequested();
    if (stopping && !forwarded) {
      // a SIGTERM sent to the batch alone reaches its runs too (Ctrl-C already reached the group):
      // each writes what it has and stops, instead of the batch waiting for them to finish
      for (const auto& [pid, run] : running) ::kill(pid, SIGTERM);
      forwarded = true;
    }
    while (!stopping && next < todo.size() && static_cast<int>(running.size()) < jobs) launch(todo[next++]);
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
