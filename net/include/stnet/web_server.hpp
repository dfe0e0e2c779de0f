#pragma once
// An HTTP + WebSocket server on Boost.Beast, beside the framed Server (stnet/server.hpp) and with
// its bounds, loopback default, connection ids, close reasons and signal handling: plain GETs are
// answered by the handler (a page and its files), an upgrade on `wsPath` opens a WebSocket whose
// text messages go to the handler. Every resource is bounded: request size and time, message size,
// output queued per socket, time a write may stall (a client that stops reading), number of
// connections. Single-threaded, like Server: the handler runs on the thread that calls run().
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>

#include <boost/asio/io_context.hpp>

#include <stnet/server.hpp>

namespace st::net {

struct WebConfig {
  // address, port, maxFrame (bytes of one WebSocket message), maxOutput (bytes queued to one
  // socket), maxConnections (HTTP and WebSocket together), frameTimeout (an HTTP request or a
  // WebSocket handshake must be complete within it), idleTimeout (0: none; else a silent peer is
  // pinged and closed if it stays silent), handleSignals
  ServerConfig net;
  std::size_t maxRequest = 8 * 1024;            // bytes of an HTTP request's header
  std::chrono::milliseconds writeTimeout{5000};  // a write stalled this long drops the socket
  std::string wsPath = "/ws";
};

struct HttpReply {
  unsigned status = 200;
  std::string contentType = "text/plain; charset=utf-8";
  std::string body;
};

class WebServer;

class WebHandler {
 public:
  virtual ~WebHandler() = default;
  // A GET (or HEAD) of anything but wsPath; target is the request target as sent ("/", "/x?y").
  virtual HttpReply onGet(const std::string& target) = 0;
  virtual void onOpen(WebServer&, ConnectionId) {}
  virtual void onMessage(WebServer&, ConnectionId, std::string_view text) = 0;
  virtual void onClose(WebServer&, ConnectionId, CloseReason, const std::string& /*detail*/) {}
  // The socket's output queue has just emptied: a producer that streams in parts sends the next.
  virtual void onDrained(WebServer&, ConnectionId) {}
};

class WebServer {
 public:
  // Binds and listens; throws std::runtime_error naming the address on failure.
  WebServer(boost::asio::io_context& io, WebConfig cfg, WebHandler& handler);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  std::uint16_t port() const;
  const WebConfig& config() const { return cfg_; }

  // Runs until stop() or a signal; returns the signal number (0 if none).
  int run();
  void stop();

  // Queues a text message (false if the socket is gone or was dropped because its queue would
  // pass maxOutput).
  bool send(ConnectionId id, std::string_view text);
  // Bytes queued to the socket and not yet written (0 if it is gone).
  std::size_t queued(ConnectionId id) const;
  // Closes the WebSocket with a policy-violation close frame carrying `message`.
  void fail(ConnectionId id, const std::string& message, CloseReason why = CloseReason::Refused);
  std::size_t webSockets() const { return sockets_.size(); }

  struct Counters {
    std::uint64_t accepted = 0, refusedFull = 0, requests = 0, messages = 0, bytesIn = 0, bytesOut = 0, failed = 0;
  };
  const Counters& counters() const { return counters_; }

 private:
  struct HttpSession;
  struct Socket;
  friend struct HttpSession;
  friend struct Socket;
  void accept();
  void closed(ConnectionId id, CloseReason why, const std::string& detail);

  boost::asio::io_context& io_;
  WebConfig cfg_;
  WebHandler& handler_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::unordered_map<ConnectionId, std::shared_ptr<Socket>> sockets_;
  std::size_t httpSessions_ = 0;
  ConnectionId nextId_ = 1;
  Counters counters_;
  bool stopping_ = false;
  int signal_ = 0;
};

}  // namespace st::net
