// stsim pool serve: the game protocol (PlaySession, no sockets) and the server on 127.0.0.1
// with a Beast WebSocket client: shots streamed as events equal to `stsim pool`'s, bad messages
// named by field while the game goes on, garbage, oversized frames and a client that stops
// reading. Every wait bounded.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <future>
#include <numbers>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <nlohmann/json.hpp>

#include <stio/format.hpp>
#include <stpool/report.hpp>

#include "net/ws_client.hpp"
#include "play_session.hpp"
#include "pool_server.hpp"
#include "pool_test_util.hpp"

namespace st::pool {
namespace {

using json = nlohmann::json;
using namespace std::chrono_literals;
using net::test::WsClient;

Scenario practice() {
  Scenario s = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/practice.yaml");
  s.until = 60.0;
  return s;
}

// Every part of the shot being streamed.
std::vector<json> drain(PlaySession& g) {
  std::vector<json> out;
  while (auto p = g.nextPart()) out.push_back(json::parse(*p));
  return out;
}

json one(PlaySession& g, const std::string& message) {
  const auto r = g.handle(message);
  EXPECT_EQ(r.size(), 1u) << message;
  return r.empty() ? json() : json::parse(r.front());
}

// An error naming `field`.
void expectError(PlaySession& g, const std::string& message, const std::string& field) {
  const json e = one(g, message);
  EXPECT_EQ(e.value("type", ""), "error") << message << " -> " << e.dump();
  EXPECT_EQ(e.value("field", ""), field) << message << " -> " << e.dump();
}

TEST(PlaySession, AShotStreamsTheGamesEventsBitForBit) {
  const Scenario s = practice();
  PlaySession g(s);
  ASSERT_TRUE(g.handle(R"({"type":"shoot","ball":0,"angle":0.37,"speed":7.3})").empty());
  ASSERT_TRUE(g.streaming());
  const auto parts = drain(g);
  ASSERT_GE(parts.size(), 4u);
  EXPECT_EQ(parts.front()["type"], "shot");
  EXPECT_EQ(parts[parts.size() - 2]["type"], "shot_end");
  EXPECT_EQ(parts.back()["type"], "state");
  // the same shot through the Game API, event for event and bit for bit
  Scenario ref = s;
  ref.shots = {Shot{0, 7.3 * Vec2(std::cos(0.37 * std::numbers::pi / 180.0), std::sin(0.37 * std::numbers::pi / 180.0)), -1}};
  Game game(ref, simulatorConfig(ref));
  const std::uint64_t checks0 = game.simulator().counters().pairChecks;
  const RunRecord run = playScenario(game, ref);
  std::vector<json> events;
  bool regions = false;
  for (const json& p : parts)
    if (p["type"] == "events")
      for (const json& e : p["events"]) {
        events.push_back(e);
        regions = regions || e.contains("r");
        EXPECT_LE(p.dump().size(), 64u * 1024u);
      }
  ASSERT_EQ(events.size(), run.events.size());
  for (std::size_t k = 0; k < events.size(); ++k) {
    const PoolEvent& e = run.events[k];
    ASSERT_EQ(events[k]["k"], toString(e.kind)) << k;
    EXPECT_EQ(events[k]["t"].get<double>(), e.t) << k;
    EXPECT_EQ(events[k]["p"][0].get<double>(), e.p.x()) << k;
    EXPECT_EQ(events[k]["p"][1].get<double>(), e.p.y()) << k;
    EXPECT_EQ(events[k]["v"][0].get<double>(), e.v.x()) << k;
    EXPECT_EQ(events[k]["v"][1].get<double>(), e.v.y()) << k;
  }
  EXPECT_TRUE(regions) << "version II streams its regions as they change";
  const json& end = parts[parts.size() - 2];
  EXPECT_EQ(end["ending"], "rest");
  EXPECT_EQ(end["events"].get<std::uint64_t>(), run.shots[0].events);
  EXPECT_EQ(end["checks"].get<std::uint64_t>(), game.simulator().counters().pairChecks - checks0);
}

TEST(PlaySession, BadMessagesNameTheFieldAndTheGameGoesOn) {
  PlaySession g(practice());
  expectError(g, "{\"type\":\"shoot\",", "(message)");
  expectError(g, "[1,2]", "(message)");
  expectError(g, std::string(100, '[') + std::string(100, ']'), "(message)");
  expectError(g, R"({"type":"dance"})", "type");
  expectError(g, R"({"kind":"shoot"})", "type");
  expectError(g, R"({"type":"shoot","angle":0})", "speed");
  expectError(g, R"({"type":"shoot","angle":"north","speed":1})", "angle");
  expectError(g, R"({"type":"shoot","angle":1e999,"speed":1})", "angle");  // JSON's way to say inf
  expectError(g, R"({"type":"shoot","angle":0,"speed":2000})", "speed");
  expectError(g, R"({"type":"shoot","angle":0,"speed":0})", "speed");
  expectError(g, R"({"type":"shoot","ball":77,"angle":0,"speed":1})", "ball");
  expectError(g, R"({"type":"shoot","angle":0,"speed":1,"spin":3})", "spin");
  expectError(g, R"({"type":"shoot","cue":{"from":[0,0],"to":[1]}})", "cue.to");
  expectError(g, R"({"type":"shoot","angle":0,"speed":1,"until":1e9})", "until");
  expectError(g, R"({"type":"move","ball":0,"position":[5,5]})", "position");   // off the table
  expectError(g, R"({"type":"move","ball":0,"position":[1.905,0.635]})", "position");  // onto ball 1
  expectError(g, R"({"type":"remove","ball":99})", "ball");
  expectError(g, R"({"type":"settings","version":3})", "version");
  expectError(g, R"({"type":"settings","df":0})", "df");
  expectError(g, R"({"type":"settings","friction":-1})", "friction");
  // and the game goes on: a good shot plays, and a second one while it streams is refused
  ASSERT_TRUE(g.handle(R"({"type":"shoot","angle":0,"speed":6})").empty());
  expectError(g, R"({"type":"shoot","angle":0,"speed":6})", "type");
  expectError(g, R"({"type":"move","ball":0,"position":[0.5,0.5]})", "type");
  EXPECT_EQ(drain(g).back()["type"], "state");
  EXPECT_EQ(g.shotsTaken(), 1);
}

// The page's settings (df, friction, until) are keys of the pool's settings table: refused in the
// words of the YAML and of stsim pool, and past this server's own bounds with that said.
TEST(PlaySession, SettingsSpeakTheSettingsTablesWords) {
  PlaySession g(practice());
  auto problem = [&](const std::string& message) { return one(g, message).value("message", ""); };
  EXPECT_EQ(problem(R"({"type":"settings","friction":-1})"), "must not be negative, got -1");
  EXPECT_EQ(problem(R"({"type":"settings","df":0})"), "must be in [1, 1000000000], got 0");
  EXPECT_EQ(problem(R"({"type":"settings","until":0})"), "must be positive, got 0");
  EXPECT_EQ(problem(R"({"type":"settings","until":1e9})"), "must be at most 120 s on this server");
  EXPECT_EQ(problem(R"({"type":"shoot","angle":0,"speed":1,"until":1e9})"), "must be at most 120 s on this server");
  EXPECT_EQ(problem(R"({"type":"settings","friction":20})"), "must be at most 10 m/s^2 on this server");
}

// fuzz_pool_session (fuzz/corpus/pool_session/invalid_utf8_in_error.txt): the JSON library's
// error quotes the bytes it stopped at, and a byte that is not UTF-8 went out raw: a text frame a
// browser refuses (it closes the socket), a reply no JSON reader takes. It is U+FFFD now.
TEST(PlaySession, AnErrorQuotingBytesThatAreNotUtf8IsStillUtf8) {
  PlaySession g(practice());
  for (const std::string bad : {"\xec\"type\":\"state\"}", "{\"type\":\"shoot\",\xff", "\xc0\xaf", "\xed\xa0\x80"}) {
    const auto r = g.handle(bad);
    ASSERT_EQ(r.size(), 1u);
    json e;
    ASSERT_NO_THROW(e = json::parse(r.front())) << r.front();
    EXPECT_EQ(e["type"], "error");
    EXPECT_EQ(e["field"], "(message)");
  }
  // valid UTF-8 is quoted as it is
  const json e = one(g, "{\"type\":\"tir\u00e9\"}");
  EXPECT_NE(e["message"].get<std::string>().find("tir\u00e9"), std::string::npos) << e.dump();
}

TEST(PlaySession, EditsRestartSettingsAndDownloadReplayWithTheCli) {
  PlaySession g(practice());
  // move the cue ball, add a ball, remove one, switch to version I with more friction
  EXPECT_EQ(one(g, R"({"type":"move","ball":0,"position":[0.5,0.4]})")["type"], "state");
  json st = one(g, R"({"type":"add","position":[0.3,1.0]})");
  ASSERT_EQ(st["type"], "state");
  EXPECT_EQ(st["balls"].size(), 17u);
  EXPECT_EQ(one(g, R"({"type":"remove","ball":15})")["balls"].size(), 16u);
  st = one(g, R"({"type":"settings","version":1,"friction":0.3})");
  EXPECT_EQ(st["settings"]["version"], 1);
  EXPECT_EQ(st["regions"].size(), 1u);  // one space
  ASSERT_TRUE(g.handle(R"({"type":"shoot","angle":3.1,"speed":7})").empty());
  drain(g);
  // (if the break pocketed the cue ball this is an error, and the game goes on)
  g.handle(R"({"type":"shoot","cue":{"from":[0.2,0.2],"to":[0.9,0.7],"scale":3}})");
  drain(g);
  // the download replays with the CLI to the events this game streamed
  const json d = one(g, R"({"type":"download"})");
  ASSERT_EQ(d["type"], "download");
  const auto dir = test::tempDir("serve_download");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "game.yaml") << d["yaml"].get<std::string>();
  const auto r = test::runStsim("pool " + (dir / "game.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.out;
  Scenario replay = loadScenario((dir / "game.yaml").string());
  EXPECT_EQ(replay.balls.size(), 16u);
  EXPECT_EQ(replay.space.kind, SpaceKind::Single);
  EXPECT_EQ(replay.friction, 0.3);
  EXPECT_EQ(replay.shots.size(), static_cast<std::size_t>(g.shotsTaken()));
  std::ostringstream played;
  RunRecord rec;
  Game again(replay, simulatorConfig(replay));
  rec = playScenario(again, replay);
  writeEventsCsv(played, rec, again);
  EXPECT_EQ(test::slurp(dir / "out" / "events.csv"), played.str());
  // the final positions the session shows are the CLI's last events
  const json now = one(g, R"({"type":"state"})");
  for (const json& b : now["balls"]) {
    const int h = b["h"].get<int>();
    EXPECT_EQ(b["p"][0].get<double>(), again.simulator().ball(h).p.x()) << h;
    EXPECT_EQ(b["p"][1].get<double>(), again.simulator().ball(h).p.y()) << h;
  }
  // an edit after shots starts a new layout from where the balls rest; restart brings the rack back
  st = one(g, R"({"type":"restart"})");
  EXPECT_EQ(st["balls"].size(), 16u);
  EXPECT_EQ(st["layout_shots"], 0);
  EXPECT_EQ(st["balls"][0]["p"][0].get<double>(), practice().balls[0].position.x());
  EXPECT_EQ(st["settings"]["friction"], 0.3);  // settings stay
}

TEST(PlaySession, ShotsAndBallsAreBounded) {
  SessionLimits lim;
  lim.maxShots = 2;
  lim.maxBalls = 17;
  lim.maxShotEvents = 50;
  PlaySession g(practice(), lim);
  EXPECT_EQ(one(g, R"({"type":"add","position":[0.3,1.0]})")["type"], "state");
  expectError(g, R"({"type":"add","position":[0.3,0.3]})", "type");
  // a shot needing more events than allowed is undone, and the game goes on from before it
  const json before = one(g, R"({"type":"state"})");
  expectError(g, R"({"type":"shoot","angle":0,"speed":8})", "until");
  EXPECT_FALSE(g.streaming());
  EXPECT_EQ(one(g, R"({"type":"state"})").dump(), before.dump());
  ASSERT_TRUE(g.handle(R"({"type":"shoot","angle":90,"speed":0.05})").empty());
  drain(g);
  ASSERT_TRUE(g.handle(R"({"type":"shoot","angle":-90,"speed":0.05})").empty());
  drain(g);
  expectError(g, R"({"type":"shoot","angle":0,"speed":0.05})", "type");
}

// ---- the server on 127.0.0.1

struct Served {
  boost::asio::io_context io;
  std::unique_ptr<PoolServer> server;
  std::thread thread;
  explicit Served(ServeConfig cfg) {
    cfg.web.net.port = 0;
    cfg.web.net.handleSignals = false;
    cfg.page = "<!doctype html><title>pool</title>";
    server = std::make_unique<PoolServer>(io, practice(), cfg);
    thread = std::thread([this] { server->run(); });
  }
  ~Served() {
    boost::asio::post(io, [this] { server->stop(); });
    thread.join();
  }
  // The number of games, asked on the server's thread.
  std::size_t games() {
    std::promise<std::size_t> n;
    boost::asio::post(io, [&] { n.set_value(server->games()); });
    return n.get_future().get();
  }
  std::unique_ptr<WsClient> open() {
    auto c = std::make_unique<WsClient>();
    EXPECT_TRUE(c->connect(server->port())) << c->error();
    const auto first = c->receive();
    EXPECT_TRUE(first && json::parse(*first)["type"] == "state");
    return c;
  }
};

// Messages until one of `type` (or none in time): all of them.
std::vector<json> until(WsClient& c, const std::string& type, std::chrono::milliseconds timeout = 5s) {
  std::vector<json> got;
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    const auto m = c.receive(std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now()));
    if (!m) break;
    got.push_back(json::parse(*m));
    if (got.back()["type"] == type) break;
  }
  return got;
}

// The rows of an events.csv `stsim pool` wrote: kind, time, x, y, vx, vy (printed with 17 digits,
// read back to the same doubles).
struct CsvEvent {
  std::string kind;
  double t, x, y, vx, vy;
};
std::vector<CsvEvent> readEventsCsv(const std::filesystem::path& path) {
  std::vector<CsvEvent> out;
  std::istringstream in(test::slurp(path));
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) f.push_back(cell);
    if (f.size() < 10) continue;
    out.push_back({f[2], std::stod(f[1]), std::stod(f[6]), std::stod(f[7]), std::stod(f[8]), std::stod(f[9])});
  }
  return out;
}

