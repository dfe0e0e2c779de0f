#include <stbatch/rates.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <stbatch/conflicts.hpp>
#include <stbatch/stats.hpp>
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
    // the conflicts with a bicycle (car-bicycle and bicycle-bicycle) apart, under with_bicycle.<type>;
    // unknown (NaN, an empty cell) for a file without the classes
    const std::string bike = "with_bicycle.";
    const double none = conflicts.classes ? 0.0 : std::numeric_limits<double>::quiet_NaN();
    counted[bike + "all"] = none;
    for (const char* t : kConflictTypes) counted[bike + t] = none;
    for (const auto& row : conflicts.rows)
      if (row.withBicycle) counted[bike + row.type] += 1.0, counted[bike + "all"] += 1.0;
    auto rate = [](double n, double exposure) {
      return exposure > 0.0 ? n / exposure : std::numeric_limits<double>::quiet_NaN();
    };
    r.metrics.emplace_back("exposure.vehicle_km", x.vehicleKm);
    r.metrics.emplace_back("exposure.hours", x.hours);
    r.metrics.emplace_back("exposure.entering_vehicles", x.enteringVehicles);
    std::vector<std::string> types{"all"};
    types.insert(types.end(), std::begin(kConflictTypes), std::end(kConflictTypes));
    // each family: every type, then the same with a bicycle (counted.all ... counted.with_bicycle.pedestrian)
    const std::size_t n = types.size();
    for (std::size_t i = 0; i < n; ++i) types.push_back(bike + types[i]);
    for (const auto& t : types) r.metrics.emplace_back("counted." + t, counted[t]);
    for (const auto& t : types) r.metrics.emplace_back("rate.per_vehicle_km." + t, rate(counted[t], x.vehicleKm));
    for (const auto& t : types) r.metrics.emplace_back("rate.per_hour." + t, rate(counted[t], x.hours));
    for (const auto& t : types)
      r.metrics.emplace_back("rate.per_entering_vehicle." + t, rate(counted[t], x.enteringVehicles));
  }
}

namespace {

// Events after the warm-up: how many, how many warned, the warned ones' lead times.
struct EventCount {
  double events = 0.0, warned = 0.0;
  std::vector<double> leads;
  void add(const std::string& prefix, std::vector<std::pair<std::string, double>>& metrics) const {
    metrics.emplace_back(prefix + ".events", events);
    metrics.emplace_back(prefix + ".warned", warned);
    metrics.emplace_back(prefix + ".lead_s.median", median(leads));
  }
};

void addRunAfterWarmup(RunResult& r, const fs::path& dir, double warmup) {
  std::vector<std::string> kinds;  // summary.json's, in its order
  for (const auto& [k, v] : r.metrics)
    if (std::string kind = judgedKind(k); !kind.empty()) kinds.push_back(std::move(kind));
  if (kinds.empty()) return;  // hindsight off: nothing of its to count
  const std::string why = "warmup needs it";
  std::map<std::string, double> warnings, judged, confirmed;
  {
    const detail::CsvTable csv = detail::readCsvTable(dir / "warnings.csv");
    const std::size_t kind = csv.column("kind", why), begin = csv.column("begin", why), verdict = csv.column("verdict", why);
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
      if (!(csv.required(i, begin) >= warmup)) continue;  // begun in the warm-up: the warm-up's
      const std::string& k = csv.rows[i][kind];
      warnings[k] += 1.0;
      if (!csv.rows[i][verdict].empty()) judged[k] += 1.0;
      if (csv.rows[i][verdict] == "confirmed") confirmed[k] += 1.0;
    }
  }
  EventCount nearMisses, crossings;
  {
    const detail::CsvTable csv = detail::readCsvTable(dir / "events.csv");
    const std::size_t time = csv.column("time", why), kind = csv.column("kind", why), warned = csv.column("warned", why),
                      lead = csv.column("lead", why);
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
      if (!(csv.required(i, time) >= warmup)) continue;
      const std::string& k = csv.rows[i][kind];
      EventCount& c = k == "near_miss" ? nearMisses : crossings;
      if (k != "near_miss" && k != "crossing")
        throw std::runtime_error((dir / "events.csv").string() + ":" + std::to_string(i + 2) + ": kind: \"" + k +
                                 "\" is neither near_miss nor crossing");
      c.events += 1.0;
      if (csv.required(i, warned) == 1.0) c.warned += 1.0, c.leads.push_back(csv.required(i, lead));
    }
  }
  for (const auto& k : kinds) {
    r.metrics.emplace_back("after_warmup.warnings.by_kind." + k, warnings[k]);
    r.metrics.emplace_back("after_warmup.hindsight.by_kind." + k + ".judged", judged[k]);
    r.metrics.emplace_back("after_warmup.hindsight.by_kind." + k + ".confirmed", confirmed[k]);
  }
  nearMisses.add("after_warmup.hindsight.near_misses", r.metrics);
  crossings.add("after_warmup.hindsight.crossings", r.metrics);
  // collisions: only a run that counts them (summary.json's collisions.events; not an attached one)
  if (std::isnan(metric(r, "collisions.events"))) return;
  const double leadNeeded = metric(r, "hindsight.lead_s");
  EventCount collisions;
  const detail::CsvTable csv = detail::readCsvTable(dir / "collision_warnings.csv");
  const std::size_t time = csv.column("time", why), warned = csv.column("collider_warned", why),
                    lead = csv.column("lead_time_s", why);
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    if (!(csv.required(i, time) >= warmup)) continue;
    collisions.events += 1.0;
    // warned as hindsight counts it: the lead time ahead
    if (csv.required(i, warned) == 1.0 && csv.required(i, lead) >= leadNeeded)
      collisions.warned += 1.0, collisions.leads.push_back(csv.required(i, lead));
  }
  collisions.add("after_warmup.collisions", r.metrics);
}

}  // namespace

void addWarnedAfterWarmup(const Experiment& e, std::vector<RunResult>& results, const fs::path& outDir) {
  if (e.command != "highway" || !(e.warmup > 0.0)) return;
  for (RunResult& r : results)
    if (r.status == RunStatus::Done) addRunAfterWarmup(r, detail::runDir(outDir, r.spec), e.warmup);
}

std::string judgedKind(const std::string& key) {
  const std::string byKind = "hindsight.by_kind.", judgedTail = ".judged";
  if (key.size() <= byKind.size() + judgedTail.size() || key.rfind(byKind, 0) != 0 ||
      key.compare(key.size() - judgedTail.size(), judgedTail.size(), judgedTail) != 0)
    return "";
  return key.substr(byKind.size(), key.size() - byKind.size() - judgedTail.size());
}

}  // namespace st::batch
