#pragma once
// Ctrl-C, SIGTERM and SIGHUP during a run: the handler only notes the signal; the run asks
// requested() between whole steps, stops there, writes what it has (whole rows, a summary) and
// the command exits 128 + signal (130, 143, 129). The guard restores the previous handlers.
// The same mechanism as `stsim highway` (highway_run.cpp) and `stsim pool`, in one place for
// the commands that take it up.
#include <signal.h>

namespace st::cli {

class StopSignals {
 public:
  StopSignals() {
    signal_ = 0;
    struct sigaction sa {};
    sa.sa_handler = note;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], &sa, &old_[i]);
  }
  ~StopSignals() {
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], &old_[i], nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  static bool requested() { return signal_ != 0; }
  static int signal() { return signal_; }  // the signal that asked to stop, 0 if none
  static const char* name(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP"; }

 private:
  static void note(int sig) { signal_ = sig; }
  static constexpr int kCount = 3;
  static constexpr int kSignals[kCount] = {SIGINT, SIGTERM, SIGHUP};  // SIGHUP: a closed terminal
  static inline volatile sig_atomic_t signal_ = 0;
  struct sigaction old_[kCount] {};
};

}  // namespace st::cli
