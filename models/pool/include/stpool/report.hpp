#pragma once
#include <functional>
// What a run leaves behind: the event log, a JSON summary, the final table as SVG (with the space's
// regions drawn, like the report's Fig. 7) and a self-contained HTML animation. Writers take
// streams; the caller opens files.
#include <ostream>
#include <string>
#include <vector>

#include <stpool/game.hpp>

namespace st::pool {

// Everything one scenario run produced.
struct RunRecord {
  std::string scenario;                   // its name
  std::string spaceDescription;           // e.g. "tree df=5 divisions=4"
  std::vector<BallSpec> initial;          // balls as placed before the first shot
  std::vector<PoolEvent> events;
  std::vector<ShotSummary> shots;
  double wallSeconds = 0.0;
  std::string error;                      // non-empty if the run stopped on an error
  bool eventLimitReached = false;         // it stopped at playScenario's maxEvents
};

// Plays every shot of the scenario in order (or lets the balls coast if it has none), recording
// events. A run-time failure (a shot at a pocketed ball) ends the run: it is kept in `error` and
// what was computed before it stays in the record. `untilOverride` > 0 replaces every time limit.
// The work a run may do is bounded: past maxEvents recorded events (at most kMaxEvents: hundreds
// of MB of record and events.csv) the run stops with an error naming `until` and
// eventLimitReached set. stopRequested, if given, is polled at every event; true stops the run
// with error "interrupted at t = ... s" (results so far kept).
inline constexpr std::size_t kMaxEvents = 2'000'000;
RunRecord playScenario(Game& game, const Scenario& scenario, double untilOverride = -1.0,
                       const std::function<bool()>& stopRequested = {}, std::size_t maxEvents = kMaxEvents);

// "tree df=5 divisions=4", "single", ...
std::string describe(const SpaceSpec& space);

void writeEventsCsv(std::ostream& os, const RunRecord& run, const Game& game);
void writeSummaryJson(std::ostream& os, const RunRecord& run, const Game& game);
void writeTableSvg(std::ostream& os, const Game& game, const std::string& title);
void writeAnimationHtml(std::ostream& os, const RunRecord& run, const Game& game);

// Counts of events of each kind.
std::vector<std::uint64_t> eventCounts(const std::vector<PoolEvent>& events);

}  // namespace st::pool
