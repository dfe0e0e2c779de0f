#include <stnet/client.hpp>

#include <stdexcept>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>

#include <stnet/frame.hpp>

namespace st::net {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using boost::system::error_code;

struct Client::Impl {
  asio::io_context io;
  tcp::socket socket{io};
  std::string in;     // bytes received, not yet split
  std::size_t used = 0;
  char chunk[16384];
};

Client::Client(std::size_t maxFrame) : impl_(std::make_unique<Impl>()), maxFrame_(maxFrame) {}
Client::~Client() = default;

void Client::connect(const std::string& host, std::uint16_t port, std::chrono::milliseconds timeout) {
  const std::string where = host + ":" + std::to_string(port);
  error_code ec;
  tcp::resolver resolver(impl_->io);
  const auto eps = resolver.resolve(host, std::to_string(port), ec);
  if (ec) throw std::runtime_error(where + ": cannot resolve: " + ec.message());
  bool done = false;
  error_code result = asio::error::timed_out;
  asio::async_connect(impl_->socket, eps, [&](const error_code& e, const tcp::endpoint&) {
    done = true;
    result = e;
  });
  impl_->io.restart();
  impl_->io.run_for(timeout);
  if (!done) {
    impl_->socket.close(ec);
    impl_->io.restart();
    impl_->io.run();  // let the cancelled operation finish
    throw std::runtime_error(where + ": connect timed out");
  }
  if (result) throw std::runtime_error(where + ": cannot connect: " + result.message());
  impl_->socket.set_option(tcp::no_delay(true), ec);
  closed_ = false;
}

bool Client::connected() const { return impl_->socket.is_open() && !closed_; }

void Client::sendRaw(std::string_view bytes) {
  error_code ec;
  asio::write(impl_->socket, asio::buffer(bytes.data(), bytes.size()), ec);
  if (ec) {
    closed_ = true;
    throw std::runtime_error("send: " + ec.message());
  }
}

void Client::send(std::string_view payload) { sendRaw(frame(payload)); }

std::optional<std::string> Client::receive(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const std::string_view rest(impl_->in.data() + impl_->used, impl_->in.size() - impl_->used);
    const FrameSplit f = splitFrame(rest, maxFrame_);
    if (f.state == FrameSplit::State::Frame) {
      std::string out(f.payload);
      impl_->used += f.consumed;
      if (impl_->used == impl_->in.size()) {
        impl_->in.clear();
        impl_->used = 0;
      }
      return out;
    }
    if (f.state == FrameSplit::State::TooLong) throw std::runtime_error("receive: frame too long");
    if (closed_) return std::nullopt;
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) return std::nullopt;
    // one read, bounded by the time left
    bool done = false;
    error_code result;
    std::size_t got = 0;
    impl_->socket.async_read_some(asio::buffer(impl_->chunk), [&](const error_code& e, std::size_t n) {
      done = true;
      result = e;
      got = n;
    });
    impl_->io.restart();
    impl_->io.run_for(std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - now));
    if (!done) {
      impl_->socket.cancel();
      impl_->io.restart();
      impl_->io.run();
      if (!done || result == asio::error::operation_aborted) {
        if (got > 0) impl_->in.append(impl_->chunk, got);
        return std::nullopt;
      }
    }
    if (got > 0) {
      if (impl_->used > 0 && impl_->used == impl_->in.size()) {
        impl_->in.clear();
        impl_->used = 0;
      }
      impl_->in.append(impl_->chunk, got);
    }
    if (result && result != asio::error::operation_aborted) closed_ = true;
  }
}

void Client::close() {
  error_code ec;
  impl_->socket.shutdown(tcp::socket::shutdown_both, ec);
  impl_->socket.close(ec);
  closed_ = true;
}

}  // namespace st::net
