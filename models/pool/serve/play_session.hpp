#pragma once
// One player's game for `stsim pool serve` (the report's interactive OOSPG, §2.1.2): JSON
// messages in, JSON messages out, no sockets. A shot is played at once with stcore and its
// events are handed out in parts of bounded size (nextPart), so a page animates the event log
// and never simulates. Bad input (malformed JSON, an unknown field, a ball off the table, a
// number that is not finite, a shot while one streams) is an error message naming the field and
// the game goes on. The messages are listed in models/pool/README.md ("Playing in the browser").
#include <cstddef>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <stpool/game.hpp>
#include <stpool/scenario.hpp>

namespace st::pool {

// What one game may cost. Every message and every part is bounded by these.
struct SessionLimits {
  int maxBalls = 64;                      // on the table at once (add refuses more)
  int maxShots = 1000;                    // shots per game, restarts included
  std::size_t maxShotEvents = 200'000;    // events of one shot (a longer one is undone, with an error)
  std::size_t partBytes = 48 * 1024;      // an events message stops growing past this size
  double maxUntil = 120.0;                // s, a shot's time limit
  double maxFriction = 10.0;              // m/s^2
  int maxDecompositionFactor = 1000;
};

class PlaySession {
 public:
  // The game starts from the scenario's balls and settings (its shots are not played).
  // Throws ScenarioError if the scenario breaks a limit.
  explicit PlaySession(const Scenario& initial, SessionLimits limits = {});
  ~PlaySession();
  PlaySession(const PlaySession&) = delete;
  PlaySession& operator=(const PlaySession&) = delete;

  // Answers one message: the replies to send, in order. Never throws for bad input.
  std::vector<std::string> handle(std::string_view message);
  // The next part of the shot being streamed (events messages, then "shot_end" and the new
  // "state"); nullopt when nothing is left.
  std::optional<std::string> nextPart();
  bool streaming() const { return !parts_.empty(); }

  // {"type":"state", ...}: the table, the balls on it, the space's regions, settings, counters.
  std::string stateMessage() const;
  // The game since its last edit as a scenario (layout + shots taken since), which
  // `stsim pool` replays to the same events.
  std::string downloadYaml() const;
  const Game& game() const { return *game_; }
  int shotsTaken() const { return shotsTaken_; }

 private:
  friend struct SessionMessages;  // the message handlers (play_session.cpp), on the JSON library
  Scenario restingLayout() const;
  void rebuild(Scenario layout);

  Scenario initial_;
  SessionLimits limits_;
  Scenario layout_;               // the balls and settings since the last edit, and the shots since
  std::unique_ptr<Game> game_;
  std::deque<std::string> parts_;  // the streamed shot's messages still to hand out
  int shotsTaken_ = 0;
};

}  // namespace st::pool
