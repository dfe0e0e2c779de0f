// st::net's server (stnet/server.hpp) over a real loopback connection: the input is cut into
// chunks ([u8 n] [n bytes] ...), written one after the other; the server splits frames out of
// them and an echo handler sends each back (a payload starting with '!' is refused instead).
// What comes back must be what splitFrame() makes of the whole stream in one piece: the same
// frames in order, then for a frame over the limit or a refused one the single error frame
// and the end of the connection. A lost, extra, reordered or cut frame is a finding, as is a
// server that never answers (2 s).
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include <boost/asio/io_context.hpp>
#include <stnet/frame.hpp>
#include <stnet/server.hpp>

namespace {

constexpr std::size_t kMaxFrame = 64;

struct Echo final : st::net::Handler {
  void onFrame(st::net::Server& s, st::net::ConnectionId id, std::string_view payload) override {
    if (!payload.empty() && payload[0] == '!') s.fail(id, "refused");
    else s.send(id, payload);
  }
};

struct Fixture {
  boost::asio::io_context io;
  Echo echo;
  st::net::Server server;
  static st::net::ServerConfig config() {
    st::net::ServerConfig c;
    c.maxFrame = kMaxFrame;
    c.handleSignals = false;
    return c;
  }
  Fixture() : server(io, config(), echo) {}
};

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "stnet_server: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Fixture fx;
  // what the server must send back: splitFrame over the whole stream at once
  std::string stream;
  for (std::size_t i = 0; i < size;) {
    const std::size_t n = std::min<std::size_t>(data[i], size - i - 1);
    stream.append(reinterpret_cast<const char*>(data + i + 1), n);
    i += 1 + n;
  }
  std::string expected;
  bool closes = false;
  for (std::string_view rest = stream; !closes;) {
    const st::net::FrameSplit f = st::net::splitFrame(rest, kMaxFrame);
    if (f.state == st::net::FrameSplit::State::NeedMore) break;
    if (f.state == st::net::FrameSplit::State::TooLong) {
      st::net::appendFrame(expected, "error: frame of " + std::to_string(f.length) + " bytes exceeds the limit of " +
                                         std::to_string(kMaxFrame) + " bytes");
      closes = true;
    } else if (!f.payload.empty() && f.payload[0] == '!') {
      st::net::appendFrame(expected, "error: refused");
      closes = true;
    } else {
      st::net::appendFrame(expected, f.payload);
      rest.remove_prefix(f.consumed);
    }
  }

  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(fx.server.port());
  ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);  // EINPROGRESS: done once accepted
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  std::string got;
  bool eof = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  // what is ready now (loopback delivers at once); waiting, a short wait when nothing was
  auto pump = [&](bool wait) {
    fx.io.restart();
    if (fx.io.poll() == 0 && wait) {
      fx.io.restart();
      fx.io.run_for(std::chrono::microseconds(100));
    }
    char buf[4096];
    for (;;) {
      const ssize_t k = ::recv(fd, buf, sizeof buf, 0);
      if (k > 0) got.append(buf, static_cast<std::size_t>(k));
      if (k == 0 || (k < 0 && errno != EAGAIN && errno != EINTR)) eof = true;  // closed, or reset
      if (k <= 0) break;
    }
    if (std::chrono::steady_clock::now() > deadline) finding("no answer within 2 s");
  };
  while (fx.server.connections() == 0) pump(true);
  for (std::size_t i = 0; i < size && !eof;) {
    const std::size_t n = std::min<std::size_t>(data[i], size - i - 1);
    for (std::size_t sent = 0; sent < n && !eof;) {
      const ssize_t k = ::send(fd, data + i + 1 + sent, n - sent, MSG_NOSIGNAL);
      if (k > 0) sent += static_cast<std::size_t>(k);
      else if (k < 0 && errno != EAGAIN) eof = true;  // the server closed: what it sent is in got
      pump(k <= 0);
    }
    i += 1 + n;
    pump(false);
  }
  while (got.size() < expected.size() && !eof) pump(true);
  if (closes)
    while (!eof) pump(true);
  if (got != expected) {
    std::fprintf(stderr, "stnet_server: got %zu bytes, expected %zu%s\n", got.size(), expected.size(),
                 eof ? " (closed)" : "");
    finding("the frames sent back differ from splitFrame's");
  }
  if (eof && !closes) finding("closed a connection that kept to the protocol");
  ::close(fd);
  while (fx.server.connections() > 0) pump(true);
  return 0;
}
