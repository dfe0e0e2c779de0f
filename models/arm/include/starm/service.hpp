#pragma once
// The arm service (`stsim arm serve`): the monitor behind an st::net server speaking
// starm/protocol.hpp. Sensor clients send joint readings and obstacle poses; each cycle (the
// readings that arrived together, at the latest time among them) the monitor runs and every
// subscriber gets a verdict. A verdict log (CSV, one row per cycle) and a connection log are
// written and flushed as they go. A connection that breaks the protocol gets one ERROR and is
// closed; the monitor state and the other clients are not touched by a rejected message.
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <starm/protocol.hpp>
#include <starm/scenario.hpp>
#include <stnet/server.hpp>

namespace st::arm {

struct ServiceConfig {
  net::ServerConfig net;
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
  struct Peer {
    bool hello = false;
    bool subscribed = false;
    bool ownOnly = false;
    bool inCycle = false;
    std::uint32_t ack = 0;
    double lastT = -std::numeric_limits<double>::infinity();  // of its last READINGS
  };
  // Each returns "" or the one-line reason to refuse the message.
  std::string onHello(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onReadings(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onObstacles(net::ConnectionId id, Peer& p, std::string_view payload);
  void runCycle();
  void logConnection(net::ConnectionId id, const std::string& event, const std::string& detail);

  ServiceConfig cfg_;
  Monitor monitor_;
  net::Server server_;
  std::unordered_map<net::ConnectionId, Peer> peers_;
  std::vector<net::ConnectionId> inCycle_;
  std::vector<double> lastReading_;  // per arm, time of its last reading
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
  std::string out_;
  std::ofstream verdictLog_, connLog_;
  ServiceCounters counters_;
};

}  // namespace st::arm
