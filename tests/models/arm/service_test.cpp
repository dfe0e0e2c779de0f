// The arm service over loopback: closed loop through the network equals closed loop in
// process; every kind of bad client gets one ERROR and is closed while the service and the
// other clients go on and the log keeps every cycle; SIGINT / SIGTERM / SIGHUP end `stsim arm serve`
// cleanly. Only 127.0.0.1, ports picked by the system, every wait bounded.
#include <gtest/gtest.h>

#include <random>
#include <tuple>

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <starm/service.hpp>
#include <starm/stream.hpp>
#include <starm/study.hpp>
#include <stnet/client.hpp>
#include <stnet/frame.hpp>

#include "files.hpp"

namespace st::arm {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string scenarioPath(const std::string& name) {
  return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + name + ".yaml";
}

fs::path tempDir(const std::string& name) { return st::test::freshDir("arm_svc", name); }

using st::test::slurp;

int lineCount(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// The scenario's nominal (open-loop) sensor stream as a CSV trace.
fs::path recordTrace(const Scenario& s, const fs::path& file) {
  auto src = makeSensor(s);
  std::vector<std::string> names;
  for (const ArmInstance& a : s.arms) names.push_back(a.name);
  RecordingSensor rec(*src, file.string(), names);
  Reading r;
  while (rec.next(r)) {
  }
  return file;
}

struct Service {
  boost::asio::io_context io;
  ArmService service;
  std::thread thread;
  Service(const Scenario& s, ServiceConfig cfg) : service(io, s, withoutSignals(cfg)), thread([this] { service.run(); }) {}
  static ServiceConfig withoutSignals(ServiceConfig c) {
    c.net.handleSignals = false;
    return c;
  }
  ~Service() { stop(); }
  void stop() {
    if (!thread.joinable()) return;
    boost::asio::post(io, [this] { service.stop(); });
    thread.join();
  }
};

// A protocol client: HELLO, WELCOME, optional SUBSCRIBE.
struct Peer {
  net::Client c;
  explicit Peer(std::uint16_t port, bool subscribe = true, const std::string& token = "") {
    c.connect("127.0.0.1", port, 2s);
    c.send(proto::encode(proto::Hello{proto::kVersion, token}));
    const auto w = c.receive(2s);
    if (!w) throw std::runtime_error("no WELCOME");
    const proto::Decoded d = proto::decode(*w);
    if (!d.ok || !std::holds_alternative<proto::Welcome>(d.message)) throw std::runtime_error("not a WELCOME");
    if (subscribe) c.send(proto::encode(proto::Subscribe{proto::Subscribe::kOwnOnly}));
  }
  std::optional<proto::Message> next(std::chrono::milliseconds t = 2s) {
    const auto f = c.receive(t);
    if (!f) return std::nullopt;
    const proto::Decoded d = proto::decode(*f);
    if (!d.ok) return std::nullopt;
    return d.message;
  }
};

proto::Readings pandaReading(std::uint32_t seq, double t, std::uint16_t arm = 0) {
  proto::Readings r;
  r.seq = seq;
  r.t = t;
  r.arms = {{arm, {0, -0.785, 0, -2.356, 0, 1.571, 0.785}, std::vector<double>(7, 0.0)}};
  return r;
}

proto::Readings bothArms(std::uint32_t seq, double t) {
  proto::Readings r = pandaReading(seq, t, 0);
  r.arms.push_back(pandaReading(seq, t, 1).arms[0]);
  return r;
}

// The connection is told (ERROR naming the cause, one line) and closed.
void expectError(net::Client& c, const std::string& mention) {
  std::optional<std::string> f;
  // a verdict or two may be ahead of the error
  for (int k = 0; k < 5; ++k) {
    f = c.receive(3s);
    if (!f) break;
    const proto::Decoded d = proto::decode(*f);
    if (d.ok && std::holds_alternative<proto::Error>(d.message)) break;
  }
  ASSERT_TRUE(f.has_value()) << "no ERROR before close (expected: " << mention << ")";
  const proto::Decoded d = proto::decode(*f);
  ASSERT_TRUE(d.ok && std::holds_alternative<proto::Error>(d.message)) << "not an ERROR";
  const std::string& msg = std::get<proto::Error>(d.message).message;
  EXPECT_NE(msg.find(mention), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos);
  EXPECT_FALSE(c.receive(3s).has_value());
  EXPECT_TRUE(c.closed());
}

TEST(ArmService, ClosedLoopThroughTheNetworkEqualsInProcess) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path d = tempDir("loop");
  ServiceConfig cfg;
  cfg.logDir = (d / "log").string();
  Service svc(s, cfg);
  StreamConfig sc;
  sc.port = svc.service.port();
  sc.trace = recordTrace(s, d / "sensors.csv").string();
  sc.rate = 0.0;
  sc.braking = s.braking;
  StreamResult r;
  runStream(sc, r);
  svc.stop();
  const CourseOutcome inProcess = runCourse(s, true);
  EXPECT_EQ(r.cycles, 3001u);
  EXPECT_EQ(r.verdicts, 3001u);
  EXPECT_EQ(r.timeouts, 0u);
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(r.firstStop[a], 1.071, 1e-9);
    EXPECT_EQ(r.finalSpeed[a], 0.0) << "arm " << a << " was not stopped through the network";
  }
  EXPECT_EQ(r.minDistance, inProcess.minDistance);
  EXPECT_FALSE(inProcess.contact);
  // the log holds every cycle
  EXPECT_EQ(lineCount(slurp(d / "log" / "verdicts.csv")), 1 + 3001);
  fs::remove_all(d);
}

TEST(ArmService, OpenLoopStreamSeesTheContact) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path d = tempDir("open");
  Service svc(s, {});
  StreamConfig sc;
  sc.port = svc.service.port();
  sc.trace = recordTrace(s, d / "sensors.csv").string();
  sc.rate = 0.0;
  sc.closedLoop = false;
  StreamResult r;
  runStream(sc, r);
  EXPECT_EQ(r.minDistance, 0.0);
  EXPECT_EQ(r.finalSpeed[0], 1.0);
  fs::remove_all(d);
}

TEST(ArmService, RealTimeReplayKeepsTheTraceClock) {
  // 0.3 s of trace at rate 2 takes about 0.15 s of wall time, not "as fast as possible"
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path d = tempDir("rate");
  std::ofstream csv(d / "short.csv");
  {
    std::ifstream full(recordTrace(s, d / "sensors.csv"));
    std::string line;
    int n = 0;
    while (std::getline(full, line) && n++ < 1 + 2 * 301) csv << line << '\n';
  }
  csv.close();
  Service svc(s, {});
  StreamConfig sc;
  sc.port = svc.service.port();
  sc.trace = (d / "short.csv").string();
  sc.rate = 2.0;
  StreamResult r;
  const auto t0 = std::chrono::steady_clock::now();
  runStream(sc, r);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.cycles, 301u);
  EXPECT_GE(wall, 0.149);
  EXPECT_LT(wall, 5.0);
  fs::remove_all(d);
}

