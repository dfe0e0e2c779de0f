#include <stnet/web_server.hpp>

#include <cctype>
#include <deque>
#include <optional>
#include <stdexcept>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "listen.hpp"

namespace st::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using boost::system::error_code;

struct WebServer::Impl {
  tcp::acceptor acceptor;
  asio::signal_set signals;
  explicit Impl(asio::io_context& io) : acceptor(io), signals(io) {}
};

namespace {

// "http://host:port" -> "host:port"; a page served by us opens its socket from our own origin.
bool sameOrigin(std::string_view origin, std::string_view host) {
  const auto scheme = origin.find("://");
  if (scheme != std::string_view::npos) origin.remove_prefix(scheme + 3);
  return origin == host;
}

// A Host header naming this server: an IP literal ("127.0.0.1", "[::1]") or "localhost", with
// our port (or none only on port 80). A browser sends the name it resolved: a foreign name that
// resolves to us (DNS rebinding) is refused, whatever Origin says, since Origin then matches it.
bool ourHost(std::string_view host, std::uint16_t port) {
  std::string_view name = host, portText;
  if (!host.empty() && host.front() == '[') {
    const auto close = host.find(']');
    if (close == std::string_view::npos) return false;
    name = host.substr(1, close - 1);
    if (close + 1 < host.size()) {
      if (host[close + 1] != ':') return false;
      portText = host.substr(close + 2);
    }
  } else if (const auto colon = host.rfind(':'); colon != std::string_view::npos) {
    name = host.substr(0, colon);
    portText = host.substr(colon + 1);
  }
  if (portText.empty() ? port != 80 : portText != std::to_string(port)) return false;
  std::string lower(name);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "localhost") return true;
  boost::system::error_code ec;
  asio::ip::make_address(lower, ec);
  return !ec;
}

}  // namespace

// One open WebSocket: one read in flight, one write in flight, the rest queued (bounded).
struct WebServer::Socket : std::enable_shared_from_this<Socket> {
  WebServer& server;
  ConnectionId id;
  websocket::stream<beast::tcp_stream> ws;
  beast::flat_buffer in;
  std::deque<std::string> out;
  std::size_t queued = 0;
  asio::steady_timer writeTimer;
  bool opened = false;   // the handshake succeeded: the handler knows it
  bool open = true;      // the server still counts it
  bool writing = false;
  bool closing = false;  // a close frame goes out once the write in flight ends
  std::string closeMessage;
  CloseReason closeWhy = CloseReason::Refused;
  http::request<http::string_body> upgrade;  // kept until the handshake is answered

  Socket(WebServer& s, ConnectionId i, tcp::socket sock)
      : server(s), id(i), ws(std::move(sock)), writeTimer(s.io_) {}

