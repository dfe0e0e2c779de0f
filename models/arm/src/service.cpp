#include <starm/service.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include <boost/asio/ip/address.hpp>
#include <stio/format.hpp>

namespace st::arm {

namespace {

std::string num(double x) { return io::number(x, 9); }

double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

bool isLoopback(const std::string& address) {
  boost::system::error_code ec;
  const auto a = boost::asio::ip::make_address(address, ec);
  return !ec && a.is_loopback();
}

// Constant-time comparison: the token check does not leak how much of a guess was right.
bool sameToken(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ (i < b.size() ? b[i] : 0));
  return diff == 0;
}

// A time in seconds beyond any sensor clock (seconds since 1970 are 1.7e9): refused, so that no
// extrapolation over it overflows the monitor's geometry.
constexpr double kMaxClock = 1e12;
// A sensor counts as talking (its time bounds the others') for this long after its last message.
constexpr auto kTalking = std::chrono::seconds(1);

net::ServerConfig checked(const ServiceConfig& c) {
  if (!isLoopback(c.net.address) && c.token.empty())
    throw std::runtime_error(c.net.address + ": listening on a non-loopback address needs a shared token (--token)");
  if (c.maxClients < 1 || c.maxPending < 1) throw std::runtime_error("service: maxClients and maxPending must be at least 1");
  if (c.helloTimeout.count() <= 0) throw std::runtime_error("service: helloTimeout must be positive");
  if (!(c.cycleBudgetUs >= 0.0)) throw std::runtime_error("service: cycleBudgetUs must be a time >= 0 (us)");
  if (!(c.staleAfter >= 0.0 && c.staleAfter <= kMaxClock)) throw std::runtime_error("service: staleAfter must be a time >= 0 (s)");
  if (!(c.maxLead > 0.0 && c.maxLead <= kMaxClock)) throw std::runtime_error("service: maxLead must be a time > 0 (s)");
  net::ServerConfig n = c.net;
  // the sockets: every client slot and every pending one (the service sheds pending ones itself)
  n.maxConnections = c.maxClients + c.maxPending;
  // the sockets are the service's two kinds of slot: a connection past both is told both limits
  n.fullMessage = "server full (" + std::to_string(c.maxClients) + " clients and " + std::to_string(c.maxPending) +
                  " connections waiting for their HELLO)";
  return n;
}

}  // namespace

ArmService::ArmService(boost::asio::io_context& io, const Scenario& scenario, ServiceConfig cfg)
    : cfg_(std::move(cfg)), monitor_(makeMonitor(scenario)), server_(io, checked(cfg_), *this), helloTimer_(io) {
  const int arms = monitor_.armCount();
  monitor_.setStampedCycles(true);  // a cycle runs at the newest stamp among its messages
  armOwner_.assign(arms, kNobody);
  armDisputed_.assign(arms, 0);
  obstacleOwner_.assign(monitor_.obstacles().size(), kNobody);
  obstacleDisputed_.assign(monitor_.obstacles().size(), 0);
  poseT_.assign(monitor_.obstacles().size(), std::numeric_limits<double>::quiet_NaN());
  pendingArm_.resize(arms);
  static_assert(proto::kSkeletonJoints == static_cast<std::size_t>(kSkeletonJoints));
  for (const Scenario::Person& person : scenario.persons) {
    auto h = std::make_unique<HeldPerson>();
    held_.push_back(h.get());
    persons_.add(person.name, std::move(h));
  }
  personOwner_.assign(held_.size(), kNobody);
  personDisputed_.assign(held_.size(), 0);
  personT_.assign(held_.size(), std::numeric_limits<double>::quiet_NaN());
  if (!held_.empty()) ssm_.emplace(scenario.ssm, arms);
  // a reading older than this could not start the braking in time
  staleAfter_ = cfg_.staleAfter > 0.0 ? cfg_.staleAfter : monitor_.safety().reactionTime + monitor_.safety().cycleTime;
  personNew_.assign(held_.size(), 0);
  personMarkStamp_.assign(held_.size(), std::numeric_limits<double>::quiet_NaN());
  personMarkAfter_.assign(held_.size(), 0.0);
  for (const Scenario::Person& person : scenario.persons) {
    const proto::SensorRate rate{proto::SensorRate::Person, 0, person.sensorPeriod, person.sensorJitter, person.sensorDrift};
    scenarioPersonRates_.push_back(rate);
    personStaleAfter_.push_back(0.0);
    personClock_.emplace_back();
    setPersonRate(personClock_.size() - 1, rate);
  }
  for (int a = 0; a < arms; ++a) {
    const ArmInstance& inst = monitor_.arm(a);
    scenarioArmRates_.push_back({proto::SensorRate::Arm, static_cast<std::uint16_t>(a), inst.sensorPeriod, inst.sensorJitter,
                                 inst.sensorDrift});
  }
  if (!cfg_.logDir.empty()) {
    namespace fs = std::filesystem;
    fs::create_directories(cfg_.logDir);
    std::string header = "cycle,t_s,readings_from";
    for (int a = 0; a < arms; ++a)
      for (const char* column : {"_level", "_min_ttc_s", "_cause", "_cause_body", "_cause_other", "_cause_distance_m", "_cause_ttc_s"})
        header += ',' + io::csvField(monitor_.arm(a).name + column);
    header += ",nearest,nearest_other,distance_m,ttc_s";
    if (!held_.empty())
      for (int a = 0; a < arms; ++a)
        for (const char* column : {"_factor", "_person_separation_m", "_S_p_m", "_person"})
          header += ',' + io::csvField(monitor_.arm(a).name + column);
    verdictLog_.emplace(fs::path(cfg_.logDir) / "verdicts.csv", header);
    connLog_.emplace(fs::path(cfg_.logDir) / "connections.csv", "wall_s,connection,event,detail");
  }
  verdict_.arms.resize(arms);
}

