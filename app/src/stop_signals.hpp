#pragma once
// Ctrl-C, SIGTERM and SIGHUP (a closed terminal) during a command: the handler only notes the
// signal; the command asks requested() between whole steps, stops there, writes what it has
// (whole rows, a summary) and exits exitCode(): 128 + the signal (130, 143, 129). The one guard
// of every command (stsim highway, pool, arm, batch); the services on Asio (st::net) wait for
// the same three signals with an asio::signal_set in their event loop.
//
// A scope guard: the previous handlers come back on every way out of the scope, an exception
// included. The handlers are installed without SA_RESTART, so a signal also wakes a blocking
// wait (batch's waitpid) at once.
#include <signal.h>

namespace st::cli {

class StopSignals {
 public:
  // Ignore: SIGPIPE is ignored while the guard lives, so that a peer closing a socket (TraCI) or
  // a pipe gives a write error to report instead of killing the process.
  enum class Pipe { Default, Ignore };

  explicit StopSignals(Pipe pipe = Pipe::Default) : pipe_(pipe) {
    signal_ = 0;
    struct sigaction sa {};
    sa.sa_handler = note;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], &sa, &old_[i]);
    if (pipe_ == Pipe::Ignore) {
      struct sigaction ign {};
      ign.sa_handler = SIG_IGN;
      sigemptyset(&ign.sa_mask);
      sigaction(SIGPIPE, &ign, &oldPipe_);
    }
  }
  ~StopSignals() {
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], &old_[i], nullptr);
    if (pipe_ == Pipe::Ignore) sigaction(SIGPIPE, &oldPipe_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  static bool requested() { return signal_ != 0; }
  static int signal() { return signal_; }  // the signal that asked to stop, 0 if none
  static int exitCode() { return 128 + (signal_ ? static_cast<int>(signal_) : SIGINT); }
  static const char* name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP"; }

 private:
  static void note(int sig) { signal_ = sig; }
  static constexpr int kCount = 3;
  static constexpr int kSignals[kCount] = {SIGINT, SIGTERM, SIGHUP};
  static inline volatile sig_atomic_t signal_ = 0;
  Pipe pipe_;
  struct sigaction old_[kCount] {};
  struct sigaction oldPipe_ {};
};

}  // namespace st::cli
