#pragma once
// A framed TCP server on Boost.Asio, model-agnostic: it accepts connections, splits their bytes
// into length-delimited frames (stnet/frame.hpp) and hands each frame to a Handler; it sends
// frames back. Every resource is bounded: frame size, queued output per connection, number of
// connections, time to finish a frame once begun (a client trickling bytes, "slowloris"), idle
// time. A connection that breaks a bound gets one error frame (one line, built by the handler)
// and is closed; the others go on. Single-threaded: the handler runs on the thread that calls
// run(), so it needs no locks. SIGINT / SIGTERM / SIGHUP stop it cleanly (run() returns, signal noted).
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>

#include <boost/asio/io_context.hpp>

namespace st::net {

struct ServerConfig {
  std::string address = "127.0.0.1";  // loopback unless told otherwise
  std::uint16_t port = 0;             // 0: the system picks one (see Server::port())
  std::size_t maxFrame = 64 * 1024;   // bytes of payload; a longer announced frame is refused
  std::size_t maxOutput = 1 << 20;    // bytes queued to one connection; a client not reading is dropped
  std::size_t maxConnections = 128;   // beyond: accepted, told, closed
  // what a connection beyond maxConnections is told ("": "server full (N connections)"); a
  // handler that counts its own slots names them here
  std::string fullMessage;
  std::chrono::milliseconds frameTimeout{2000};  // first byte of a frame to its last
  std::chrono::milliseconds idleTimeout{0};      // no byte for this long closes (0: never)
  bool handleSignals = true;                     // SIGINT / SIGTERM / SIGHUP stop the server
};

using ConnectionId = std::uint64_t;

// Why a connection ended, for the handler's log.
enum class CloseReason {
  PeerClosed,      // orderly, between frames
  MidFrame,        // the peer went away inside a frame
  FrameTooLong,
  FrameTimeout,    // a frame begun was not finished in time
  IdleTimeout,
  OutputOverflow,  // it does not read what it is sent
  Refused,         // the handler's fail()
  ServerFull,
  Shutdown,
  Error,           // a socket error
};
const char* toString(CloseReason r);

class Server;

class Handler {
 public:
  virtual ~Handler() = default;
  virtual void onOpen(Server&, ConnectionId) {}
  virtual void onFrame(Server&, ConnectionId, std::string_view payload) = 0;
  virtual void onClose(Server&, ConnectionId, CloseReason, const std::string& /*detail*/) {}
  // The payload of the one error frame a misbehaving connection gets before it is closed.
  virtual std::string errorPayload(const std::string& message) { return "error: " + message; }
  // Called after the frames of one read of a connection are handed over, before it reads again:
  // a handler that knows its batch is complete answers here, without waiting for onIdle (which
  // comes a pass of the event loop later, after a poll of every socket).
  virtual void onReadDone(Server&, ConnectionId) {}
  // Called once per run of queued frames (after the frames read in one go), for batching work.
  virtual void onIdle(Server&) {}
};

class Server {
 public:
  // Binds and listens; throws std::runtime_error naming the address on failure.
  Server(boost::asio::io_context& io, ServerConfig cfg, Handler& handler);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  std::uint16_t port() const;
  const ServerConfig& config() const { return cfg_; }

  // Runs until stop() or a signal; returns the signal number (0 if none).
  int run();
  void stop();

  // Frames and queues the payload (false if the connection is gone or was dropped for overflow).
  bool send(ConnectionId id, std::string_view payload);
  // Queues handler.errorPayload(message) after the frames already queued and closes once it is
  // written (0.5 s at most); for OutputOverflow the queue is dropped first.
  void fail(ConnectionId id, const std::string& message, CloseReason why = CloseReason::Refused);
  // Closes at once, no error frame, no grace period: for shedding a connection that has not
  // identified itself (a flood must not hold sockets while an error frame lingers).
  void close(ConnectionId id, CloseReason why, const std::string& detail);
  std::size_t connections() const { return conns_.size(); }

  struct Counters {
    std::uint64_t accepted = 0, refusedFull = 0, frames = 0, bytesIn = 0, bytesOut = 0, failed = 0;
  };
  const Counters& counters() const { return counters_; }

 private:
  struct Connection;
  friend struct Connection;
  void accept();
  void closed(ConnectionId id, CloseReason why, const std::string& detail);
  void scheduleIdle();

  boost::asio::io_context& io_;
  ServerConfig cfg_;
  Handler& handler_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::unordered_map<ConnectionId, std::shared_ptr<Connection>> conns_;
  ConnectionId nextId_ = 1;
  Counters counters_;
  bool stopping_ = false;
  bool idlePosted_ = false;
  int signal_ = 0;
};

}  // namespace st::net