TEST(ArmService, BadClientsAreToldAndClosedOthersGoOn) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path d = tempDir("bad");
  ServiceConfig cfg;
  cfg.logDir = (d / "log").string();
  cfg.net.frameTimeout = 300ms;
  cfg.net.maxFrame = 4096;
  cfg.maxClients = 24;
  Service svc(s, cfg);
  const std::uint16_t port = svc.service.port();
  Peer good(port);
  std::uint32_t seq = 0;
  double t = 0.0;
  int answered = 0;
  // the good client: one reading, one verdict acknowledging it
  auto goodCycle = [&] {
    good.c.send(proto::encode(pandaReading(++seq, t += 0.001, 1)));
    for (int k = 0; k < 10; ++k) {
      const auto m = good.next();
      ASSERT_TRUE(m.has_value()) << "the good client lost its service";
      if (const auto* v = std::get_if<proto::Verdict>(&*m); v && v->ack == seq) {
        ++answered;
        return;
      }
    }
    FAIL() << "no verdict for seq " << seq;
  };
  goodCycle();

  auto raw = [&] {
    auto c = std::make_unique<net::Client>();
    c->connect("127.0.0.1", port, 2s);
    return c;
  };
  int bad = 0;
  {  // garbage bytes: an HTTP request is a frame "length" of 1.2 GB
    auto c = raw();
    c->sendRaw("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
    expectError(*c, "exceeds the limit of 4096 bytes");
    ++bad;
  }
  goodCycle();
  {  // oversized frame
    auto c = raw();
    c->sendRaw(net::frame(std::string(10000, 'z')));
    expectError(*c, "exceeds the limit");
    ++bad;
  }
  {  // a whole frame holding a truncated READINGS
    Peer p(port);
    const std::string m = proto::encode(pandaReading(1, 0.5));
    p.c.send(m.substr(0, m.size() - 5));
    expectError(p.c, "READINGS: truncated");
    ++bad;
  }
  goodCycle();
  {  // one byte at a time, slower than the frame timeout allows
    Peer p(port);
    const std::string f = net::frame(proto::encode(pandaReading(1, 0.5)));
    bool told = false;
    for (std::size_t k = 0; k < f.size() && !told; ++k) {
      try {
        p.c.sendRaw(f.substr(k, 1));
      } catch (const std::exception&) {
        break;
      }
      if (auto e = p.c.receive(150ms)) {
        const proto::Decoded dd = proto::decode(*e);
        ASSERT_TRUE(dd.ok && std::holds_alternative<proto::Error>(dd.message));
        EXPECT_NE(std::get<proto::Error>(dd.message).message.find("frame not completed within 300 ms"), std::string::npos);
        told = true;
      }
    }
    EXPECT_TRUE(told);
    ++bad;
  }
  goodCycle();
  {  // unknown arm id
    Peer p(port);
    p.c.send(proto::encode(pandaReading(1, 0.5, 5)));
    expectError(p.c, "unknown arm id 5 (the scenario has 2 arms");
    ++bad;
  }
  {  // NaN joint
    Peer p(port);
    proto::Readings r = pandaReading(1, 0.5);
    r.arms[0].q[1] = std::nan("");
    p.c.send(proto::encode(r));
    expectError(p.c, "joint 2 angle is not a finite number");
    ++bad;
  }
  {  // out-of-limit joint (Panda joint 4 is in [-3.07, -0.07])
    Peer p(port);
    proto::Readings r = pandaReading(1, 0.5);
    r.arms[0].q[3] = 0.5;
    p.c.send(proto::encode(r));
    expectError(p.c, "joint 4 angle 0.5 rad is beyond its limits");
    ++bad;
  }
  {  // wrong joint count
    Peer p(port);
    proto::Readings r = pandaReading(1, 0.5);
    r.arms[0].q.resize(6);
    r.arms[0].qdot.resize(6);
    p.c.send(proto::encode(r));
    expectError(p.c, "expected 7 joint angles and rates");
    ++bad;
  }
  {  // one arm twice in one message, the two differing: which state is it in? (the later won)
    Peer p(port);
    proto::Readings r = pandaReading(1, 0.5);
    r.arms.push_back(r.arms[0]);
    r.arms[1].q[0] = 0.1;
    p.c.send(proto::encode(r));
    expectError(p.c, "READINGS seq 1: arm 0 is given twice with different joint values");
    ++bad;
  }
  {  // readings before HELLO
    auto c = raw();
    c->send(proto::encode(pandaReading(1, 0.5)));
    expectError(*c, "expected HELLO first");
    ++bad;
  }
  {  // a protocol version from the future
    auto c = raw();
    std::string h = proto::encode(proto::Hello{});
    h[0] = 9;
    c->send(h);
    expectError(*c, "protocol version 9 not supported");
    ++bad;
  }
  goodCycle();
  {  // disconnect mid-frame
    Peer p(port);
    const std::string f = net::frame(proto::encode(pandaReading(1, 0.5)));
    p.c.sendRaw(f.substr(0, f.size() / 2));
    p.c.close();
    ++bad;
    std::this_thread::sleep_for(200ms);  // the service sees the close before the count below
  }
  goodCycle();
  {  // many clients at once: beyond the limit they are told at their HELLO, the held ones work
    std::vector<std::unique_ptr<Peer>> held;
    for (int k = 0; k < 20; ++k) held.push_back(std::make_unique<Peer>(port, false));
    std::vector<std::unique_ptr<net::Client>> extra;
    for (int k = 0; k < 10; ++k) {
      extra.push_back(raw());
      extra.back()->send(proto::encode(proto::Hello{proto::kVersion, ""}));
    }
    int full = 0;
    for (auto& c : extra) {
      const auto f = c->receive(500ms);
      if (f && proto::decode(*f).ok &&
          std::holds_alternative<proto::Error>(proto::decode(*f).message) &&
          std::get<proto::Error>(proto::decode(*f).message).message.find("server full (24 connections)") != std::string::npos)
        ++full;
    }
    // 20 held + the good one = 21 of 24: three extra fit, seven are told
    EXPECT_EQ(full, 7);
    for (auto& p : held) {
      p->c.send(proto::encode(proto::Subscribe{}));
    }
    goodCycle();
    // every held subscriber (all cycles) sees the good client's cycle
    for (auto& p : held) {
      const auto m = p->next();
      ASSERT_TRUE(m.has_value());
      EXPECT_TRUE(std::holds_alternative<proto::Verdict>(*m));
    }
  }
  std::this_thread::sleep_for(100ms);
  goodCycle();
  svc.stop();
  // the log: one row per cycle the good client asked for, none from a refused message
  EXPECT_EQ(svc.service.counters().cycles, static_cast<std::uint64_t>(answered));
  EXPECT_EQ(lineCount(slurp(d / "log" / "verdicts.csv")), 1 + answered);
  const std::string conns = slurp(d / "log" / "connections.csv");
  EXPECT_EQ(svc.service.counters().rejected, 8u);  // the protocol refusals; frame-level ones are the server's
  for (const char* why : {"frame too long", "frame timeout", "refused", "peer closed mid-frame", "server full"})
    EXPECT_NE(conns.find(why), std::string::npos) << why << "\n" << conns;
  EXPECT_EQ(svc.service.monitor().arm(0).name, "left");
  fs::remove_all(d);
}

TEST(ArmService, OneConnectionReportsEachArmAndAConnectionMayNotGoBack) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  Peer a(svc.service.port()), b(svc.service.port());
  proto::Readings both = bothArms(1, 0.2);
  a.c.send(proto::encode(both));
  auto v = a.next();
  ASSERT_TRUE(v && std::holds_alternative<proto::Verdict>(*v));
  EXPECT_EQ(std::get<proto::Verdict>(*v).arms[0].level, proto::Level::Ok);
  // b reports a's arm: refused, and the arm stops (two accounts of one arm) until a leaves
  b.c.send(proto::encode(pandaReading(1, 0.2005)));
  expectError(b.c, "arm 0 (left) is reported by connection");
  a.c.send(proto::encode(bothArms(2, 0.201)));
  v = a.next();
  ASSERT_TRUE(v && std::holds_alternative<proto::Verdict>(*v));
  EXPECT_EQ(std::get<proto::Verdict>(*v).arms[0].level, proto::Level::Stop) << "a disputed arm went on";
  EXPECT_EQ(std::get<proto::Verdict>(*v).arms[1].level, proto::Level::Ok) << "the undisputed arm was stopped";
  // a going back on its own connection is refused too
  a.c.send(proto::encode(pandaReading(3, 0.05)));
  expectError(a.c, "time 0.05 s goes backwards (this connection's last was 0.201 s)");
  std::this_thread::sleep_for(100ms);  // the service sees the close first
  // a has left: the arm is free, its next owner is alone and the dispute is over; the arms'
  // sensor left, so their STOP is held until a RESET
  Peer c(svc.service.port());
  c.c.send(proto::encode(bothArms(1, 0.202)));
  v = c.next();
  ASSERT_TRUE(v && std::holds_alternative<proto::Verdict>(*v));
  EXPECT_EQ(std::get<proto::Verdict>(*v).arms[0].cause, proto::Cause::Latched);
  c.c.send(proto::encode(proto::Reset{{0, 1}}));
  c.c.send(proto::encode(bothArms(2, 0.203)));
  v = c.next();
  ASSERT_TRUE(v && std::holds_alternative<proto::Verdict>(*v));
  EXPECT_EQ(std::get<proto::Verdict>(*v).arms[0].level, proto::Level::Ok);
  svc.stop();
  EXPECT_EQ(svc.service.counters().disputes, 1u);
  EXPECT_EQ(svc.service.counters().disputeStops, 1u);
}

TEST(ArmService, AClaimNamesWhatAConnectionReports) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  Peer a(svc.service.port());
  a.c.send(proto::encode(proto::Claim{{1}, {}}));
  // its claim is all it may report
  a.c.send(proto::encode(pandaReading(1, 0.1, 0)));
  expectError(a.c, "arm 0 (left) is not in this connection's CLAIM");
  Peer b(svc.service.port());
  b.c.send(proto::encode(proto::Claim{{0}, {0}}));
  b.c.send(proto::encode(pandaReading(1, 0.1, 0)));
  ASSERT_TRUE(b.next());
  Peer c(svc.service.port());
  c.c.send(proto::encode(proto::Claim{{}, {0}}));
  expectError(c.c, "CLAIM: obstacle 0 (column) is reported by connection");
  // an obstacle the scenario does not track stands where it is put: no client moves it
  Peer d(svc.service.port());
  proto::Obstacles o;
  o.seq = 1;
  o.t = 0.1;
  o.obstacles = {{1, Vec3(5, 5, 5), Vec3::Zero()}};
  d.c.send(proto::encode(o));
  expectError(d.c, "obstacle 1 (bin) is not tracked");
  Peer e(svc.service.port());
  e.c.send(proto::encode(pandaReading(1, 0.1, 1)));
  ASSERT_TRUE(e.next());
  e.c.send(proto::encode(proto::Claim{{1}, {}}));
  expectError(e.c, "CLAIM after this connection's first READINGS or OBSTACLES");
}