ArmService::~ArmService() = default;

int ArmService::run() {
  const int sig = server_.run();
  // a cycle whose readings arrived just before the stop still runs and is logged
  if (pending_) runCycle();
  if (verdictLog_) verdictLog_->flush();
  if (connLog_) connLog_->flush();
  return sig;
}

void ArmService::stop() { server_.stop(); }

void ArmService::logConnection(net::ConnectionId id, const std::string& event, const std::string& detail) {
  if (!connLog_) return;
  connLog_->row(io::fixed(wallSeconds(), 6) + ',' + std::to_string(id) + ',' + io::csvField(event) + ',' +
                io::csvField(io::oneLine(detail)));
  connLog_->flush();
}

void ArmService::onOpen(net::Server&, net::ConnectionId id) {
  peers_[id] = Peer{};
  ++counters_.connections;
  ++awaitingHello_;
  helloQueue_.emplace_back(id, Clock::now() + cfg_.helloTimeout);
  logConnection(id, "open", "");
  // one more than the pending slots: the oldest pending connection makes room (a flood sheds
  // itself; a sensor says HELLO at once and leaves the queue before many arrive)
  while (awaitingHello_ > cfg_.maxPending && !helloQueue_.empty()) {
    const net::ConnectionId oldest = helloQueue_.front().first;
    helloQueue_.pop_front();
    const auto it = peers_.find(oldest);
    if (it == peers_.end() || it->second.stage != Stage::Pending) continue;
    it->second.stage = Stage::Leaving;
    --awaitingHello_;
    ++counters_.shed;
    server_.close(oldest, net::CloseReason::ServerFull,
                  "shed: " + std::to_string(cfg_.maxPending) + " connections already wait for their HELLO");
  }
  armHelloTimer();
}

void ArmService::armHelloTimer() {
  if (helloTimerArmed_ || helloQueue_.empty()) return;
  helloTimerArmed_ = true;
  helloTimer_.expires_at(helloQueue_.front().second);
  helloTimer_.async_wait([this](const boost::system::error_code& e) {
    helloTimerArmed_ = false;
    if (!e) onHelloTimer();
  });
}

void ArmService::onHelloTimer() {
  const auto now = Clock::now();
  while (!helloQueue_.empty() && helloQueue_.front().second <= now) {
    const net::ConnectionId id = helloQueue_.front().first;
    helloQueue_.pop_front();
    const auto it = peers_.find(id);
    if (it == peers_.end() || it->second.stage != Stage::Pending) continue;
    it->second.stage = Stage::Leaving;
    --awaitingHello_;
    ++counters_.helloTimeouts;
    server_.fail(id, "no HELLO within " + std::to_string(cfg_.helloTimeout.count()) + " ms of connecting");
  }
  armHelloTimer();
}

void ArmService::onClose(net::Server&, net::ConnectionId id, net::CloseReason why, const std::string& detail) {
  const auto it = peers_.find(id);
  if (it != peers_.end()) {
    if (it->second.stage == Stage::Pending) --awaitingHello_;
    if (it->second.stage == Stage::Client) --clients_;
    peers_.erase(it);
  }
  release(id);
  // it takes its time with it: the service's time is the newest of those still connected
  lastCycleT_ = -1e300;
  for (const auto& [pid, p] : peers_) lastCycleT_ = std::max(lastCycleT_, p.newestT);
  logConnection(id, net::toString(why), detail);
}

void ArmService::setPersonRate(std::size_t k, const proto::SensorRate& r) {
  const double gap = r.period > 0.0 ? r.period + r.jitter : staleAfter_;
  personStaleAfter_[k] = gap * (1.0 + r.drift);
  personClock_[k] = SensorClock{r.drift};
  personMarkStamp_[k] = std::numeric_limits<double>::quiet_NaN();
}

void ArmService::release(net::ConnectionId id) {
  // what it reported is free, and its disputes are over: the next claimant owns it alone
  for (std::size_t a = 0; a < armOwner_.size(); ++a)
    if (armOwner_[a] == id) {
      armOwner_[a] = kNobody, armDisputed_[a] = 0;
      // its readings leave with it: the next owner's clock starts afresh (and until it reports,
      // the arm has no reading: STOP)
      monitor_.forget(static_cast<int>(a));
      pendingArm_[a].fresh = false;
      // rates it declared leave with it: the scenario's again for the next owner
      const proto::SensorRate& r = scenarioArmRates_[a];
      monitor_.setSensorRate(static_cast<int>(a), r.period, r.jitter, r.drift);
    }
  for (std::size_t o = 0; o < obstacleOwner_.size(); ++o)
    if (obstacleOwner_[o] == id) obstacleOwner_[o] = kNobody, obstacleDisputed_[o] = 0;
  // a person's tracker that leaves leaves the person where it was last seen, going stale: every
  // arm STOPs until a pose comes again (a person no longer seen may be anywhere)
  for (std::size_t k = 0; k < personOwner_.size(); ++k)
    if (personOwner_[k] == id) {
      personOwner_[k] = kNobody, personDisputed_[k] = 0;
      setPersonRate(k, scenarioPersonRates_[k]);  // the next tracker keeps a clock of its own
    }
}

