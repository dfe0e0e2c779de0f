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

namespace st::cosim::detail {

// The relay's checks on bytes alone, no sockets, so they are tested and fuzzed on their own
// (fuzz/traci_relay.cpp): which command each request of libtraci's starts with, and whether the
// server's bytes begin with whole, sound replies to them, oldest first.
class TraciFraming {
 public:
  using Clock = std::chrono::steady_clock;
  // A reply shorter than this cannot hold the 4-byte length and a minimal status block (bytes).
  static constexpr std::uint32_t kMinReply = 4 + 7;
  // Longest reply accepted (bytes). The largest stsim asks for (every lane's shape of a network,
  // one step's subscription results) are a few MB; 256 MiB is far above and far below a garbage
  // length's typical gigabytes.
  static constexpr std::uint32_t kMaxReply = 256u << 20;

  // Bytes libtraci sent, as they come: each complete request's first command is noted as pending.
  void request(const unsigned char* bytes, std::size_t n, Clock::time_point now);
  // Of the server's bytes not yet passed on (`n` of them from `bytes`): the length of the whole,
  // sound replies at their front, each answering (and removing) the oldest pending request. When
  // the next reply is malformed, or answers nothing or another command, `failure` says why
  // (one line); the replies before it are still whole and may be passed on.
  std::size_t replies(const unsigned char* bytes, std::size_t n, std::string& failure);

  struct Pending {
    int command;
    Clock::time_point sent;
  };
  const std::deque<Pending>& pending() const { return pending_; }
  bool answered() const { return answered_; }  // a whole reply has passed

 private:
  std::vector<unsigned char> request_;  // bytes of the client's current request frame(s)
  std::deque<Pending> pending_;         // requests sent, oldest first
  bool answered_ = false;
};

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
