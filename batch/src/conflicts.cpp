#include <stbatch/conflicts.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <stbatch/stats.hpp>
#include <stio/format.hpp>
#include <stio/output.hpp>

#include "files.hpp"

namespace st::batch {

namespace fs = std::filesystem;
using namespace detail;

namespace {

// A combination's conflicts, pooled over its done runs.
struct Pool {
  int runs = 0;
  int conflicts = 0;  // all three types
  std::map<std::string, int> byType;
  std::map<std::string, std::vector<double>> values;  // measure -> its finite values
};

// Adds one run's conflicts (one row per conflict: a pair and an encounter, counted once).
void addRun(const fs::path& file, double warmup, Pool& pool, std::set<std::string>& measures) {
  const RunConflicts run = readRunConflicts(file, warmup);
  measures.insert(run.measures.begin(), run.measures.end());
  ++pool.runs;
  for (const RunConflicts::Row& row : run.rows) {
    ++pool.byType[row.type];
    ++pool.conflicts;
    for (std::size_t m = 0; m < run.measures.size(); ++m)
      if (std::isfinite(row.values[m])) pool.values[run.measures[m]].push_back(row.values[m]);
  }
}

struct Welch {
  double diff = 0.0, ci95 = 0.0, t = 0.0;
  bool ok = false;  // both sides have two values or more and a spread
};

// Difference of two means with Welch's interval; the degrees of freedom (Welch-Satterthwaite)
// rounded down, so the interval errs wide.
Welch welch(const std::vector<double>& x, const std::vector<double>& y) {
  Welch w;
  const Summary a = summarize(x), b = summarize(y);
  w.diff = a.mean - b.mean;
  if (a.n < 2 || b.n < 2) return w;
  const double va = a.sd * a.sd / a.n, vb = b.sd * b.sd / b.n, se2 = va + vb;
  if (!(se2 > 0.0)) return w;
  const double dof = se2 * se2 / (va * va / (a.n - 1) + vb * vb / (b.n - 1));
  const double se = std::sqrt(se2);
  w.ci95 = studentT975(std::max(1, static_cast<int>(std::floor(dof)))) * se;
  w.t = w.diff / se;
  w.ok = true;
  return w;
}

}  // namespace

RunConflicts readRunConflicts(const fs::path& file, double warmup) {
  const CsvTable csv = readCsvTable(file);
  const std::size_t type = csv.column("type", "not a highway conflicts.csv");
  const int begin = csv.find("begin");
  if (warmup > 0.0 && begin < 0)
    throw std::runtime_error(file.string() + ": no begin column, so warmup cannot be applied");
  RunConflicts run;
  const int firstClass = csv.find("first_class"), secondClass = csv.find("second_class");
  run.classes = firstClass >= 0 && secondClass >= 0;
  std::vector<std::size_t> at;
  for (const char* m : kConflictMeasures)
    if (const int c = csv.find(m); c >= 0) run.measures.emplace_back(m), at.push_back(static_cast<std::size_t>(c));
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    const std::string& kind = csv.rows[i][type];
    if (std::find(std::begin(kConflictTypes), std::end(kConflictTypes), kind) == std::end(kConflictTypes)) continue;
    // the warm-up: an encounter that began before it is the warm-up's, left out whole
    if (warmup > 0.0 && !(csv.number(i, static_cast<std::size_t>(begin)) >= warmup)) continue;
    RunConflicts::Row r{kind, {}, false};
    if (run.classes)
      r.withBicycle = csv.rows[i][static_cast<std::size_t>(firstClass)] == "bicycle" ||
                      csv.rows[i][static_cast<std::size_t>(secondClass)] == "bicycle";
    for (std::size_t c : at) {
      const double v = csv.number(i, c);
      r.values.push_back(std::isfinite(v) ? v : std::nan(""));
    }
    run.rows.push_back(std::move(r));
  }
  return run;
}

void writeConflictTables(const Experiment& e, const std::vector<RunResult>& results, const fs::path& outDir) {
  std::map<std::vector<std::string>, Pool> pools;
  std::vector<std::vector<std::string>> order;
  std::set<std::string> present;
  bool any = false;
  for (const RunResult& r : results) {
    std::vector<std::string> key;
    for (const auto& [k, v] : r.spec.params) key.push_back(v);
    if (!pools.count(key)) order.push_back(key);
    Pool& p = pools[key];
    if (r.status != RunStatus::Done) continue;
    addRun(runDir(outDir, r.spec) / "conflicts.csv", e.warmup, p, present);
    any = true;
  }
  if (!any) return;
  std::vector<std::string> measures;  // in kConflictMeasures' order
  for (const char* m : kConflictMeasures)
    if (present.count(m)) measures.emplace_back(m);

  std::ostringstream t;
  for (const auto& axis : e.sweep) t << csvField(axis.key) << ",";
  t << "runs,conflicts";
  for (const char* type : kConflictTypes) t << "," << type;
  for (const auto& m : measures) t << "," << m << ".n," << m << ".mean," << m << ".sd," << m << ".ci95";
  t << "\n";
  for (const auto& key : order) {
    const Pool& p = pools[key];
    for (const auto& v : key) t << csvField(v) << ",";
    t << p.runs << "," << p.conflicts;
    for (const char* type : kConflictTypes) t << "," << (p.byType.count(type) ? p.byType.at(type) : 0);
    for (const auto& m : measures) {
      const auto at = p.values.find(m);
      const Summary s = summarize(at == p.values.end() ? std::vector<double>{} : at->second);
      t << "," << s.n;
      if (s.n == 0) t << ",,,";
      else t << "," << number(s.mean) << "," << (s.n > 1 ? number(s.sd) : "") << "," << (s.n > 1 ? number(s.ci95) : "");
    }
    t << "\n";
  }
  io::writeFileAtomically(outDir / "conflicts.csv", t.str());

  std::ostringstream c;
  c << "compared,baseline";
  for (const auto& axis : e.sweep) c << "," << csvField(axis.key);
  c << ",conflicts,baseline_conflicts";
  for (const auto& m : measures) c << "," << m << ".diff_mean," << m << ".diff_ci95," << m << ".t";
  c << "\n";
  for (std::size_t a = 0; a < e.sweep.size(); ++a) {
    const SweepAxis& axis = e.sweep[a];
    for (const auto& key : order) {
      if (key[a] == axis.values.front()) continue;
      std::vector<std::string> baseKey = key;
      baseKey[a] = axis.values.front();
      const Pool& x = pools[key];
      const Pool& y = pools[baseKey];
      c << csvField(axis.key) << "," << csvField(axis.values.front());
      for (const auto& v : key) c << "," << csvField(v);
      c << "," << x.conflicts << "," << y.conflicts;
      static const std::vector<double> none;
      for (const auto& m : measures) {
        const auto xv = x.values.find(m), yv = y.values.find(m);
        const Welch w = welch(xv == x.values.end() ? none : xv->second, yv == y.values.end() ? none : yv->second);
        if (!w.ok) c << ",,,";
        else c << "," << number(w.diff) << "," << number(w.ci95) << "," << number(w.t);
      }
      c << "\n";
    }
  }
  io::writeFileAtomically(outDir / "conflicts_compared.csv", c.str());
}

}  // namespace st::batch