// practice.yaml as the served game plays it (until 60 s) with only its first shot, the break.
std::filesystem::path breakScenarioFile(const std::string& tag) {
  std::string text = test::slurp(std::string(STSIM_SOURCE_DIR) + "/models/pool/scenarios/practice.yaml");
  const auto until = text.find("until: 120.0");
  EXPECT_NE(until, std::string::npos);
  text.replace(until, 12, "until: 60.0");
  const auto second = text.find("  - ball: 0", text.find("shots:") + 14);
  const auto space = text.find("space:");
  EXPECT_TRUE(second != std::string::npos && space != std::string::npos && second < space);
  text.erase(second, space - second);
  const auto dir = test::tempDir("serve_" + tag);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "break.yaml") << text;
  return dir / "break.yaml";
}

// A shot's events as streamed, flattened.
std::vector<json> streamedEvents(const std::vector<json>& messages) {
  std::vector<json> events;
  for (const json& m : messages)
    if (m["type"] == "events")
      for (const json& e : m["events"]) events.push_back(e);
  return events;
}

TEST(PoolServe, ABreakOverTheSocketStreamsTheClisEvents) {
  // the truth: `stsim pool` on the same layout and shot, its events.csv
  const auto yaml = breakScenarioFile("socket_break");
  const auto out = yaml.parent_path() / "out";
  const auto r = test::runStsim("pool " + yaml.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::vector<CsvEvent> cli = readEventsCsv(out / "events.csv");
  ASSERT_GT(cli.size(), 100u);
  // the same break from a tab over 127.0.0.1
  Served s(defaultServeConfig());
  auto tab = s.open();
  ASSERT_TRUE(tab->send(R"({"type":"shoot","ball":0,"angle":0,"speed":8})"));
  const auto got = until(*tab, "state", 20s);
  ASSERT_FALSE(got.empty());
  ASSERT_EQ(got.back()["type"], "state");
  const std::vector<json> events = streamedEvents(got);
  ASSERT_EQ(events.size(), cli.size());
  for (std::size_t k = 0; k < cli.size(); ++k) {
    ASSERT_EQ(events[k]["k"], cli[k].kind) << k;
    EXPECT_EQ(events[k]["t"].get<double>(), cli[k].t) << k;
    EXPECT_EQ(events[k]["p"][0].get<double>(), cli[k].x) << k;
    EXPECT_EQ(events[k]["p"][1].get<double>(), cli[k].y) << k;
    EXPECT_EQ(events[k]["v"][0].get<double>(), cli[k].vx) << k;
    EXPECT_EQ(events[k]["v"][1].get<double>(), cli[k].vy) << k;
  }
}

TEST(PoolServe, FiftyTabsPlayAtOnceEachItsOwnBreak) {
  constexpr int kTabs = 50;
  // each tab breaks at its own angle; the truth for each is the same shot in a game of its own
  auto shot = [](int k) { return 0.02 * k - 0.5; };
  std::vector<std::size_t> expected(kTabs);
  for (int k = 0; k < kTabs; ++k) {
    PlaySession g(practice());
    g.handle(R"({"type":"shoot","angle":)" + io::jsonNumber(shot(k)) + R"(,"speed":8})");
    expected[k] = streamedEvents(drain(g)).size();
  }
  Served s(defaultServeConfig());
  std::vector<std::unique_ptr<WsClient>> tabs;
  for (int k = 0; k < kTabs; ++k) tabs.push_back(s.open());
  EXPECT_EQ(s.games(), static_cast<std::size_t>(kTabs));
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < kTabs; ++k)
    ASSERT_TRUE(tabs[k]->send(R"({"type":"shoot","angle":)" + io::jsonNumber(shot(k)) + R"(,"speed":8})"));
  for (int k = 0; k < kTabs; ++k) {
    const auto got = until(*tabs[k], "state", 20s);
    ASSERT_FALSE(got.empty()) << k;
    ASSERT_EQ(got.back()["type"], "state") << k;
    EXPECT_EQ(streamedEvents(got).size(), expected[k]) << k;
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 20s);
}