bool samePair(const proto::Nearest& a, const Warning& w) {
  return a.arm == w.arm && a.body == w.body && a.otherArm == w.otherArm && a.otherBody == w.otherBody &&
         a.obstacle == w.obstacle;
}

TEST(ArmService, AStopNamesItsCauseNotTheNearestPair) {
  // in process: the first open-loop cycle of two_pandas where an arm is STOPped by a pair that is
  // not the nearest one (a close pair that is not closing in is nearer than the one that decides)
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Monitor m = makeMonitor(s);
  auto src = makeSensor(s);
  std::vector<Reading> cycle;
  Reading r;
  bool more = src->next(r);
  proto::Readings found;
  int arm = -1;
  Warning cause;
  while (more && arm < 0) {
    cycle.clear();
    const double t = r.t;
    while (more && r.t == t) cycle.push_back(r), more = src->next(r);
    for (const Reading& c : cycle) m.setJointState(c.arm, c.t, c.q.data(), c.qdot.data());
    m.cycle(t);
    for (int a = 0; a < m.armCount() && arm < 0; ++a) {
      const Warning& w = m.worst(a);
      const Warning& n = m.nearest();
      const bool nearest = (n.arm == a && n.body == w.body && n.otherArm == w.otherArm && n.otherBody == w.otherBody &&
                            n.obstacle == w.obstacle) ||
                           (n.otherArm == a && n.otherBody == w.body && n.arm == w.otherArm && n.body == w.otherBody);
      if (!m.stopped(a) || nearest) continue;
      arm = a;
      cause = w;
      found.t = t;
      found.seq = 1;
      for (const Reading& c : cycle) found.arms.push_back({static_cast<std::uint16_t>(c.arm), c.q, c.qdot});
      // the cause is the arm's worst warning: no warning of the arm has a smaller time to collision
      for (const Warning& x : m.warnings()) {
        if (x.arm == a) {
          EXPECT_GE(x.ttc, w.ttc);
        }
      }
    }
  }
  ASSERT_GE(arm, 0) << "no cycle where the nearest pair is not the cause";
  ASSERT_LE(cause.ttc, s.safety.safeTime());
  // the service, told that cycle's readings, names the cause in the VERDICT and in verdicts.csv
  const fs::path d = tempDir("cause");
  ServiceConfig cfg;
  cfg.logDir = (d / "log").string();
  Service svc(s, cfg);
  Peer p(svc.service.port());
  p.c.send(proto::encode(found));
  const auto m1 = p.next();
  ASSERT_TRUE(m1 && std::holds_alternative<proto::Verdict>(*m1));
  const auto* v = &std::get<proto::Verdict>(*m1);
  const proto::ArmVerdict& av = v->arms[arm];
  EXPECT_EQ(av.level, proto::Level::Stop);
  EXPECT_EQ(av.cause, cause.outcome == Outcome::Overlapping ? proto::Cause::Separation : proto::Cause::Collision);
  EXPECT_TRUE(samePair(av.pair, cause)) << av.pair.body << " " << av.pair.otherArm << " " << av.pair.otherBody;
  EXPECT_EQ(av.pair.ttc, av.minTtc);
  EXPECT_EQ(av.pair.distance, cause.distance);
  EXPECT_FALSE(av.pair.body == v->nearest.body && av.pair.otherBody == v->nearest.otherBody &&
               av.pair.otherArm == v->nearest.otherArm)
      << "the nearest pair is the cause after all";
  svc.stop();
  const std::string log = slurp(d / "log" / "verdicts.csv");
  const std::string name = s.arms[arm].name;
  EXPECT_NE(log.find(name + "_cause," + name + "_cause_body"), std::string::npos) << log;
  EXPECT_NE(log.find(cause.outcome == Outcome::Overlapping ? ",separation," : ",collision,"), std::string::npos) << log;
  const Monitor& sm = svc.service.monitor();
  EXPECT_NE(log.find(name + "/" + bodyName(sm.arm(arm).model, cause.body) + "," + otherName(sm, cause)), std::string::npos)
      << log;
  fs::remove_all(d);
}

TEST(ArmService, AnArmNotYetReportedIsStoppedAsStale) {
  // the monitor's resting pose before any reading is no reading: at t = 0 too
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  Peer p(svc.service.port());
  p.c.send(proto::encode(pandaReading(1, 0.0, 1)));
  const auto m = p.next();
  ASSERT_TRUE(m && std::holds_alternative<proto::Verdict>(*m));
  const auto& v = std::get<proto::Verdict>(*m);
  EXPECT_EQ(v.arms[0].level, proto::Level::Stop);
  EXPECT_EQ(v.arms[0].cause, proto::Cause::Stale);
  EXPECT_EQ(v.arms[0].pair.body, -1);
  EXPECT_EQ(v.arms[1].level, proto::Level::Ok);
  EXPECT_EQ(v.arms[1].cause, proto::Cause::None);
}

TEST(ArmService, AVersionOneClientIsStillServed) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  net::Client c;
  c.connect("127.0.0.1", svc.service.port(), 2s);
  c.send(proto::encode(proto::Hello{1, ""}, 1));
  auto f = c.receive(2s);
  ASSERT_TRUE(f);
  EXPECT_EQ((*f)[0], 1) << "not answered in version 1";
  ASSERT_TRUE(std::holds_alternative<proto::Welcome>(proto::decode(*f).message));
  EXPECT_EQ(std::get<proto::Welcome>(proto::decode(*f).message).version, 1);
  c.send(proto::encode(proto::Subscribe{proto::Subscribe::kOwnOnly}, 1));
  c.send(proto::encode(bothArms(1, 0.0), 1));
  f = c.receive(2s);
  ASSERT_TRUE(f);
  EXPECT_EQ((*f)[0], 1);
  const proto::Decoded d = proto::decode(*f);
  ASSERT_TRUE(d.ok) << d.error;
  EXPECT_EQ(std::get<proto::Verdict>(d.message).arms[0].level, proto::Level::Ok);
  // a version 5 HELLO is refused naming what is spoken
  net::Client five;
  five.connect("127.0.0.1", svc.service.port(), 2s);
  five.send(proto::encode(proto::Hello{5, ""}, 4));
  expectError(five, "protocol version 5 not supported (this service speaks 1 to 4)");
}

TEST(ArmService, ACycleOverItsBudgetIsStopForEveryArm) {
  // a budget no cycle keeps (1 ns): every verdict STOP, cause deadline (version 2: stale), counted
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  ServiceConfig cfg;
  cfg.cycleBudgetUs = 0.001;
  Service svc(s, cfg);
  Peer p(svc.service.port());
  p.c.send(proto::encode(bothArms(1, 0.0)));
  auto m = p.next();
  ASSERT_TRUE(m && std::holds_alternative<proto::Verdict>(*m));
  for (const proto::ArmVerdict& v : std::get<proto::Verdict>(*m).arms) {
    EXPECT_EQ(v.level, proto::Level::Stop);
    EXPECT_EQ(v.cause, proto::Cause::Deadline);
    EXPECT_EQ(v.factor, 0.0);
  }
  net::Client two;
  two.connect("127.0.0.1", svc.service.port(), 2s);
  two.send(proto::encode(proto::Hello{2, ""}, 2));
  ASSERT_TRUE(two.receive(2s));
  two.send(proto::encode(proto::Subscribe{}, 2));
  p.c.send(proto::encode(bothArms(2, 0.001)));
  const auto f = two.receive(2s);
  ASSERT_TRUE(f);
  const proto::Decoded d = proto::decode(*f);
  ASSERT_TRUE(d.ok) << d.error;
  EXPECT_EQ(std::get<proto::Verdict>(d.message).arms[0].cause, proto::Cause::Stale);
  svc.stop();
  EXPECT_GE(svc.service.counters().deadlineMisses, 2u);
  // unwatched (the library's default): the same cycle is OK
  Service free(s, {});
  Peer q(free.service.port());
  q.c.send(proto::encode(bothArms(1, 0.0)));
  m = q.next();
  ASSERT_TRUE(m && std::holds_alternative<proto::Verdict>(*m));
  EXPECT_EQ(std::get<proto::Verdict>(*m).arms[0].level, proto::Level::Ok);
}

proto::Skeletons skeletonAt(std::uint32_t seq, double t, double x) {
  const Skeleton sk = standingSkeleton(Vec3(x, 0, 0), 3.141592653589793);
  proto::Skeletons m;
  m.seq = seq;
  m.t = t;
  m.persons = {{0, std::vector<Vec3>(sk.p.begin(), sk.p.end())}};
  return m;
}

