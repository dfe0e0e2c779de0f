// Arm service (starm/service.hpp) behind its st::net framing: the input is a byte stream of
// records [u8 connection] [u32 length] [payload], as three clients would send them. Each payload
// goes to the service's handler the way st::net hands it over; a refused connection is closed
// and another opens in its place, as the server does. No exception may leave the handler (it
// would stop the service for every client), and the monitor's time never goes back from one
// cycle to the next unless a client left between them (a sensor that leaves takes its time with
// it: the cycles are stamped by those still connected).
#include <cmath>
#include <cstdlib>
#include <string_view>

#include <boost/asio/io_context.hpp>
#include <starm/scenario.hpp>
#include <starm/service.hpp>
#include <stnet/frame.hpp>

namespace {

const st::arm::Scenario& scenario() {
  static const st::arm::Scenario s = st::arm::loadScenario(STSIM_SOURCE_DIR "/models/arm/scenarios/two_pandas.yaml");
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  boost::asio::io_context io;
  st::arm::ServiceConfig cfg;
  cfg.net.handleSignals = false;
  st::arm::ArmService svc(io, scenario(), cfg);
  // the handler's Server& argument: the service's own server is not reachable from here, and
  // what it does with a refusal (close the connection) is played below
  st::net::ServerConfig quiet;
  quiet.handleSignals = false;
  st::net::Server server(io, quiet, svc);

  constexpr int kClients = 3;
  st::net::ConnectionId ids[kClients];
  st::net::ConnectionId next = 1;
  for (auto& id : ids) svc.onOpen(server, id = next++);
  std::string_view in(reinterpret_cast<const char*>(data), size);
  double lastT = -INFINITY;
  bool left = false;  // a client closed since the last cycle
  while (!in.empty()) {
    const int c = static_cast<unsigned char>(in[0]) % kClients;
    const st::net::FrameSplit f = st::net::splitFrame(in.substr(1), 1 << 16);
    if (f.state != st::net::FrameSplit::State::Frame) break;
    in.remove_prefix(1 + f.consumed);
    const auto refused = svc.counters().rejected;
    svc.onFrame(server, ids[c], f.payload);
    if (svc.counters().rejected != refused) {
      svc.onClose(server, ids[c], st::net::CloseReason::Refused, "");
      svc.onOpen(server, ids[c] = next++);
      left = true;
    }
    const auto cycles = svc.counters().cycles;
    svc.onIdle(server);  // the end of one read: the cycle runs
    if (svc.counters().cycles == cycles) continue;
    const double t = svc.monitor().time();  // of the cycle that ran (before the first: 0, no cycle's)
    if (t < lastT && !left) std::abort();
    lastT = t;
    left = false;
  }
  for (auto id : ids) svc.onClose(server, id, st::net::CloseReason::PeerClosed, "");
  return 0;
}