TEST(PoolServe, TabsPlayTheirOwnGamesAndErrorsKeepThemGoing) {
  Served s(defaultServeConfig());
  EXPECT_EQ(net::test::httpGet(s.server->port(), "/").second, "<!doctype html><title>pool</title>");
  auto a = s.open();
  auto b = s.open();
  ASSERT_TRUE(a->send(R"({"type":"move","ball":0,"position":[0.4,0.3]})"));
  ASSERT_EQ(until(*a, "state").back()["balls"][0]["p"][0], 0.4);
  ASSERT_TRUE(b->send("{not json"));
  auto e = until(*b, "error");
  ASSERT_FALSE(e.empty());
  EXPECT_EQ(e.back()["field"], "(message)");
  // both shoot; b's game did not see a's move
  ASSERT_TRUE(a->send(R"({"type":"shoot","angle":20,"speed":5})"));
  ASSERT_TRUE(b->send(R"({"type":"shoot","angle":0,"speed":7.3})"));
  const auto sa = until(*a, "state"), sb = until(*b, "state");
  ASSERT_FALSE(sa.empty());
  ASSERT_FALSE(sb.empty());
  EXPECT_EQ(sa.back()["type"], "state");
  EXPECT_EQ(sb.back()["type"], "state");
  EXPECT_EQ(sa.front()["velocity"][0].get<double>(), 5 * std::cos(20 * std::numbers::pi / 180));
  // a second shot while the first streams is refused by name (a long frictionless shot: many parts)
  ASSERT_TRUE(b->send(R"({"type":"settings","friction":0,"until":30})"));
  ASSERT_EQ(until(*b, "state").back()["type"], "state");
  ASSERT_TRUE(b->send(R"({"type":"shoot","angle":180,"speed":9})"));
  ASSERT_TRUE(b->send(R"({"type":"shoot","angle":180,"speed":9})"));
  const auto sc = until(*b, "state");
  int refused = 0;
  for (const json& m : sc) refused += m["type"] == "error" && m["field"] == "type";
  EXPECT_EQ(refused, 1);
  EXPECT_EQ(until(*b, "error", 1s).size(), 0u);
}