TEST(ArmService, A30HzPersonTrackerIsCurrentOnceItsRateIsDeclared) {
  // poses every 33 ms with the tracker declared at 30 Hz +-5 ms: never stale while it talks;
  // silent, every arm STOPs once its last pose is older than period + jitter
  Scenario s = loadScenario(scenarioPath("person_walkup"));
  s.persons[0].sensorPeriod = 1.0 / 30.0;
  s.persons[0].sensorJitter = 0.005;
  Service svc(s, {});
  Peer p(svc.service.port());
  std::uint32_t seq = 0;
  auto verdictAt = [&](double t) {
    p.c.send(proto::encode(pandaReading(++seq, t)));
    std::optional<proto::Message> m;
    const proto::Verdict* v = nullptr;
    while ((m = p.next()) && (!(v = std::get_if<proto::Verdict>(&*m)) || v->ack < seq)) {
    }
    return v ? v->arms[0] : proto::ArmVerdict{proto::Level::Stop, 0.0, proto::Cause::None, {}};
  };
  double lastPose = 0.0;
  for (int k = 0; k <= 300; ++k) {
    const double t = 0.001 * k;
    if (k % 33 == 0 && k <= 264) {
      p.c.send(proto::encode(skeletonAt(++seq, t, 3.0)));
      lastPose = t;
    }
    const proto::ArmVerdict v = verdictAt(t);
    const bool stale = t - lastPose > 1.0 / 30.0 + 0.005 + 1e-12;
    ASSERT_EQ(v.level == proto::Level::Stop, stale) << "t = " << t;
    if (stale) {
      EXPECT_EQ(v.cause, proto::Cause::ObstacleLost);
    }
  }
}

// person_walkup over the service with two sensors on clocks of their own: joint states at 50 Hz
// +-3 ms (uniform) on the reference clock, the person tracker at 30 Hz +-5 ms on a clock running
// 2 % slow, silent from 3 s; the arm at rest, the person 3 m away. Each message is sent alone and
// its verdict awaited. Returns the joint sensor's verdicts (time, level, cause).
std::optional<proto::Verdict> verdictFor(Peer& p, std::uint32_t seq);

struct DriftRun {
  std::vector<std::tuple<double, proto::Level, proto::Cause>> verdicts;
  double lastPose = 0.0;  // the reference time the tracker's last pose was taken
};
DriftRun driftOverTheService(double declaredDrift) {
  Scenario s = loadScenario(scenarioPath("person_walkup"));
  s.arms[0].sensorPeriod = 0.02, s.arms[0].sensorJitter = 0.003, s.arms[0].sensorDrift = declaredDrift;
  s.persons[0].sensorPeriod = 1.0 / 30.0, s.persons[0].sensorJitter = 0.005, s.persons[0].sensorDrift = declaredDrift;
  Service svc(s, {});
  Peer joints(svc.service.port()), tracker(svc.service.port());
  std::mt19937_64 g(11);
  auto jitter = [&](double j) { return (2.0 * (static_cast<double>(g() >> 11) * 0x1.0p-53) - 1.0) * j; };
  std::uint32_t seq = 0;
  double nextJoint = 0.0, nextPose = 0.0;  // each on its own clock
  const double rate = -0.02;               // the tracker's clock against the reference
  DriftRun r;
  for (int k = 0; k <= 4000; ++k) {
    const double t = 0.001 * k;
    if (nextPose / (1.0 + rate) <= t && nextPose < 3.0 * (1.0 + rate)) {
      tracker.c.send(proto::encode(skeletonAt(++seq, nextPose, 3.0)));
      if (!verdictFor(tracker, seq)) ADD_FAILURE() << "no verdict for the pose at " << t;
      r.lastPose = t;
      nextPose += 1.0 / 30.0 + jitter(0.005);
    }
    if (nextJoint <= t) {
      joints.c.send(proto::encode(pandaReading(++seq, nextJoint)));
      const auto v = verdictFor(joints, seq);
      if (!v) ADD_FAILURE() << "no verdict for the reading at " << t;
      else r.verdicts.emplace_back(t, v->arms[0].level, v->arms[0].cause);
      nextJoint += 0.02 + jitter(0.003);
    }
  }
  return r;
}

TEST(ArmService, TwoSensorClocksTwoPerCentApartAreNoStopOnceTheirDriftIsDeclared) {
  // undeclared, the tracker's poses age by its clock's lag (20 ms a second) and every arm STOPs
  // (cause obstacle_lost) within about two seconds while the tracker still talks
  const DriftRun undeclared = driftOverTheService(0.0);
  int stopsTalking = 0;
  for (const auto& v : undeclared.verdicts)
    if (std::get<0>(v) < undeclared.lastPose && std::get<1>(v) == proto::Level::Stop) ++stopsTalking;
  EXPECT_GT(stopsTalking, 20);
  // declared (drift 0.02 on both sensors): no STOP while both talk; the tracker silent, STOP
  // (obstacle_lost) by the first verdict after its last pose is (period + jitter)(1 + drift)
  // old, and none before
  const DriftRun declared = driftOverTheService(0.02);
  const double staleAfter = (1.0 / 30.0 + 0.005) * 1.02;
  double firstStop = -1.0;
  for (const auto& [t, level, cause] : declared.verdicts) {
    const bool stop = level == proto::Level::Stop;
    if (t <= declared.lastPose + staleAfter) {
      EXPECT_FALSE(stop) << "a spurious STOP at " << t << " s, cause " << proto::toString(cause);
    } else if (firstStop < 0.0) {
      EXPECT_TRUE(stop) << "the silent tracker was not stopped at " << t << " s";
      EXPECT_EQ(cause, proto::Cause::ObstacleLost);
      firstStop = t;
    }
  }
  EXPECT_GT(firstStop, declared.lastPose + staleAfter);
  // the cycles' clock is the newest stamp: the last pose is marked as arrived at the first cycle
  // after it (a joint reading, at most 23 ms later); STOP within (period + jitter)(1 + drift) +
  // one cycle (a joint period) of that mark
  double marked = -1.0;
  for (const auto& v : declared.verdicts)
    if (std::get<0>(v) > declared.lastPose) {
      marked = std::get<0>(v);
      break;
    }
  EXPECT_LE(firstStop, marked + staleAfter + 0.023 + 1e-9);
}

// two_pandas with arm 0's joint sensor declared at 50 Hz +-3 ms (no drift) in the scenario;
// arm 1 reported at 50 Hz on the reference clock, arm 0 at 50 Hz +-3 ms on a clock 2 % slow.
// A version 4 client that declares its drift in its CLAIM is not stopped; once it leaves, a
// version 3 client on the same clock is judged by the scenario's rate again.
TEST(ArmService, AVersionFourClaimDeclaresItsSensorsRate) {
  Scenario s = loadScenario(scenarioPath("two_pandas"));
  s.arms[0].sensorPeriod = 0.02, s.arms[0].sensorJitter = 0.003;
  Service svc(s, {});
  Peer reference(svc.service.port());
  std::uint32_t seq = 0;
  std::mt19937_64 g(13);
  double next = 0.0;  // arm 0's sensor's own clock
  int stops = 0, verdicts = 0;
  double lastTaken = 0.0, firstStop = -1.0;
  const double staleAfter = 0.023 * 1.02;
  // from t0 to t1 (reference time): arm 0's readings through `sensor` until `quiet`, arm 1's
  // through reference; counted: verdicts and STOPs of arm 0 while its readings are current
  const auto run = [&](net::Client& sensor, std::uint8_t version, double t0, double t1, double quiet) {
    for (int k = static_cast<int>(std::lround(t0 * 1000)); k < static_cast<int>(std::lround(t1 * 1000)); ++k) {
      const double t = 0.001 * k;
      if (next / 0.98 <= t && t < quiet) {
        lastTaken = next / 0.98;
        sensor.send(proto::encode(pandaReading(++seq, next, 0), version));
        next += 0.02 + (2.0 * (static_cast<double>(g() >> 11) * 0x1.0p-53) - 1.0) * 0.003;
        for (int n = 0; n < 10; ++n) {
          const auto f = sensor.receive(2s);
          if (!f) break;
          const proto::Decoded d = proto::decode(*f);
          const auto* v = d.ok ? std::get_if<proto::Verdict>(&d.message) : nullptr;
          if (v && v->ack >= seq) break;
        }
      }
      if (k % 20 == 0) {
        reference.c.send(proto::encode(pandaReading(++seq, t, 1)));
        const auto v = verdictFor(reference, seq);
        if (!v) ADD_FAILURE() << "no verdict at " << t;
        else if (t > t0 + 0.03 && t <= lastTaken + staleAfter) ++verdicts, stops += v->arms[0].level == proto::Level::Stop;
        else if (t > lastTaken + staleAfter && firstStop < 0.0 && v && v->arms[0].level == proto::Level::Stop) firstStop = t;
      }
    }
  };
  {
    Peer sensor(svc.service.port());
    // a rate for an arm it does not claim, or out of range, is refused naming it
    Peer wrong(svc.service.port());
    wrong.c.send(proto::encode(proto::Claim{{1}, {}, {{proto::SensorRate::Arm, 0, 0.02, 0.003, 0.02}}}));
    expectError(wrong.c, "CLAIM: a rate for arm 0, which this CLAIM does not name");
    Peer bad(svc.service.port());
    bad.c.send(proto::encode(proto::Claim{{0}, {}, {{proto::SensorRate::Arm, 0, 0.02, 0.003, 0.7}}}));
    expectError(bad.c, "CLAIM: arm 0 rate: drift 0.7 is not in [0, 0.5)");
    sensor.c.send(proto::encode(proto::Claim{{0}, {}, {{proto::SensorRate::Arm, 0, 0.02, 0.003, 0.02}}}));
    run(sensor.c, proto::kVersion, 0.0, 3.0, 2.5);
    EXPECT_GT(verdicts, 120);
    EXPECT_EQ(stops, 0) << "a declared drift of 2 % was STOPped";
    // silent from 2.5 s: STOP once its last reading is (period + jitter)(1 + drift) old, by the
    // reference's cycle after the one that marks its arrival (two reference periods)
    EXPECT_GT(firstStop, lastTaken + staleAfter);
    EXPECT_LE(firstStop, lastTaken + staleAfter + 2 * 0.02 + 1e-9);
  }
  // the version 4 client left: its rate with it (arm 0 STOP while no one reports it)
  std::this_thread::sleep_for(100ms);  // the service sees the close first
  net::Client old;
  old.connect("127.0.0.1", svc.service.port(), 2s);
  old.send(proto::encode(proto::Hello{3, ""}, 3));
  ASSERT_TRUE(old.receive(2s));
  old.send(proto::encode(proto::Subscribe{proto::Subscribe::kOwnOnly}, 3));
  stops = verdicts = 0;
  run(old, 3, 3.0, 5.0, 5.0);
  EXPECT_GT(verdicts, 90);
  EXPECT_GT(stops, verdicts / 2) << "the scenario's rate (no drift) did not come back";
}

