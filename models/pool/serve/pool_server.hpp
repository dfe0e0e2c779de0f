#pragma once
// stsim pool serve: the page over HTTP and one PlaySession per WebSocket (each browser tab its
// own game), on st::net's WebServer. A tab's messages go to its game; a shot's parts go out one
// at a time, the next when the socket has written the last (a tab that stops reading holds one
// part, then is dropped by the server's write timeout). A closed tab frees its game.
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>

#include <boost/asio/io_context.hpp>
#include <stnet/web_server.hpp>

#include "play_session.hpp"

namespace st::pool {

// The scenario a served game starts from when none is given: the standard rack with a seeded
// gap, a little rolling resistance so every shot comes to rest, version II.
inline constexpr const char* kServeDefaultScenario = R"(name: rack
table: {width: 2.54, height: 1.27}
rack: {kind: standard, gap: 2.0e-5}
friction: 0.15
until: 60
space: {kind: quadtree, decomposition_factor: 5}
)";

struct ServeConfig {
  net::WebConfig web;      // address, port and the server's bounds
  SessionLimits limits;    // per game
  std::string page;        // the page's HTML, served at / (and /index.html)
};

// Bounds a served game runs with unless told otherwise: client messages are small (16 KiB), a
// part is at most SessionLimits::partBytes (48 KiB), 64 games, a silent tab pinged after 60 s.
ServeConfig defaultServeConfig();

struct ServeCounters {
  std::uint64_t games = 0, messages = 0, shots = 0, errors = 0, parts = 0;
};

class PoolServer final : public net::WebHandler {
 public:
  // Throws ScenarioError if the scenario breaks a game's limits, std::runtime_error if it
  // cannot listen.
  PoolServer(boost::asio::io_context& io, const Scenario& scenario, ServeConfig cfg);
  ~PoolServer() override;

  std::uint16_t port() const { return server_->port(); }
  int run() { return server_->run(); }  // until stop() or SIGINT / SIGTERM / SIGHUP; the signal or 0
  void stop() { server_->stop(); }
  std::size_t games() const { return games_.size(); }
  const ServeCounters& counters() const { return counters_; }
  const net::WebServer& web() const { return *server_; }

  net::HttpReply onGet(const std::string& target) override;
  void onOpen(net::WebServer&, net::ConnectionId) override;
  void onMessage(net::WebServer&, net::ConnectionId, std::string_view text) override;
  void onClose(net::WebServer&, net::ConnectionId, net::CloseReason, const std::string&) override;
  void onDrained(net::WebServer&, net::ConnectionId) override;

 private:
  void pump(net::WebServer& s, net::ConnectionId id);

  Scenario scenario_;
  ServeConfig cfg_;
  std::unordered_map<net::ConnectionId, std::unique_ptr<PlaySession>> games_;
  ServeCounters counters_;
  std::unique_ptr<net::WebServer> server_;
};

}  // namespace st::pool