TEST(PoolServe, GarbageOversizedFramesAndAClientThatStopsReading) {
  ServeConfig cfg = defaultServeConfig();
  cfg.web.writeTimeout = 500ms;
  cfg.web.net.idleTimeout = 1000ms;
  Served s(cfg);
  auto good = s.open();
  {  // an oversized frame: that socket is closed (1009), the server goes on
    auto big = s.open();
    // (a client still writing the rest when the server closes may miss the close frame)
    const bool sent = big->send(std::string(20000, ' '));
    EXPECT_FALSE(until(*big, "never").size());
    EXPECT_TRUE(big->closed());
    if (sent) {
      EXPECT_EQ(big->closeCode(), 1009u) << big->error();
    }
  }
  {  // raw garbage on the socket
    auto bad = s.open();
    ASSERT_TRUE(bad->sendRaw(std::string("\x82\xff\x00\x00\x00\x00\x00\x00\x00\x10garbage", 17)));
    EXPECT_FALSE(until(*bad, "never", 2s).size() > 0 && !bad->closed());
  }
  {  // a client that shoots and never reads again (nor answers pings): its game streams one
     // part at a time, and the tab is dropped by the write timeout or the unanswered ping
    auto slow = s.open();
    ASSERT_TRUE(slow->send(R"({"type":"settings","friction":0,"until":30})"));
    ASSERT_TRUE(slow->send(R"({"type":"shoot","angle":0.5,"speed":9})"));
    const auto t0 = std::chrono::steady_clock::now();
    while (s.games() > 1 && std::chrono::steady_clock::now() - t0 < 20s) {
      ASSERT_TRUE(good->send(R"({"type":"state"})"));
      ASSERT_FALSE(until(*good, "state").empty());
      std::this_thread::sleep_for(50ms);
    }
    EXPECT_EQ(s.games(), 1u) << "the stalled tab's game is freed";
  }
  ASSERT_TRUE(good->send(R"({"type":"shoot","angle":0,"speed":6})"));
  EXPECT_EQ(until(*good, "state").back()["type"], "state");
}

TEST(PoolServe, AClosedTabFreesItsGameMidShot) {
  Served s(defaultServeConfig());
  auto keep = s.open();
  for (int k = 0; k < 5; ++k) {
    auto tab = s.open();
    ASSERT_TRUE(tab->send(R"({"type":"shoot","angle":0,"speed":9})"));
  }  // closed without reading the shot
  const auto t0 = std::chrono::steady_clock::now();
  while (s.games() > 1 && std::chrono::steady_clock::now() - t0 < 5s) std::this_thread::sleep_for(20ms);
  EXPECT_EQ(s.games(), 1u);
  ASSERT_TRUE(keep->send(R"({"type":"state"})"));
  EXPECT_FALSE(until(*keep, "state").empty());
}

}  // namespace
}  // namespace st::pool