std::string ArmService::checkTime(net::ConnectionId id, const Peer& p, const char* kind, std::uint32_t seqNo, double t) const {
  // the message's name is only built for a refusal (none on the way of a message taken)
  const auto name = [&] { return std::string(kind) + " seq " + std::to_string(seqNo); };
  if (!std::isfinite(t)) return name() + ": time is not a finite number";
  if (std::abs(t) > kMaxClock) return name() + ": time " + num(t) + " s is beyond any clock (at most 1e12 s either way)";
  // A connection with a clock of its own, or one that owns what it reports (CLAIM), is held to
  // its own clock alone: no other client's time may get a sensor refused (it would lose its arms
  // to whoever claims them next). A clock jumping ahead is a fault of this connection.
  if (std::isfinite(p.newestT) || p.owns) {
    if (!std::isfinite(p.newestT)) return "";
    if (t - p.newestT > cfg_.maxLead)
      return name() + ": time " + num(t) + " s jumps more than " + num(cfg_.maxLead) + " s ahead of this connection's last (" +
             num(p.newestT) + " s)";
    return "";
  }
  // its first time: within maxLead of the newest of the sensors that are talking
  const auto now = Clock::now();
  double fastest = -std::numeric_limits<double>::infinity();
  for (const auto& [pid, q] : peers_)
    if (pid != id && q.stage != Stage::Leaving && std::isfinite(q.newestT) && now - q.lastHeard <= kTalking)
      fastest = std::max(fastest, q.newestT);
  if (std::isfinite(fastest) && std::abs(t - fastest) > cfg_.maxLead)
    return name() + ": time " + num(t) + " s is more than " + num(cfg_.maxLead) + " s " + (t > fastest ? "ahead of" : "behind") +
           " a sensor that is talking (at " + num(fastest) + " s)";
  return "";
}

void ArmService::heard(Peer& p, double t) {
  p.newestT = std::max(p.newestT, t);
  p.lastHeard = Clock::now();
}

std::string ArmService::errorPayload(const std::string& message) { return proto::encode(proto::Error{message}); }

void ArmService::onFrame(net::Server& s, net::ConnectionId id, std::string_view payload) {
  const auto it = peers_.find(id);
  if (it == peers_.end()) return;
  Peer& p = it->second;
  if (p.stage == Stage::Leaving) return;  // refused or shed: nothing more it sends counts
  proto::Type type;
  std::string err;
  if (proto::peekType(payload, type, err)) {
    if (!p.hello && type != proto::Type::Hello) {
      err = "expected HELLO first";
    } else {
      switch (type) {
        case proto::Type::Hello: err = onHello(id, p, payload); break;
        case proto::Type::Readings: err = onReadings(id, p, payload); break;
        case proto::Type::Obstacles: err = onObstacles(id, p, payload); break;
        case proto::Type::Claim: err = onClaim(id, p, payload); break;
        case proto::Type::Skeletons: err = onSkeletons(id, p, payload); break;
        case proto::Type::Reset: {
          const proto::Decoded d = proto::decode(payload);
          if (!d.ok) {
            err = d.error;
            break;
          }
          // any client may ask (the latch is an acknowledgement, not a reading): an arm whose
          // sensor is not current again stays latched, and the verdict says so
          for (const std::uint16_t a : std::get<proto::Reset>(d.message).arms)
            if (a >= monitor_.armCount()) err = "RESET: unknown arm id " + std::to_string(a);
          if (err.empty())
            for (const std::uint16_t a : std::get<proto::Reset>(d.message).arms) monitor_.reset(a);
          break;
        }
        case proto::Type::Subscribe: {
          const proto::Decoded d = proto::decode(payload);
          if (!d.ok) {
            err = d.error;
            break;
          }
          p.subscribed = true;
          p.ownOnly = (std::get<proto::Subscribe>(d.message).flags & proto::Subscribe::kOwnOnly) != 0;
          break;
        }
        default: err = "a client does not send this message type"; break;
      }
    }
  }
  if (!err.empty()) {
    ++counters_.rejected;
    // it leaves now (the server closes it once the ERROR is out): what it owned is free at once
    if (p.stage == Stage::Pending) --awaitingHello_;
    if (p.stage == Stage::Client) --clients_;
    p.stage = Stage::Leaving;
    release(id);
    s.fail(id, err);
    return;
  }
  // a cycle per message unless batching: the first client's verdict does not wait for the reads of the rest
  if (pending_ && !cfg_.batchCycles) runCycle();
}

