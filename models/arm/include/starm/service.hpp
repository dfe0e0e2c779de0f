#pragma once
// The arm service (`stsim arm serve`): the monitor behind an st::net server speaking
// starm/protocol.hpp. Sensor clients send joint readings and obstacle poses; each cycle (the
// readings that arrived together, at the latest time among them) the monitor runs and every
// subscriber gets a verdict. A verdict log (CSV, one row per cycle) and a connection log are
// written and flushed as they go; a log that cannot be written stops the service (run() throws
// naming the file). A connection that breaks the protocol gets one ERROR and is closed; the
// monitor state and the other clients are not touched by a rejected message.
//
// The sensor model (models/arm/README.md): each arm and each tracked obstacle is reported by
// one connection, its owner, which claims it (CLAIM, or its first report of it) and holds it
// until it leaves. A report of it from any other connection is refused, and the dispute is
// itself a reason to STOP: a monitor that hears two accounts of one arm cannot know which is
// true, so the arm (for an obstacle: every arm) stays STOP until the owner it was disputed with
// has left. No client can make the monitor hold a reading its owner did not give.
//
// Fail safe on time: an arm whose last reading is not current at the cycle's time (the
// monitor's watchdog, by the arm's declared sensor period: a sensor fallen silent, a clock far
// behind, no reading yet) gets STOP, whatever the geometry says; so does every arm while a
// tracked obstacle that has been reported has no pose within `staleAfter`.
// No one sensor sets the others' time: a time beyond any clock, or more than `maxLead` ahead of
// or behind the other sensors that are talking, is refused; a sensor that leaves takes its time
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
  // s; a tracked obstacle's pose older (or newer) than this at the cycle: every arm STOPs. 0:
  // reaction + cycle time. (An arm's reading: its declared sensor period, Monitor::staleAfter.)
  double staleAfter = 0.0;
  double maxLead = 1.0;     // s; a message's time this far from the other talking sensors' is refused
  std::string token;   // required from every client when set; required to set for a non-loopback address
  std::string logDir;  // verdicts.csv, connections.csv ("" : no logs)
  // true: the messages read in one pass of the event loop share one cycle; false: a cycle per
  // message (the first client's verdict does not wait for the others' reads, but with many
  // clients the cycles pile up: bench/arm_service measures both)
  bool batchCycles = true;
  // Deadline (us): a cycle whose compute time (readings applied, detection, persons) exceeds it
  // is STOP for every arm, cause `deadline` (a verdict late is no verdict). 0: not watched (the
  // library's default, so a test on a loaded machine does not turn preemption into STOPs);
  // `stsim arm serve` watches the cycle time unless --budget-us says otherwise.
  double cycleBudgetUs = 0.0;
};

struct ServiceCounters {
  std::uint64_t cycles = 0, readings = 0, obstaclePoses = 0, verdictsSent = 0, rejected = 0, connections = 0;
  std::uint64_t disputes = 0;     // reports refused because another connection owns the arm or obstacle
  std::uint64_t disputeStops = 0;  // arm verdicts forced to STOP: its (or a tracked obstacle's) report disputed
  std::uint64_t staleStops = 0;  // arm verdicts forced to STOP: no current reading of the arm
  std::uint64_t deadlineMisses = 0;  // cycles over cfg.cycleBudgetUs: every arm STOP
  std::uint64_t helloTimeouts = 0, shed = 0, refusedFull = 0;  // pending closed late / shed; HELLO past maxClients
};

class ArmService final : public net::Handler {
 public:
  // Throws std::runtime_error for a non-loopback address without a token, or when it cannot listen.
  ArmService(boost::asio::io_context& io, const Scenario& scenario, ServiceConfig cfg);
  ~ArmService() override;

  std::uint16_t port() const { return server_.port(); }
  // Serves until stop() or SIGINT / SIGTERM / SIGHUP; returns the signal (0 if none). Logs flushed.
  int run();
  void stop();  // from the service's thread; from another: post it to the io_context
  const ServiceCounters& counters() const { return counters_; }
  const Monitor& monitor() const { return monitor_; }
  // The verdict of the last cycle (as sent to the subscribers); cycle 0: none yet.
  const proto::Verdict& lastVerdict() const { return verdict_; }