TEST(ArmService, UnderPflARestingArmIsSlowedNotStoppedAsInProcess) {
  // the same walk-in under ssm.response pfl: the verdicts equal the in-process check's pose by
  // pose; the arm at rest (0 m/s, within every region's limit) is never STOPped for the person,
  // below S_p is allowed, and the arm is slowed (the torso's and legs' limits, below its top speed)
  Scenario s = loadScenario(scenarioPath("person_walkup"));
  s.ssm.response = SsmResponse::Pfl;
  Service svc(s, {});
  Peer p(svc.service.port());
  Monitor mon = makeMonitor(s);
  PersonSet persons;
  auto held = std::make_unique<HeldPerson>();
  HeldPerson* h = held.get();
  persons.add("visitor", std::move(held));
  SeparationMonitor ssm(s.ssm, 1);
  std::uint32_t seq = 0;
  bool allowed = false, slowed = false;
  for (int k = 0; k <= 24; ++k) {
    const double t = 0.001 * k, x = 3.0 - 0.1 * k;
    p.c.send(proto::encode(skeletonAt(++seq, t, x)));
    proto::Readings r = pandaReading(++seq, t);
    p.c.send(proto::encode(r));
    std::optional<proto::Message> m;
    const proto::Verdict* v = nullptr;
    while ((m = p.next()) && (!(v = std::get_if<proto::Verdict>(&*m)) || v->ack < seq)) {
    }
    ASSERT_TRUE(v) << k;
    mon.setJointState(0, t, r.arms[0].q.data(), r.arms[0].qdot.data());
    mon.cycle(t);
    h->set(standingSkeleton(Vec3(x, 0, 0), 3.141592653589793));
    persons.pose(t);
    ssm.cycle(mon, persons);
    const SsmVerdict& ref = ssm.verdict(0);
    EXPECT_EQ(v->arms[0].factor, ref.factor) << k;
    EXPECT_EQ(v->arms[0].personSeparation, ref.separation) << k;
    EXPECT_FALSE(ref.stop) << k;
    EXPECT_NE(v->arms[0].cause, proto::Cause::Person) << k;
    allowed = allowed || ref.pflAllowed;
    slowed = slowed || (ref.factor > 0.0 && ref.factor < 1.0);
  }
  EXPECT_TRUE(allowed);
  EXPECT_TRUE(slowed);
}

TEST(ArmService, ASkeletonSlowsAndStopsTheArmInVersionThree) {
  // person_walkup's Panda at rest at its home pose, its person reported by SKELETONS walking in:
  // factor 1 far away, a factor between 0 and 1 nearer, STOP (cause person) closest; the
  // verdicts equal the in-process SeparationMonitor's on the same poses
  const Scenario s = loadScenario(scenarioPath("person_walkup"));
  Service svc(s, {});
  Peer p(svc.service.port());
  Monitor mon = makeMonitor(s);
  PersonSet persons;
  auto held = std::make_unique<HeldPerson>();
  HeldPerson* h = held.get();
  persons.add("visitor", std::move(held));
  SeparationMonitor ssm(s.ssm, 1);
  std::uint32_t seq = 0;
  bool scaled = false;
  proto::ArmVerdict last;
  for (int k = 0; k <= 24; ++k) {
    const double t = 0.001 * k, x = 3.0 - 0.1 * k;
    p.c.send(proto::encode(skeletonAt(++seq, t, x)));
    proto::Readings r = pandaReading(++seq, t);
    p.c.send(proto::encode(r));
    std::optional<proto::Message> m;
    const proto::Verdict* v = nullptr;
    while ((m = p.next()) && (!(v = std::get_if<proto::Verdict>(&*m)) || v->ack < seq)) {
    }
    ASSERT_TRUE(v) << k;
    // in process, the same poses
    mon.setJointState(0, t, r.arms[0].q.data(), r.arms[0].qdot.data());
    mon.cycle(t);
    h->set(standingSkeleton(Vec3(x, 0, 0), 3.141592653589793));
    persons.pose(t);
    ssm.cycle(mon, persons);
    const SsmVerdict& ref = ssm.verdict(0);
    last = v->arms[0];
    EXPECT_EQ(last.factor, ref.factor) << k;
    EXPECT_EQ(last.personSeparation, ref.separation) << k;
    EXPECT_EQ(last.person, 0);
    EXPECT_EQ(last.level == proto::Level::Stop, ref.stop) << k;
    if (ref.stop) {
      EXPECT_EQ(last.cause, proto::Cause::Person) << k;
    }
    if (k == 0) {
      EXPECT_EQ(last.factor, 1.0);
    }
    scaled = scaled || (last.factor > 0.0 && last.factor < 1.0);
  }
  EXPECT_TRUE(scaled);
  EXPECT_EQ(last.level, proto::Level::Stop) << "0.6 m from the base";
  // the person's tracker falls silent: every arm STOPs until a pose comes again
  p.c.send(proto::encode(pandaReading(++seq, 0.2)));
  std::optional<proto::Message> m;
  const proto::Verdict* v = nullptr;
  while ((m = p.next()) && (!(v = std::get_if<proto::Verdict>(&*m)) || v->ack < seq)) {
  }
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Stop);
  EXPECT_EQ(v->arms[0].cause, proto::Cause::ObstacleLost);
  // a version 2 client may not send SKELETONS; its verdicts tell a person STOP as separation
  net::Client two;
  two.connect("127.0.0.1", svc.service.port(), 2s);
  two.send(proto::encode(proto::Hello{2, ""}, 2));
  ASSERT_TRUE(two.receive(2s));
  two.send(proto::encode(skeletonAt(1, 0.3, 2.0), 3));
  expectError(two, "SKELETONS needs protocol version 3 (this connection said HELLO with version 2)");
}

TEST(ArmService, ASocketPastEverySlotIsToldTheServicesLimits) {
  // 2 clients past HELLO and 2 pending fill the sockets: one more is told both limits, not the
  // sum of them (it said "server full (4 connections)" past a limit of 2)
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  ServiceConfig cfg;
  cfg.maxClients = 2;
  cfg.maxPending = 2;
  Service svc(s, cfg);
  Peer a(svc.service.port()), b(svc.service.port());
  net::Client p1, p2, extra;
  p1.connect("127.0.0.1", svc.service.port(), 2s);
  p2.connect("127.0.0.1", svc.service.port(), 2s);
  std::this_thread::sleep_for(100ms);  // the service has counted both
  extra.connect("127.0.0.1", svc.service.port(), 2s);
  expectError(extra, "server full (2 clients and 2 connections waiting for their HELLO)");
}

