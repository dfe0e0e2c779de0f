#pragma once
// The checks a TraCI relay makes on a conversation's bytes alone, no sockets and no SUMO: which
// command each of libtraci's requests starts with, and whether the server's bytes begin with
// whole, sound replies to them. The relay (`--traci HOST:PORT`, cosim/README.md) passes on only
// what they accept; tested and fuzzed on their own (tests/cosim, fuzz/traci_relay.cpp).
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace st::cosim {

// Requests and replies are matched oldest first.
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

}  // namespace st::cosim