  void onOpen(net::Server&, net::ConnectionId) override;
  void onFrame(net::Server&, net::ConnectionId, std::string_view payload) override;
  void onClose(net::Server&, net::ConnectionId, net::CloseReason, const std::string& detail) override;
  std::string errorPayload(const std::string& message) override;
  // the cycle at the end of a read once every connection that reports is in it (the batch is
  // complete: its verdict does not wait for onIdle); otherwise at onIdle, as before
  void onReadDone(net::Server&, net::ConnectionId) override;
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
    bool claimed = false;   // sent CLAIM: reports only what it claimed
    bool reported = false;  // sent READINGS or OBSTACLES
    bool owns = false;      // claimed an arm or obstacle by CLAIM (its clock is then its own)
    std::uint8_t version = proto::kVersion;  // its HELLO's: what it is answered in
    std::uint32_t ack = 0;
    double lastT = -std::numeric_limits<double>::infinity();  // of its last READINGS
    double newestT = -std::numeric_limits<double>::infinity();  // of its READINGS and OBSTACLES
    Clock::time_point lastHeard{};  // when newestT last moved
  };
  // Each returns "" or the one-line reason to refuse the message.
  std::string onHello(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onReadings(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onObstacles(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onClaim(net::ConnectionId id, Peer& p, std::string_view payload);
  std::string onSkeletons(net::ConnectionId id, Peer& p, std::string_view payload);
  // the persons' speed and separation verdicts folded into the cycle's verdict
  void applyPersons(double t);
  // "" if `id` may report arm a (or obstacle o): it owns it, or it is free and `id` claims by
  // reporting; otherwise the reason, and another owner's arm is marked disputed
  // true where that holds at once for an item whose owner is `owner` (no reason needs a name)
  static bool mayReportAtOnce(net::ConnectionId id, const Peer& p, net::ConnectionId owner);
  std::string mayReportArm(net::ConnectionId id, const Peer& p, int a, const std::string& where);
  std::string mayReportObstacle(net::ConnectionId id, const Peer& p, int o, const std::string& where);
  std::string mayReport(net::ConnectionId id, const Peer& p, std::vector<net::ConnectionId>& owners,
                        std::vector<char>& disputed, std::size_t k, const std::string& name, const std::string& where,
                        const char* stopped);
  // "" or why a message at time t from `id` cannot be taken: beyond any clock, a jump ahead of
  // its own last time, or (its first time) too far from the sensors that are talking
  // (the reason names the message as "<kind> seq <seqNo>")
  std::string checkTime(net::ConnectionId id, const Peer& p, const char* kind, std::uint32_t seqNo, double t) const;
  void heard(Peer& p, double t);
  void release(net::ConnectionId id);  // frees the arms and obstacles `id` owns
  void armHelloTimer();
  void onHelloTimer();
  // a cycle: the readings into the monitor, its cycle, each arm's verdict (geometry, then the
  // fail-safe causes, the persons, the deadline), sent, then logged
  void runCycle();
  void takeReadings();
  void armVerdicts(double t);
  void applyDeadline(Clock::time_point started);
  void sendVerdicts();
  void logVerdict(double t);
  void logConnection(net::ConnectionId id, const std::string& event, const std::string& detail);

  ServiceConfig cfg_;
  Monitor monitor_;
  net::Server server_;
  std::unordered_map<net::ConnectionId, Peer> peers_;
  std::vector<net::ConnectionId> inCycle_;
  static constexpr net::ConnectionId kNobody = 0;  // st::net numbers connections from 1
  std::vector<net::ConnectionId> armOwner_, obstacleOwner_;  // per arm / obstacle, the connection reporting it
  std::vector<char> armDisputed_, obstacleDisputed_;         // reported by another too: STOP until its owner leaves
  // persons (protocol version 3's SKELETONS): their poses as last reported, who reports each,
  // when (NaN: never; then no person is there to check), and the speed and separation check
  PersonSet persons_;
  std::vector<HeldPerson*> held_;
  std::vector<net::ConnectionId> personOwner_;
  std::vector<char> personDisputed_;
  std::vector<double> personT_;
  std::vector<double> personStaleAfter_;  // s, per person: its tracker's (period + jitter)(1 + drift), or staleAfter_
  std::vector<SensorClock> personClock_;  // per person: its tracker's clock against the cycles'
  // the scenario's declared rates (period, jitter, drift), put back when a CLAIM's owner leaves
  std::vector<proto::SensorRate> scenarioArmRates_, scenarioPersonRates_;
  void setPersonRate(std::size_t person, const proto::SensorRate& rate);
  std::vector<char> personNew_;           // a pose with a later stamp since the last cycle
  // a pose's arrival on the cycles' clock: the first cycle later than the one it came in (the
  // cycles' time is the newest stamp, which lags the pose's arrival by up to a sensor's period
  // in the cycle it comes in); NaN: none waiting
  std::vector<double> personMarkStamp_, personMarkAfter_;
  std::optional<SeparationMonitor> ssm_;
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
  proto::Skeletons skeletons_;  // reused
  Reading check_;             // reused for validation
  proto::Verdict verdict_;
  std::string out_, logRow_;
  std::optional<io::CsvRowWriter> verdictLog_, connLog_;
  ServiceCounters counters_;
};

}  // namespace st::arm
