#include <stbatch/rates.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <stbatch/conflicts.hpp>
#include <stio/format.hpp>

#include "files.hpp"

namespace st::batch {

namespace fs = std::filesystem;

namespace {

double metric(const RunResult& r, const std::string& name) {
  for (const auto& [k, v] : r.metrics)
    if (k == name) return v;
  return std::numeric_limits<double>::quiet_NaN();
}

// exposure.csv's figures at the last tick at or before `t`: (vehicle_km, vehicles); zeros
// before its first row.
std::pair<double, double> exposureAt(const fs::path& file, double t) {
  const detail::CsvTable csv = detail::readCsvTable(file);
  const std::string why = "warmup needs it";
  const std::size_t time = csv.column("time", why), km = csv.column("vehicle_km", why),
                    vehicles = csv.column("vehicles", why);
  std::pair<double, double> at{0.0, 0.0};
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    if (csv.required(i, time) > t) break;
    at = {csv.required(i, km), csv.required(i, vehicles)};
  }
  return at;
}

}  // namespace

Exposure runExposure(const RunResult& r, const fs::path& runDir, double warmup) {
  Exposure x;
  const double km = metric(r, "vehicle_km"), vehicles = metric(r, "vehicles"), seconds = metric(r, "simulated_s");
  x.vehicleKm = km;
  x.enteringVehicles = vehicles;
  x.hours = seconds / 3600.0;
  if (warmup > 0.0) {
    if (!(seconds > warmup))
      throw std::runtime_error((runDir / "summary.json").string() + ": simulated_s " + detail::number(seconds) +
                               " is not longer than the experiment's warmup of " + detail::number(warmup) + " s");
    const auto [kmAt, vehiclesAt] = exposureAt(runDir / "exposure.csv", warmup);
    x.vehicleKm = km - kmAt;
    x.enteringVehicles = vehicles - vehiclesAt;
    x.hours = (seconds - warmup) / 3600.0;
  }
  return x;
}

void addRates(const Experiment& e, std::vector<RunResult>& results, const fs::path& outDir) {
  if (e.command != "highway") return;
  for (RunResult& r : results) {
    if (r.status != RunStatus::Done) continue;
    const fs::path dir = detail::runDir(outDir, r.spec);
    const RunConflicts conflicts = readRunConflicts(dir / "conflicts.csv", e.warmup);
    const Exposure x = runExposure(r, dir, e.warmup);
    std::map<std::string, double> counted{{"all", 0.0}};
    for (const char* t : kConflictTypes) counted[t] = 0.0;
    for (const auto& row : conflicts.rows) counted[row.type] += 1.0, counted["all"] += 1.0;
    auto rate = [](double n, double exposure) {
      return exposure > 0.0 ? n / exposure : std::numeric_limits<double>::quiet_NaN();
    };
    r.metrics.emplace_back("exposure.vehicle_km", x.vehicleKm);
    r.metrics.emplace_back("exposure.hours", x.hours);
    r.metrics.emplace_back("exposure.entering_vehicles", x.enteringVehicles);
    std::vector<std::string> types{"all"};
    types.insert(types.end(), std::begin(kConflictTypes), std::end(kConflictTypes));
    for (const auto& t : types) r.metrics.emplace_back("counted." + t, counted[t]);
    for (const auto& t : types) r.metrics.emplace_back("rate.per_vehicle_km." + t, rate(counted[t], x.vehicleKm));
    for (const auto& t : types) r.metrics.emplace_back("rate.per_hour." + t, rate(counted[t], x.hours));
    for (const auto& t : types)
      r.metrics.emplace_back("rate.per_entering_vehicle." + t, rate(counted[t], x.enteringVehicles));
  }
}

}  // namespace st::batch