TEST(ArmService, TokenIsRequiredOffLoopbackAndChecked) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  boost::asio::io_context io;
  ServiceConfig open;
  open.net.address = "0.0.0.0";
  open.net.handleSignals = false;
  try {
    ArmService svc(io, s, open);
    FAIL() << "a non-loopback address without a token was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("needs a shared token (--token)"), std::string::npos) << e.what();
  }
  ServiceConfig tok;
  tok.token = "s3cret";
  Service svc(s, tok);
  EXPECT_NO_THROW(Peer(svc.service.port(), true, "s3cret"));
  net::Client c;
  c.connect("127.0.0.1", svc.service.port(), 2s);
  c.send(proto::encode(proto::Hello{proto::kVersion, "guess"}));
  expectError(c, "bad token");
}

TEST(ArmService, ObstaclePosesMoveTheObstacle) {
  // put the column right at the resting left arm's hand: STOP for the left arm at once
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  Peer p(svc.service.port());
  // both arms at home (before its first reading an arm rests at zero clamped into the limits,
  // a pose where the Panda's wrist touches its hand)
  proto::Readings both = pandaReading(1, 0.0, 0);
  both.arms.push_back(pandaReading(1, 0.0, 1).arms[0]);
  p.c.send(proto::encode(both));
  auto first = p.next();
  ASSERT_TRUE(first && std::holds_alternative<proto::Verdict>(*first));
  EXPECT_EQ(std::get<proto::Verdict>(*first).arms[0].level, proto::Level::Ok);
  const auto f = forwardKinematics(pandaModel(), Eigen::Isometry3d::Identity(), {0, -0.785, 0, -2.356, 0, 1.571, 0.785});
  proto::Obstacles o;
  o.seq = 2;
  o.t = 0.001;
  o.obstacles = {{0, f.back().translation(), Vec3::Zero()}};
  p.c.send(proto::encode(o));
  auto second = p.next();
  ASSERT_TRUE(second && std::holds_alternative<proto::Verdict>(*second));
  const auto& v = std::get<proto::Verdict>(*second);
  EXPECT_EQ(v.ack, 2u);
  EXPECT_EQ(v.arms[0].level, proto::Level::Stop);
  EXPECT_EQ(v.nearest.obstacle, 0) << v.nearest.arm << " " << v.nearest.body << " " << v.nearest.otherArm << " " << v.nearest.otherBody;
  EXPECT_EQ(v.nearest.distance, 0.0);
  // an unknown obstacle id is refused
  o.obstacles[0].obstacle = 9;
  p.c.send(proto::encode(o));
  expectError(p.c, "unknown obstacle id 9");
}

// Fault tests: a sensor's clock far ahead or behind, a sensor that falls silent, a
// flood of connections that never say HELLO. Each: a colliding pose still gets STOP at once, a
// real sensor can still connect.


// The verdict acknowledging seq (earlier ones skipped), or nullopt.
std::optional<proto::Verdict> verdictFor(Peer& p, std::uint32_t seq) {
  for (int k = 0; k < 10; ++k) {
    const auto m = p.next();
    if (!m) return std::nullopt;
    if (const auto* v = std::get_if<proto::Verdict>(&*m); v && v->ack >= seq) return *v;
  }
  return std::nullopt;
}

// The column moved onto the resting left arm's hand: a collision, STOP for the left arm.
proto::Obstacles columnOnTheLeftHand(std::uint32_t seq, double t) {
  const auto f = forwardKinematics(pandaModel(), Eigen::Isometry3d::Identity(), {0, -0.785, 0, -2.356, 0, 1.571, 0.785});
  proto::Obstacles o;
  o.seq = seq;
  o.t = t;
  o.obstacles = {{0, f.back().translation(), Vec3::Zero()}};
  return o;
}

TEST(ArmServiceFaults, AClockFarAheadOrBehindIsRefusedAndTheCollisionStillStops) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  Peer good(svc.service.port());
  good.c.send(proto::encode(bothArms(1, 0.0)));
  ASSERT_TRUE(verdictFor(good, 1));
  good.c.send(proto::encode(columnOnTheLeftHand(2, 0.001)));
  const auto before = verdictFor(good, 2);
  ASSERT_TRUE(before);
  ASSERT_EQ(before->arms[0].level, proto::Level::Stop);
  // a sensor whose clock is off: told and closed, its time never the cycle's
  const std::pair<double, const char*> bad[] = {
      {1e300, "time 1e+300 s is beyond any clock"},
      {-1e300, "time -1e+300 s is beyond any clock"},
      {1e6, "time 1000000 s is more than 1 s ahead of a sensor that is talking (at 0.001 s)"},
      {-50.0, "time -50 s is more than 1 s behind a sensor that is talking (at 0.001 s)"},
  };
  for (const auto& [t, why] : bad) {
    Peer p(svc.service.port());
    p.c.send(proto::encode(bothArms(1, t)));
    expectError(p.c, why);
  }
  good.c.send(proto::encode(bothArms(3, 0.002)));
  const auto after = verdictFor(good, 3);
  ASSERT_TRUE(after);
  EXPECT_EQ(after->t, 0.002) << "another sensor's clock decided the cycle's time";
  EXPECT_EQ(after->arms[0].level, proto::Level::Stop) << "the colliding pose was let through";
}

TEST(ArmServiceFaults, ALoneSensorsClockLeavesWithIt) {
  // a sensor alone sets its own time (1e6 s, the left arm turned away), then leaves; the next
  // sensor's readings at t = 0 are current, not stale: the column on the hand is a STOP at t = 0.001
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  {
    Peer early(svc.service.port());
    proto::Readings r = bothArms(1, 1e6);
    r.arms[0].q[0] = 2.0;
    early.c.send(proto::encode(r));
    const auto v = verdictFor(early, 1);
    ASSERT_TRUE(v);
    EXPECT_EQ(v->t, 1e6);
    early.c.close();
  }
  std::this_thread::sleep_for(100ms);  // the service sees the close first
  Peer good(svc.service.port());
  good.c.send(proto::encode(bothArms(1, 0.0)));
  ASSERT_TRUE(verdictFor(good, 1));
  good.c.send(proto::encode(columnOnTheLeftHand(2, 0.001)));
  const auto v = verdictFor(good, 2);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->t, 0.001) << "the departed sensor's clock still stamps the cycles";
  EXPECT_EQ(v->arms[0].level, proto::Level::Stop) << "the current readings were dropped as stale";
  svc.stop();
  EXPECT_EQ(svc.service.counters().disputes, 0u) << "the departed sensor still held its arms";
}

TEST(ArmServiceFaults, AnArmWithoutACurrentReadingIsStopped) {
  // two_pandas: reaction 0.010 s + cycle 0.001 s: a reading is current for 0.011 s
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  Peer p(svc.service.port());
  p.c.send(proto::encode(bothArms(2, 0.001)));
  auto v = verdictFor(p, 2);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Ok);
  EXPECT_EQ(v->arms[1].level, proto::Level::Ok);
  // the left arm's sensor falls silent; the right one goes on
  p.c.send(proto::encode(pandaReading(3, 0.011, 1)));
  v = verdictFor(p, 3);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Ok) << "0.010 s old is still current";
  p.c.send(proto::encode(pandaReading(4, 0.013, 1)));
  v = verdictFor(p, 4);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Stop) << "a verdict on a 0.012 s old reading is no verdict";
  EXPECT_EQ(v->arms[1].level, proto::Level::Ok);
  EXPECT_EQ(v->arms[0].cause, proto::Cause::Stale);
  // back: current again, but the STOP is held until someone resets it (a deliberate restart)
  p.c.send(proto::encode(bothArms(5, 0.014)));
  v = verdictFor(p, 5);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Stop) << "a silent sensor's STOP cleared itself";
  EXPECT_EQ(v->arms[0].cause, proto::Cause::Latched);
  EXPECT_EQ(v->arms[1].level, proto::Level::Ok);
  p.c.send(proto::encode(proto::Reset{{0}}));
  p.c.send(proto::encode(bothArms(6, 0.015)));
  v = verdictFor(p, 6);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Ok);
  // a RESET naming no arm of the scenario is refused
  p.c.send(proto::encode(proto::Reset{{9}}));
  expectError(p.c, "RESET: unknown arm id 9");
  svc.stop();
  EXPECT_EQ(svc.service.counters().staleStops, 2u);
}

