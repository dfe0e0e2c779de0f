#pragma once
// One highway run, whatever feeds it: frames of vehicle states from a source (an FCD trace, a
// test, Python) stepped through the monitor, every output written in one place: the tick files
// (TickFiles), summary.json and the conflict map. On an error it closes what is open, writes
// everything so far (summary.json with the error), then rethrows. Prints nothing.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <sthighway/conflict_map.hpp>
#include <sthighway/frame_source.hpp>
#include <sthighway/monitor.hpp>
#include <sthighway/report.hpp>

namespace st::highway {

struct DriveSetup {
  std::filesystem::path out = ".";
  bool trajectories = false;  // trajectories.csv
  std::optional<double> end;  // s: the run ends before the first frame after it
  // Below 1: each vehicle is a smart car with this probability, drawn from seed and id
  // (drawnEquipped, as a SUMO run draws); persons on foot are foes, never equipped.
  double penetration = 1.0;
  std::uint64_t seed = 42;
  std::string source;              // summary.json's source: the trace
  std::filesystem::path net;       // the network: summary.json's net, the map's roads
  std::optional<std::string> map;  // the conflict map's title; none: no map
  std::chrono::steady_clock::time_point wallStart = std::chrono::steady_clock::now();
};

struct DriveResult {
  RunInfo info;                            // as summary.json has it
  std::optional<ConflictMapOutcome> map;   // whether the map was drawn (none: not asked)
};

// Runs the frames through the monitor to the source's end or setup.end. Throws
// std::runtime_error when the outputs cannot be written; an error of the source or the monitor
// is rethrown after everything so far is written. The map is drawn only after a whole run.
DriveResult driveRun(FrameSource& source, HighwayMonitor& monitor, const DriveSetup& setup);

}  // namespace st::highway
