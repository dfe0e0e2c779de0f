#pragma once
// A pool scenario: table, balls, shots, space and run limits, read from YAML (models/pool/README.md
// documents every key; docs/pool_settings.md the settings among them, stpool/settings.hpp).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <stcore/simulator.hpp>
#include <stpool/ball.hpp>
#include <stpool/settings.hpp>
#include <stpool/table.hpp>

namespace st::pool {

// A cue strike (§2.3). The struck ball's new velocity is `velocity`; loadScenario derives it
// from a cue vector (velocity = scale * (to - from), as the report's cue) or from speed + angle.
struct Shot {
  int ball = 0;                 // ball number (0: the cue ball)
  Vec2 velocity = Vec2::Zero(); // m/s
  double until = -1.0;          // s, this shot's time limit; < 0: the scenario's `until`
};

struct SpaceSpec {
  SpaceKind kind = SpaceKind::Tree;
  int decompositionFactor = 5;
  bool autoFactor = false;  // decomposition_factor: auto (SpaceRule::autoFactor)
  int divisions = 4;
  int maxDepth = -1;      // -1: deepest level whose regions are still at least one ball across
  double cellSize = 0.1;  // m, Cells kind only
  // Cells only: the fat-box margin, as a fraction of each ball's radius
  // (SimulatorConfig::marginFactor); a ball is re-filed when its box reaches a cell outside the
  // block its grown box touches. <= 0: automatic, 0.5. (A tree lists each ball by its own box and
  // takes its region events from the leaf walls: no margin.)
  double margin = -1.0;
  double marginFactor() const { return margin > 0.0 ? margin : 0.5; }
};

struct Scenario {
  std::string name;
  TableSpec table;
  std::vector<BallSpec> balls;   // simulator handles are indices into this list
  std::vector<Shot> shots;       // played in order, each from the state the previous one left
  SpaceSpec space;
  double until = 10.0;           // s, time limit of each shot
  double friction = 0.0;         // m/s^2, rolling-resistance deceleration (0: the report's frictionless table)
  std::uint64_t seed = 1;
};

// A scenario the loader rejected. what() is one line: "FILE:LINE:COL: KEY: problem".
struct ScenarioError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The scenario of a file, with the command line's settings over the file's (stpool/settings.hpp).
// A bad value in the file throws ScenarioError; a bad override, SettingError naming its key (the
// front end names the option that gave it).
Scenario loadScenario(const std::string& path, const std::vector<SettingOverride>& overrides = {});
// Same from YAML text; `source` names it in messages.
Scenario parseScenario(const std::string& yamlText, const std::string& source,
                       const std::vector<SettingOverride>& overrides = {});

// Rejects a scenario whose balls overlap, leave the table, have non-positive size, share a
// number, or whose shots name a missing ball. `source` prefixes messages. Throws ScenarioError.
void validateScenario(const Scenario& s, const std::string& source);

}  // namespace st::pool
