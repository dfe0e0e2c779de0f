#pragma once
// A child process for the tests: started with posix_spawnp (found on PATH), its stdout and stderr
// written to stdout.txt and stderr.txt in a folder, killed (SIGKILL) if the test leaves it running.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "files.hpp"

extern char** environ;

namespace st::test {

struct ProcessOptions {
  std::vector<std::string> env;  // NAME=VALUE, each replacing the variable of that name
  bool ownGroup = false;         // in a process group of its own (killed as a group)
};

class Process {
 public:
  using Options = ProcessOptions;

  Process(std::vector<std::string> argv, const std::filesystem::path& dir, Options opt = {})
      : dir_(dir), ownGroup_(opt.ownGroup) {
    std::vector<char*> c;
    for (auto& a : argv) c.push_back(a.data());
    c.push_back(nullptr);
    // the environment, each of opt.env's variables replacing one of the same name
    std::vector<std::string> envStore;
    auto name = [](const std::string& e) { return e.substr(0, e.find('=')); };
    for (char** e = environ; *e; ++e)
      if (std::none_of(opt.env.begin(), opt.env.end(), [&](const std::string& x) { return name(x) == name(*e); }))
        envStore.emplace_back(*e);
    envStore.insert(envStore.end(), opt.env.begin(), opt.env.end());
    std::vector<char*> env;
    for (auto& e : envStore) env.push_back(e.data());
    env.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
    posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    if (ownGroup_) {
      posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
      posix_spawnattr_setpgroup(&attr, 0);
    }
    if (posix_spawnp(&pid_, c[0], &fa, &attr, c.data(), env.data()) != 0) pid_ = -1;
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&fa);
  }
  ~Process() {
    if (pid_ > 0) {
      ::kill(ownGroup_ ? -pid_ : pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  pid_t pid() const { return pid_; }
  void signal(int sig) { ::kill(pid_, sig); }  // the process alone, not its group
  void killGroup() { ::kill(-pid_, SIGKILL); }
  // Exit code, or 128 + signal; -1 if it could not be started.
  int wait() {
    if (pid_ > 0) {
      int status = 0;
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
      code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    return code_;
  }
  // True while the process runs (reaps it when it has ended; wait() then gives its code).
  bool running() {
    int status = 0;
    if (pid_ <= 0 || ::waitpid(pid_, &status, WNOHANG) != pid_) return pid_ > 0;
    pid_ = -1;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return false;
  }
  std::string out() const { return slurp(dir_ / "stdout.txt"); }
  std::string err() const { return slurp(dir_ / "stderr.txt"); }

 private:
  std::filesystem::path dir_;
  bool ownGroup_ = false;
  pid_t pid_ = -1;
  int code_ = -1;
};

}  // namespace st::test