std::string ArmService::onHello(net::ConnectionId id, Peer& p, std::string_view payload) {
  if (p.hello) return "HELLO twice";
  const proto::Decoded d = proto::decode(payload);
  if (!d.ok) return d.error;
  const auto& h = std::get<proto::Hello>(d.message);
  if (h.version < proto::kOldestVersion || h.version > proto::kVersion)
    return "protocol version " + std::to_string(h.version) + " not supported (this service speaks " +
           std::to_string(proto::kOldestVersion) + " to " + std::to_string(proto::kVersion) + ")";
  p.version = static_cast<std::uint8_t>(h.version);
  if (!cfg_.token.empty() && !sameToken(h.token, cfg_.token)) return "bad token";
  // a client slot: those are apart from the pending ones, so a flood of pending connections never takes them
  p.stage = Stage::Leaving;
  --awaitingHello_;
  if (clients_ >= cfg_.maxClients) {
    ++counters_.refusedFull;
    server_.fail(id, "server full (" + std::to_string(cfg_.maxClients) + " connections)", net::CloseReason::ServerFull);
    return "";
  }
  p.stage = Stage::Client;
  ++clients_;
  p.hello = true;
  proto::Welcome w;
  w.version = p.version;
  w.cycleTime = monitor_.safety().cycleTime;
  w.safeTime = monitor_.safety().safeTime();
  for (int a = 0; a < monitor_.armCount(); ++a) {
    w.armNames.push_back(monitor_.arm(a).name);
    w.armDofs.push_back(static_cast<std::uint8_t>(monitor_.arm(a).model.dof()));
  }
  for (const Obstacle& o : monitor_.obstacles()) w.obstacleNames.push_back(o.name);
  for (int k = 0; k < persons_.size(); ++k) w.personNames.push_back(persons_.name(k));
  server_.send(id, proto::encode(w, p.version));
  return "";
}

// "" if `id` may report the item `owners[k]` keeps (it owns it, or it is free and `id` claims
// by reporting); else the reason, and another owner's item is marked disputed.
std::string ArmService::mayReport(net::ConnectionId id, const Peer& p, std::vector<net::ConnectionId>& owners,
                                  std::vector<char>& disputed, std::size_t k, const std::string& name,
                                  const std::string& where, const char* stopped) {
  const net::ConnectionId owner = owners[k];
  if (owner == id) return "";
  if (owner == kNobody) return p.claimed ? where + ": " + name + " is not in this connection's CLAIM" : "";
  // two accounts of one thing: neither can be trusted; STOP until its owner leaves
  disputed[k] = 1;
  ++counters_.disputes;
  return where + ": " + name + " is reported by connection " + std::to_string(owner) + " (" + stopped +
         " until that connection leaves)";
}

bool ArmService::mayReportAtOnce(net::ConnectionId id, const Peer& p, net::ConnectionId owner) {
  return owner == id || (owner == kNobody && !p.claimed);
}

std::string ArmService::mayReportArm(net::ConnectionId id, const Peer& p, int a, const std::string& where) {
  if (mayReportAtOnce(id, p, armOwner_[a])) return "";
  return mayReport(id, p, armOwner_, armDisputed_, static_cast<std::size_t>(a),
                   "arm " + std::to_string(a) + " (" + monitor_.arm(a).name + ")", where,
                   "one connection per arm; the arm is stopped");
}

std::string ArmService::mayReportObstacle(net::ConnectionId id, const Peer& p, int o, const std::string& where) {
  const Obstacle& ob = monitor_.obstacles()[o];
  const std::string name = "obstacle " + std::to_string(o) + " (" + ob.name + ")";
  if (!ob.tracked) return where + ": " + name + " is not tracked (the scenario puts it; obstacles[i].tracked)";
  return mayReport(id, p, obstacleOwner_, obstacleDisputed_, static_cast<std::size_t>(o), name, where,
                   "one connection per obstacle; every arm is stopped");
}