TEST(ArmServiceFaults, StsimArmResetReleasesALatchedStop) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path d = tempDir("reset");
  Service svc(s, {});
  Peer p(svc.service.port());
  p.c.send(proto::encode(bothArms(1, 0.0)));
  ASSERT_TRUE(verdictFor(p, 1));
  p.c.send(proto::encode(pandaReading(2, 0.02, 1)));  // the left arm's sensor silent for 20 ms
  auto v = verdictFor(p, 2);  // its own cycle (sent together, the two would share one)
  ASSERT_TRUE(v);
  ASSERT_EQ(v->arms[0].cause, proto::Cause::Stale);
  p.c.send(proto::encode(bothArms(3, 0.021)));
  v = verdictFor(p, 3);
  ASSERT_TRUE(v);
  ASSERT_EQ(v->arms[0].cause, proto::Cause::Latched);
  const auto reset = [&](const std::string& arms) {
    const std::string cmd = std::string("timeout 20 ") + STSIM_BINARY + " arm reset --connect 127.0.0.1:" +
                            std::to_string(svc.service.port()) + arms + " > " + (d / "stdout").string() + " 2> " +
                            (d / "stderr").string();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(reset(" --arms elbow"), 1);
  EXPECT_NE(slurp(d / "stderr").find("no arm 'elbow' in the service's scenario"), std::string::npos) << slurp(d / "stderr");
  EXPECT_EQ(reset(" --arms left"), 0) << slurp(d / "stderr");
  EXPECT_EQ(slurp(d / "stdout"), "arm reset: left\n");
  std::this_thread::sleep_for(100ms);  // the service has read it
  p.c.send(proto::encode(bothArms(4, 0.022)));
  v = verdictFor(p, 4);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Ok);
  fs::remove_all(d);
}

TEST(ArmServiceFaults, ATrackedObstacleWithoutACurrentPoseStopsEveryArm) {
  // the column is tracked (OBSTACLES), far from both arms; its tracker falls silent while the
  // arms' sensors go on: past reaction + cycle time (0.011 s) nobody knows where it is
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  Peer p(svc.service.port());
  proto::Obstacles o;
  o.seq = 1;
  o.t = 0.0;
  o.obstacles = {{0, Vec3(0.55, 2.0, 0.75), Vec3::Zero()}};
  p.c.send(proto::encode(o));
  ASSERT_TRUE(verdictFor(p, 1));
  p.c.send(proto::encode(bothArms(2, 0.010)));
  auto v = verdictFor(p, 2);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Ok);
  EXPECT_EQ(v->arms[1].level, proto::Level::Ok);
  p.c.send(proto::encode(bothArms(3, 0.012)));
  v = verdictFor(p, 3);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Stop) << "a verdict against an obstacle of unknown place";
  EXPECT_EQ(v->arms[1].level, proto::Level::Stop);
  // its tracker is back: the arms go on
  o.seq = 4;
  o.t = 0.013;
  p.c.send(proto::encode(o));
  v = verdictFor(p, 4);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->arms[0].level, proto::Level::Ok);
  EXPECT_EQ(v->arms[1].level, proto::Level::Ok);
}

TEST(ArmServiceFaults, AFloodWithoutHelloNeverLocksASensorOut) {
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path d = tempDir("flood");
  ServiceConfig cfg;
  cfg.maxClients = 4;
  cfg.maxPending = 4;
  cfg.helloTimeout = 1000ms;
  cfg.logDir = (d / "log").string();
  Service svc(s, cfg);
  // 40 connections that never say HELLO, ten times the pending slots
  std::vector<std::unique_ptr<net::Client>> flood;
  for (int k = 0; k < 40; ++k) {
    flood.push_back(std::make_unique<net::Client>());
    flood.back()->connect("127.0.0.1", svc.service.port(), 2s);
  }
  // a sensor connecting now is served at once, not after the flood's HELLO time has run out
  const auto t0 = std::chrono::steady_clock::now();
  Peer sensor(svc.service.port());
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 900ms);
  sensor.c.send(proto::encode(bothArms(1, 0.0)));
  ASSERT_TRUE(verdictFor(sensor, 1));
  // the shed ones are closed without a word; the last three waiting are told at 1 s
  int told = 0, closed = 0;
  for (auto& c : flood) {
    const auto f = c->receive(3s);
    if (!f) {
      closed += c->closed() ? 1 : 0;
      continue;
    }
    const proto::Decoded m = proto::decode(*f);
    if (m.ok && std::holds_alternative<proto::Error>(m.message) &&
        std::get<proto::Error>(m.message).message == "no HELLO within 1000 ms of connecting")
      ++told;
  }
  EXPECT_EQ(told, 3);
  EXPECT_EQ(closed, 37);
  // the sensor still has its service
  sensor.c.send(proto::encode(bothArms(2, 0.001)));
  EXPECT_TRUE(verdictFor(sensor, 2));
  svc.stop();
  EXPECT_EQ(svc.service.counters().shed, 37u);
  EXPECT_EQ(svc.service.counters().helloTimeouts, 3u);
  fs::remove_all(d);
}

// `stsim arm serve` as a process: the port it prints, a stream against it, then a signal.
struct Process {
  pid_t pid = -1;
  int out = -1;
};

// fileLimit > 0: the files it writes may not grow beyond that many bytes (RLIMIT_FSIZE, the
// write then fails with EFBIG): a file system that fills while the service runs, without root.
Process spawnServe(const fs::path& logDir, rlim_t fileLimit = 0) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe");
  Process p;
  p.pid = fork();
  if (p.pid == 0) {
    dup2(fds[1], 1);
    if (fileLimit > 0) {
      dup2(fds[1], 2);
      const rlimit lim{fileLimit, fileLimit};
      setrlimit(RLIMIT_FSIZE, &lim);
      signal(SIGXFSZ, SIG_IGN);
    }
    close(fds[0]);
    const std::string scen = scenarioPath("two_pandas"), out = logDir.string();
    // a budget of 1 s: these check the loop and the log, not the deadline (its own test, in
    // process); at the default 1 ms a cycle slowed by a loaded machine (ASan under ctest -j2) was
    // a STOP and the closed loop stopped at 0.373 s instead of 1.071 s
    execl(STSIM_BINARY, STSIM_BINARY, "arm", "serve", scen.c_str(), "--listen", "127.0.0.1:0", "--out", out.c_str(),
          "--budget-us", "1000000", static_cast<char*>(nullptr));
    _exit(127);
  }
  close(fds[1]);
  p.out = fds[0];
  return p;
}

std::uint16_t readPort(int fd) {
  std::string text;
  char ch;
  // bounded: the first line, at most 200 bytes
  while (text.size() < 200 && read(fd, &ch, 1) == 1 && ch != '\n') text += ch;
  const auto colon = text.rfind(':');
  if (text.find("listening on 127.0.0.1:") == std::string::npos || colon == std::string::npos) return 0;
  return static_cast<std::uint16_t>(std::stoi(text.substr(colon + 1)));
}

int waitExit(pid_t pid) {
  for (int k = 0; k < 500; ++k) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(10ms);
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -2;
}

