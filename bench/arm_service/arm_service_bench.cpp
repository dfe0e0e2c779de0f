// bench/arm_service: end-to-end latency of the arm service over loopback, reading sent ->
// verdict received, at 1 kHz with 1, 8 and 64 sensor clients, side by side in one run with the
// same cycles in process (readings applied + detection, no network) and Shaffer & Herb's
// 30 ms per cycle (the report's [Shaf90]) as the historic anchor.
//
// The service runs on its own thread (as `stsim arm serve` does); the clients share one thread
// driving every socket with Asio, one per millisecond each: the first the two Pandas' readings
// of one trace cycle (bench: models/arm/scenarios/two_pandas.yaml, 3001 cycles), the others a
// READINGS of no arm at the same time (an arm has one reporting connection); each subscribes to
// the verdicts of its own messages. Both threads' CPU time is reported beside the figures: the
// two cores are shared by the service, the clients and whatever else runs on the machine.
// A last row replays the trace at real time with `stsim arm stream`'s client (runStream).
// Two more pairs of rows say where the time goes: the service with a cycle per message instead
// of per batch of messages read together, and a floor: the same protocol and st::net server
// answering each reading at once without a monitor.
//
// With a person: one Panda and one person (models/arm/scenarios/person_walkup.yaml), the sensor
// client sending each cycle's READINGS and the person's SKELETONS (protocol version 3, the
// scripted person's 17 joints), the service running the collision monitor and the speed and
// separation check; beside it the same cycles in process (readings and pose applied, monitor +
// SSM), and the ratio of its p99 to the echo floor's (1 client) of the same run.
//
// The p99 ratio is judged as before (pooled service p99 <= 1.1x pooled floor p99); beside it a
// bootstrap over the pairs (the pairs drawn with replacement, 2000 times, the pooled ratio of
// each draw) gives its 5-95 % interval: the target is shown met when the whole interval is at or
// below 1.1x, shown not met when it is above, and otherwise inside the noise of the run (with 10
// pairs or more; fewer are not judged).
//
// usage: arm_service_bench [CYCLES] [person [PAIRS]]   (default 3001: the whole trace, ~3 s per
//        row; "person": only the rows with a person, in process and PAIRS floor/service pairs,
//        default 5)

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <functional>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <stcore/cpu_clock.hpp>
#include <starm/service.hpp>
#include <starm/stream.hpp>
#include <stnet/frame.hpp>