  void accept(http::request<http::string_body> req) {
    upgrade = std::move(req);
    // the stream's own timeouts take over from the HTTP request's
    beast::get_lowest_layer(ws).expires_never();
    websocket::stream_base::timeout t{};
    t.handshake_timeout = server.cfg_.net.frameTimeout;
    t.idle_timeout = server.cfg_.net.idleTimeout.count() > 0
                         ? std::chrono::duration_cast<websocket::stream_base::duration>(server.cfg_.net.idleTimeout)
                         : websocket::stream_base::none();
    t.keep_alive_pings = true;  // an idle browser tab answers pings; a dead peer does not
    ws.set_option(t);
    ws.read_message_max(server.cfg_.net.maxFrame);
    ws.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& r) { r.set(http::field::server, "stsim"); }));
    auto self = shared_from_this();
    ws.async_accept(upgrade, [self](const error_code& ec) {
      if (!self->open) return;
      if (ec) {
        self->finish(CloseReason::Error, "handshake: " + ec.message());
        return;
      }
      self->opened = true;
      self->server.handler_.onOpen(self->server, self->id);
      self->read();
    });
  }

  void read() {
    if (!open) return;
    auto self = shared_from_this();
    ws.async_read(in, [self](const error_code& ec, std::size_t n) {
      if (!self->open) return;
      if (ec) {
        if (ec == websocket::error::closed || ec == asio::error::eof || ec == asio::error::connection_reset)
          self->finish(CloseReason::PeerClosed, "");
        else if (ec == websocket::error::message_too_big)
          self->finish(CloseReason::FrameTooLong, "message over " + std::to_string(self->server.cfg_.net.maxFrame) + " bytes");
        else if (ec == beast::error::timeout)
          self->finish(CloseReason::IdleTimeout, "no answer to a ping");
        else
          self->finish(CloseReason::Error, ec.message());
        return;
      }
      self->server.counters_.bytesIn += n;
      ++self->server.counters_.messages;
      const std::string text = beast::buffers_to_string(self->in.data());
      self->in.consume(self->in.size());
      if (!self->closing) self->server.handler_.onMessage(self->server, self->id, text);
      self->read();
    });
  }

  bool send(std::string_view text) {
    if (!open || closing) return false;
    if (queued + text.size() > server.cfg_.net.maxOutput) {
      finish(CloseReason::OutputOverflow, "not reading its output (" + std::to_string(queued) + " bytes queued)");
      return false;
    }
    out.emplace_back(text);
    queued += text.size();
    write();
    return true;
  }

  void write() {
    if (writing || out.empty() || !open) return;
    writing = true;
    ws.text(true);
    // a peer that stops reading stalls the write once its receive window fills: drop it then
    writeTimer.expires_after(server.cfg_.writeTimeout);
    auto self = shared_from_this();
    writeTimer.async_wait([self](const error_code& e) {
      if (e || !self->open || !self->writing) return;
      self->finish(CloseReason::OutputOverflow,
                   "a write stalled for " + std::to_string(self->server.cfg_.writeTimeout.count()) + " ms");
    });
    ws.async_write(asio::buffer(out.front()), [self](const error_code& ec, std::size_t n) {
      self->writing = false;
      self->writeTimer.cancel();
      if (!self->open) return;
      if (ec) {
        self->finish(CloseReason::Error, ec.message());
        return;
      }
      self->server.counters_.bytesOut += n;
      self->queued -= self->out.front().size();
      self->out.pop_front();
      if (self->closing) self->sendClose();
      else if (!self->out.empty()) self->write();
      else self->server.handler_.onDrained(self->server, self->id);
    });
  }

  // A close frame with the reason (policy violation), after the write in flight.
  void fail(const std::string& message, CloseReason why) {
    if (!open || closing) return;
    ++server.counters_.failed;
    closing = true;
    closeWhy = why;
    closeMessage = message;
    while (out.size() > (writing ? 1u : 0u)) {
      queued -= out.back().size();
      out.pop_back();
    }
    if (!writing) sendClose();
  }

  void sendClose() {
    // a close reason is at most 123 bytes (RFC 6455 5.5)
    websocket::close_reason reason(websocket::close_code::policy_error, closeMessage.substr(0, 120));
    auto self = shared_from_this();
    ws.async_close(reason, [self](const error_code&) { self->finish(self->closeWhy, self->closeMessage); });
  }

  void finish(CloseReason why, const std::string& detail) {
    if (!open) return;
    open = false;
    error_code ignored;
    auto& sock = beast::get_lowest_layer(ws).socket();
    sock.shutdown(tcp::socket::shutdown_both, ignored);
    sock.close(ignored);
    writeTimer.cancel();
    server.closed(id, why, opened ? detail : std::string());
  }
};

// One HTTP request: a GET answered by the handler and closed, or an upgrade handed to a Socket.
struct WebServer::HttpSession : std::enable_shared_from_this<HttpSession> {
  WebServer& server;
  beast::tcp_stream stream;
  beast::flat_buffer buffer;
  std::optional<http::request_parser<http::string_body>> parser;
  http::response<http::string_body> res;

  HttpSession(WebServer& s, tcp::socket sock) : server(s), stream(std::move(sock)) { ++server.httpSessions_; }
  ~HttpSession() { --server.httpSessions_; }

  void start() {
    parser.emplace();
    parser->header_limit(static_cast<std::uint32_t>(server.cfg_.maxRequest));
    parser->body_limit(server.cfg_.maxRequest);
    // the whole request within frameTimeout: a client trickling bytes holds no slot for long
    stream.expires_after(server.cfg_.net.frameTimeout);
    auto self = shared_from_this();
    http::async_read(stream, buffer, *parser, [self](const error_code& ec, std::size_t n) { self->onRead(ec, n); });
  }

