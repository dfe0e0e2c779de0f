// bench/pool_serve: latency of `stsim pool serve` over loopback, from the release of the cue (the
// page's shoot message sent) to the first event frame on the socket, for the break (the standard
// rack, friction 0.15, version II df 5, the cue ball at 8 m/s), with 1 tab and 50 tabs shooting
// at once; beside it the time to the shot's last frame (the new state) and, as the floor, the
// same shot in process (PlaySession: played and cut into parts, no socket).
//
// The server runs on its own thread, as `stsim pool serve` does; each tab is a WebSocket client
// (tests/net/ws_client.hpp) on a thread of its own, all released together per round. Rounds:
// shoot, read to the state after the shot, restart.
//
// usage: pool_serve_bench [ROUNDS]   (default 100 for 1 tab; 50 tabs run ROUNDS / 5 rounds)
#include <algorithm>
#include <barrier>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>

#include "net/ws_client.hpp"
#include "play_session.hpp"
#include "pool_server.hpp"

namespace {

using namespace st;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

const char* kBreak = R"({"type":"shoot","ball":0,"angle":0,"speed":8})";

double us(Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); }
double pct(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}
double loadAverage() {
  std::ifstream in("/proc/loadavg");
  double l = 0;
  in >> l;
  return l;
}
bool isType(const std::string& m, const char* type) {
  return m.rfind(std::string("{\"type\":\"") + type + "\"", 0) == 0;
}

struct Samples {
  std::vector<double> first, last;
  int failed = 0;
};

// `tabs` clients on threads of their own, `rounds` breaks each, released together.
Samples overSockets(const pool::Scenario& rack, int tabs, int rounds) {
  pool::ServeConfig cfg = pool::defaultServeConfig();
  cfg.web.net.port = 0;
  cfg.web.net.handleSignals = false;
  cfg.page = "<!doctype html>";
  boost::asio::io_context io;
  pool::PoolServer server(io, rack, cfg);
  std::thread serverThread([&] { server.run(); });
  Samples all;
  std::vector<Samples> each(tabs);
  std::barrier sync(tabs);
  std::vector<std::thread> threads;
  for (int k = 0; k < tabs; ++k)
    threads.emplace_back([&, k] {
      net::test::WsClient c;
      Samples& s = each[k];
      if (!c.connect(server.port()) || !c.receive(5s)) {
        ++s.failed;
        for (int r = 0; r < rounds; ++r) sync.arrive_and_wait();
        return;
      }
      for (int r = 0; r < rounds; ++r) {
        sync.arrive_and_wait();
        const auto t0 = Clock::now();
        bool ok = c.send(kBreak), first = false;
        while (ok) {
          const auto m = c.receive(10s);
          if (!m) { ok = false; break; }
          if (!first && isType(*m, "events")) { s.first.push_back(us(Clock::now() - t0)); first = true; }
          if (isType(*m, "state")) { s.last.push_back(us(Clock::now() - t0)); break; }
        }
        ok = ok && c.send(R"({"type":"restart"})") && c.receive(5s).has_value();
        if (!ok) ++s.failed;
      }
    });
  for (auto& t : threads) t.join();
  boost::asio::post(io, [&] { server.stop(); });
  serverThread.join();
  for (const Samples& s : each) {
    all.first.insert(all.first.end(), s.first.begin(), s.first.end());
    all.last.insert(all.last.end(), s.last.begin(), s.last.end());
    all.failed += s.failed;
  }
  return all;
}

Samples inProcess(const pool::Scenario& rack, int rounds) {
  Samples s;
  pool::PlaySession g(rack);
  for (int r = 0; r < rounds; ++r) {
    const auto t0 = Clock::now();
    g.handle(kBreak);
    std::string part = *g.nextPart();  // the shot's header
    part = *g.nextPart();              // the first events frame
    s.first.push_back(us(Clock::now() - t0));
    while (g.nextPart()) {
    }
    s.last.push_back(us(Clock::now() - t0));
    g.handle(R"({"type":"restart"})");
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(5, std::atoi(argv[1])) : 100;
  const pool::Scenario rack = pool::parseScenario(pool::kServeDefaultScenario, "(rack)");
  std::printf("pool_serve_bench: the break (standard rack, friction 0.15, version II df 5, 8 m/s) over 127.0.0.1;\n"
              "cue released (shoot sent) -> first events frame, and -> the shot's last frame (state); load %.1f\n\n",
              loadAverage());
  std::printf("| tabs | shots | first event frame p50 / p99 us | last frame p50 / p99 us | failed |\n|---|---|---|---|---|\n");
  const Samples floor = inProcess(rack, rounds);
  std::printf("| in process (no socket) | %zu | %.0f / %.0f | %.0f / %.0f | 0 |\n", floor.first.size(), pct(floor.first, 0.5),
              pct(floor.first, 0.99), pct(floor.last, 0.5), pct(floor.last, 0.99));
  for (const int tabs : {1, 50}) {
    const Samples s = overSockets(rack, tabs, tabs == 1 ? rounds : std::max(2, rounds / 5));
    std::printf("| %d | %zu | %.0f / %.0f | %.0f / %.0f | %d |\n", tabs, s.first.size(), pct(s.first, 0.5), pct(s.first, 0.99),
                pct(s.last, 0.5), pct(s.last, 0.99), s.failed);
  }
  std::printf("\nload after: %.1f\n", loadAverage());
  return 0;
}
