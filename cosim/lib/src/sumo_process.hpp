#pragma once
// A SUMO (or sumo-gui) child process serving TraCI on a free port.
#include <string>
#include <sys/types.h>
#include <vector>

#include <stcosim/sumo_home.hpp>  // ensureSumoHome

namespace st::cosim::detail {

class SumoProcess {
 public:
  // Spawns `binary args... --remote-port <free port>` in its own process group, with stdout and
  // stderr to logFile ("" = /dev/null), and waits until it listens (or exits: throws SumoError
  // naming the log file).
  SumoProcess(const std::string& binary, const std::vector<std::string>& args, const std::string& logFile);
  ~SumoProcess();
  SumoProcess(const SumoProcess&) = delete;
  SumoProcess& operator=(const SumoProcess&) = delete;

  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  // Waits up to `seconds` for a normal exit, then terminates it (SIGTERM, SIGKILL 2 s later).
  // Idempotent.
  void stop(double seconds) noexcept;
  // The last lines of the log (for error messages), "" if none.
  std::string logTail() const;

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  std::string log_;
};

// Holds this process's stderr (fd 2) in a temporary file from construction to finish() (or
// destruction), for SUMO's own error lines during libsumo's start. Not for use while other threads
// write to stderr.
class StderrCapture {
 public:
  StderrCapture();
  ~StderrCapture();
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  // Restores stderr and returns what was written meanwhile (idempotent: "" the second time).
  std::string finish();

 private:
  int saved_ = -1;
  int file_ = -1;
};

// One line from SUMO's error output and an exception's text: the "Error: ..." lines SUMO printed
// (with their indented detail lines) and the exception's message unless it is SUMO's bare
// "Process Error" / "Loading failed.", newlines and indentation collapsed, joined by "; ".
std::string sumoErrorLine(const std::string& printed, const std::string& what);

// A TCP port that nothing listens on right now.
int freePort();
// True if some socket on this host listens on `port` (from /proc/net/tcp{,6}); lets us wait for
// SUMO without connecting, since a probing connection would take one of its --num-clients slots.
bool portListening(int port);

}  // namespace st::cosim::detail