  void onRead(const error_code& ec, std::size_t n) {
    if (server.stopping_) return;
    server.counters_.bytesIn += n;
    if (ec == beast::error::timeout || ec == http::error::end_of_stream || ec == asio::error::eof) return close();
    if (ec) return reply(ec == http::error::header_limit ? 431 : 400, "bad request: " + ec.message() + "\n");
    ++server.counters_.requests;
    http::request<http::string_body>& req = parser->get();
    const std::string target(req.target().data(), req.target().size());
    const auto hostField = req[http::field::host];
    if (!ourHost(std::string_view(hostField.data(), hostField.size()), server.port()))
      return reply(421, "not this server: Host must be its address or localhost with its port\n");
    if (websocket::is_upgrade(req)) {
      if (target != server.cfg_.wsPath) return reply(404, "no WebSocket at " + target + "\n");
      const auto origin = req[http::field::origin];
      const auto host = req[http::field::host];
      if (!origin.empty() && !sameOrigin(std::string_view(origin.data(), origin.size()), std::string_view(host.data(), host.size())))
        return reply(403, "WebSocket from another origin\n");
      if (server.sockets_.size() >= server.cfg_.net.maxConnections) {
        ++server.counters_.refusedFull;
        return reply(503, "server full (" + std::to_string(server.cfg_.net.maxConnections) + " games)\n");
      }
      const ConnectionId id = server.nextId_++;
      auto s = std::make_shared<Socket>(server, id, stream.release_socket());
      server.sockets_.emplace(id, s);
      s->accept(parser->release());
      return;
    }
    if (req.method() != http::verb::get && req.method() != http::verb::head) return reply(405, "only GET\n");
    if (target == server.cfg_.wsPath) return reply(426, "WebSocket upgrade required\n");
    HttpReply r = server.handler_.onGet(target);
    res.result(r.status);
    res.set(http::field::content_type, r.contentType);
    res.set(http::field::cache_control, "no-store");
    res.body() = req.method() == http::verb::head ? std::string() : std::move(r.body);
    send();
  }

  void reply(unsigned status, std::string body) {
    res.result(status);
    res.set(http::field::content_type, "text/plain; charset=utf-8");
    res.body() = std::move(body);
    send();
  }

  void send() {
    res.version(11);
    res.set(http::field::server, "stsim");
    res.keep_alive(false);
    res.prepare_payload();
    stream.expires_after(server.cfg_.writeTimeout);
    auto self = shared_from_this();
    http::async_write(stream, res, [self](const error_code&, std::size_t n) {
      self->server.counters_.bytesOut += n;
      self->close();
    });
  }

  void close() {
    error_code ignored;
    stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
    stream.close();
  }
};

WebServer::WebServer(asio::io_context& io, WebConfig cfg, WebHandler& handler)
    : io_(io), cfg_(std::move(cfg)), handler_(handler), impl_(std::make_unique<Impl>(io)) {
  detail::listen(impl_->acceptor, cfg_.net.address, cfg_.net.port);
  if (cfg_.net.handleSignals)
    detail::watchStopSignals(impl_->signals, [this](int signo) {
      signal_ = signo;
      stop();
    });
  accept();
}

WebServer::~WebServer() {
  for (auto& [id, s] : sockets_) {
    error_code ignored;
    s->open = false;
    beast::get_lowest_layer(s->ws).socket().close(ignored);
    s->writeTimer.cancel();
  }
}

std::uint16_t WebServer::port() const { return impl_->acceptor.local_endpoint().port(); }

void WebServer::accept() {
  impl_->acceptor.async_accept([this](const error_code& ec, tcp::socket sock) {
    if (stopping_) return;
    if (!ec) {
      error_code ignored;
      sock.set_option(tcp::no_delay(true), ignored);
      // requests in progress are bounded too: past the limit a connection is closed unread
      if (httpSessions_ + sockets_.size() >= 2 * cfg_.net.maxConnections) {
        ++counters_.refusedFull;
        sock.close(ignored);
      } else {
        ++counters_.accepted;
        std::make_shared<HttpSession>(*this, std::move(sock))->start();
      }
    }
    // accept errors (e.g. out of descriptors) are transient: go on accepting
    accept();
  });
}

int WebServer::run() {
  io_.run();
  return signal_;
}

void WebServer::stop() {
  if (stopping_) return;
  stopping_ = true;
  error_code ignored;
  impl_->acceptor.close(ignored);
  impl_->signals.cancel(ignored);
  std::vector<std::shared_ptr<Socket>> all;
  for (auto& [id, s] : sockets_) all.push_back(s);
  for (auto& s : all) s->finish(CloseReason::Shutdown, "");
  io_.stop();
}

bool WebServer::send(ConnectionId id, std::string_view text) {
  const auto it = sockets_.find(id);
  if (it == sockets_.end()) return false;
  const auto s = it->second;  // send may drop it from the map
  return s->opened && s->send(text);
}

std::size_t WebServer::queued(ConnectionId id) const {
  const auto it = sockets_.find(id);
  return it == sockets_.end() ? 0 : it->second->queued;
}

void WebServer::fail(ConnectionId id, const std::string& message, CloseReason why) {
  const auto it = sockets_.find(id);
  if (it == sockets_.end()) return;
  const auto s = it->second;
  s->fail(message, why);
}

void WebServer::closed(ConnectionId id, CloseReason why, const std::string& detail) {
  const auto it = sockets_.find(id);
  if (it == sockets_.end()) return;
  const bool opened = it->second->opened;
  sockets_.erase(it);
  if (opened) handler_.onClose(*this, id, why, detail);
}

}  // namespace st::net
