// What a hostile user may try: signals other than Ctrl-C, an output folder of an earlier
// run, a SUMO that cannot start, a missing or directory sumocfg, an impossible --traci port.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <atomic>

#include "test_util.hpp"
#include "traci_relay.hpp"

namespace st::cosim {
namespace {

using namespace st::cosim::test;
namespace fs = std::filesystem;

int stopRingWith(int sig, const fs::path& dir) {
  const auto ring = sourceDir() / "networks/ring/scenario.yaml";
  StsimProcess p({"highway", ring.string(), "--end", "36000", "--out", (dir / "out").string()}, dir);
  EXPECT_TRUE(waitForWarningRows(dir / "out/warnings.csv", p)) << p.err();
  p.signal(sig);
  const int code = p.wait();
  EXPECT_NE(p.err().find("interrupted at t = "), std::string::npos) << p.err();
  EXPECT_TRUE(validWarningsCsv(dir / "out/warnings.csv"));
  EXPECT_EQ(jsonString(slurp(dir / "out/summary.json"), "stop_reason"), "interrupted");
  return code;
}

TEST(HighwayReliability, SigtermAndSighupStopLikeCtrlC) {
  // 143 is 128 + SIGTERM (not 130, Ctrl-C's); a closed terminal (SIGHUP) stops at a whole row too, 129
  EXPECT_EQ(stopRingWith(SIGTERM, freshDir("rel_term")), 143);
  EXPECT_EQ(stopRingWith(SIGHUP, freshDir("rel_hup")), 129);
}

TEST(HighwayReliability, EveryFileInOutBelongsToThisRun) {
  const auto dir = freshDir("rel_stale");
  const fs::path out = dir / "out";
  fs::create_directories(out);
  // an earlier run's files, as a SUMO run leaves them
  std::ofstream(out / "summary.json") << "{\"stop_reason\": \"end\", \"warnings\": {\"total\": 59}}\n";
  std::ofstream(out / "collisions.csv") << "time,collider\n1,x\n";
  std::ofstream(out / "validation.json") << "{}\n";
  // a SUMO that cannot start (an option it does not know)
  std::ofstream(dir / "s.yaml") << "sumocfg: " << (sourceDir() / "networks/motorway/motorway.sumocfg").string()
                                << "\nsumo_args: [\"--no-such-option\", \"1\"]\n";
  auto r = runStsim({"highway", (dir / "s.yaml").string(), "--out", out.string()}, dir);
  EXPECT_EQ(r.code, 1) << r.err;
  const std::string summary = slurp(out / "summary.json");
  EXPECT_EQ(jsonString(summary, "stop_reason"), "error") << summary;
  EXPECT_NE(summary.find("\"error\": "), std::string::npos) << summary;
  EXPECT_FALSE(fs::exists(out / "validation.json"));
  EXPECT_EQ(lines(slurp(out / "collisions.csv")).size(), 1u);  // this run's header only
  // an FCD replay into the folder of a SUMO run leaves none of the SUMO run's files
  std::ofstream(out / "collision_warnings.csv") << "time\n";
  std::ofstream(out / "validation.json") << "{}\n";
  r = runStsim({"highway", "--fcd", (sourceDir() / "tests/data/highway/motorway_merge.fcd.xml").string(), "--net",
                (sourceDir() / "networks/motorway/motorway.net.xml").string(), "--out", out.string(), "--no-map"},
               dir);
  EXPECT_EQ(r.code, 0) << r.err;
  std::set<std::string> files;
  for (const auto& f : fs::directory_iterator(out)) files.insert(f.path().filename().string());
  EXPECT_EQ(files, (std::set<std::string>{"conflicts.csv", "events.csv", "summary.json", "warnings.csv"}));
}

TEST(HighwayReliability, SumocfgAndTraciMistakesAreNamed) {
  const auto dir = freshDir("rel_sumocfg");
  std::ofstream(dir / "s.yaml") << "seed: 1\nsumocfg: gone.sumocfg\n";
  auto r = runStsim({"highway", (dir / "s.yaml").string(), "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("s.yaml:2: sumocfg: no such file"), std::string::npos) << r.err;
  fs::create_directories(dir / "d.sumocfg");
  std::ofstream(dir / "t.yaml") << "sumocfg: d.sumocfg\n";
  r = runStsim({"highway", (dir / "t.yaml").string(), "--out", (dir / "out").string()}, dir);
  EXPECT_NE(r.err.find("t.yaml:1: sumocfg: is a directory"), std::string::npos) << r.err;
  r = runStsim({"highway", (dir / "d.sumocfg").string(), "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("d.sumocfg: is a directory"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("basic_filebuf"), std::string::npos) << r.err;
  r = runStsim({"highway", motorway().string(), "--traci", "localhost:99999", "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("PORT must be a whole number from 1 to 65535, got '99999'"), std::string::npos) << r.err;
}

// SUMO's "Error: A vehicle with id 'v00' already exists." names no file: stsim says it in one line
// naming the route file and line, exit 1, before SUMO starts
TEST(HighwayReliability, ARepeatedVehicleIdNamesTheRouteFile) {
  const auto dir = freshDir("rel_dup");
  const auto ring = sourceDir() / "networks/ring";
  fs::copy_file(ring / "ring.net.xml", dir / "ring.net.xml");
  std::string routes = slurp(ring / "ring.rou.xml");
  routes.replace(routes.find("<vehicle id=\"v01\""), 17, "<vehicle id=\"v00\"");
  std::ofstream(dir / "ring.rou.xml") << routes;
  fs::copy_file(ring / "ring.sumocfg", dir / "ring.sumocfg");
  std::ofstream(dir / "s.yaml") << "sumocfg: ring.sumocfg\nend: 10\n";
  const auto r = runStsim({"highway", (dir / "s.yaml").string(), "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
  EXPECT_NE(r.err.find((dir / "ring.rou.xml").string() + ":15: <vehicle id=\"v00\">: the id is given twice (first at line 14)"),
            std::string::npos)
      << r.err;
}

// The relay's framing checks on bytes: a reply passes only whole and only as the answer to the
// request it follows; anything else is named (fuzz/traci_relay.cpp runs the same on any bytes).
TEST(TraciRelay, FramingPassesWholeRepliesToTheirRequests) {
  TraciFraming f;
  const auto now = TraciFraming::Clock::now();
  const unsigned char getVersion[] = {0, 0, 0, 6, 2, 0};
  f.request(getVersion, 3, now);  // requests arrive in pieces too
  EXPECT_TRUE(f.pending().empty());
  f.request(getVersion + 3, 3, now);
  ASSERT_EQ(f.pending().size(), 1u);
  EXPECT_EQ(f.pending().front().command, 0x00);
  // [length 15] [status: 7, command 0x00, OK, ""] [4 bytes of payload]
  const unsigned char reply[] = {0, 0, 0, 15, 7, 0x00, 0x00, 0, 0, 0, 0, 1, 2, 3, 4};
  std::string why;
  EXPECT_EQ(f.replies(reply, 10, why), 0u);  // not whole yet
  EXPECT_EQ(why, "");
  EXPECT_FALSE(f.answered());
  EXPECT_EQ(f.replies(reply, sizeof reply, why), sizeof reply);
  EXPECT_EQ(why, "");
  EXPECT_TRUE(f.answered());
  EXPECT_TRUE(f.pending().empty());
  // a reply to nothing; then an HTTP answer to a request
  EXPECT_EQ(f.replies(reply, sizeof reply, why), 0u);
  EXPECT_EQ(why.rfind("not a TraCI server: a reply to no request", 0), 0u) << why;
  f.request(getVersion, sizeof getVersion, now);
  const std::string http = "HTTP/1.0 400 Bad request\r\n";
  why.clear();
  EXPECT_EQ(f.replies(reinterpret_cast<const unsigned char*>(http.data()), http.size(), why), 0u);
  EXPECT_EQ(why, "not a TraCI server: reply length field 1213486160 (bytes \"HTTP/1.0\")");
  // a sound reply to another command
  TraciFraming g;
  const unsigned char step[] = {0, 0, 0, 14, 10, 0x02, 0, 0, 0, 0, 0, 0, 0, 0};
  g.request(step, sizeof step, now);
  why.clear();
  EXPECT_EQ(g.replies(reply, sizeof reply, why), 0u);
  EXPECT_EQ(why, "not a TraCI server: reply to command 0x00, asked 0x02");
}

// A loopback peer that accepts one connection, reads whatever comes and never answers (an HTTP
// server waiting for its request line, a SUMO stopped with SIGSTOP). Gives up after 60 s.
class SilentPeer {
 public:
  SilentPeer() {
    listen_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    EXPECT_EQ(::bind(listen_, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    EXPECT_EQ(::listen(listen_, 1), 0);
    ::getsockname(listen_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] {
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
      int client = -1;
      char buf[4096];
      while (!stop_ && std::chrono::steady_clock::now() < until) {
        pollfd p{client >= 0 ? client : listen_, POLLIN, 0};
        if (::poll(&p, 1, 50) <= 0) continue;
        if (client < 0) client = ::accept(listen_, nullptr, nullptr);
        else if (::recv(client, buf, sizeof buf, 0) <= 0) break;
      }
      if (client >= 0) ::close(client);
    });
  }
  ~SilentPeer() {
    stop_ = true;
    thread_.join();
    ::close(listen_);
  }
  int port() const { return port_; }

 private:
  int listen_ = -1, port_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// The relay between libtraci and an attached peer: a request nobody answers ends the connection
// (it waited forever: 70 s of silence in the probe, with an HTTP server on the port).
TEST(TraciRelay, APeerThatNeverAnswersIsCutOff) {
  SilentPeer peer;
  detail::TraciRelay relay("127.0.0.1", peer.port(), 1, 0.5, 0.5);
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<std::uint16_t>(relay.localPort()));
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  // libtraci's handshake: getVersion (command 0x00) in a 6-byte frame
  const unsigned char getVersion[] = {0, 0, 0, 6, 2, 0};
  ASSERT_EQ(::send(fd, getVersion, sizeof getVersion, MSG_NOSIGNAL), static_cast<ssize_t>(sizeof getVersion));
  // the relay closes our side once the time is up; bounded wait (the test must not hang either)
  pollfd p{fd, POLLIN, 0};
  ASSERT_EQ(::poll(&p, 1, 10000), 1) << "the relay kept waiting";
  char c;
  EXPECT_LE(::recv(fd, &c, 1, 0), 0);
  ::close(fd);
  EXPECT_NE(relay.failure().find("no TraCI answer within"), std::string::npos) << relay.failure();
}

}  // namespace
}  // namespace st::cosim