std::string ArmService::onClaim(net::ConnectionId id, Peer& p, std::string_view payload) {
  if (p.claimed) return "CLAIM twice";
  if (p.reported) return "CLAIM after this connection's first READINGS or OBSTACLES";
  const proto::Decoded d = proto::decode(payload);
  if (!d.ok) return d.error;
  const auto& c = std::get<proto::Claim>(d.message);
  // every claim checked before any is taken: a refused CLAIM owns nothing; each item another
  // connection owns is disputed, not just the first
  for (const std::uint16_t a : c.arms)
    if (a >= monitor_.armCount())
      return "CLAIM: unknown arm id " + std::to_string(a) + " (the scenario has " + std::to_string(monitor_.armCount()) + " arms)";
  for (const std::uint16_t o : c.obstacles)
    if (o >= monitor_.obstacles().size())
      return "CLAIM: unknown obstacle id " + std::to_string(o) + " (the scenario has " +
             std::to_string(monitor_.obstacles().size()) + ")";
  // version 4: the rates of its sensors, each of an arm it claims or of a person (claimed with it)
  std::vector<std::uint16_t> persons;
  for (const proto::SensorRate& r : c.rates) {
    const bool arm = r.kind == proto::SensorRate::Arm;
    const std::string what = std::string(arm ? "arm " : "person ") + std::to_string(r.id);
    if (arm && std::find(c.arms.begin(), c.arms.end(), r.id) == c.arms.end())
      return "CLAIM: a rate for " + what + ", which this CLAIM does not name";
    if (!arm && r.id >= held_.size())
      return "CLAIM: unknown person id " + std::to_string(r.id) + " (the scenario has " + std::to_string(held_.size()) + " persons)";
    if (!(std::isfinite(r.period) && r.period > 0.0 && r.period <= 60.0))
      return "CLAIM: " + what + " rate: period " + num(r.period) + " s is not in (0, 60]";
    if (!(r.jitter >= 0.0 && r.jitter < r.period))
      return "CLAIM: " + what + " rate: jitter " + num(r.jitter) + " s is not in [0, period)";
    if (!(r.drift >= 0.0 && r.drift < 0.5)) return "CLAIM: " + what + " rate: drift " + num(r.drift) + " is not in [0, 0.5)";
    if (!arm) {
      if (std::find(persons.begin(), persons.end(), r.id) != persons.end()) return "CLAIM: " + what + " has two rates";
      persons.push_back(r.id);
    }
  }
  std::string owned;
  for (const std::uint16_t a : c.arms)
    if (std::string e = mayReportArm(id, p, a, "CLAIM"); !e.empty() && owned.empty()) owned = std::move(e);
  for (const std::uint16_t o : c.obstacles)
    if (std::string e = mayReportObstacle(id, p, o, "CLAIM"); !e.empty() && owned.empty()) owned = std::move(e);
  for (const std::uint16_t k : persons)
    if (std::string e = mayReport(id, p, personOwner_, personDisputed_, k, "person " + std::to_string(k) + " (" + persons_.name(k) + ")",
                                  "CLAIM", "one connection per person; every arm is stopped");
        !e.empty() && owned.empty())
      owned = std::move(e);
  if (!owned.empty()) return owned;
  for (const std::uint16_t a : c.arms) armOwner_[a] = id;
  for (const std::uint16_t o : c.obstacles) obstacleOwner_[o] = id;
  for (const std::uint16_t k : persons) personOwner_[k] = id;
  for (const proto::SensorRate& r : c.rates) {
    if (r.kind == proto::SensorRate::Arm) monitor_.setSensorRate(r.id, r.period, r.jitter, r.drift);
    else setPersonRate(r.id, r);
  }
  p.claimed = true;
  p.owns = !c.arms.empty() || !c.obstacles.empty() || !persons.empty();
  return "";
}

std::string ArmService::onReadings(net::ConnectionId id, Peer& p, std::string_view payload) {
  if (std::string e = proto::decodeReadings(payload, readings_); !e.empty()) return e;
  const proto::Readings& r = readings_;
  // the message's name only for a refusal (a message taken builds no text)
  const auto seqName = [&] { return "READINGS seq " + std::to_string(r.seq); };
  if (std::string e = checkTime(id, p, "READINGS", r.seq, r.t); !e.empty()) return e;
  if (r.t < p.lastT)
    return seqName() + ": time " + num(r.t) + " s goes backwards (this connection's last was " + num(p.lastT) + " s)";
  // whose arms: every one named that another connection owns is disputed, not just the first
  std::string owned;
  for (const proto::ArmReading& a : r.arms)
    if (a.arm < monitor_.armCount() && !mayReportAtOnce(id, p, armOwner_[a.arm]))
      if (std::string e = mayReportArm(id, p, a.arm, seqName()); !e.empty() && owned.empty()) owned = std::move(e);
  if (!owned.empty()) return owned;
  // every reading checked before any is applied: a refused message leaves the monitor as it was
  for (std::size_t k = 0; k < r.arms.size(); ++k) {
    const proto::ArmReading& a = r.arms[k];
    if (a.arm >= monitor_.armCount())
      return seqName() + ": unknown arm id " + std::to_string(a.arm) + " (the scenario has " +
             std::to_string(monitor_.armCount()) + " arms, ids 0.." + std::to_string(monitor_.armCount() - 1) + ")";
    // one arm, one time, one state (as in a trace: CsvSensor); the same reading twice is harmless
    for (std::size_t j = 0; j < k; ++j)
      if (r.arms[j].arm == a.arm && (r.arms[j].q != a.q || r.arms[j].qdot != a.qdot))
        return seqName() + ": arm " + std::to_string(a.arm) + " is given twice with different joint values";
    // the reading as a trace's would be checked (validateReading); its name is made only for the
    // reason of a refusal, the check run again with it
    const ArmModel& model = monitor_.arm(a.arm).model;
    bool valid = static_cast<int>(a.q.size()) == model.dof() && static_cast<int>(a.qdot.size()) == model.dof();
    if (valid) try {
        validateJointState(model, a.q.data(), a.qdot.data(), "");
      } catch (const InputError&) {
        valid = false;
      }
    if (!valid) {
      check_.t = r.t;
      check_.arm = a.arm;
      check_.q = a.q;
      check_.qdot = a.qdot;
      check_.where = seqName() + " arm " + std::to_string(a.arm);
      try {
        validateReading(model, check_);
      } catch (const InputError& e) {
        return e.what();
      }
    }
  }
  for (const proto::ArmReading& a : r.arms) {
    armOwner_[a.arm] = id;  // claimed by its first report, if not by CLAIM
    // kept until the cycle: of several readings of one arm in a cycle only the newest (its
    // owner's times never go back) is worked on
    Pending& pa = pendingArm_[a.arm];
    pa.q = a.q;
    pa.qdot = a.qdot;
    pa.t = r.t;
    pa.fresh = true;
  }
  p.reported = true;
  p.lastT = r.t;
  heard(p, r.t);
  counters_.readings += r.arms.size();
  if (!p.inCycle) {
    p.inCycle = true;
    inCycle_.push_back(id);
  }
  p.ack = r.seq;
  cycleT_ = pending_ ? std::max(cycleT_, r.t) : r.t;
  pending_ = true;
  return "";
}

