// st::net::WebServer: pages over HTTP, text over WebSockets, and a server that survives bad
// clients. 127.0.0.1 only, on a port the system picks; every wait bounded.
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <map>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <stnet/web_server.hpp>

#include "ws_client.hpp"

namespace st::net {
namespace {

using namespace std::chrono_literals;
using test::httpGet;
using test::WsClient;

// Serves "/" and echoes text; "fail" is refused; "stream N" sends N messages of 64 KiB, each
// once the previous is written (onDrained), as the pool server streams a shot.
struct Echo : WebHandler {
  std::atomic<int> opened{0}, closed{0};
  std::map<ConnectionId, int> toStream;
  std::vector<CloseReason> closes;  // read after the server thread joined
  HttpReply onGet(const std::string& target) override {
    if (target == "/") return {200, "text/html", "<p>the page</p>"};
    return {404, "text/plain", "no " + target};
  }
  void onOpen(WebServer&, ConnectionId) override { ++opened; }
  void onMessage(WebServer& s, ConnectionId id, std::string_view text) override {
    if (text == "fail") s.fail(id, "refused on request");
    else if (text.rfind("stream ", 0) == 0) {
      toStream[id] = std::stoi(std::string(text.substr(7)));
      onDrained(s, id);
    } else s.send(id, text);
  }
  void onDrained(WebServer& s, ConnectionId id) override {
    auto it = toStream.find(id);
    if (it == toStream.end() || it->second == 0) return;
    --it->second;
    s.send(id, std::string(64 * 1024, 'x'));
  }
  void onClose(WebServer&, ConnectionId id, CloseReason r, const std::string&) override {
    toStream.erase(id);
    closes.push_back(r);
    ++closed;
  }
};

WebConfig small() {
  WebConfig c;
  c.net.maxFrame = 1024;
  c.net.frameTimeout = 500ms;
  c.net.maxConnections = 4;
  c.net.maxOutput = 256 * 1024;
  c.net.handleSignals = false;
  c.writeTimeout = 500ms;
  return c;
}

struct Running {
  boost::asio::io_context io;
  Echo echo;
  WebServer server;
  std::thread thread;
  explicit Running(WebConfig cfg) : server(io, cfg, echo), thread([this] { server.run(); }) {}
  ~Running() { stop(); }
  void stop() {
    if (!thread.joinable()) return;
    boost::asio::post(io, [this] { server.stop(); });
    thread.join();
  }
  std::unique_ptr<WsClient> connect() {
    auto c = std::make_unique<WsClient>();
    EXPECT_TRUE(c->connect(server.port())) << c->error();
    return c;
  }
};

void expectEcho(WsClient& c, const std::string& text) {
  ASSERT_TRUE(c.send(text));
  EXPECT_EQ(c.receive().value_or("<none>"), text);
}

TEST(WebServer, ServesPagesAndEchoesOnLoopback) {
  Running r(small());
  EXPECT_EQ(httpGet(r.server.port(), "/"), std::make_pair(200u, std::string("<p>the page</p>")));
  EXPECT_EQ(httpGet(r.server.port(), "/nothing").first, 404u);
  EXPECT_EQ(httpGet(r.server.port(), "/ws").first, 426u);  // the socket's path needs an upgrade
  auto c = r.connect();
  for (int k = 0; k < 50; ++k) expectEcho(*c, "message " + std::to_string(k));
  WsClient wrongPath;
  EXPECT_FALSE(wrongPath.connect(r.server.port(), "/elsewhere"));
}

TEST(WebServer, OversizedMessageClosesThatSocketOnly) {
  Running r(small());
  auto good = r.connect();
  auto big = r.connect();
  // the server refuses the message at its first frame over the limit and closes; a client still
  // writing the rest (Beast fragments at 4 KiB) may then see its write fail and miss the close frame
  const bool sent = big->send(std::string(5000, 'y'));
  EXPECT_FALSE(big->receive().has_value());
  EXPECT_TRUE(big->closed());
  if (sent) {
    EXPECT_EQ(big->closeCode(), 1009u) << big->error();  // RFC 6455: message too big
  }
  expectEcho(*good, "still here");
  r.stop();
  EXPECT_NE(std::find(r.echo.closes.begin(), r.echo.closes.end(), CloseReason::FrameTooLong), r.echo.closes.end());
}

TEST(WebServer, GarbageOnTheSocketClosesItOthersGoOn) {
  Running r(small());
  auto good = r.connect();
  for (const std::string& garbage : {std::string("\xff\xff\xff\xff\xff\xff\xff\xff", 8), std::string("GET / HTTP/1.1\r\n\r\n"),
                                    std::string("\x81\x05hello", 7)}) {  // the last is unmasked: clients must mask
    auto bad = r.connect();
    ASSERT_TRUE(bad->sendRaw(garbage));
    EXPECT_FALSE(bad->receive().has_value());
    EXPECT_TRUE(bad->closed());
  }
  // and garbage instead of an HTTP request
  EXPECT_EQ(httpGet(r.server.port(), std::string("/\x01\x02 x")).first, 400u);
  expectEcho(*good, "still here");
}

TEST(WebServer, RefusalIsACloseFrameWithTheReason) {
  Running r(small());
  auto c = r.connect();
  expectEcho(*c, "before");
  ASSERT_TRUE(c->send("fail"));
  EXPECT_FALSE(c->receive().has_value());
  EXPECT_EQ(c->closeCode(), 1008u);  // policy violation
  EXPECT_EQ(c->closeReason(), "refused on request");
}

TEST(WebServer, ClientThatStopsReadingIsDroppedOthersGoOn) {
  Running r(small());
  auto good = r.connect();
  auto slow = r.connect();
  // 64 MiB asked for, none read: the write stalls once the socket buffers fill
  ASSERT_TRUE(slow->send("stream 1024"));
  const auto t0 = std::chrono::steady_clock::now();
  while (r.echo.closed.load() == 0 && std::chrono::steady_clock::now() - t0 < 10s) {
    expectEcho(*good, "meanwhile");
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(r.echo.closed.load(), 1);
  expectEcho(*good, "still here");
  r.stop();
  ASSERT_FALSE(r.echo.closes.empty());
  EXPECT_EQ(r.echo.closes.front(), CloseReason::OutputOverflow);
}

TEST(WebServer, StreamedPartsAllArriveForAReader) {
  Running r(small());
  auto c = r.connect();
  ASSERT_TRUE(c->send("stream 40"));  // 2.5 MiB through a 256 KiB queue bound, paced by onDrained
  for (int k = 0; k < 40; ++k) {
    const auto m = c->receive();
    ASSERT_TRUE(m.has_value()) << k;
    EXPECT_EQ(m->size(), 64u * 1024u);
  }
  expectEcho(*c, "after");
}

TEST(WebServer, ConnectionLimitRefusesTheExtraOnes) {
  Running r(small());
  std::vector<std::unique_ptr<WsClient>> held;
  for (int k = 0; k < 4; ++k) held.push_back(r.connect());
  WsClient extra;
  EXPECT_FALSE(extra.connect(r.server.port()));  // 503 instead of the upgrade
  held.pop_back();
  const auto t0 = std::chrono::steady_clock::now();
  while (r.echo.closed.load() == 0 && std::chrono::steady_clock::now() - t0 < 3s) std::this_thread::sleep_for(10ms);
  WsClient again;
  EXPECT_TRUE(again.connect(r.server.port())) << again.error();
}

// A WebSocket handshake to 127.0.0.1:port sending these Host and Origin headers: did it open?
bool handshake(std::uint16_t port, const std::string& host, const std::string& origin) {
  boost::asio::io_context io;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws(io);
  boost::beast::get_lowest_layer(ws).expires_after(3s);
  boost::beast::get_lowest_layer(ws).connect(boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), port));
  ws.set_option(boost::beast::websocket::stream_base::decorator(
      [origin](boost::beast::websocket::request_type& q) { q.set(boost::beast::http::field::origin, origin); }));
  boost::system::error_code ec;
  ws.handshake(host, "/ws", ec);
  return !ec;
}

TEST(WebServer, OtherOriginsCannotOpenASocket) {
  Running r(small());
  EXPECT_FALSE(handshake(r.server.port(), "127.0.0.1:" + std::to_string(r.server.port()), "http://evil.example"));
}

TEST(WebServer, AForeignHostIsRefusedEvenWhenOriginAgrees) {
  // DNS rebinding: a page at evil.example whose name now resolves to 127.0.0.1 sends Host and
  // Origin both evil.example; the server's own names pass
  Running r(small());
  const std::string port = std::to_string(r.server.port());
  const auto opens = [&](const std::string& host, const std::string& origin) {
    return handshake(r.server.port(), host, origin);
  };
  EXPECT_FALSE(opens("evil.example:" + port, "http://evil.example:" + port));
  EXPECT_FALSE(opens("127.0.0.1:" + std::to_string(r.server.port() + 1), "http://127.0.0.1:" + port));
  EXPECT_TRUE(opens("127.0.0.1:" + port, "http://127.0.0.1:" + port));
  EXPECT_TRUE(opens("localhost:" + port, "http://localhost:" + port));
  EXPECT_TRUE(opens("LOCALHOST:" + port, "http://LOCALHOST:" + port));
  // plain pages too: the page would be read by the foreign site's script
  EXPECT_EQ(test::httpGet(r.server.port(), "/").first, 200u);
  EXPECT_EQ(test::httpGet(r.server.port(), "/", 3000ms, "evil.example:" + port).first, 421u);
  EXPECT_EQ(test::httpGet(r.server.port(), "/", 3000ms, "[::1]:" + port).first, 200u);
}

TEST(WebServer, SigintStopsRun) {
  boost::asio::io_context io;
  Echo echo;
  WebConfig cfg = small();
  cfg.net.handleSignals = true;
  WebServer server(io, cfg, echo);
  std::thread t([] {
    std::this_thread::sleep_for(100ms);
    std::raise(SIGINT);
  });
  EXPECT_EQ(server.run(), SIGINT);
  t.join();
}

TEST(WebServer, RefusesToListenOnABadAddress) {
  boost::asio::io_context io;
  Echo echo;
  WebConfig cfg = small();
  cfg.net.address = "not-an-ip";
  EXPECT_THROW(WebServer(io, cfg, echo), std::runtime_error);
}

}  // namespace
}  // namespace st::net
