// The one stop-signal guard of every command (app/src/stop_signals.hpp): while it lives SIGINT,
// SIGTERM and SIGHUP are noted, not fatal, without SA_RESTART (a blocking wait wakes), SIGPIPE is
// ignored when asked; the previous handlers come back however the scope ends, an exception
// included. Each command's use of it is tested end to end in fault_matrix.sh (all three signals
// mid-write: whole files, exit 128 + signal).
#include <gtest/gtest.h>

#include <signal.h>

#include <stdexcept>

#include "stop_signals.hpp"

namespace {

volatile sig_atomic_t gOurs = 0;
void ours(int sig) { gOurs = sig; }

struct sigaction current(int sig) {
  struct sigaction sa {};
  sigaction(sig, nullptr, &sa);
  return sa;
}

void installOurs() {
  struct sigaction sa {};
  sa.sa_handler = ours;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaction(sig, &sa, nullptr);
}

void restoreDefaults() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) signal(sig, SIG_DFL);
}

TEST(StopSignals, NotesEachSignalAndRestoresThePreviousHandlersOnAnException) {
  installOurs();
  for (const auto& [sig, code] : {std::pair{SIGINT, 130}, std::pair{SIGTERM, 143}, std::pair{SIGHUP, 129}}) {
    gOurs = 0;
    try {
      const st::cli::StopSignals guard(st::cli::StopSignals::Pipe::Ignore);
      EXPECT_FALSE(st::cli::StopSignals::requested());
      for (int s : {SIGINT, SIGTERM, SIGHUP}) {
        EXPECT_NE(current(s).sa_handler, &ours);
        EXPECT_EQ(current(s).sa_flags & SA_RESTART, 0) << "a signal must wake a blocking wait";
      }
      EXPECT_EQ(current(SIGPIPE).sa_handler, SIG_IGN);
      raise(sig);
      EXPECT_TRUE(st::cli::StopSignals::requested());
      EXPECT_EQ(st::cli::StopSignals::signal(), sig);
      EXPECT_EQ(st::cli::StopSignals::exitCode(), code);
      EXPECT_EQ(gOurs, 0) << "the guard's handler, not the previous one, took the signal";
      throw std::runtime_error("a command failing mid-run");
    } catch (const std::runtime_error&) {
    }
    for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) EXPECT_EQ(current(s).sa_handler, &ours) << s;
    raise(sig);
    EXPECT_EQ(gOurs, sig);
  }
  restoreDefaults();
}

TEST(StopSignals, LeavesSigpipeAloneUnlessAsked) {
  installOurs();
  {
    const st::cli::StopSignals guard;
    EXPECT_EQ(current(SIGPIPE).sa_handler, &ours);
    EXPECT_FALSE(st::cli::StopSignals::requested()) << "a new guard starts with no signal noted";
  }
  EXPECT_EQ(current(SIGINT).sa_handler, &ours);
  restoreDefaults();
}

}  // namespace
