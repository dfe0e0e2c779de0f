#pragma once
// The arm service (`stsim arm serve`): the monitor behind an st::net server speaking
// starm/protocol.hpp. Sensor clients send joint readings and obstacle poses; each cycle (the
// readings that arrived together, at the latest time among them) the monitor runs and every
// subscriber gets a verdict. A verdict log (CSV, one row per cycle) and a connection log are
// written and flushed as they go; a log that cannot be written stops the service (run() throws
// naming the file). A connection that breaks the protocol gets one ERROR and is closed; the
// monitor state and the other clients are not touched by a rejected message.
//
// Fail safe: an arm whose last reading is not within `staleAfter` of the cycle's time (a sensor
// fallen silent, a clock far behind, no reading yet) gets STOP, whatever the geometry says; so
// does every arm while an obstacle that has been tracked (OBSTACLES) has no current pose. No
// one sensor sets the others' time: a time beyond any clock, or more than `maxLead` ahead of or
// behind the other sensors that are talking, is refused; a sensor that leaves takes its time
// with it. Sensors that said HELLO have their own slots (`maxClients`), apart from connections
// that have not yet (`maxPending`, each with `helloTimeout` to do so; the oldest is shed when
// more arrive), so a flood of silent connections cannot lock a sensor out.
#include <chrono>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <starm/protocol.hpp>
#include <starm/scenario.hpp>
#include <stio/output.hpp>
#include <stnet/server.hpp>

namespace st::arm {

struct ServiceConfig {
  net::ServerConfig net;  // its maxConnections is set by the service: maxClients + maxPending
  std::size_t maxClients = 128;  // connections past HELLO served at once (more are told "server full")
  std::size_t maxPending = 16;   // connections before HELLO; one more sheds the oldest of them
  std::chrono::milliseconds helloTimeout{2000};  // from connect to HELLO
  double staleAfter = 0.0;  // s; an arm's reading older (or newer) than this at the cycle: STOP. 0: reaction + cycle time
  double maxLead = 1.0;     // s; a message's time this far from the other talking sensors' is refused
  std::string token;   // required from every client when set; required to set for a non-loopback address
  std::string logDir;  // verdicts.csv, connections.csv ("" : no logs)
  // true: the messages read in one pass of the event loop share one cycle; false: a cycle per
  // message (the first client's verdict does not wait for the others' reads, but with many
  // clients the cycles pile up: bench/arm_service measures both)
  bool batchCycles = true;
};

struct ServiceCounters {
  std::uint64_t cycles = 0, readings = 0, obstaclePoses = 0, verdictsSent = 0, rejected = 0, connections = 0;
  std::uint64_t stale = 0;  // readings older than the arm's newest (from another client): not applied
  std::uint64_t staleStops = 0;  // arm verdicts forced to STOP: no current reading of the arm
  std::uint64_t helloTimeouts = 0, shed = 0, refusedFull = 0;  // pending closed late / shed; HELLO past maxClients
};

class ArmService final : public net::Handler {
 public:
  // Throws std::runtime_error for a non-loopback address without a token, or when it cannot listen.
  ArmService(boost::asio::io_context& io, const Scenario& scenario, ServiceConfig cfg);
  ~ArmService() override;

  std::uint16_t port() const { return server_.port(); }
  // Serves until stop() or SIGINT / SIGTERM; returns the signal (0 if none). Logs flushed.
  int run();
  void stop();  // from the service's thread; from another: post it to the io_context
  const ServiceCounters& counters() const { return counters_; }
  const Monitor& monitor() const { return monitor_; }

  void onOpen(net::Server&, net::ConnectionId) override;
  void onFrame(net::Server&, net::ConnectionId, std::string_view payload) override;
  void onClose(net::Server&, net::ConnectionId, net::CloseReason, const std::string& detail) override;
  std::string errorPayload(const std::string& message) override;
  void onIdle(net::Server&) override;

 private:
  using Clock = std::chrono::steady_clock;
  enum class Stage { Pending, Client, Leaving };  // before HELLO, past it, refused or shed
  struct Peer {
    Stage stage = Stage::Pending;
    bool hello = false;
    bool subscribed = false;
    bool ownOnly = false;
    bool inCycle = false;
    std::uint32_t ack = 0;
    double lastT = -std::numeric_limits<double>::infinity();  // of its last READINGS
    double newestT = -std::numeric_limits<double>::infinity();  // of its READINGS and OBSTACLES
    Clock::time_point lastHeard{};  // when newestT last moved
  };
  // Each returns "" or the one-line reason to refuse the message.
  std::string onHello(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onReadings(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onObstacles(net::ConnectionId id, Peer& p, std::string_view payload);
  // "" or why a message at time t from `id` cannot be taken (beyond any clock, too far from the others)
  std::string checkTime(net::ConnectionId id, const std::string& what, double t) const;
  void heard(Peer& p, double t);
  void armHelloTimer();
  void onHelloTimer();
  void runCycle();
  void logConnection(net::ConnectionId id, const std::string& event, const std::string& detail);

  ServiceConfig cfg_;
  Monitor monitor_;
  net::Server server_;
  std::unordered_map<net::ConnectionId, Peer> peers_;
  std::vector<net::ConnectionId> inCycle_;
  std::vector<double> lastReading_;  // per arm, time of its newest reading taken (-inf: free for any)
  std::vector<net::ConnectionId> readingFrom_;  // per arm, the connection that gave it
  std::vector<double> appliedT_;     // per arm, time of the reading the monitor holds (-inf: none)
  std::vector<double> poseT_;        // per obstacle, time of its last pose report (NaN: never, it stands where the scenario put it)
  // connections before HELLO, oldest first, with their deadlines (entries of closed or greeted
  // connections are skipped when they come up)
  std::deque<std::pair<net::ConnectionId, Clock::time_point>> helloQueue_;
  std::size_t awaitingHello_ = 0, clients_ = 0;
  boost::asio::steady_timer helloTimer_;
  bool helloTimerArmed_ = false;
  double staleAfter_ = 0.0;
  struct Pending {
    std::vector<double> q, qdot;
    double t = 0.0;
    bool fresh = false;
  };
  std::vector<Pending> pendingArm_;  // per arm, the newest reading not yet applied
  bool pending_ = false;
  double cycleT_ = 0.0;
  double lastCycleT_ = -1e300;
  proto::Readings readings_;  // reused
  Reading check_;             // reused for validation
  proto::Verdict verdict_;
  std::string out_, logRow_;
  std::optional<io::CsvRowWriter> verdictLog_, connLog_;
  ServiceCounters counters_;
};

}  // namespace st::arm
