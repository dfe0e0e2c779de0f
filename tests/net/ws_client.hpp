#pragma once
// A WebSocket client for tests on Boost.Beast: connect, send text (or raw bytes after the
// handshake, to test a server against garbage), receive with a timeout. Every call is bounded in
// time: each runs its own io_context for at most the given duration.
#include <chrono>
#include <optional>
#include <string>
#include <string_view>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace st::net::test {

class WsClient {
 public:
  using ms = std::chrono::milliseconds;

  // Opens ws://127.0.0.1:port/path; false on failure or timeout (error() says why).
  bool connect(std::uint16_t port, const std::string& path = "/ws", ms timeout = ms(3000),
               std::size_t readMax = 64 << 20) {
    namespace beast = boost::beast;
    bool done = false;
    boost::system::error_code result;
    auto& tcp = beast::get_lowest_layer(ws_);
    const boost::asio::ip::tcp::endpoint ep(boost::asio::ip::make_address("127.0.0.1"), port);
    tcp.async_connect(ep, [&](const boost::system::error_code& ec) {
      if (ec) {
        result = ec;
        done = true;
        return;
      }
      ws_.async_handshake("127.0.0.1:" + std::to_string(port), path, [&](const boost::system::error_code& e) {
        result = e;
        done = true;
      });
    });
    ws_.read_message_max(readMax);
    if (!runUntil(done, timeout)) {
      error_ = "connect timed out";
      return false;
    }
    if (result) error_ = result.message();
    connected_ = !result;
    return connected_;
  }

  bool send(std::string_view text, ms timeout = ms(3000)) {
    bool done = false;
    boost::system::error_code result;
    ws_.text(true);
    ws_.async_write(boost::asio::buffer(text.data(), text.size()), [&](const boost::system::error_code& ec, std::size_t) {
      result = ec;
      done = true;
    });
    return runUntil(done, timeout) && !result;
  }

  // Bytes as they are on the TCP stream (not framed): garbage for the server's parser.
  bool sendRaw(std::string_view bytes, ms timeout = ms(3000)) {
    bool done = false;
    boost::system::error_code result;
    boost::asio::async_write(boost::beast::get_lowest_layer(ws_).socket(), boost::asio::buffer(bytes.data(), bytes.size()),
                             [&](const boost::system::error_code& ec, std::size_t) {
                               result = ec;
                               done = true;
                             });
    return runUntil(done, timeout) && !result;
  }

  // The next text message, or nullopt on timeout or close (then closed() is true and
  // closeReason() holds the server's reason, if it sent one).
  std::optional<std::string> receive(ms timeout = ms(3000)) {
    if (closed_) return std::nullopt;
    bool done = false;
    boost::system::error_code result;
    buffer_.consume(buffer_.size());
    ws_.async_read(buffer_, [&](const boost::system::error_code& ec, std::size_t) {
      result = ec;
      done = true;
    });
    if (!runUntil(done, timeout)) return std::nullopt;
    if (result) {
      closed_ = true;
      error_ = result.message();
      closeReason_ = ws_.reason().reason.c_str();
      closeCode_ = ws_.reason().code;
      return std::nullopt;
    }
    return boost::beast::buffers_to_string(buffer_.data());
  }

  bool closed() const { return closed_; }
  const std::string& closeReason() const { return closeReason_; }
  unsigned closeCode() const { return closeCode_; }
  const std::string& error() const { return error_; }

 private:
  // Runs the io_context until `done` or the timeout; on a timeout cancels what is pending (and
  // lets the cancellation run) so the next call starts clean.
  bool runUntil(bool& done, ms timeout) {
    io_.restart();
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done && std::chrono::steady_clock::now() < end) io_.run_one_for(end - std::chrono::steady_clock::now());
    if (done) return true;
    boost::system::error_code ignored;
    boost::beast::get_lowest_layer(ws_).socket().cancel(ignored);
    io_.restart();
    io_.run_for(ms(200));
    closed_ = true;
    return false;
  }

  boost::asio::io_context io_;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_{io_};
  boost::beast::flat_buffer buffer_;
  bool connected_ = false, closed_ = false;
  std::string error_, closeReason_;
  unsigned closeCode_ = 0;
};

// One HTTP GET on a fresh connection: status and body ("" and 0 on failure).
inline std::pair<unsigned, std::string> httpGet(std::uint16_t port, const std::string& target,
                                                std::chrono::milliseconds timeout = std::chrono::milliseconds(3000),
                                                const std::string& host = "") {
  namespace beast = boost::beast;
  namespace http = beast::http;
  boost::asio::io_context io;
  beast::tcp_stream stream(io);
  beast::flat_buffer buffer;
  http::request<http::empty_body> req(http::verb::get, target, 11);
  req.set(http::field::host, host.empty() ? "127.0.0.1:" + std::to_string(port) : host);
  http::response<http::string_body> res;
  bool ok = false;
  stream.expires_after(timeout);
  stream.async_connect(boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), port),
                       [&](const boost::system::error_code& ec) {
                         if (ec) return;
                         http::async_write(stream, req, [&](const boost::system::error_code& e, std::size_t) {
                           if (e) return;
                           http::async_read(stream, buffer, res, [&](const boost::system::error_code& r, std::size_t) { ok = !r; });
                         });
                       });
  io.run();
  return ok ? std::make_pair(res.result_int(), res.body()) : std::make_pair(0u, std::string());
}

}  // namespace st::net::test