std::string ArmService::onObstacles(net::ConnectionId id, Peer& p, std::string_view payload) {
  const proto::Decoded d = proto::decode(payload);
  if (!d.ok) return d.error;
  const auto& m = std::get<proto::Obstacles>(d.message);
  const std::string seq = "OBSTACLES seq " + std::to_string(m.seq);
  if (std::string e = checkTime(id, p, "OBSTACLES", m.seq, m.t); !e.empty()) return e;
  for (const proto::ObstaclePose& o : m.obstacles) {
    if (o.obstacle >= monitor_.obstacles().size())
      return seq + ": unknown obstacle id " + std::to_string(o.obstacle) + " (the scenario has " +
             std::to_string(monitor_.obstacles().size()) + ")";
    if (!o.position.allFinite() || !o.velocity.allFinite())
      return seq + ": obstacle " + std::to_string(o.obstacle) + " pose is not finite";
    if (o.velocity.norm() > 100.0) return seq + ": obstacle " + std::to_string(o.obstacle) + " faster than 100 m/s";
  }
  std::string owned;
  for (const proto::ObstaclePose& o : m.obstacles)
    if (std::string e = mayReportObstacle(id, p, o.obstacle, seq); !e.empty() && owned.empty()) owned = std::move(e);
  if (!owned.empty()) return owned;
  p.reported = true;
  for (const proto::ObstaclePose& o : m.obstacles) {
    obstacleOwner_[o.obstacle] = id;
    monitor_.setObstaclePose(o.obstacle, m.t, o.position, o.velocity);
    poseT_[o.obstacle] = m.t;
  }
  counters_.obstaclePoses += m.obstacles.size();
  heard(p, m.t);
  if (!p.inCycle) {
    p.inCycle = true;
    inCycle_.push_back(id);
  }
  p.ack = m.seq;
  cycleT_ = pending_ ? std::max(cycleT_, m.t) : m.t;
  pending_ = true;
  return "";
}

std::string ArmService::onSkeletons(net::ConnectionId id, Peer& p, std::string_view payload) {
  if (p.version < 3)
    return "SKELETONS needs protocol version 3 (this connection said HELLO with version " + std::to_string(p.version) + ")";
  // decoded into storage kept from message to message; the message's name only for a refusal
  if (std::string e = proto::decodeSkeletons(payload, skeletons_); !e.empty()) return e;
  const proto::Skeletons& m = skeletons_;
  const auto seqName = [&] { return "SKELETONS seq " + std::to_string(m.seq); };
  if (std::string e = checkTime(id, p, "SKELETONS", m.seq, m.t); !e.empty()) return e;
  // every pose checked before any is taken
  for (const proto::PersonPose& pp : m.persons) {
    if (pp.person >= held_.size())
      return seqName() + ": unknown person id " + std::to_string(pp.person) + " (the scenario has " + std::to_string(held_.size()) +
             " persons)";
    for (std::size_t j = 0; j < pp.joints.size(); ++j)
      if (!pp.joints[j].allFinite() || pp.joints[j].cwiseAbs().maxCoeff() > 1000.0)
        return seqName() + ": person " + std::to_string(pp.person) + " joint " + jointName(static_cast<int>(j)) +
               " is not a finite position within 1 km of the cell";
  }
  std::string owned;
  for (const proto::PersonPose& pp : m.persons)
    if (!mayReportAtOnce(id, p, personOwner_[pp.person]))
      if (std::string e = mayReport(id, p, personOwner_, personDisputed_, pp.person,
                                    "person " + std::to_string(pp.person) + " (" + persons_.name(pp.person) + ")", seqName(),
                                    "one connection per person; every arm is stopped");
          !e.empty() && owned.empty())
        owned = std::move(e);
  if (!owned.empty()) return owned;
  p.reported = true;
  for (const proto::PersonPose& pp : m.persons) {
    personOwner_[pp.person] = id;
    held_[pp.person]->set(pp.joints.data(), m.t);
    if (std::isnan(personT_[pp.person]) || m.t > personT_[pp.person]) personNew_[pp.person] = 1;
    personT_[pp.person] = m.t;
  }
  heard(p, m.t);
  if (!p.inCycle) {
    p.inCycle = true;
    inCycle_.push_back(id);
  }
  p.ack = m.seq;
  cycleT_ = pending_ ? std::max(cycleT_, m.t) : m.t;
  pending_ = true;
  return "";
}