void signalTest(int sig, int expectCode) {
  const fs::path d = tempDir("sig" + std::to_string(sig));
  Process p = spawnServe(d / "log");
  const std::uint16_t port = readPort(p.out);
  ASSERT_GT(port, 0);
  int cycles = 0;
  {
    Peer peer(port);
    for (std::uint32_t k = 1; k <= 50; ++k) {
      peer.c.send(proto::encode(pandaReading(k, 0.001 * k)));
      const auto m = peer.next();
      ASSERT_TRUE(m && std::holds_alternative<proto::Verdict>(*m));
      ++cycles;
    }
    kill(p.pid, sig);
    EXPECT_EQ(waitExit(p.pid), expectCode);
    // the open connection was closed by the shutdown
    EXPECT_FALSE(peer.c.receive(2s).has_value());
  }
  std::string rest;
  char buf[256];
  ssize_t n;
  while ((n = read(p.out, buf, sizeof buf)) > 0) rest.append(buf, static_cast<std::size_t>(n));
  close(p.out);
  EXPECT_NE(rest.find(sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP"), std::string::npos) << rest;
  EXPECT_EQ(lineCount(slurp(d / "log" / "verdicts.csv")), 1 + cycles) << "the log lost cycles";
  fs::remove_all(d);
}

TEST(ArmServeCli, StreamCommandClosesTheLoopThroughServe) {
  const fs::path d = tempDir("cli");
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path trace = recordTrace(s, d / "sensors.csv");
  Process p = spawnServe(d / "log");
  const std::uint16_t port = readPort(p.out);
  ASSERT_GT(port, 0);
  auto stream = [&](const std::string& extra) {
    const std::string cmd = std::string("timeout 60 ") + STSIM_BINARY + " arm stream --connect 127.0.0.1:" +
                            std::to_string(port) + " " + trace.string() + " --rate 0 --out " + (d / "out").string() + " " +
                            extra + " > " + (d / "stdout").string() + " 2> " + (d / "stderr").string();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  ASSERT_EQ(stream(""), 0) << slurp(d / "stderr");
  const std::string out = slurp(d / "stdout");
  EXPECT_NE(out.find("3001 cycles, 3001 verdicts, 0 unanswered"), std::string::npos) << out;
  EXPECT_NE(out.find("left: first STOP 1.071 s, stopped"), std::string::npos) << out;
  EXPECT_NE(out.find("right: first STOP 1.071 s, stopped"), std::string::npos) << out;
  EXPECT_EQ(lineCount(slurp(d / "out" / "stream_verdicts.csv")), 1 + 3001);
  // a token offered to a service that asks for none is no error
  EXPECT_EQ(stream("--token nope"), 0) << slurp(d / "stderr");
  kill(p.pid, SIGTERM);
  EXPECT_EQ(waitExit(p.pid), 143);
  close(p.out);
  // nothing listens any more: connection refused, one line, exit 1
  EXPECT_EQ(stream(""), 1);
  const std::string err = slurp(d / "stderr");
  EXPECT_EQ(lineCount(err), 1) << err;
  EXPECT_NE(err.find("stsim arm: error: 127.0.0.1:" + std::to_string(port) + ": cannot connect"), std::string::npos) << err;
  fs::remove_all(d);
}

// Ctrl-C on `stsim arm stream` (a real-time replay can be long): it stops after a whole cycle,
// its log rows whole, the summary line printed, exit 130 (it died, the last row perhaps cut)
TEST(ArmServeCli, SigintStopsAStreamAfterAWholeCycle) {
  const fs::path d = tempDir("stream_sig");
  const fs::path trace = recordTrace(loadScenario(scenarioPath("two_pandas")), d / "sensors.csv");
  Process serve = spawnServe(d / "log");
  const std::uint16_t port = readPort(serve.out);
  ASSERT_GT(port, 0);
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string connect = "127.0.0.1:" + std::to_string(port), out = (d / "out").string(), t = trace.string();
    std::freopen((d / "stdout").c_str(), "w", stdout);
    std::freopen((d / "stderr").c_str(), "w", stderr);
    // a tenth of real time: 30 s for the 3 s trace
    execl(STSIM_BINARY, STSIM_BINARY, "arm", "stream", "--connect", connect.c_str(), t.c_str(), "--rate", "0.1",
          "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int k = 0; k < 1000 && lineCount(slurp(d / "out" / "stream_verdicts.csv")) < 20; ++k) std::this_thread::sleep_for(10ms);
  kill(pid, SIGINT);
  EXPECT_EQ(waitExit(pid), 130);
  const std::string err = slurp(d / "stderr");
  EXPECT_NE(err.find("stsim arm stream: SIGINT: interrupted after "), std::string::npos) << err;
  EXPECT_NE(slurp(d / "stdout").find("arm stream (closed loop): "), std::string::npos);
  const std::string log = slurp(d / "out" / "stream_verdicts.csv");
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log.back(), '\n');
  const auto fields = [](const std::string& row) { return std::count(row.begin(), row.end(), ','); };
  std::istringstream rows(log);
  std::string header;
  std::getline(rows, header);
  int n = 0;
  for (std::string row; std::getline(rows, row); ++n) EXPECT_EQ(fields(row), fields(header)) << row;
  EXPECT_GE(n, 19);
  EXPECT_LT(n, 3001);
  kill(serve.pid, SIGTERM);
  EXPECT_EQ(waitExit(serve.pid), 143);
  close(serve.out);
  fs::remove_all(d);
}

TEST(ArmServeCli, AFullDiskStopsTheServiceNamingTheLog) {
  // verdicts.csv may grow to 16 KB: about 200 cycles in, the write fails; the service stops
  // (exit 1, the file named) rather than serve on without its record
  const fs::path d = tempDir("fullserve");
  Process p = spawnServe(d / "log", 16 * 1024);
  const std::uint16_t port = readPort(p.out);
  ASSERT_GT(port, 0);
  int cycles = 0;
  {
    Peer peer(port);
    for (std::uint32_t k = 1; k <= 2000; ++k) {
      peer.c.send(proto::encode(pandaReading(k, 0.001 * k)));
      const auto m = peer.next();
      if (!m || !std::holds_alternative<proto::Verdict>(*m)) break;
      ++cycles;
    }
  }
  EXPECT_LT(cycles, 2000) << "the service served on past its full log";
  EXPECT_EQ(waitExit(p.pid), 1);
  std::string rest;
  char buf[256];
  ssize_t n;
  while ((n = read(p.out, buf, sizeof buf)) > 0) rest.append(buf, static_cast<std::size_t>(n));
  close(p.out);
  EXPECT_NE(rest.find("stsim arm: error: write failed: " + (d / "log" / "verdicts.csv").string()), std::string::npos)
      << rest;
  // what it wrote is whole rows, none cut where the limit fell
  const std::string log = slurp(d / "log" / "verdicts.csv");
  ASSERT_FALSE(log.empty());
  EXPECT_LE(log.size(), 16u * 1024u);
  EXPECT_EQ(log.back(), '\n');
  std::istringstream rows(log);
  std::string header;
  std::getline(rows, header);
  const auto fields = std::count(header.begin(), header.end(), ',');
  for (std::string row; std::getline(rows, row);) EXPECT_EQ(std::count(row.begin(), row.end(), ','), fields) << row;
  fs::remove_all(d);
}

TEST(ArmServeCli, StreamOnAFullDiskIsAnErrorNamingTheFile) {
  const fs::path d = tempDir("fullstream");
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  const fs::path trace = recordTrace(s, d / "sensors.csv");
  Service svc(s, {});
  fs::create_directories(d / "out");
  fs::create_symlink("/dev/full", d / "out" / "stream_verdicts.csv");
  const std::string cmd = std::string("timeout 60 ") + STSIM_BINARY + " arm stream --connect 127.0.0.1:" +
                          std::to_string(svc.service.port()) + " " + trace.string() + " --rate 0 --out " +
                          (d / "out").string() + " > " + (d / "stdout").string() + " 2> " + (d / "stderr").string();
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  const std::string err = slurp(d / "stderr");
  EXPECT_EQ(lineCount(err), 1) << err;
  EXPECT_NE(err.find("write failed: " + (d / "out" / "stream_verdicts.csv").string()), std::string::npos) << err;
  fs::remove_all(d);
}

TEST(ArmServeCli, StreamOfABadTraceNamesTheFileAndLine) {
  // a folder or an empty trace was "0 cycles", exit 0; a NaN or a joint beyond its limits was
  // named by the protocol message
  const fs::path d = tempDir("badtrace");
  const Scenario s = loadScenario(scenarioPath("two_pandas"));
  Service svc(s, {});
  std::ofstream(d / "empty.csv") << "t,arm,q...,qdot...\n";
  std::ofstream(d / "nan.csv") << "t,arm,q...,qdot...\n0,left,0,-0.785,0,-2.356,0,1.571,0.785,0,0,0,0,0,0,0\n"
                                  "0.001,left,0,nan,0,-2.356,0,1.571,0.785,0,0,0,0,0,0,0\n";
  // Panda joint 4 is in [-3.07, -0.07]: the client knows no limits, the service refuses the reading
  std::ofstream(d / "limit.csv") << "t,arm,q...,qdot...\n0,left,0,-0.785,0,-2.356,0,1.571,0.785,0,0,0,0,0,0,0\n"
                                    "0.001,left,0,-0.785,0,0.5,0,1.571,0.785,0,0,0,0,0,0,0\n";
  fs::create_directories(d / "dir");
  const std::pair<std::string, std::string> cases[] = {
      {(d / "dir").string(), (d / "dir").string() + ": is a directory, not a sensor trace"},
      {(d / "empty.csv").string(), (d / "empty.csv").string() + ": holds no readings"},
      {(d / "nan.csv").string(), (d / "nan.csv").string() + ":3: joint 2 angle is not a finite number"},
      {(d / "limit.csv").string(), (d / "limit.csv").string() + ":3: the service refused this reading: READINGS seq 2 arm 0: joint 4 angle 0.5 rad is beyond its limits"},
  };
  for (const auto& [trace, why] : cases) {
    const std::string cmd = std::string("timeout 60 ") + STSIM_BINARY + " arm stream --connect 127.0.0.1:" +
                            std::to_string(svc.service.port()) + " " + trace + " --rate 0 --out " + (d / "out").string() +
                            " > /dev/null 2> " + (d / "stderr").string();
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1) << trace;
    const std::string err = slurp(d / "stderr");
    EXPECT_EQ(lineCount(err), 1) << err;
    EXPECT_NE(err.find(why), std::string::npos) << err;
  }
  fs::remove_all(d);
}

TEST(ArmServeCli, SigintShutsDownCleanlyWithTheLogFlushed) { signalTest(SIGINT, 130); }
TEST(ArmServeCli, SigtermShutsDownCleanlyWithTheLogFlushed) { signalTest(SIGTERM, 143); }
TEST(ArmServeCli, SighupShutsDownCleanlyWithTheLogFlushed) { signalTest(SIGHUP, 129); }

}  // namespace
}  // namespace st::arm
