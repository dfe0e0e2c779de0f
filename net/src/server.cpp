#include <stnet/server.hpp>

#include <cstring>
#include <deque>
#include <stdexcept>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>

#include <stnet/frame.hpp>

#include "listen.hpp"

namespace st::net {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using boost::system::error_code;

const char* toString(CloseReason r) {
  switch (r) {
    case CloseReason::PeerClosed: return "peer closed";
    case CloseReason::MidFrame: return "peer closed mid-frame";
    case CloseReason::FrameTooLong: return "frame too long";
    case CloseReason::FrameTimeout: return "frame timeout";
    case CloseReason::IdleTimeout: return "idle timeout";
    case CloseReason::OutputOverflow: return "output overflow";
    case CloseReason::Refused: return "refused";
    case CloseReason::ServerFull: return "server full";
    case CloseReason::Shutdown: return "shutdown";
    case CloseReason::Error: return "socket error";
  }
  return "?";
}

struct Server::Impl {
  tcp::acceptor acceptor;
  asio::signal_set signals;
  explicit Impl(asio::io_context& io) : acceptor(io), signals(io) {}
};

// One client. Reads into a bounded buffer (one largest frame plus its header), splits frames,
// writes queued frames one at a time. Async handlers hold a shared_ptr; `open` says whether
// the server still counts it.
struct Server::Connection : std::enable_shared_from_this<Connection> {
  Server& server;
  ConnectionId id;
  tcp::socket socket;
  asio::steady_timer frameTimer, idleTimer;
  std::vector<char> in;
  std::size_t have = 0;
  bool frameTimerArmed = false;
  std::deque<std::string> out;
  std::size_t queued = 0;
  bool writing = false;
  bool open = true;
  bool closing = false;  // an error frame is on its way; then close
  bool draining = false;  // it is written: dropping the peer's input until it closes
  bool reading = false;   // a read is in flight
  CloseReason closeWhy = CloseReason::Refused;
  std::string closeDetail;

  Connection(Server& s, ConnectionId i, tcp::socket sock)
      : server(s), id(i), socket(std::move(sock)), frameTimer(s.io_), idleTimer(s.io_),
        in(kFrameHeader + s.cfg_.maxFrame) {}

  void start() {
    resetIdle();
    read();
  }

  void read() {
    if (!open || closing) return;
    reading = true;
    auto self = shared_from_this();
    socket.async_read_some(asio::buffer(in.data() + have, in.size() - have),
                           [self](const error_code& ec, std::size_t n) { self->onRead(ec, n); });
  }

  void onRead(const error_code& ec, std::size_t n) {
    reading = false;
    if (!open) return;
    if (draining) {
      if (ec) finish(closeWhy, closeDetail);
      else drain();
      return;
    }
    if (closing) return;
    if (ec) {
      if (ec == asio::error::eof || ec == asio::error::connection_reset)
        finish(have > 0 ? CloseReason::MidFrame : CloseReason::PeerClosed,
               have > 0 ? std::to_string(have) + " bytes of an unfinished frame" : "");
      else finish(CloseReason::Error, ec.message());
      return;
    }
    have += n;
    server.counters_.bytesIn += n;
    resetIdle();
    std::size_t used = 0;
    while (open && !closing) {
      const FrameSplit f = splitFrame(std::string_view(in.data() + used, have - used), server.cfg_.maxFrame);
      if (f.state == FrameSplit::State::NeedMore) break;
      if (f.state == FrameSplit::State::TooLong) {
        fail("frame of " + std::to_string(f.length) + " bytes exceeds the limit of " +
                 std::to_string(server.cfg_.maxFrame) + " bytes",
             CloseReason::FrameTooLong);
        return;
      }
      used += f.consumed;
      ++server.counters_.frames;
      server.handler_.onFrame(server, id, f.payload);
    }
    if (!open || closing) return;
    if (used > 0) {
      std::memmove(in.data(), in.data() + used, have - used);
      have -= used;
    }
    // a frame begun must be finished in time (a client trickling bytes holds no slot for long)
    if (have == 0) {
      frameTimerArmed = false;
      frameTimer.cancel();
    } else if (!frameTimerArmed) {
      frameTimerArmed = true;
      frameTimer.expires_after(server.cfg_.frameTimeout);
      auto self = shared_from_this();
      frameTimer.async_wait([self](const error_code& e) {
        if (e || !self->open || self->closing || !self->frameTimerArmed) return;
        self->fail("frame not completed within " + std::to_string(self->server.cfg_.frameTimeout.count()) + " ms",
                   CloseReason::FrameTimeout);
      });
    }
    server.scheduleIdle();
    if (used > 0) server.handler_.onReadDone(server, id);
    read();
  }

  void resetIdle() {
    if (server.cfg_.idleTimeout.count() <= 0) return;
    idleTimer.expires_after(server.cfg_.idleTimeout);
    auto self = shared_from_this();
    idleTimer.async_wait([self](const error_code& e) {
      if (e || !self->open || self->closing) return;
      self->fail("idle for " + std::to_string(self->server.cfg_.idleTimeout.count()) + " ms", CloseReason::IdleTimeout);
    });
  }

  bool send(std::string_view payload, bool force) {
    if (!open || (closing && !force)) return false;
    if (!force && queued + kFrameHeader + payload.size() > server.cfg_.maxOutput) {
      fail("not reading its output (" + std::to_string(queued) + " bytes queued)", CloseReason::OutputOverflow);
      return false;
    }
    out.push_back(frame(payload));
    queued += out.back().size();
    write();
    return true;
  }

