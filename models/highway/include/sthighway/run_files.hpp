#pragma once
// The files a highway run writes tick by tick, whatever drives it (an FCD replay, SUMO, a test):
// warnings.csv, conflicts.csv, events.csv, and optionally trajectories.csv and exposure.csv,
// streamed so a run that stops early leaves valid files (every write checked, st::io).
#include <filesystem>
#include <optional>
#include <vector>

#include <sthighway/monitor.hpp>
#include <sthighway/report.hpp>

namespace st::highway {

struct TickFileOptions {
  bool trajectories = false;  // trajectories.csv (the monitor must record them: recordTrajectories)
  bool exposure = false;      // exposure.csv: vehicle-km and vehicles seen up to each tick
};

class TickFiles {
 public:
  // Creates `out`, removes what an earlier run wrote there (removeRunOutputs: every file in it
  // belongs to this run), then opens the files.
  TickFiles(const std::filesystem::path& out, TickFileOptions options);
  // What the monitor finished since the last call: warnings, conflicts, hindsight's events, the
  // trajectories; the exposure at its last tick.
  void write(HighwayMonitor& monitor);
  void flush();
  // Every vehicle warning written so far (SUMO's collisions' warning lead times).
  const std::vector<Warning>& vehicleWarnings() const { return vehicleWarnings_; }

 private:
  WarningsCsvWriter warnings_;
  ConflictsCsvWriter conflicts_;
  EventsCsvWriter events_;
  std::optional<TrajectoriesCsvWriter> series_;
  std::optional<CsvRowWriter> exposure_;
  double exposureTime_ = -1.0;
  std::vector<Warning> vehicleWarnings_;
  // one buffer each for every tick
  std::vector<Warning> finished_;
  std::vector<Conflict> conflictBuffer_;
  std::vector<HindsightEvent> eventBuffer_;
  std::vector<TrajectoryPoint> seriesBuffer_;
};

}  // namespace st::highway