void ArmService::applyPersons(double t) {
  if (!ssm_) return;
  persons_.pose(t);
  ssm_->cycle(monitor_, persons_);
  // a person whose tracker fell silent (or left) may be anywhere: every arm stops, as for an obstacle
  bool lost = false, disputed = false;
  for (std::size_t k = 0; k < personT_.size(); ++k) {
    // for a tracker whose clock may drift: a pose new since the last cycle is marked as arrived
    // at the first later cycle (this cycle's time may be older than the pose's arrival)
    if (!std::isnan(personMarkStamp_[k]) && t > personMarkAfter_[k]) {
      personClock_[k].arrived(personMarkStamp_[k], t);
      personMarkStamp_[k] = std::numeric_limits<double>::quiet_NaN();
    }
    if (personNew_[k] && std::isnan(personMarkStamp_[k]) && personClock_[k].drift > 0.0)
      personMarkStamp_[k] = personT_[k], personMarkAfter_[k] = t;
    personNew_[k] = 0;
    lost = lost || (!std::isnan(personT_[k]) && !(std::abs(personClock_[k].age(personT_[k], t)) <= personStaleAfter_[k]));
  }
  for (const char d : personDisputed_) disputed = disputed || d;
  for (int a = 0; a < monitor_.armCount(); ++a) {
    proto::ArmVerdict& v = verdict_.arms[a];
    const SsmVerdict& s = ssm_->verdict(a);
    v.factor = s.factor;
    v.personSeparation = s.separation;
    v.required = s.required;
    v.person = static_cast<std::int16_t>(s.person);
    v.part = static_cast<std::int16_t>(s.part);
    if (v.level == proto::Level::Stop) {
      v.factor = 0.0;
      continue;
    }
    if (lost || disputed) {
      v.level = proto::Level::Stop;
      v.cause = lost ? proto::Cause::ObstacleLost : proto::Cause::Disputed;
      v.pair = proto::Nearest{};
      v.pair.arm = static_cast<std::int16_t>(a);
      v.factor = 0.0;
      ++(lost ? counters_.staleStops : counters_.disputeStops);
    } else if (s.stop) {
      v.level = proto::Level::Stop;
      v.cause = proto::Cause::Person;
      v.pair = proto::Nearest{};
      v.pair.arm = static_cast<std::int16_t>(a);
      v.pair.distance = s.separation;
    }
  }
}

void ArmService::onReadDone(net::Server&, net::ConnectionId) {
  if (!pending_ || !cfg_.batchCycles) return;
  // complete when every connection that reports is in it: no later read of this pass adds to it,
  // so the verdict goes out in this read (as the echo floor answers) rather than a pass of the
  // event loop later, after a poll of every socket; a sensor that has not reported yet in this
  // cycle leaves it to onIdle, as before
  for (const auto& [id, p] : peers_)
    if (p.reported && p.stage == Stage::Client && !p.inCycle) return;
  runCycle();
}

void ArmService::onIdle(net::Server&) {
  if (pending_) runCycle();
}

void ArmService::runCycle() {
  const auto started = Clock::now();
  pending_ = false;
  const double t = std::max(cycleT_, lastCycleT_);
  lastCycleT_ = t;
  takeReadings();
  monitor_.cycle(t);
  ++counters_.cycles;
  verdict_.cycle = counters_.cycles;
  verdict_.t = t;
  armVerdicts(t);
  applyPersons(t);
  applyDeadline(started);
  const Warning& n = monitor_.nearest();
  verdict_.nearest = {static_cast<std::int16_t>(n.arm), static_cast<std::int16_t>(n.body),
                      static_cast<std::int16_t>(n.otherArm), static_cast<std::int16_t>(n.otherBody),
                      static_cast<std::int16_t>(n.obstacle), n.distance, n.ttc};
  sendVerdicts();
  // the log row after the verdicts are on their way (the write is off the latency path)
  if (verdictLog_) logVerdict(t);
  for (net::ConnectionId id : inCycle_) {
    const auto it = peers_.find(id);
    if (it != peers_.end()) it->second.inCycle = false;
  }
  inCycle_.clear();
}

void ArmService::takeReadings() {
  for (int a = 0; a < monitor_.armCount(); ++a) {
    Pending& pa = pendingArm_[a];
    if (!pa.fresh) continue;
    pa.fresh = false;
    try {
      monitor_.setJointState(a, pa.t, pa.q.data(), pa.qdot.data());
    } catch (const InputError&) {
      // checked when it arrived; should the monitor still refuse it, the arm has no reading
      // (STOP) rather than the service stopping for every client
      monitor_.forget(a);
    }
  }
}

