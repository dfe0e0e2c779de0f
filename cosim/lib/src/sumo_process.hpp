#pragma once
// A SUMO (or sumo-gui) child process serving TraCI on a free port.
#include <string>
#include <sys/types.h>
#include <vector>

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

// SUMO validates its XML inputs against the schemas under $SUMO_HOME/data/xsd; without SUMO_HOME it
// tries to fetch them from the web and, offline, rejects every input. If SUMO_HOME is unset and
// Debian's /usr/share/sumo exists, sets it (for this process and the SUMO processes it starts).
void ensureSumoHome();

// A TCP port that nothing listens on right now.
int freePort();
// True if some socket on this host listens on `port` (from /proc/net/tcp{,6}); lets us wait for
// SUMO without connecting, since a probing connection would take one of its --num-clients slots.
bool portListening(int port);

}  // namespace st::cosim::detail
