#include "pool_server.hpp"

namespace st::pool {

ServeConfig defaultServeConfig() {
  ServeConfig c;
  c.web.net.address = "127.0.0.1";
  c.web.net.port = 8080;
  c.web.net.maxFrame = 16 * 1024;
  c.web.net.maxOutput = 1 << 20;
  c.web.net.maxConnections = 64;
  c.web.net.frameTimeout = std::chrono::milliseconds(5000);
  c.web.net.idleTimeout = std::chrono::milliseconds(60000);
  c.web.writeTimeout = std::chrono::milliseconds(10000);
  return c;
}

PoolServer::PoolServer(boost::asio::io_context& io, const Scenario& scenario, ServeConfig cfg)
    : scenario_(scenario), cfg_(std::move(cfg)) {
  PlaySession check(scenario_, cfg_.limits);  // refuse a scenario no game can take, before listening
  server_ = std::make_unique<net::WebServer>(io, cfg_.web, *this);
}

PoolServer::~PoolServer() = default;

net::HttpReply PoolServer::onGet(const std::string& target) {
  if (target == "/" || target == "/index.html") return {200, "text/html; charset=utf-8", cfg_.page};
  return {404, "text/plain; charset=utf-8", "not found: " + target + "\n"};
}

void PoolServer::onOpen(net::WebServer& s, net::ConnectionId id) {
  auto game = std::make_unique<PlaySession>(scenario_, cfg_.limits);
  const std::string state = game->stateMessage();
  games_[id] = std::move(game);
  ++counters_.games;
  s.send(id, state);  // (a send that fails closes the socket: onClose frees the game)
}

void PoolServer::onMessage(net::WebServer& s, net::ConnectionId id, std::string_view text) {
  const auto it = games_.find(id);
  if (it == games_.end()) return;
  ++counters_.messages;
  PlaySession& game = *it->second;
  const bool wasStreaming = game.streaming();
  const std::vector<std::string> replies = game.handle(text);
  if (!wasStreaming && game.streaming()) ++counters_.shots;
  for (const std::string& reply : replies) {
    if (reply.rfind("{\"type\":\"error\"", 0) == 0) ++counters_.errors;
    // a send can drop the socket (its queue full), and onClose frees the game: look again
    if (!s.send(id, reply) || !games_.count(id)) return;
  }
  pump(s, id);
}

void PoolServer::onDrained(net::WebServer& s, net::ConnectionId id) { pump(s, id); }

void PoolServer::pump(net::WebServer& s, net::ConnectionId id) {
  const auto it = games_.find(id);
  if (it == games_.end() || s.queued(id) > 0) return;
  if (auto part = it->second->nextPart()) {
    ++counters_.parts;
    s.send(id, *part);
  }
}

void PoolServer::onClose(net::WebServer&, net::ConnectionId id, net::CloseReason, const std::string&) {
  games_.erase(id);  // a tab closed mid-shot: its unsent parts go with it
}

}  // namespace st::pool