namespace {

using namespace st;
using namespace st::arm;
namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

double loadAverage() {
  std::ifstream in("/proc/loadavg");
  double l = 0;
  in >> l;
  return l;
}

struct Stats {
  double p50 = 0, p99 = 0, max = 0;
  std::size_t n = 0;
};
Stats stats(std::vector<double> us) {
  Stats s;
  s.n = us.size();
  if (us.empty()) return s;
  s.p50 = percentile(us, 50);
  s.p99 = percentile(us, 99);
  s.max = *std::max_element(us.begin(), us.end());
  return s;
}

std::vector<std::vector<Reading>> recordCycles(const Scenario& s, std::size_t limit) {
  std::vector<std::vector<Reading>> cycles;
  auto src = makeSensor(s);
  Reading r;
  while (src->next(r)) {
    if (cycles.empty() || cycles.back().front().t != r.t) {
      if (cycles.size() == limit) break;
      cycles.emplace_back();
    }
    cycles.back().push_back(r);
  }
  return cycles;
}

Stats inProcess(const Scenario& s, const std::vector<std::vector<Reading>>& cycles) {
  std::vector<double> us;
  for (int rep = 0; rep < 3; ++rep) {
    Monitor m = makeMonitor(s);
    for (const auto& c : cycles) {
      const auto t0 = Clock::now();
      for (const Reading& r : c) m.setJointState(r.arm, r.t, r.q.data(), r.qdot.data());
      m.cycle(c.front().t);
      const auto t1 = Clock::now();
      if (rep > 0) us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
  }
  return stats(us);
}

// The person's skeleton at every cycle of the trace (the scenario's script).
std::vector<Skeleton> recordPoses(const Scenario& s, const std::vector<std::vector<Reading>>& cycles) {
  PersonSet persons = makePersons(s);
  std::vector<Skeleton> poses;
  for (const auto& c : cycles) {
    persons.pose(c.front().t);
    poses.push_back(persons.skeleton(0));
  }
  return poses;
}

// One arm and one person in process: readings and pose applied, the collision monitor's cycle and
// the persons' check, as the service's cycle does them.
Stats inProcessWithPerson(const Scenario& s, const std::vector<std::vector<Reading>>& cycles,
                          const std::vector<Skeleton>& poses) {
  std::vector<double> us;
  for (int rep = 0; rep < 3; ++rep) {
    Monitor m = makeMonitor(s);
    PersonSet persons;
    auto held = std::make_unique<HeldPerson>();
    HeldPerson& tracker = *held;
    persons.add(s.persons[0].name, std::move(held));
    SeparationMonitor ssm(s.ssm, m.armCount());
    for (std::size_t k = 0; k < cycles.size(); ++k) {
      const auto t0 = Clock::now();
      for (const Reading& r : cycles[k]) m.setJointState(r.arm, r.t, r.q.data(), r.qdot.data());
      tracker.set(poses[k]);
      m.cycle(cycles[k].front().t);
      persons.pose(m.time());
      ssm.cycle(m, persons);
      const auto t1 = Clock::now();
      if (rep > 0) us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
  }
  return stats(us);
}

// One sensor client on the shared client thread: a socket, its reads parsed into frames, the
// send time of every seq.
struct SensorClient {
  tcp::socket socket;
  std::vector<char> in = std::vector<char>(1 << 16);
  std::size_t have = 0;
  std::deque<std::string> out;
  bool writing = false;
  std::vector<Clock::time_point> sentAt;
  std::vector<double>* rtt = nullptr;
  std::size_t answered = 0;
  std::uint32_t acked = 0;  // readings answered so far
  explicit SensorClient(asio::io_context& io) : socket(io) {}

  void write() {
    if (writing || out.empty()) return;
    writing = true;
    asio::async_write(socket, asio::buffer(out.front()), [this](const boost::system::error_code& ec, std::size_t) {
      writing = false;
      if (ec) return;
      out.pop_front();
      write();
    });
  }
  void send(std::string payload) {
    out.push_back(net::frame(payload));
    write();
  }
  // several messages in one write: the service reads them in one pass, one cycle
  void sendTogether(const std::string& a, const std::string& b) {
    out.push_back(net::frame(a) + net::frame(b));
    write();
  }
  void read() {
    socket.async_read_some(asio::buffer(in.data() + have, in.size() - have),
                           [this](const boost::system::error_code& ec, std::size_t n) {
                             if (ec) return;
                             const auto now = Clock::now();
                             have += n;
                             std::size_t used = 0;
                             while (true) {
                               const net::FrameSplit f = net::splitFrame({in.data() + used, have - used}, in.size());
                               if (f.state != net::FrameSplit::State::Frame) break;
                               used += f.consumed;
                               const proto::Decoded d = proto::decode(f.payload);
                               if (const auto* v = d.ok ? std::get_if<proto::Verdict>(&d.message) : nullptr) {
                                 // a verdict answers every reading up to its ack (readings that
                                 // arrived together share a cycle): each timed from its own send
                                 for (; acked < v->ack && acked < sentAt.size(); ++acked, ++answered)
                                   rtt->push_back(std::chrono::duration<double, std::micro>(now - sentAt[acked]).count());
                               }
                             }
                             std::copy(in.begin() + static_cast<long>(used), in.begin() + static_cast<long>(have), in.begin());
                             have -= used;
                             read();
                           });
  }
};

struct NetRow {
  Stats rtt;
  std::vector<double> rttUs;  // every round trip, us
  std::size_t sent = 0, answered = 0;
  double serviceCpu = 0, clientCpu = 0, wall = 0;
  std::uint64_t cycles = 0;
  double load = 0;
};

// A loopback case's row of the table: messages, round trips, share answered, CPU of each side.
void printNetRow(const char* name, const NetRow& r) {
  std::printf("%-44s %8zu %8.2f %8.2f %8.1f %8.2f%% %11.1f%% %11.1f%%\n", name, r.sent, r.rtt.p50, r.rtt.p99, r.rtt.max,
              100.0 * static_cast<double>(r.answered) / static_cast<double>(std::max<std::size_t>(1, r.sent)),
              100.0 * r.serviceCpu / r.wall, 100.0 * r.clientCpu / r.wall);
}

// The floor: the same protocol over the same st::net server, answering every READINGS at once
// with a VERDICT (no monitor): what the network and the scheduling cost on their own.
class EchoService final : public net::Handler {
 public:
  EchoService(asio::io_context& io, net::ServerConfig cfg, int arms) : server_(io, cfg, *this) { v_.arms.resize(arms); }
  std::uint16_t port() const { return server_.port(); }
  void run() { server_.run(); }
  void stop() { server_.stop(); }
  struct Counters {
    std::uint64_t cycles = 0;
  };
  const Counters& counters() const { return c_; }
  void onFrame(net::Server& s, net::ConnectionId id, std::string_view p) override {
    proto::Type t;
    std::string err;
    if (!proto::peekType(p, t, err)) return s.fail(id, err);
    if (t == proto::Type::Hello) {
      s.send(id, proto::encode(proto::Welcome{}));
    } else if (t == proto::Type::Readings) {
      if (!proto::decodeReadings(p, r_).empty()) return s.fail(id, "bad READINGS");
      v_.ack = r_.seq;
      v_.t = r_.t;
      ++c_.cycles;
      out_.clear();
      proto::encodeInto(out_, v_);
      s.send(id, out_);
    }
  }

 private:
  net::Server server_;
  proto::Readings r_;
  proto::Verdict v_;
  std::string out_;
  Counters c_;
};

template <class Backend>
NetRow overLoopback(const Scenario& s, const std::vector<std::vector<Reading>>& cycles, int clients, bool batch = true,
                    const std::vector<Skeleton>* poses = nullptr) {
  asio::io_context serviceIo;
  ServiceConfig cfg;
  cfg.batchCycles = batch;
  cfg.net.handleSignals = false;
  cfg.net.maxConnections = 256;  // the echo floor's server
  cfg.maxClients = 256;           // the service's (it sets its server's from this)
  // no log: its flush is off the latency path anyway; measured without disk noise
  cfg.logDir = std::getenv("ARM_BENCH_LOG") ? std::getenv("ARM_BENCH_LOG") : "";
  std::unique_ptr<Backend> backend;
  if constexpr (std::is_same_v<Backend, ArmService>) backend = std::make_unique<ArmService>(serviceIo, s, cfg);
  else backend = std::make_unique<EchoService>(serviceIo, cfg.net, static_cast<int>(s.arms.size()));
  Backend& service = *backend;
  double serviceCpu0 = 0, serviceCpu1 = 0;
  std::thread serviceThread([&] {
    serviceCpu0 = st::threadCpuSeconds();
    service.run();
    serviceCpu1 = st::threadCpuSeconds();
  });

  NetRow row;
  row.load = loadAverage();
  asio::io_context io;
  std::vector<double> rtt;
  rtt.reserve(cycles.size() * clients);
  std::vector<std::unique_ptr<SensorClient>> cs;
  const tcp::endpoint ep(asio::ip::make_address("127.0.0.1"), service.port());
  for (int i = 0; i < clients; ++i) {
    auto c = std::make_unique<SensorClient>(io);
    c->socket.connect(ep);
    c->socket.set_option(tcp::no_delay(true));
    // HELLO, WELCOME (read synchronously once), SUBSCRIBE own-only
    asio::write(c->socket, asio::buffer(net::frame(proto::encode(proto::Hello{}))));
    char hdr[4];
    asio::read(c->socket, asio::buffer(hdr));
    const std::uint32_t n = (static_cast<std::uint32_t>(static_cast<unsigned char>(hdr[0])) << 24) |
                            (static_cast<std::uint32_t>(static_cast<unsigned char>(hdr[1])) << 16) |
                            (static_cast<std::uint32_t>(static_cast<unsigned char>(hdr[2])) << 8) |
                            static_cast<std::uint32_t>(static_cast<unsigned char>(hdr[3]));
    std::string welcome(n, '\0');
    asio::read(c->socket, asio::buffer(welcome));
    asio::write(c->socket, asio::buffer(net::frame(proto::encode(proto::Subscribe{proto::Subscribe::kOwnOnly}))));
    c->rtt = &rtt;
    c->sentAt.reserve(cycles.size());
    c->read();
    cs.push_back(std::move(c));
  }
  // the messages, encoded before the clock starts: client 0 reports the arms (each arm has one
  // reporting connection); the others send a READINGS holding no arm at the same time (a sensor
  // of something else, heard and answered each cycle)
  // (with poses: client 0 sends the person's SKELETONS of the same seq and time with its READINGS,
  // in one write: the service reads both in one pass and runs one cycle on them)
  std::vector<std::string> msgs, others, skeletons;
  for (std::size_t k = 0; k < cycles.size(); ++k) {
    proto::Readings m;
    m.seq = static_cast<std::uint32_t>(k + 1);
    m.t = cycles[k].front().t;
    others.push_back(proto::encode(m));
    for (const Reading& r : cycles[k]) m.arms.push_back({static_cast<std::uint16_t>(r.arm), r.q, r.qdot});
    msgs.push_back(proto::encode(m));
    if (poses) {
      proto::Skeletons sk;
      sk.seq = m.seq;
      sk.t = m.t;
      sk.persons.push_back({0, std::vector<Vec3>((*poses)[k].p.begin(), (*poses)[k].p.end())});
      skeletons.push_back(proto::encode(sk));
    }
  }
  const std::uint64_t cycles0 = service.counters().cycles;
  asio::steady_timer tick(io);
  std::size_t k = 0;
  const auto start = Clock::now() + std::chrono::milliseconds(20);
  const double clientCpu0 = st::threadCpuSeconds();
  std::function<void()> next = [&] {
    tick.expires_at(start + std::chrono::microseconds(1000 * k));
    tick.async_wait([&](const boost::system::error_code& ec) {
      if (ec) return;
      for (std::size_t i = 0; i < cs.size(); ++i) {
        cs[i]->sentAt.push_back(Clock::now());
        if (i == 0 && poses) cs[i]->sendTogether(skeletons[k], msgs[k]);
        else cs[i]->send(i == 0 ? msgs[k] : others[k]);
      }
      ++row.sent;
      if (++k < msgs.size()) next();
      else {
        // the last verdicts: up to 200 ms more, then stop
        tick.expires_after(std::chrono::milliseconds(200));
        tick.async_wait([&](const boost::system::error_code&) { io.stop(); });
      }
    });
  };
  next();
  io.run();
  row.clientCpu = st::threadCpuSeconds() - clientCpu0;
  row.wall = std::chrono::duration<double>(Clock::now() - start).count();
  row.sent *= static_cast<std::size_t>(clients);
  for (auto& c : cs) row.answered += c->answered;
  asio::post(serviceIo, [&] { service.stop(); });
  serviceThread.join();
  row.serviceCpu = serviceCpu1 - serviceCpu0;
  row.cycles = service.counters().cycles - cycles0;
  row.rtt = stats(rtt);
  row.rttUs = std::move(rtt);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t limit = argc > 1 ? static_cast<std::size_t>(std::stoul(argv[1])) : 3001;
  const bool personOnly = argc > 2 && std::string(argv[2]) == "person";
  const int kPairs = personOnly && argc > 3 ? std::max(2, std::stoi(argv[3])) : 5;
  const Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/two_pandas.yaml");
  const auto cycles = recordCycles(s, limit);
  std::printf("arm service: two_pandas, %zu cycles at 1 kHz per row, load average %.2f at start, 2 cores shared\n\n",
              cycles.size(), loadAverage());
  Stats local;
  std::vector<std::pair<int, NetRow>> rows;
  std::vector<std::pair<int, NetRow>> perMessage;
  std::vector<std::pair<int, NetRow>> floor;
  if (!personOnly) {
    local = inProcess(s, cycles);
    for (int n : {1, 8, 64}) rows.emplace_back(n, overLoopback<ArmService>(s, cycles, n));
    for (int n : {8, 64}) perMessage.emplace_back(n, overLoopback<ArmService>(s, cycles, n, false));
    for (int n : {1, 8}) floor.emplace_back(n, overLoopback<EchoService>(s, cycles, n));
  }
  // one arm and one person: SKELETONS every cycle beside the READINGS
  const Scenario sp = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/person_walkup.yaml");
  const auto personCycles = recordCycles(sp, limit);
  const auto poses = recordPoses(sp, personCycles);
  const Stats localPerson = inProcessWithPerson(sp, personCycles, poses);
  // its floor: the echo server sent the same messages (READINGS answered, SKELETONS read), the two
  // rows alternated kPairs times so both see the same machine; each pair's ratio, and the ratio of
  // the pooled round trips (all floor rows against all service rows)
  std::vector<std::pair<NetRow, NetRow>> personPairs;
  std::vector<double> pooledFloor, pooledService;
  for (int rep = 0; rep < kPairs; ++rep) {
    personPairs.emplace_back(overLoopback<EchoService>(sp, personCycles, 1, true, &poses),
                             overLoopback<ArmService>(sp, personCycles, 1, true, &poses));
    pooledFloor.insert(pooledFloor.end(), personPairs.back().first.rttUs.begin(), personPairs.back().first.rttUs.end());
    pooledService.insert(pooledService.end(), personPairs.back().second.rttUs.begin(), personPairs.back().second.rttUs.end());
  }
  const Stats personFloor = stats(pooledFloor), personService = stats(pooledService);
  std::vector<double> pairRatios;
  for (const auto& pr : personPairs) pairRatios.push_back(pr.second.rtt.p99 / pr.first.rtt.p99);
  std::sort(pairRatios.begin(), pairRatios.end());
  // the pooled ratios' spread over the pairs: a bootstrap (pairs drawn with replacement), 5-95 %;
  // with a handful of pairs it is narrower than the spread it estimates (5 pairs: 126 draws in
  // all), so it judges nothing below kFewestPairs
  constexpr int kFewestPairs = 10;
  std::array<double, 2> p50Band{}, p99Band{};
  {
    constexpr int kDraws = 2000;
    std::mt19937_64 rng(1);
    std::vector<double> r50, r99, f, sv;
    for (int d = 0; d < kDraws; ++d) {
      f.clear(), sv.clear();
      for (int k = 0; k < kPairs; ++k) {
        const auto& pr = personPairs[rng() % static_cast<std::uint64_t>(kPairs)];
        f.insert(f.end(), pr.first.rttUs.begin(), pr.first.rttUs.end());
        sv.insert(sv.end(), pr.second.rttUs.begin(), pr.second.rttUs.end());
      }
      r50.push_back(percentile(sv, 50) / percentile(f, 50));
      r99.push_back(percentile(sv, 99) / percentile(f, 99));
    }
    p50Band = {percentile(r50, 5), percentile(r50, 95)};
    p99Band = {percentile(r99, 5), percentile(r99, 95)};
  }

  // the stream client at real time (one client, blocking, as `stsim arm stream --rate 1` runs)
  StreamResult sr;
  if (!personOnly) {
    asio::io_context serviceIo;
    ServiceConfig cfg;
    cfg.net.handleSignals = false;
    ArmService service(serviceIo, s, cfg);
    std::thread t([&] { service.run(); });
    const std::string trace = "/tmp/arm_service_bench_" + std::to_string(::getpid()) + ".csv";
    {
      Scenario copy = s;
      auto src = makeSensor(copy);
      std::vector<std::string> names{s.arms[0].name, s.arms[1].name};
      RecordingSensor rec(*src, trace, names);
      Reading r;
      std::size_t n = 0;
      double last = -1;
      while (rec.next(r)) {
        if (r.t != last && ++n > cycles.size()) break;
        last = r.t;
      }
    }
    StreamConfig sc;
    sc.port = service.port();
    sc.trace = trace;
    sc.rate = 1.0;
    runStream(sc, sr);
    asio::post(serviceIo, [&] { service.stop(); });
    t.join();
    std::remove(trace.c_str());
  }
  const Stats stream = stats(sr.rttUs);

  std::printf("%-44s %8s %8s %8s %8s %9s %12s %12s\n", "case", "msgs", "p50 us", "p99 us", "max us", "answered",
              "service CPU", "client CPU");
  if (!personOnly)
    std::printf("%-44s %8zu %8.2f %8.2f %8.1f %9s %12s %12s\n", "in process: readings applied + cycle", local.n, local.p50,
                local.p99, local.max, "-", "-", "-");
  for (const auto& [n, r] : rows) {
    char name[64];
    std::snprintf(name, sizeof name, "loopback, %d client%s at 1 kHz (%.2f cycles/ms)", n, n == 1 ? "" : "s",
                  static_cast<double>(r.cycles) / (r.wall * 1000.0));
    printNetRow(name, r);
  }
  for (const auto& [n, r] : perMessage) {
    char name[64];
    std::snprintf(name, sizeof name, "  %d clients, a cycle per message (%.2f cycles/ms)", n,
                  static_cast<double>(r.cycles) / (r.wall * 1000.0));
    printNetRow(name, r);
  }
  for (const auto& [n, r] : floor) {
    char name[64];
    std::snprintf(name, sizeof name, "floor: st::net echo, no monitor, %d client%s", n, n == 1 ? "" : "s");
    printNetRow(name, r);
  }
  std::printf("%-44s %8zu %8.2f %8.2f %8.1f %9s %12s %12s\n", "in process: 1 arm + 1 person, monitor + SSM",
              localPerson.n, localPerson.p50, localPerson.p99, localPerson.max, "-", "-", "-");
  for (std::size_t i = 0; i < personPairs.size(); ++i) {
    for (const NetRow* r : {&personPairs[i].first, &personPairs[i].second}) {
      char name[64];
      std::snprintf(name, sizeof name, "%s %zu: 1 arm + 1 person, 1 client", r == &personPairs[i].first ? "floor" : "service",
                    i + 1);
      printNetRow(name, *r);
    }
  }
  if (!personOnly) {
  std::printf("%-44s %8zu %8.2f %8.2f %8.1f %8.2f%% %12s %12s\n", "loopback, stsim arm stream --rate 1 (1 client)",
              sr.cycles, stream.p50, stream.p99, stream.max,
              100.0 * static_cast<double>(sr.verdicts) / static_cast<double>(std::max<std::uint64_t>(1, sr.cycles)), "-", "-");
  std::printf("%-44s %8s %8.0f %8s %8s\n", "Shaffer & Herb 1990 (report [Shaf90])", "-", 30000.0, "-", "-");
  const NetRow& eight = rows[1].second;
  std::printf("\nratios: 30 ms / loopback p50 with 8 clients = %.0fx; loopback p50 / in-process p50 = %.1fx (1 client), "
              "%.1fx (8), %.1fx (64)\n",
              30000.0 / eight.rtt.p50, rows[0].second.rtt.p50 / local.p50, eight.rtt.p50 / local.p50,
              rows[2].second.rtt.p50 / local.p50);
  std::printf("target at 1 kHz with 8 clients: p50 <= 50 us (%.2f: %s), p99 <= 250 us (%.2f: %s)\n", eight.rtt.p50,
              eight.rtt.p50 <= 50 ? "met" : "NOT met", eight.rtt.p99, eight.rtt.p99 <= 250 ? "met" : "NOT met");
  }
  std::printf("1 arm + 1 person over loopback against its echo floor (1 client, %d pairs alternated): pooled p50 %.2f / "
              "%.2f us = %.2fx, pooled p99 %.2f / %.2f us = %.2fx (target p99 <= 1.1x: %s); per pair p99 ratio %.2fx .. "
              "%.2fx (median %.2fx)\n",
              kPairs, personService.p50, personFloor.p50, personService.p50 / personFloor.p50, personService.p99,
              personFloor.p99, personService.p99 / personFloor.p99,
              personService.p99 <= 1.1 * personFloor.p99 ? "met" : "NOT met", pairRatios.front(), pairRatios.back(),
              pairRatios[pairRatios.size() / 2]);
  std::printf("bootstrap over the %d pairs (2000 draws), 5-95 %%: pooled p50 ratio %.2fx .. %.2fx, pooled p99 ratio "
              "%.2fx .. %.2fx: the p99 target %s\n",
              kPairs, p50Band[0], p50Band[1], p99Band[0], p99Band[1],
              kPairs < kFewestPairs ? "not judged (too few pairs for a band; 10 or more)"
              : p99Band[1] <= 1.1   ? "shown met"
              : p99Band[0] > 1.1    ? "shown NOT met"
                                    : "inside the run's noise");
  std::printf("in process monitor + SSM, 1 arm + 1 person: p99 %.2f us (target <= 100 us: %s)\n", localPerson.p99,
              localPerson.p99 <= 100.0 ? "met" : "NOT met");
  std::printf("CPU: per cent of one core over the row's wall time (service thread; all client sockets on one thread)\n");
  return 0;
}
