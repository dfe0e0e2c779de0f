#include "sumo_process.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <sstream>
#include <thread>

#include <stcosim/backend.hpp>

extern char** environ;

namespace st::cosim {

void ensureSumoHome() {
  if (std::getenv("SUMO_HOME") == nullptr && ::access("/usr/share/sumo/data/xsd", F_OK) == 0)
    ::setenv("SUMO_HOME", "/usr/share/sumo", 0);
}

}  // namespace st::cosim

namespace st::cosim::detail {

StderrCapture::StderrCapture() {
  std::fflush(stderr);
  char path[] = "/tmp/stsim_sumo_stderr_XXXXXX";
  file_ = ::mkstemp(path);
  if (file_ < 0) return;  // nothing captured: SUMO prints as it would
  ::unlink(path);
  saved_ = ::dup(STDERR_FILENO);
  if (saved_ < 0 || ::dup2(file_, STDERR_FILENO) < 0) {
    if (saved_ >= 0) ::close(saved_);
    ::close(file_);
    saved_ = file_ = -1;
  }
}

StderrCapture::~StderrCapture() { finish(); }

std::string StderrCapture::finish() {
  if (file_ < 0) return {};
  std::fflush(stderr);
  ::dup2(saved_, STDERR_FILENO);
  ::close(saved_);
  std::string text;
  char buf[4096];
  ::lseek(file_, 0, SEEK_SET);
  for (ssize_t n; (n = ::read(file_, buf, sizeof buf)) > 0;) text.append(buf, static_cast<std::size_t>(n));
  ::close(file_);
  saved_ = file_ = -1;
  return text;
}

namespace {

// "a\n  b" -> "a b": one line, single spaces at the joints, trimmed.
std::string collapse(const std::string& s) {
  std::string out;
  bool space = false;
  for (char c : s) {
    if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
      space = !out.empty();
      continue;
    }
    if (space) out += ' ';
    space = false;
    out += c;
  }
  return out;
}

}  // namespace

std::string sumoErrorLine(const std::string& printed, const std::string& what) {
  std::vector<std::string> parts;
  std::istringstream in(printed);
  std::string line;
  bool inError = false;
  while (std::getline(in, line)) {
    if (line.rfind("Error: ", 0) == 0) {
      parts.push_back(collapse(line.substr(7)));
      inError = true;
    } else if (inError && !line.empty() && line[0] == ' ') {
      parts.back().append(" ").append(collapse(line));
    } else {
      inError = false;
    }
  }
  const std::string w = collapse(what);
  if (!w.empty() && w != "Process Error" && w != "Loading failed." &&
      std::find(parts.begin(), parts.end(), w) == parts.end())
    parts.push_back(w);
  if (parts.empty()) parts.push_back(w.empty() ? std::string("unknown error") : w);
  std::string out;
  for (const auto& p : parts) {
    if (!out.empty()) out.append("; ");
    out.append(p);
  }
  return out;
}

int freePort() {
  // bind to port 0 and let the kernel pick; the small race until SUMO binds is accepted practice
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw SumoError(std::string("cannot create a socket: ") + std::strerror(errno));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    ::close(fd);
    throw SumoError(std::string("cannot find a free TCP port: ") + std::strerror(errno));
  }
  const int port = ntohs(addr.sin_port);
  ::close(fd);
  return port;
}

bool portListening(int port) {
  for (const char* file : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    std::ifstream in(file);
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      // "  sl  local_address rem_address   st ..." with local_address = HEXIP:HEXPORT, st 0A = LISTEN
      std::istringstream ss(line);
      std::string sl, local, remote, state;
      ss >> sl >> local >> remote >> state;
      const auto colon = local.rfind(':');
      if (colon == std::string::npos) continue;
      if (state == "0A" && std::stoi(local.substr(colon + 1), nullptr, 16) == port) return true;
    }
  }
  return false;
}

SumoProcess::SumoProcess(const std::string& binary, const std::vector<std::string>& args, const std::string& logFile)
    : log_(logFile) {
  ensureSumoHome();
  port_ = freePort();
  std::vector<std::string> argv{binary};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.push_back("--remote-port");
  argv.push_back(std::to_string(port_));
  std::vector<char*> cargv;
  for (auto& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);

  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  const std::string out = logFile.empty() ? "/dev/null" : logFile;
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  // own process group: a Ctrl-C at the terminal goes to stsim, which then closes SUMO cleanly
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  const int rc = posix_spawnp(&pid_, binary.c_str(), &fa, &attr, cargv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) {
    pid_ = -1;
    throw SumoError("cannot run '" + binary + "': " + std::strerror(rc));
  }

  // wait until it listens, or exits (bad config), at most 60 s (sumo-gui can be slow to come up)
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!portListening(port_)) {
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      const std::string tail = logTail();
      throw SumoError("'" + binary + "' exited before accepting TraCI connections" +
                      (tail.empty() ? std::string() : ": " + tail));
    }
    if (std::chrono::steady_clock::now() > deadline) {
      stop(0.0);
      throw SumoError("'" + binary + "' did not open TraCI port " + std::to_string(port_) + " within 60 s");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

SumoProcess::~SumoProcess() { stop(5.0); }

void SumoProcess::stop(double seconds) noexcept {
  if (pid_ <= 0) return;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (::waitpid(pid_, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() >= deadline) {
      // SUMO exits "gracefully" on SIGTERM only when its loop gets control back; blocked on a
      // TraCI client that keeps its socket open it would not, so it gets a moment, then SIGKILL
      ::kill(pid_, SIGTERM);
      const auto grace = std::chrono::steady_clock::now() + std::chrono::seconds(2);
      while (::waitpid(pid_, &status, WNOHANG) == 0) {
        if (std::chrono::steady_clock::now() >= grace) {
          ::kill(pid_, SIGKILL);
          ::waitpid(pid_, &status, 0);
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  pid_ = -1;
}

std::string SumoProcess::logTail() const {
  // SUMO's first error, with its indented detail lines ("In file ...", "At line/column ...") joined
  // into one line; else the last line of the log
  if (log_.empty()) return {};
  std::ifstream in(log_);
  std::string line, error, last;
  bool inError = false;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (error.empty() && line.rfind("Error", 0) == 0) {
      error = line;
      inError = true;
    } else if (inError && line[0] == ' ') {
      error += ";" + line;
    } else {
      inError = false;
    }
    last = line;
  }
  return error.empty() ? last : error;
}

}  // namespace st::cosim::detail
