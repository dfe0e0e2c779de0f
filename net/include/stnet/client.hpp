#pragma once
// A framed TCP client on Boost.Asio for tools and tests: connect, send frames (or raw bytes, to
// test a server against garbage), receive frames with a timeout. Blocking calls, each bounded
// in time; its own io_context, one thread.
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace st::net {

class Client {
 public:
  explicit Client(std::size_t maxFrame = 1 << 20);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Throws std::runtime_error naming host:port on failure or timeout.
  void connect(const std::string& host, std::uint16_t port, std::chrono::milliseconds timeout = std::chrono::seconds(5));
  void send(std::string_view payload);     // one frame; throws if the connection is gone
  void sendRaw(std::string_view bytes);    // bytes as they are
  // The next frame, or nullopt when none arrives in time or the peer closed (then closed() is true).
  std::optional<std::string> receive(std::chrono::milliseconds timeout);
  bool closed() const { return closed_; }
  bool connected() const;
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::size_t maxFrame_;
  bool closed_ = false;
};

}  // namespace st::net