void ArmService::armVerdicts(double t) {
  // the verdict: per arm OK / WARN / STOP, the nearest pair and its time to collision
  // a tracked obstacle whose tracker fell silent may be anywhere near any arm: every arm stops
  bool obstacleLost = false;
  for (const double pt : poseT_) obstacleLost = obstacleLost || (!std::isnan(pt) && !(std::abs(t - pt) <= staleAfter_));
  // a disputed obstacle may be where either account puts it: every arm stops
  bool obstacleDisputed = false;
  for (const char d : obstacleDisputed_) obstacleDisputed = obstacleDisputed || d;
  for (int a = 0; a < monitor_.armCount(); ++a) {
    proto::ArmVerdict& v = verdict_.arms[a];
    v.minTtc = monitor_.minTtc(a);
    // the geometry's level (the monitor's STOP also holds its watchdog's, below)
    v.level = monitor_.warned(a) ? proto::Level::Stop : std::isfinite(v.minTtc) ? proto::Level::Warn : proto::Level::Ok;
    // the cause: the pair with the arm's smallest time to collision (not the nearest pair: a
    // close pair at rest may be nearer than the fast one that decides)
    const Warning& w = monitor_.worst(a);
    v.pair = {static_cast<std::int16_t>(a), static_cast<std::int16_t>(w.body), static_cast<std::int16_t>(w.otherArm),
              static_cast<std::int16_t>(w.otherBody), static_cast<std::int16_t>(w.obstacle), w.distance, w.ttc};
    proto::Nearest none;
    none.arm = static_cast<std::int16_t>(a);
    if (v.level == proto::Level::Ok) v.pair = none;
    v.cause = v.level == proto::Level::Ok     ? proto::Cause::None
              : v.level == proto::Level::Warn ? proto::Cause::Lookahead
              : w.outcome == Outcome::Overlapping ? proto::Cause::Separation
                                                : proto::Cause::Collision;
    // fail safe: a verdict on a reading that is not current (or none: the monitor's watchdog, by
    // the arm's declared sensor period) is no verdict: STOP, and the geometry (of a pose no sensor
    // gave now) is not its cause
    if (monitor_.stale(a) || monitor_.latched(a)) {
      if (v.level != proto::Level::Stop) ++counters_.staleStops;
      v.level = proto::Level::Stop;
      v.cause = monitor_.stale(a) ? proto::Cause::Stale : proto::Cause::Latched;
      v.pair = none;
      continue;
    }
    if (v.level == proto::Level::Stop) continue;
    if (obstacleLost) {
      v.level = proto::Level::Stop;
      v.cause = proto::Cause::ObstacleLost;
      v.pair = none;
      ++counters_.staleStops;
    } else if (armDisputed_[a] || obstacleDisputed) {
      v.level = proto::Level::Stop;
      v.cause = proto::Cause::Disputed;
      v.pair = none;
      ++counters_.disputeStops;
    }
  }
}

void ArmService::applyDeadline(Clock::time_point started) {
  // the deadline: a cycle that took longer than its budget fails safe, every arm STOP for it
  if (!(cfg_.cycleBudgetUs > 0.0 &&
        std::chrono::duration<double, std::micro>(Clock::now() - started).count() > cfg_.cycleBudgetUs))
    return;
  ++counters_.deadlineMisses;
  for (int a = 0; a < monitor_.armCount(); ++a) {
    proto::ArmVerdict& v = verdict_.arms[a];
    if (v.level == proto::Level::Stop) continue;
    v.level = proto::Level::Stop;
    v.cause = proto::Cause::Deadline;
    v.pair = proto::Nearest{};
    v.pair.arm = static_cast<std::int16_t>(a);
    v.factor = 0.0;
  }
}

void ArmService::sendVerdicts() {
  for (auto& [id, p] : peers_) {
    if (!p.subscribed || (p.ownOnly && !p.inCycle)) continue;
    verdict_.ack = p.inCycle ? p.ack : 0;
    out_.clear();
    proto::encodeInto(out_, verdict_, p.version);
    if (server_.send(id, out_)) ++counters_.verdictsSent;
  }
}

void ArmService::logVerdict(double t) {
  const Warning& n = monitor_.nearest();
  std::string& row = logRow_;
  row = std::to_string(counters_.cycles) + ',' + num(t) + ',';
  for (std::size_t k = 0; k < inCycle_.size(); ++k) (row += k ? " " : "") += std::to_string(inCycle_[k]);
  for (int a = 0; a < monitor_.armCount(); ++a) {
    const proto::ArmVerdict& v = verdict_.arms[a];
    row += ',' + std::string(proto::toString(v.level)) + ',' + num(v.minTtc) + ',' + proto::toString(v.cause);
    const Warning& w = monitor_.worst(a);
    const bool pair = v.pair.body >= 0;
    row += ',' + (pair ? io::csvField(monitor_.arm(a).name + "/" + bodyName(monitor_.arm(a).model, w.body)) : "") + ',' +
           (pair ? io::csvField(otherName(monitor_, w)) : "") + ',' + num(v.pair.distance) + ',' + num(v.pair.ttc);
  }
  if (n.arm >= 0)
    row += ',' + io::csvField(monitor_.arm(n.arm).name + "/" + bodyName(monitor_.arm(n.arm).model, n.body)) + ',' +
           io::csvField(otherName(monitor_, n)) + ',' + num(n.distance) + ',' + num(n.ttc);
  else row += ",,,inf,inf";
  if (ssm_)
    for (const proto::ArmVerdict& v : verdict_.arms)
      row += ',' + num(v.factor) + ',' + num(v.personSeparation) + ',' + num(v.required) + ',' +
             (v.person >= 0 ? io::csvField(persons_.name(v.person) + "/" + bodyParts()[v.part].name) : std::string());
  verdictLog_->row(row);
  verdictLog_->flush();
}

}  // namespace st::arm