  void write() {
    if (writing || out.empty() || !open) return;
    writing = true;
    auto self = shared_from_this();
    asio::async_write(socket, asio::buffer(out.front()), [self](const error_code& ec, std::size_t n) {
      self->writing = false;
      if (!self->open) return;
      if (ec) {
        self->finish(self->closing ? self->closeWhy : CloseReason::Error, self->closing ? self->closeDetail : ec.message());
        return;
      }
      self->server.counters_.bytesOut += n;
      self->queued -= self->out.front().size();
      self->out.pop_front();
      if (!self->out.empty()) self->write();
      else if (self->closing) self->linger();
    });
  }

  // One error frame, then close once it is written (or after a grace period if never read).
  void fail(const std::string& message, CloseReason why) {
    if (!open || closing) return;
    ++server.counters_.failed;
    closing = true;
    closeWhy = why;
    closeDetail = message;
    frameTimerArmed = false;
    idleTimer.cancel();
    // the error goes after what is queued: the answers to the frames before the mistake are the
    // client's whatever the timing (dropping them lost some, depending on which write was in
    // flight); only a client that does not read loses its queue, which it would never read
    if (why == CloseReason::OutputOverflow) {
      while (out.size() > (writing ? 1u : 0u)) {
        queued -= out.back().size();
        out.pop_back();
      }
    }
    send(server.handler_.errorPayload(message), true);
    frameTimer.expires_after(std::chrono::milliseconds(500));
    auto self = shared_from_this();
    frameTimer.async_wait([self](const error_code& e) {
      if (e || !self->open) return;
      self->finish(self->closeWhy, self->closeDetail);
    });
  }

  // The error frame is written: end our side (FIN) and read and drop what the peer still sends
  // until it closes (or the grace period ends). Closing a socket with unread input sends a reset,
  // which can destroy the error frame before the peer reads it (fuzz finding: an oversized
  // header with more bytes behind it than one read takes).
  void linger() {
    draining = true;
    error_code ignored;
    socket.shutdown(tcp::socket::shutdown_send, ignored);
    if (!reading) drain();
  }
  void drain() {
    reading = true;
    auto self = shared_from_this();
    socket.async_read_some(asio::buffer(in), [self](const error_code& ec, std::size_t n) { self->onRead(ec, n); });
  }

  void finish(CloseReason why, const std::string& detail) {
    if (!open) return;
    open = false;
    error_code ignored;
    socket.shutdown(tcp::socket::shutdown_both, ignored);
    socket.close(ignored);
    frameTimer.cancel();
    idleTimer.cancel();
    server.closed(id, why, detail);
  }
};

Server::Server(asio::io_context& io, ServerConfig cfg, Handler& handler)
    : io_(io), cfg_(std::move(cfg)), handler_(handler), impl_(std::make_unique<Impl>(io)) {
  detail::listen(impl_->acceptor, cfg_.address, cfg_.port);
  if (cfg_.handleSignals)
    detail::watchStopSignals(impl_->signals, [this](int signo) {
      signal_ = signo;
      stop();
    });
  accept();
}

Server::~Server() {
  for (auto& [id, c] : conns_) {
    error_code ignored;
    c->open = false;
    c->socket.close(ignored);
    c->frameTimer.cancel();
    c->idleTimer.cancel();
  }
}

std::uint16_t Server::port() const { return impl_->acceptor.local_endpoint().port(); }

void Server::accept() {
  impl_->acceptor.async_accept([this](const error_code& ec, tcp::socket sock) {
    if (stopping_) return;
    if (!ec) {
      error_code ignored;
      sock.set_option(tcp::no_delay(true), ignored);
      const ConnectionId id = nextId_++;
      auto c = std::make_shared<Connection>(*this, id, std::move(sock));
      const bool full = conns_.size() >= cfg_.maxConnections;
      conns_.emplace(id, c);
      if (full) {
        ++counters_.refusedFull;
        c->fail(cfg_.fullMessage.empty() ? "server full (" + std::to_string(cfg_.maxConnections) + " connections)"
                                         : cfg_.fullMessage,
                CloseReason::ServerFull);
      } else {
        ++counters_.accepted;
        handler_.onOpen(*this, id);
        c->start();
      }
    }
    // accept errors (e.g. out of descriptors) are transient: go on accepting
    accept();
  });
}

void Server::scheduleIdle() {
  if (idlePosted_) return;
  idlePosted_ = true;
  asio::post(io_, [this] {
    idlePosted_ = false;
    if (!stopping_) handler_.onIdle(*this);
  });
}

int Server::run() {
  io_.run();
  return signal_;
}

void Server::stop() {
  if (stopping_) return;
  stopping_ = true;
  error_code ignored;
  impl_->acceptor.close(ignored);
  impl_->signals.cancel(ignored);
  // copy: finish() erases from conns_
  std::vector<std::shared_ptr<Connection>> all;
  for (auto& [id, c] : conns_) all.push_back(c);
  for (auto& c : all) c->finish(CloseReason::Shutdown, "");
  io_.stop();
}

bool Server::send(ConnectionId id, std::string_view payload) {
  const auto it = conns_.find(id);
  return it != conns_.end() && it->second->send(payload, false);
}

void Server::fail(ConnectionId id, const std::string& message, CloseReason why) {
  const auto it = conns_.find(id);
  if (it != conns_.end()) it->second->fail(message, why);
}

void Server::close(ConnectionId id, CloseReason why, const std::string& detail) {
  const auto it = conns_.find(id);
  if (it != conns_.end()) it->second->finish(why, detail);
}

void Server::closed(ConnectionId id, CloseReason why, const std::string& detail) {
  if (conns_.erase(id) == 0) return;
  handler_.onClose(*this, id, why, detail);
}

}  // namespace st::net
