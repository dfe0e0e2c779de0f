#pragma once
// The rates a highway study reports, one definition each, as every table of the batch shows them:
// a run's rate is its conflicts (conflicts.csv, counted once, of an SSAM type, begun at or after
// the warm-up) over its exposure after the warm-up; a combination's is the mean of its runs' rates
// over the seeds (summary.csv), a comparison's the mean of the seed-by-seed differences of the
// runs' rates (paired.csv). The exposure after the warm-up comes from the run's exposure.csv.
#include <filesystem>
#include <string>
#include <vector>

#include <stbatch/experiment.hpp>
#include <stbatch/run_result.hpp>

namespace st::batch {

// A run's exposure after the warm-up.
struct Exposure {
  double vehicleKm = 0.0;         // distance driven by every vehicle
  double hours = 0.0;             // simulated time
  double enteringVehicles = 0.0;  // vehicles first seen
};

// The exposure of a done highway run from the figures of its summary.json (vehicle_km, vehicles,
// simulated_s) less, for a warm-up, exposure.csv's last row at or before it. Throws
// std::runtime_error naming the file when the warm-up needs exposure.csv and the run has none,
// or when the warm-up is not shorter than the run.
Exposure runExposure(const RunResult& r, const std::filesystem::path& runDir, double warmup);

// Adds to each done highway run's metrics (as runs.csv, summary.csv and paired.csv then show them):
//   exposure.vehicle_km, exposure.hours, exposure.entering_vehicles
//   counted.<type>                      conflicts after the warm-up
//   rate.per_vehicle_km.<type>, rate.per_hour.<type>, rate.per_entering_vehicle.<type>
// for <type> all, rear_end, lane_change, crossing. A run without conflicts.csv gets none; a rate
// over no exposure is NaN (an empty cell).
void addRates(const Experiment& e, std::vector<RunResult>& results, const std::filesystem::path& outDir);

// With a warm-up, adds to each done highway run's metrics hindsight's figures of the warnings and
// events after it, under summary.json's names with "after_warmup." before them (what hindsight.csv
// then reads): per warning kind warnings.by_kind.<kind> and hindsight.by_kind.<kind>.judged and
// .confirmed (warnings.csv's rows begun at or after the warm-up), hindsight.near_misses.* and
// hindsight.crossings.* (events.csv's rows at or after it) and, for a run that counts them,
// collisions.* (collision_warnings.csv's), each as events, warned (the lead time ahead) and
// lead_s.median. Throws std::runtime_error naming the file and line of a broken row.
void addWarnedAfterWarmup(const Experiment& e, std::vector<RunResult>& results, const std::filesystem::path& outDir);

// The warning kind of summary.json's key "hindsight.by_kind.<kind>.judged" (a kind hindsight
// judged, the way the tables find the kinds a run has), or "" for any other key.
std::string judgedKind(const std::string& key);

}  // namespace st::batch
