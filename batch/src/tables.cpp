#include <stbatch/tables.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <stbatch/conflicts.hpp>
#include <stbatch/rates.hpp>
#include <stbatch/stats.hpp>
#include <stio/output.hpp>

#include "files.hpp"

namespace st::batch {

namespace fs = std::filesystem;
using namespace detail;

namespace {

// Paired comparisons (common random numbers): for each swept key, each of its values against the
// first, with every other key held, run by run on the same seed. The spread of the differences
// leaves out what the seeds share, so a small effect shows here long before the summary's CIs part.
std::string pairedTable(const Experiment& e, const std::vector<RunResult>& results,
                        const std::vector<std::string>& metricCols) {
  // a done run's metrics by (parameters, seed)
  std::map<std::pair<std::vector<std::string>, std::int64_t>, const RunResult*> byKey;
  for (const auto& r : results) {
    if (r.status != RunStatus::Done) continue;
    std::vector<std::string> key;
    for (const auto& [k, v] : r.spec.params) key.push_back(v);
    byKey[{key, r.spec.seed}] = &r;
  }
  auto metric = [](const RunResult& r, const std::string& name, double& out) {
    for (const auto& [k, v] : r.metrics)
      if (k == name) return out = v, !std::isnan(v);
    return false;
  };
  std::ostringstream t;
  t << "compared,baseline";
  for (const auto& axis : e.sweep) t << "," << csvField(axis.key);
  t << ",pairs";
  for (const auto& m : metricCols) t << "," << csvField(m + ".diff_mean") << "," << csvField(m + ".diff_sd") << "," << csvField(m + ".diff_ci95");
  t << "\n";
  for (std::size_t a = 0; a < e.sweep.size(); ++a) {
    const SweepAxis& axis = e.sweep[a];
    // rows in the summary's order: every parameter combination whose compared key is not the baseline
    std::set<std::vector<std::string>> done;
    for (const auto& r : results) {
      std::vector<std::string> key;
      for (const auto& [k, v] : r.spec.params) key.push_back(v);
      if (key[a] == axis.values.front() || !done.insert(key).second) continue;
      std::vector<std::string> baseKey = key;
      baseKey[a] = axis.values.front();
      std::vector<std::pair<const RunResult*, const RunResult*>> pairs;
      for (std::int64_t seed : e.seeds) {
        const auto x = byKey.find({key, seed}), y = byKey.find({baseKey, seed});
        if (x != byKey.end() && y != byKey.end()) pairs.emplace_back(x->second, y->second);
      }
      t << csvField(axis.key) << "," << csvField(axis.values.front());
      for (const auto& v : key) t << "," << csvField(v);
      t << "," << pairs.size();
      for (const auto& c : metricCols) {
        std::vector<double> diffs;
        for (const auto& [x, y] : pairs) {
          double vx = 0.0, vy = 0.0;
          if (metric(*x, c, vx) && metric(*y, c, vy)) diffs.push_back(vx - vy);
        }
        const Summary s = summarize(diffs);
        if (s.n == 0) t << ",,,";
        else t << "," << number(s.mean) << "," << (s.n > 1 ? number(s.sd) : "") << "," << (s.n > 1 ? number(s.ci95) : "");
      }
      t << "\n";
    }
  }
  return t.str();
}

// hindsight.csv (highway runs): what hindsight made of the warnings, per parameter combination,
// pooled over its done runs (seeds): per warning kind the warnings per vehicle-km (the mean of the
// runs' rates), the judged and confirmed warnings and the confirmed share (precision);
// the near misses, those warned and the recall; the median of the runs' median lead times; the
// same for the unsignalled crossings and SUMO's collisions (warned the lead time ahead). A
// share of nothing (no warning judged, no near miss) and a lead time of no warned near miss are
// empty, never 0 or 1. Pooling weighs each warning once, where summary.csv's mean of the runs'
// shares would weigh a run with 3 warnings like one with 3000. With a warm-up, all of it after the
// warm-up (the runs' after_warmup.* over exposure.vehicle_km), else the whole runs.
std::string hindsightTable(const Experiment& e, const std::vector<std::vector<std::string>>& order,
                           const std::map<std::vector<std::string>, std::vector<const RunResult*>>& groups,
                           const std::vector<std::string>& metricCols) {
  std::vector<std::string> kinds;  // in summary.json's order
  for (const auto& c : metricCols)
    if (std::string kind = judgedKind(c); !kind.empty()) kinds.push_back(std::move(kind));
  if (kinds.empty()) return "";
  // with a warm-up, hindsight's figures after it (rates.hpp, addWarnedAfterWarmup) over the
  // distance driven after it
  const std::string pre = e.warmup > 0.0 ? "after_warmup." : "";
  const std::string kmKey = e.warmup > 0.0 ? "exposure.vehicle_km" : "vehicle_km";
  auto cell = [](double part, double whole) { return whole > 0.0 ? number(part / whole) : std::string(); };
  std::ostringstream t;
  for (const auto& axis : e.sweep) t << csvField(axis.key) << ",";
  t << "runs,vehicle_km";
  for (const auto& k : kinds) t << "," << csvField(k + ".per_vehicle_km");
  for (const auto& k : kinds)
    t << "," << csvField(k + ".judged") << "," << csvField(k + ".confirmed") << "," << csvField(k + ".confirmed_share");
  // the actual events: near misses, unsignalled line crossings (hindsight's), SUMO's collisions
  // (the collider warned about the victim the lead time before; cosim's run.cpp)
  struct Events {
    const char *metric, *column, *share;  // metric: summary.json's {events, warned, recall, lead_s}
  };
  const Events events[] = {{"hindsight.near_misses", "near_misses", "near_miss"},
                           {"hindsight.crossings", "crossings", "crossing"},
                           {"collisions", "collisions", "collision"}};
  for (const Events& ev : events)
    t << "," << ev.column << "," << ev.column << "_warned," << ev.share << "_recall," << ev.share << "_lead_median_s";
  t << "\n";
  for (const auto& key : order) {
    std::map<std::string, double> total;  // sums over the done runs
    std::map<std::string, std::vector<double>> leads;  // per event kind, each run's median lead time
    std::map<std::string, std::vector<double>> perKm;  // per warning kind, each run's warnings per vehicle-km
    int done = 0;
    for (const RunResult* r : groups.at(key)) {
      if (r->status != RunStatus::Done) continue;
      ++done;
      double km = 0.0;
      for (const auto& [k, v] : r->metrics)
        if (k == kmKey) km = v;
      for (const auto& [k, v] : r->metrics)
        for (const auto& kind : kinds)
          if (k == pre + "warnings.by_kind." + kind && km > 0.0 && !std::isnan(v)) perKm[kind].push_back(v / km);
      for (const auto& [k, v] : r->metrics) {
        if (std::isnan(v)) continue;
        bool lead = false;
        for (const Events& ev : events)
          if (k == pre + ev.metric + ".lead_s.median") leads[ev.column].push_back(v), lead = true;
        if (!lead) total[k] += v;
      }
    }
    for (const auto& v : key) t << csvField(v) << ",";
    const double km = total[kmKey];
    t << done << "," << (done ? number(km) : "");
    // a rate has one definition in every table: the mean of the runs' rates over the seeds
    for (const auto& k : kinds) {
      const Summary s = summarize(perKm[k]);
      t << "," << (s.n ? number(s.mean) : "");
    }
    for (const auto& k : kinds) {
      const std::string byKind = pre + "hindsight.by_kind." + k;
      const double judged = total[byKind + ".judged"], confirmed = total[byKind + ".confirmed"];
      t << "," << (done ? number(judged) : "") << "," << (done ? number(confirmed) : "") << "," << cell(confirmed, judged);
    }
    for (const Events& ev : events) {
      // a run without the figure (an attached run counts no collisions) leaves it empty
      const std::string at = pre + ev.metric;
      const bool counted = total.count(at + ".events") > 0;
      const double count = total[at + ".events"], warned = total[at + ".warned"];
      t << "," << (counted ? number(count) : "") << "," << (counted ? number(warned) : "") << "," << cell(warned, count) << ",";
      if (!leads[ev.column].empty()) t << number(median(leads[ev.column]));
    }
    t << "\n";
  }
  return t.str();
}

}  // namespace

void writeTables(const Experiment& e, std::vector<RunResult> results, const fs::path& outDir) {
  addRates(e, results, outDir);
  addWarnedAfterWarmup(e, results, outDir);
  std::sort(results.begin(), results.end(), [](const RunResult& a, const RunResult& b) { return a.spec.index < b.spec.index; });
  // metric columns: first-seen order over runs in index order (deterministic for any job count)
  std::vector<std::string> metricCols;
  // a summary leaf named like a parameter (the run's own echo of "seed" or "penetration") would
  // make a second column of that name; the parameter column already holds it
  std::set<std::string> seen{e.seedKey};
  for (const auto& axis : e.sweep) seen.insert(axis.key);
  for (const auto& r : results)
    for (const auto& [k, v] : r.metrics)
      if (seen.insert(k).second) metricCols.push_back(k);

  std::ostringstream runs;
  runs << "index,run_id,status";
  for (const auto& axis : e.sweep) runs << "," << csvField(axis.key);
  runs << "," << csvField(e.seedKey) << ",wall_seconds,error";
  for (const auto& m : metricCols) runs << "," << csvField(m);
  runs << "\n";
  for (const auto& r : results) {
    runs << r.spec.index << "," << r.spec.id << "," << toString(r.status);
    for (const auto& [k, v] : r.spec.params) runs << "," << csvField(v);
    runs << "," << r.spec.seed << "," << number(r.wallSeconds) << "," << csvField(r.error);
    std::map<std::string, double> m(r.metrics.begin(), r.metrics.end());
    for (const auto& c : metricCols) runs << "," << (m.count(c) && !std::isnan(m[c]) ? number(m[c]) : "");
    runs << "\n";
  }
  io::writeFileAtomically(outDir / "runs.csv", runs.str());

  // summary over seeds: one row per parameter combination
  std::map<std::vector<std::string>, std::vector<const RunResult*>> groups;
  std::vector<std::vector<std::string>> order;
  for (const auto& r : results) {
    std::vector<std::string> key;
    for (const auto& [k, v] : r.spec.params) key.push_back(v);
    if (!groups.count(key)) order.push_back(key);
    groups[key].push_back(&r);
  }
  std::ostringstream sum;
  for (const auto& axis : e.sweep) sum << csvField(axis.key) << ",";
  sum << "runs,failed";
  for (const auto& m : metricCols) sum << "," << csvField(m + ".mean") << "," << csvField(m + ".sd") << "," << csvField(m + ".ci95");
  sum << "\n";
  for (const auto& key : order) {
    const auto& members = groups[key];
    for (const auto& v : key) sum << csvField(v) << ",";
    int failed = 0;
    for (const auto* r : members) failed += r->status == RunStatus::Done ? 0 : 1;
    sum << members.size() << "," << failed;
    for (const auto& c : metricCols) {
      std::vector<double> xs;
      for (const auto* r : members) {
        if (r->status != RunStatus::Done) continue;
        for (const auto& [k, v] : r->metrics)
          if (k == c && !std::isnan(v)) xs.push_back(v);
      }
      const Summary s = summarize(xs);
      if (s.n == 0) sum << ",,,";
      else sum << "," << number(s.mean) << "," << (s.n > 1 ? number(s.sd) : "") << "," << (s.n > 1 ? number(s.ci95) : "");
    }
    sum << "\n";
  }
  io::writeFileAtomically(outDir / "summary.csv", sum.str());
  io::writeFileAtomically(outDir / "paired.csv", pairedTable(e, results, metricCols));
  if (const std::string h = hindsightTable(e, order, groups, metricCols); !h.empty())
    io::writeFileAtomically(outDir / "hindsight.csv", h);
  if (e.command == "highway") writeConflictTables(e, results, outDir);
}

}  // namespace st::batch
