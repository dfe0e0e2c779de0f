#pragma once
// A guard between libtraci and a TraCI server we did not start (`--traci HOST:PORT`).
//
// libtraci trusts its peer: a reply whose length field is not above 4 trips an assert inside
// libtraci (the process aborts, nothing is flushed), and a length of a gigabyte (the first bytes of
// "HTTP/1.1 ...", say) makes it wait for data that never comes. The relay owns the one connection
// to the server and gives libtraci a loopback socket instead. Requests pass through unchanged; a
// reply is passed on only once it is complete and its framing is sound: a length in
// [kMinReply, kMaxReply] and, first in it, a status block for the command that was sent, with a
// known result code and a string that fits. Anything else, or a reply that starts and then stalls
// for kStallSeconds, ends both connections; libtraci then sees its socket close (an exception, not
// an abort) and failure() says what was wrong, for the error message.
//
// A peer that never answers is bounded too: the first request (libtraci's version handshake) must
// be answered within firstReplySeconds (an HTTP server, say, waits for a request line and says
// nothing), and any later request within silenceSeconds (a SUMO stopped with SIGSTOP). The second
// bound is long because a SUMO serving several clients answers a step only when every client has
// stepped. closeWithin() bounds the wait for the final replies.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <stcosim/traci_framing.hpp>

namespace st::cosim::detail {

class TraciRelay {
 public:
  static constexpr std::uint32_t kMinReply = TraciFraming::kMinReply;
  static constexpr std::uint32_t kMaxReply = TraciFraming::kMaxReply;
  // A reply that has begun must be complete within this (s): SUMO writes a reply at once.
  static constexpr double kStallSeconds = 10.0;

  // Connects to host:port (tries `attempts` times, a second apart) and starts relaying. Throws
  // SumoError if the server cannot be reached.
  static constexpr double kFirstReplySeconds = 30.0;
  static constexpr double kSilenceSeconds = 120.0;
  TraciRelay(const std::string& host, int port, int attempts, double firstReplySeconds = kFirstReplySeconds,
             double silenceSeconds = kSilenceSeconds);
  ~TraciRelay();
  TraciRelay(const TraciRelay&) = delete;
  TraciRelay& operator=(const TraciRelay&) = delete;

  // The loopback port libtraci should connect to (127.0.0.1).
  int localPort() const { return localPort_; }
  // Why the relay cut the connection, "" if it did not.
  std::string failure() const;
  // From now on, a request left unanswered for `seconds` ends the connection (for closing).
  void closeWithin(double seconds);

 private:
  using Clock = std::chrono::steady_clock;
  void run();
  void fail(const std::string& why);
  bool forwardRequests();
  bool passReplies();

  int listenFd_ = -1;
  int clientFd_ = -1;
  int serverFd_ = -1;
  int wakeFd_[2] = {-1, -1};
  int localPort_ = 0;
  std::thread thread_;

  mutable std::mutex mutex_;
  std::string failure_;
  std::atomic<double> closeDeadline_{-1.0};  // steady-clock seconds; < 0: none

  // relay-thread state
  TraciFraming framing_;
  std::vector<unsigned char> reply_;     // bytes of the server's replies not yet passed on
  double firstReplySeconds_, silenceSeconds_;
  Clock::time_point replyBegan_{};
};

}  // namespace st::cosim::detail
