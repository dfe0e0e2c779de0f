// Rogue clients against the arm service's sensor model: a sensor replays the
// two-Panda open-loop contact (the hands touching, t = 1.290-1.310 s), which its own readings
// make STOP for both arms; other clients, in any order and timing, send what they like. No
// reading of theirs may turn one of those STOPs into OK.
//
// Two layers: over loopback, the named rogues (ahead, stale, contradicting, flooding, silent,
// first to claim) against the real server; and without sockets, the service's handler driven
// the way st::net drives it (as fuzz/arm_service.cpp does), 10 000 random rogue schedules
// checked cycle by cycle against the sensor's verdicts when it is alone.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <starm/service.hpp>
#include <stnet/client.hpp>

#include "../../test_scale.hpp"

namespace st::arm {
namespace {

using namespace std::chrono_literals;

const Scenario& twoPandas() {
  static const Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/two_pandas.yaml");
  return s;
}

// The sensor's messages: both arms' nominal (open-loop) readings for t in [from, to], one
// READINGS per time, seq from 1.
std::vector<proto::Readings> contactReadings(double from = 1.290, double to = 1.310) {
  auto src = makeSensor(twoPandas());
  std::vector<proto::Readings> out;
  Reading r;
  while (src->next(r)) {
    if (r.t < from - 1e-9) continue;
    if (r.t > to + 1e-9) break;
    if (out.empty() || out.back().t != r.t) {
      out.emplace_back();
      out.back().seq = static_cast<std::uint32_t>(out.size());
      out.back().t = r.t;
    }
    out.back().arms.push_back({static_cast<std::uint16_t>(r.arm), r.q, r.qdot});
  }
  return out;
}

// Both arms at their t = 0 pose, at rest: the "all is well" a rogue would like the monitor to see.
proto::Readings homePose(std::uint32_t seq, double t) {
  proto::Readings r;
  r.seq = seq;
  r.t = t;
  for (std::uint16_t a = 0; a < 2; ++a)
    r.arms.push_back({a, {0, -0.785, 0, -2.356, 0, 1.571, 0.785}, std::vector<double>(7, 0.0)});
  return r;
}

// ---- over loopback ----

struct Service {
  boost::asio::io_context io;
  ArmService service;
  std::thread thread;
  explicit Service(ServiceConfig cfg) : service(io, twoPandas(), quiet(cfg)), thread([this] { service.run(); }) {}
  static ServiceConfig quiet(ServiceConfig c) {
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

struct Client {
  net::Client c;
  explicit Client(std::uint16_t port, std::uint8_t subscribe = proto::Subscribe::kOwnOnly) {
    c.connect("127.0.0.1", port, 2s);
    c.send(proto::encode(proto::Hello{proto::kVersion, ""}));
    const auto w = c.receive(2s);
    if (!w || !std::holds_alternative<proto::Welcome>(proto::decode(*w).message)) throw std::runtime_error("no WELCOME");
    if (subscribe != 0xFF) c.send(proto::encode(proto::Subscribe{subscribe}));
  }
  // The next VERDICT acknowledging seq, an ERROR, or nothing.
  std::optional<proto::Message> answer(std::uint32_t seq) {
    for (int k = 0; k < 50; ++k) {
      const auto f = c.receive(2s);
      if (!f) return std::nullopt;
      proto::Decoded d = proto::decode(*f);
      if (!d.ok) return std::nullopt;
      if (std::holds_alternative<proto::Error>(d.message)) return d.message;
      if (const auto* v = std::get_if<proto::Verdict>(&d.message); v && v->ack >= seq) return d.message;
    }
    return std::nullopt;
  }
  std::string error() {
    for (int k = 0; k < 50; ++k) {
      const auto f = c.receive(2s);
      if (!f) return "";
      const proto::Decoded d = proto::decode(*f);
      if (const auto* e = std::get_if<proto::Error>(&d.message)) return e->message;
    }
    return "";
  }
};

// The sensor sends reading k and must get STOP for both arms.
void expectStop(Client& sensor, const proto::Readings& r, const std::string& rogue) {
  sensor.c.send(proto::encode(r));
  const auto m = sensor.answer(r.seq);
  ASSERT_TRUE(m) << rogue << ": no verdict for the sensor's reading at t = " << r.t;
  ASSERT_TRUE(std::holds_alternative<proto::Verdict>(*m))
      << rogue << ": the sensor was refused: " << std::get<proto::Error>(*m).message;
  const auto& v = std::get<proto::Verdict>(*m);
  for (int a = 0; a < 2; ++a)
    EXPECT_EQ(v.arms[a].level, proto::Level::Stop) << rogue << ": arm " << a << " at t = " << r.t << " (verdict at " << v.t << ")";
}

TEST(ArmServiceRogues, TheContactStaysStopWhateverAnotherClientSends) {
  const auto readings = contactReadings(1.300, 1.302);
  ASSERT_EQ(readings.size(), 3u);
  struct Rogue {
    const char* name;
    double dt;  // its time against the sensor's
    bool pose;  // true: the home pose of both arms; false: an obstacle pose (the column, far away)
  };
  // the two: a rogue 0.5 s ahead (t = 1.8) and one 0.001 s ahead; then stale, at the
  // sensor's own time, and an obstacle tracker moving the column out of the way
  const Rogue rogues[] = {{"ahead 0.5 s", 0.5, true},  {"ahead 1 ms", 0.001, true}, {"stale", -0.3, true},
                          {"same time", 0.0, true},    {"column far away", 0.0, false}};
  for (const Rogue& rg : rogues) {
    Service svc({});
    Client sensor(svc.service.port());
    sensor.c.send(proto::encode(proto::Claim{{0, 1}, {0}}));
    expectStop(sensor, readings[0], rg.name);
    Client rogue(svc.service.port(), proto::Subscribe{}.flags);
    if (rg.pose) {
      rogue.c.send(proto::encode(homePose(1, readings[0].t + rg.dt)));
      EXPECT_NE(rogue.error().find("is reported by connection"), std::string::npos) << rg.name;
    } else {
      proto::Obstacles o;
      o.seq = 1;
      o.t = readings[0].t;
      o.obstacles = {{0, Vec3(5, 5, 0.75), Vec3::Zero()}};
      rogue.c.send(proto::encode(o));
      EXPECT_NE(rogue.error().find("obstacle 0 (column) is reported by connection"), std::string::npos) << rg.name;
    }
    for (std::size_t k = 1; k < readings.size(); ++k) expectStop(sensor, readings[k], rg.name);
  }
}

TEST(ArmServiceRogues, AFloodOrASilentSubscriberDoesNotReachTheVerdict) {
  const auto readings = contactReadings(1.296, 1.305);
  Service svc({});
  Client sensor(svc.service.port());
  expectStop(sensor, readings[0], "before");
  // a flood: 2 000 home-pose readings as fast as the socket takes them, all newer than the sensor's
  net::Client flood;
  flood.connect("127.0.0.1", svc.service.port(), 2s);
  flood.send(proto::encode(proto::Hello{proto::kVersion, ""}));
  for (std::uint32_t k = 0; k < 2000 && !flood.closed(); ++k) flood.send(proto::encode(homePose(k + 1, 1.3 + 1e-4 * k)));
  // a subscriber to every cycle that never reads its verdicts
  net::Client silent;
  silent.connect("127.0.0.1", svc.service.port(), 2s);
  silent.send(proto::encode(proto::Hello{proto::kVersion, ""}));
  silent.send(proto::encode(proto::Subscribe{}));
  for (std::size_t k = 1; k < readings.size(); ++k) expectStop(sensor, readings[k], "flood");
  // the STOPs above would hold by staleness alone (the flood's times run ahead of the sensor's):
  // what keeps the flood out is its refusal at its first message
  svc.stop();
  EXPECT_EQ(svc.service.counters().disputes, 2u) << "its first message, naming both arms";
  EXPECT_EQ(svc.service.counters().readings, static_cast<std::uint64_t>(2 * readings.size()))
      << "readings other than the sensor's were taken";
}

TEST(ArmServiceRogues, AClientThatClaimsTheArmsFirstCanOnlyStopThem) {
  // the rogue is first: it owns both arms and reports them at rest. The sensor's claim is
  // refused, and from the dispute on every verdict is STOP for both arms until the rogue leaves.
  const auto readings = contactReadings(1.300, 1.302);
  Service svc({});
  Client observer(svc.service.port(), 0);  // every cycle
  Client rogue(svc.service.port());
  rogue.c.send(proto::encode(proto::Claim{{0, 1}, {}}));
  rogue.c.send(proto::encode(homePose(1, 1.3)));
  auto m = rogue.answer(1);
  ASSERT_TRUE(m && std::holds_alternative<proto::Verdict>(*m));
  EXPECT_EQ(std::get<proto::Verdict>(*m).arms[0].level, proto::Level::Ok) << "the rogue alone is believed: nothing tells it apart";
  Client sensor(svc.service.port());
  sensor.c.send(proto::encode(proto::Claim{{0, 1}, {}}));
  EXPECT_NE(sensor.error().find("arm 0 (left) is reported by connection"), std::string::npos);
  for (std::uint32_t k = 2; k < 12; ++k) {
    rogue.c.send(proto::encode(homePose(k, 1.3 + 0.001 * k)));
    m = rogue.answer(k);
    ASSERT_TRUE(m && std::holds_alternative<proto::Verdict>(*m));
    for (int a = 0; a < 2; ++a) EXPECT_EQ(std::get<proto::Verdict>(*m).arms[a].level, proto::Level::Stop) << "arm " << a;
  }
}

// ---- without sockets: the handler as st::net drives it, random rogue schedules ----

// One service; frames handed to its handler, a refused connection closed as the server would.
struct Harness {
  boost::asio::io_context io;
  ArmService svc;
  net::Server server;  // the handler's Server& argument only
  Harness() : svc(io, twoPandas(), quietService()), server(io, quietServer(), svc) {}
  static ServiceConfig quietService() {
    ServiceConfig c;
    c.net.handleSignals = false;
    return c;
  }
  static net::ServerConfig quietServer() {
    net::ServerConfig c;
    c.handleSignals = false;
    return c;
  }
  void open(net::ConnectionId id) { svc.onOpen(server, id); }
  // false: refused (the connection is closed)
  bool send(net::ConnectionId id, const std::string& payload) {
    const auto refused = svc.counters().rejected;
    svc.onFrame(server, id, payload);
    if (svc.counters().rejected == refused) return true;
    svc.onClose(server, id, net::CloseReason::Refused, "");
    return false;
  }
  void close(net::ConnectionId id) { svc.onClose(server, id, net::CloseReason::PeerClosed, ""); }
  // the end of one read of `id` (st::net's onReadDone); true when a cycle ran
  bool readDone(net::ConnectionId id) {
    const auto cycles = svc.counters().cycles;
    svc.onReadDone(server, id);
    return svc.counters().cycles != cycles;
  }
  // true when a cycle ran (its verdict is svc.lastVerdict())
  bool idle() {
    const auto cycles = svc.counters().cycles;
    svc.onIdle(server);
    return svc.counters().cycles != cycles;
  }
};

constexpr net::ConnectionId kSensor = 1;

// The sensor's verdict levels for each of its readings when it is alone.
std::vector<std::vector<proto::Level>> aloneVerdicts(const std::vector<proto::Readings>& readings) {
  Harness h;
  h.open(kSensor);
  h.send(kSensor, proto::encode(proto::Hello{proto::kVersion, ""}));
  h.send(kSensor, proto::encode(proto::Claim{{0, 1}, {}}));
  std::vector<std::vector<proto::Level>> out;
  for (const proto::Readings& r : readings) {
    if (!h.send(kSensor, proto::encode(r)) || !h.idle()) return {};
    std::vector<proto::Level> levels;
    for (const proto::ArmVerdict& v : h.svc.lastVerdict().arms) levels.push_back(v.level);
    out.push_back(levels);
  }
  return out;
}

// A rogue's next message, drawn from everything a client can send.
std::string rogueMessage(std::mt19937_64& rng, const std::vector<proto::Readings>& readings, std::size_t k,
                         std::uint32_t& seq) {
  const auto pick = [&](std::uint64_t n) { return static_cast<std::size_t>(rng() % n); };
  const auto unit = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  const double ts = readings[k].t;
  const double times[] = {ts + 0.5, ts + 0.001, ts, ts - 0.005, ts - 0.3, ts + 0.02, ts + (unit() - 0.5) * 2.4, 1e300};
  const double t = times[pick(8)];
  switch (pick(7)) {
    case 0: return proto::encode(proto::Hello{proto::kVersion, ""});
    case 1: {
      proto::Claim c;
      for (std::uint16_t a = 0; a < 3; ++a)
        if (pick(2)) c.arms.push_back(a);
      for (std::uint16_t o = 0; o < 3; ++o)
        if (pick(3) == 0) c.obstacles.push_back(o);
      return proto::encode(c);
    }
    case 2:
    case 3: {  // readings: home pose, the sensor's own (now or later), or random within the limits
      proto::Readings r;
      const std::size_t source = pick(4);
      if (source == 0) r = homePose(0, t);
      else if (source == 1) r = readings[std::min(readings.size() - 1, k + pick(4))];
      else r = readings[k];
      if (source == 3)
        for (auto& a : r.arms)
          for (std::size_t j = 0; j < a.q.size(); ++j) a.q[j] = (unit() - 0.5) * 5.0, a.qdot[j] = (unit() - 0.5) * 2.0;
      const std::size_t keep = pick(4);  // both arms, arm 0, arm 1, none
      if (keep == 1) r.arms.resize(1);
      if (keep == 2) r.arms.erase(r.arms.begin());
      if (keep == 3) r.arms.clear();
      r.t = t;
      r.seq = ++seq;
      return proto::encode(r);
    }
    case 4: {  // obstacle poses: the column (tracked) or the bin (not), near the hands or far away
      proto::Obstacles o;
      o.seq = ++seq;
      o.t = t;
      const Vec3 at = pick(2) ? Vec3(0.55, 0.0, 0.6) : Vec3(5.0, 5.0, 0.75);
      o.obstacles = {{static_cast<std::uint16_t>(pick(3) == 0 ? 1 : 0), at, Vec3::Zero()}};
      return proto::encode(o);
    }
    case 5: return proto::encode(proto::Subscribe{static_cast<std::uint8_t>(pick(2))});
    default: {  // garbage
      std::string g(1 + pick(40), '\0');
      for (char& c : g) c = static_cast<char>(rng());
      if (pick(2)) g[0] = static_cast<char>(proto::kVersion);
      return g;
    }
  }
}

TEST(ArmServiceRogues, ACycleRunsInTheReadThatCompletesItsBatch) {
  // a read's end runs the cycle when every connection that reports is in it; one still to come
  // leaves it to the end of the pass (onIdle), where everything read by then shares one cycle
  Harness h;
  const auto hello = proto::encode(proto::Hello{proto::kVersion, ""});
  const auto readings = contactReadings(1.300, 1.304);
  constexpr net::ConnectionId kOther = 2;
  h.open(kSensor);
  ASSERT_TRUE(h.send(kSensor, hello));
  ASSERT_TRUE(h.send(kSensor, proto::encode(readings[0])));
  EXPECT_TRUE(h.readDone(kSensor)) << "the only sensor is answered in its read";
  EXPECT_FALSE(h.idle());
  // a second sensor (of no arm) joins; a connection that has not reported does not hold a cycle
  h.open(kOther);
  ASSERT_TRUE(h.send(kOther, hello));
  EXPECT_FALSE(h.readDone(kOther)) << "HELLO is no batch";
  const auto others = [&](std::size_t k) {
    proto::Readings none;
    none.seq = static_cast<std::uint32_t>(k + 1);
    none.t = readings[k].t;
    return proto::encode(none);
  };
  ASSERT_TRUE(h.send(kSensor, proto::encode(readings[1])));
  EXPECT_TRUE(h.readDone(kSensor));
  // both report: the first read's end waits for the second's
  for (std::size_t k = 2; k < 4; ++k) {
    ASSERT_TRUE(h.send(kOther, others(k)));
    EXPECT_FALSE(h.readDone(kOther)) << "cycle " << k << ": the sensor is still to come";
    ASSERT_TRUE(h.send(kSensor, proto::encode(readings[k])));
    const auto cycles = h.svc.counters().cycles;
    EXPECT_TRUE(h.readDone(kSensor)) << "cycle " << k;
    EXPECT_EQ(h.svc.counters().cycles, cycles + 1);
    EXPECT_EQ(h.svc.lastVerdict().t, readings[k].t);
    EXPECT_FALSE(h.idle());
  }
  // one that is late: the cycle at the end of the pass holds the one read
  ASSERT_TRUE(h.send(kSensor, proto::encode(readings[4])));
  EXPECT_FALSE(h.readDone(kSensor));
  EXPECT_TRUE(h.idle());
  EXPECT_EQ(h.svc.lastVerdict().t, readings[4].t);
  // the other leaves: the sensor alone again, answered in its read
  h.close(kOther);
  const auto again = contactReadings(1.305, 1.305);
  proto::Readings next = again[0];
  next.seq = 6;
  ASSERT_TRUE(h.send(kSensor, proto::encode(next)));
  EXPECT_TRUE(h.readDone(kSensor));
}

TEST(ArmServiceRogues, NoClientsTimeGetsTheSensorRefused) {
  // rogues leapfrogging ahead (each first message within 1 s of the newest), one lagging 0.99 s
  // behind: the sensor, held to its own clock alone, is never refused; the cycles the rogues
  // stamp ahead make its readings stale: STOP
  Harness h;
  const auto hello = proto::encode(proto::Hello{proto::kVersion, ""});
  for (net::ConnectionId id : {kSensor, net::ConnectionId{2}, net::ConnectionId{3}, net::ConnectionId{4}}) {
    h.open(id);
    ASSERT_TRUE(h.send(id, hello));
  }
  const auto readings = contactReadings(1.300, 1.302);
  ASSERT_TRUE(h.send(kSensor, proto::encode(readings[0])));
  proto::Readings none;
  none.seq = 1;
  none.t = 0.31;
  EXPECT_TRUE(h.send(4, proto::encode(none)));
  none.t = 2.29;
  EXPECT_TRUE(h.send(2, proto::encode(none)));
  none.t = 3.28;
  EXPECT_TRUE(h.send(3, proto::encode(none)));
  ASSERT_TRUE(h.send(kSensor, proto::encode(readings[1]))) << "another client's time got the sensor refused";
  ASSERT_TRUE(h.idle());
  EXPECT_EQ(h.svc.lastVerdict().t, 3.28);
  for (int a = 0; a < 2; ++a) EXPECT_EQ(h.svc.lastVerdict().arms[a].level, proto::Level::Stop);
  // a clock jumping ahead of its own last time is this connection's fault
  none.seq = 2;
  none.t = 4.5;
  EXPECT_FALSE(h.send(3, proto::encode(none)));
  // the rogues gone, the cycles are the sensor's again
  h.close(2), h.close(3), h.close(4);
  ASSERT_TRUE(h.send(kSensor, proto::encode(readings[2])));
  ASSERT_TRUE(h.idle());
  EXPECT_EQ(h.svc.lastVerdict().t, readings[2].t);
}

TEST(ArmServiceRogues, NoRogueScheduleTurnsTheSensorsStopIntoOk) {
  const auto readings = contactReadings();
  const auto alone = aloneVerdicts(readings);
  ASSERT_EQ(alone.size(), readings.size());
  int stops = 0;
  for (const auto& levels : alone) stops += levels[0] == proto::Level::Stop && levels[1] == proto::Level::Stop;
  ASSERT_GE(stops, 10) << "the window does not hold the contact the test is about";

  const int schedules = test::scaledCount(10000);
  std::uint64_t rogueCycles = 0, refused = 0, accepted = 0;
  for (int sc = 0; sc < schedules; ++sc) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(sc) + 1);
    const auto pick = [&](std::uint64_t n) { return static_cast<std::size_t>(rng() % n); };
    Harness h;
    h.open(kSensor);
    ASSERT_TRUE(h.send(kSensor, proto::encode(proto::Hello{proto::kVersion, ""})));
    // the sensor claims its arms at once, or (a v1 client) by its first reading, sent before any
    // rogue is heard: before either, any client that claims the arms is the only account there is
    const bool claims = pick(2);
    if (claims) {
      ASSERT_TRUE(h.send(kSensor, proto::encode(proto::Claim{{0, 1}, {}})));
    }
    std::vector<net::ConnectionId> live;
    net::ConnectionId next = 2;
    std::uint32_t seq = 0;
    bool failed = false;
    int last = -1;  // the sensor's newest reading
    // a cycle that ran: every arm its newest reading alone makes STOP is STOP
    const auto judge = [&] {
      if (last < 0) return;
      ++rogueCycles;
      const proto::Verdict& v = h.svc.lastVerdict();
      for (int a = 0; a < 2 && !failed; ++a)
        if (alone[last][a] == proto::Level::Stop && v.arms[a].level != proto::Level::Stop) {
          ADD_FAILURE() << "schedule " << sc << ": the sensor's reading at t = " << readings[last].t
                        << " makes STOP for arm " << a << " but the cycle at t = " << v.t << " says "
                        << proto::toString(v.arms[a].level);
          failed = true;
        }
    };
    for (std::size_t k = 0; k < readings.size() && !failed; ++k) {
      // the sensor's reading and the rogues' messages in random order, some sharing a cycle
      const std::size_t before = k == 0 && !claims ? 0 : pick(4), after = pick(3);
      for (std::size_t step = 0; step <= before + after && !failed; ++step) {
        net::ConnectionId read = 0;  // whose frames this step is (0: none)
        if (step == before) {
          ASSERT_TRUE(h.send(kSensor, proto::encode(readings[k])))
              << "schedule " << sc << ": the sensor was refused at t = " << readings[k].t;
          last = static_cast<int>(k);
          read = kSensor;
        } else {
          const std::size_t what = pick(10);
          if (what == 0 || live.empty()) {
            if (live.size() < 3) h.open(next), live.push_back(next++);
          } else if (what == 1) {
            const std::size_t i = pick(live.size());
            h.close(live[i]);
            live.erase(live.begin() + static_cast<std::ptrdiff_t>(i));
          } else {
            const std::size_t i = pick(live.size());
            read = live[i];
            if (h.send(live[i], rogueMessage(rng, readings, k, seq))) ++accepted;
            else ++refused, live.erase(live.begin() + static_cast<std::ptrdiff_t>(i));
          }
        }
        // the end of a read: a cycle if every reporting connection is in it, else at the end of
        // the pass (unless more arrive in the same pass)
        if (read != 0 && h.readDone(read)) judge();
        if (pick(2) && h.idle()) judge();
      }
      if (h.idle()) judge();
    }
    if (failed) break;
  }
  // the schedules did reach the service: messages taken and refused, cycles judged with rogues in them
  EXPECT_GT(accepted, static_cast<std::uint64_t>(schedules));
  EXPECT_GT(refused, static_cast<std::uint64_t>(schedules));
  EXPECT_GT(rogueCycles, static_cast<std::uint64_t>(schedules));
}

}  // namespace
}  // namespace st::arm
