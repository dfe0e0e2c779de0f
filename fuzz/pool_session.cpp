// The pool page's messages (stsim pool serve): the input is lines, each one message from the
// browser to its game (pool::PlaySession), as the server hands a WebSocket text over; an empty
// line lets the socket take every part of the shot being streamed, a line "." one part (so
// messages also arrive mid-shot). The first line is also asked of the server as an HTTP target
// (PoolServer::onGet). Invariants: no exception leaves the game; every reply and part is one
// JSON object with a string "type", valid UTF-8 (a browser drops a text frame that is not), at
// most 1 MiB (the server's output bound); a message gets at most one reply; an error has a
// string "field" and a one-line "message"; a shot's parts end with shot_end and then state; a
// download is YAML that `stsim pool` reads back.
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>

#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>
#include <stpool/scenario.hpp>

#include "play_session.hpp"
#include "pool_server.hpp"

namespace {

using json = nlohmann::json;
constexpr std::size_t kMaxReply = 1 << 20;

const st::pool::Scenario& scenario() {
  static const st::pool::Scenario s = st::pool::parseScenario(st::pool::kServeDefaultScenario, "(default rack)");
  return s;
}

st::pool::PoolServer& server() {
  static boost::asio::io_context io;
  static const auto s = [] {
    st::pool::ServeConfig cfg = st::pool::defaultServeConfig();
    cfg.web.net.port = 0;  // listens, never runs: only its HTTP answers are asked
    cfg.web.net.handleSignals = false;
    cfg.page = "<!DOCTYPE html><title>pool</title>";
    return std::make_unique<st::pool::PoolServer>(io, scenario(), cfg);
  }();
  return *s;
}

// One reply or part: checked, then its type.
std::string check(const std::string& text) {
  if (text.size() > kMaxReply) std::abort();
  json j;
  try {
    j = json::parse(text);  // throws on invalid UTF-8 too
  } catch (const json::exception&) {
    std::abort();
  }
  if (!j.is_object() || !j.contains("type") || !j["type"].is_string()) std::abort();
  const std::string type = j["type"].get<std::string>();
  if (type == "error") {
    if (!j.contains("field") || !j["field"].is_string() || !j.contains("message") || !j["message"].is_string())
      std::abort();
    const std::string m = j["message"].get<std::string>();
    if (m.empty() || m.find('\n') != std::string::npos || m.find('\r') != std::string::npos) std::abort();
  } else if (type == "download") {
    try {
      (void)st::pool::parseScenario(j.at("yaml").get<std::string>(), "download.yaml");
    } catch (const std::exception&) {
      std::abort();  // the game's download must replay
    }
  }
  return type;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view in(reinterpret_cast<const char*>(data), size);
  st::pool::SessionLimits limits;
  limits.maxShotEvents = 20'000;  // a shot stays cheap; the undo path is played more often
  limits.maxShots = 50;
  st::pool::PlaySession game(scenario(), limits);
  std::string last;  // the type of the last part handed out
  auto take = [&](bool all) {
    while (auto p = game.nextPart()) {
      const std::string type = check(*p);
      if (last == "shot_end" && type != "state") std::abort();
      last = type;
      if (!all) break;
    }
    if (!game.streaming() && !last.empty() && last != "state") std::abort();
  };
  bool first = true;
  while (true) {
    const std::size_t eol = in.find('\n');
    const std::string_view line = in.substr(0, eol);
    if (first) {
      const auto reply = server().onGet(std::string(line));
      if (reply.body.size() > kMaxReply) std::abort();
      first = false;
    }
    if (line.empty()) take(true);
    else if (line == ".") take(false);
    else {
      const bool wasStreaming = game.streaming();
      const auto replies = game.handle(line);
      if (replies.size() > 1) std::abort();
      for (const auto& r : replies) check(r);
      if (!wasStreaming && game.streaming()) last.clear();  // a new shot
    }
    if (eol == std::string_view::npos) break;
    in.remove_prefix(eol + 1);
  }
  take(true);
  return 0;
}
