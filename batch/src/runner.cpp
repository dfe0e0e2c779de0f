#include <stbatch/runner.hpp>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <stbatch/stats.hpp>
#include <stio/data_file.hpp>
#include <stio/format.hpp>

extern char** environ;

namespace st::batch {

namespace fs = std::filesystem;

const char* toString(RunStatus s) {
  switch (s) {
    case RunStatus::Done: return "done";
    case RunStatus::Failed: return "failed";
    case RunStatus::Missing: return "missing";
  }
  return "?";
}

namespace {

void writeFileAtomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write");
    out << text;
    if (!out.flush()) throw std::runtime_error(tmp.string() + ": write failed");
  }
  fs::rename(tmp, path);
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::string lastLine(const std::string& text) {
  std::istringstream in(text);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty() && line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  if (last.size() > 300) last = last.substr(0, 300) + "...";
  return last;
}

// Cells of the tables: line breaks become spaces, so every row is one line of the file.
std::string csvField(const std::string& s) { return io::csvField(io::oneLine(s)); }

std::string number(double v) { return io::number(v, 12); }

// Numeric leaves of a JSON document as (dotted.key, value). An array element that is an object
// naming itself ("detector" or "name", as validation.json's per-detector entries do) is reached
// by that name; other array elements are skipped.
void flatten(const boost::property_tree::ptree& t, const std::string& prefix,
             std::vector<std::pair<std::string, double>>& out) {
  for (const auto& [key, child] : t) {
    std::string label = key;
    if (label.empty()) {  // array element
      for (const char* k : {"detector", "name"})
        if (auto n = child.get_optional<std::string>(k); n && !n->empty() && label.empty()) label = *n;
      if (label.empty()) continue;
    }
    const std::string name = prefix.empty() ? label : prefix + "." + label;
    if (child.empty()) {
      const std::string v = child.data();
      char* end = nullptr;
      const double d = std::strtod(v.c_str(), &end);
      if (!v.empty() && end && *end == '\0') out.emplace_back(name, d);
      else if (v == "true" || v == "false") out.emplace_back(name, v == "true" ? 1.0 : 0.0);
      // null: a figure with nothing to count (a share of nothing, no lead time): kept as NaN, so
      // the column is there and its cell empty, never 0 or 1
      else if (v == "null") out.emplace_back(name, std::numeric_limits<double>::quiet_NaN());
    } else {
      flatten(child, name, out);
    }
  }
}

fs::path runDir(const fs::path& outDir, const RunSpec& r) { return outDir / "runs" / r.id; }

// summary.json writes the events' lead times as null when none was warned: that null
// stands for the distribution's three figures, so their columns are there, empty
void nullLeadTimes(std::vector<std::pair<std::string, double>>& metrics) {
  for (const std::string lead : {"hindsight.near_misses.lead_s", "hindsight.crossings.lead_s", "collisions.lead_s"}) {
    const auto at = std::find_if(metrics.begin(), metrics.end(), [&](const auto& m) { return m.first == lead; });
    if (at == metrics.end() || !std::isnan(at->second)) continue;
    const double none = at->second;
    const auto next = metrics.erase(at);
    metrics.insert(next, {{lead + ".min", none}, {lead + ".median", none}, {lead + ".p90", none}});
  }
}

}  // namespace

RunResult loadRunResult(const fs::path& outDir, const RunSpec& spec) {
  RunResult r;
  r.spec = spec;
  const fs::path dir = runDir(outDir, spec);
  if (!fs::exists(dir / "result.yaml")) return r;
  try {
    const YAML::Node res = YAML::LoadFile((dir / "result.yaml").string());
    r.status = res["status"].as<std::string>() == "done" ? RunStatus::Done : RunStatus::Failed;
    r.error = res["error"] ? res["error"].as<std::string>() : "";
    r.wallSeconds = res["wall_seconds"] ? res["wall_seconds"].as<double>() : 0.0;
  } catch (const YAML::Exception&) {
    return r;  // unreadable result: the run is redone
  }
  if (r.status == RunStatus::Done) {
    try {
      boost::property_tree::ptree tree;
      boost::property_tree::read_json((dir / "summary.json").string(), tree);
      flatten(tree, "", r.metrics);
      nullLeadTimes(r.metrics);
      // --validate-ssm / validate_ssm: the agreement with SUMO's SSM device, as ssm.*
      if (fs::exists(dir / "validation.json")) {
        boost::property_tree::ptree validation;
        boost::property_tree::read_json((dir / "validation.json").string(), validation);
        flatten(validation, "ssm", r.metrics);
      }
    } catch (const std::exception& ex) {
      r.status = RunStatus::Failed;
      r.error = std::string("summary.json unreadable: ") + ex.what();
    }
  }
  r.reused = true;
  return r;
}

std::vector<RunResult> executeRuns(const Experiment& e, const std::vector<RunSpec>& runs, const BatchOptions& o) {
  fs::create_directories(o.outDir / "runs");
  std::vector<RunResult> results(runs.size());
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    results[i] = loadRunResult(o.outDir, runs[i]);
    // a finished run is reused only if it ran the scenario this experiment makes of it now: the
    // run id names the parameters, not the base's content (an edited base left every old run "done")
    if (results[i].status == RunStatus::Done &&
        readFile(runDir(o.outDir, runs[i]) / "scenario.yaml") != runScenarioYaml(e, runs[i])) {
      if (o.log) o.log(runs[i].id + " stale (its scenario changed since it ran): run again");
      results[i] = RunResult{};
      results[i].spec = runs[i];
    }
    if (results[i].status != RunStatus::Done) todo.push_back(i);  // failed runs are tried again
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  int finished = static_cast<int>(runs.size() - todo.size());
  const int total = static_cast<int>(runs.size());
  if (o.progress) o.progress(finished, total, 0.0);

  struct Running {
    std::size_t index;
    fs::path tmp;
    std::chrono::steady_clock::time_point start;
  };
  std::map<pid_t, Running> running;
  std::size_t next = 0;
  const int jobs = std::max(1, o.jobs);

  auto launch = [&](std::size_t i) {
    const RunSpec& spec = runs[i];
    const fs::path tmp = o.outDir / "runs" / (spec.id + ".tmp");
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    writeFileAtomically(tmp / "scenario.yaml", runScenarioYaml(e, spec));
    const std::string exe = o.stsim.string(), scen = (tmp / "scenario.yaml").string(), out = tmp.string();
    std::vector<std::string> args = {exe, e.command, scen, "--out", out};
    // the report draws one conflict map per parameter combination, all seeds together (plots.py)
    if (e.command == "highway") args.emplace_back("--no-map");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    const std::string log = (tmp / "log.txt").string();
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) throw std::runtime_error("cannot start " + exe + ": " + std::strerror(rc));
    running[pid] = Running{i, tmp, std::chrono::steady_clock::now()};
  };

  auto finish = [&](pid_t pid, int status) {
    const Running run = running.at(pid);
    running.erase(pid);
    RunResult& r = results[run.index];
    r = RunResult{};
    r.spec = runs[run.index];
    r.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - run.start).count();
    const std::string log = readFile(run.tmp / "log.txt");
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(run.tmp / "summary.json")) {
      r.status = RunStatus::Done;
    } else {
      r.status = RunStatus::Failed;
      if (WIFSIGNALED(status)) r.error = "crashed with signal " + std::to_string(WTERMSIG(status));
      else r.error = "exit " + std::to_string(WEXITSTATUS(status));
      if (std::string l = lastLine(log); !l.empty()) {
        // the run's folder is renamed below: name its files where they will be
        const std::string from = run.tmp.string(), to = runDir(o.outDir, r.spec).string();
        for (std::size_t at = l.find(from); at != std::string::npos; at = l.find(from, at + to.size()))
          l.replace(at, from.size(), to);
        r.error += ": " + l;
      }
    }
    YAML::Emitter em;
    em << YAML::BeginMap << YAML::Key << "status" << YAML::Value << toString(r.status) << YAML::Key << "error"
       << YAML::Value << r.error << YAML::Key << "wall_seconds" << YAML::Value << r.wallSeconds << YAML::EndMap;
    writeFileAtomically(run.tmp / "result.yaml", std::string(em.c_str()) + "\n");
    // publish the finished run in one rename; a previous failed attempt is replaced
    const fs::path dir = runDir(o.outDir, r.spec);
    fs::remove_all(dir);
    fs::rename(run.tmp, dir);
    if (r.status == RunStatus::Done) {
      const RunResult loaded = loadRunResult(o.outDir, r.spec);
      r.metrics = loaded.metrics;
      if (loaded.status != RunStatus::Done) {
        r.status = loaded.status;
        r.error = loaded.error;
      }
      r.reused = false;
    }
    ++finished;
    if (o.log) o.log(r.spec.id + " " + toString(r.status) + (r.error.empty() ? "" : " (" + r.error + ")"));
    if (o.progress) o.progress(finished, total, elapsed());
  };

  bool forwarded = false;
  while (next < todo.size() || !running.empty()) {
    const bool stopping = o.stopRequested && o.stopRequested();
    if (stopping && !forwarded) {
      // a SIGTERM sent to the batch alone reaches its runs too (Ctrl-C already reached the group):
      // each writes what it has and stops, instead of the batch waiting for them to finish
      for (const auto& [pid, run] : running) ::kill(pid, SIGTERM);
      forwarded = true;
    }
    while (!stopping && next < todo.size() && static_cast<int>(running.size()) < jobs) launch(todo[next++]);
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    }
    if (running.count(pid)) finish(pid, status);
  }
  return results;
}

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
// pooled over its done runs (seeds): per warning kind the warnings per vehicle-km (all warnings
// over all vehicle-km), the judged and confirmed warnings and the confirmed share (precision);
// the near misses, those warned and the recall; the median of the runs' median lead times; the
// same for the unsignalled crossings and SUMO's collisions (warned the lead time ahead). A
// share of nothing (no warning judged, no near miss) and a lead time of no warned near miss are
// empty, never 0 or 1. Pooling weighs each warning once, where summary.csv's mean of the runs'
// shares would weigh a run with 3 warnings like one with 3000.
std::string hindsightTable(const Experiment& e, const std::vector<std::vector<std::string>>& order,
                           const std::map<std::vector<std::string>, std::vector<const RunResult*>>& groups,
                           const std::vector<std::string>& metricCols) {
  const std::string byKind = "hindsight.by_kind.", judgedTail = ".judged";
  std::vector<std::string> kinds;  // in summary.json's order
  for (const auto& c : metricCols)
    if (c.rfind(byKind, 0) == 0 && c.size() > byKind.size() + judgedTail.size() &&
        c.compare(c.size() - judgedTail.size(), judgedTail.size(), judgedTail) == 0)
      kinds.push_back(c.substr(byKind.size(), c.size() - byKind.size() - judgedTail.size()));
  if (kinds.empty()) return "";
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
    int done = 0;
    for (const RunResult* r : groups.at(key)) {
      if (r->status != RunStatus::Done) continue;
      ++done;
      for (const auto& [k, v] : r->metrics) {
        if (std::isnan(v)) continue;
        bool lead = false;
        for (const Events& ev : events)
          if (k == std::string(ev.metric) + ".lead_s.median") leads[ev.column].push_back(v), lead = true;
        if (!lead) total[k] += v;
      }
    }
    for (const auto& v : key) t << csvField(v) << ",";
    const double km = total["vehicle_km"];
    t << done << "," << (done ? number(km) : "");
    for (const auto& k : kinds) t << "," << cell(total["warnings.by_kind." + k], km);
    for (const auto& k : kinds) {
      const double judged = total[byKind + k + ".judged"], confirmed = total[byKind + k + ".confirmed"];
      t << "," << (done ? number(judged) : "") << "," << (done ? number(confirmed) : "") << "," << cell(confirmed, judged);
    }
    for (const Events& ev : events) {
      // a run without the figure (an attached run counts no collisions) leaves it empty
      const std::string at = ev.metric;
      const bool counted = total.count(at + ".events") > 0;
      const double count = total[at + ".events"], warned = total[at + ".warned"];
      t << "," << (counted ? number(count) : "") << "," << (counted ? number(warned) : "") << "," << cell(warned, count) << ",";
      std::vector<double>& l = leads[ev.column];
      if (!l.empty()) {
        std::sort(l.begin(), l.end());
        const std::size_t n = l.size();
        t << number(n % 2 ? l[n / 2] : 0.5 * (l[n / 2 - 1] + l[n / 2]));
      }
    }
    t << "\n";
  }
  return t.str();
}

}  // namespace

void writeTables(const Experiment& e, std::vector<RunResult> results, const fs::path& outDir) {
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
  writeFileAtomically(outDir / "runs.csv", runs.str());

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
  writeFileAtomically(outDir / "summary.csv", sum.str());
  writeFileAtomically(outDir / "paired.csv", pairedTable(e, results, metricCols));
  if (const std::string h = hindsightTable(e, order, groups, metricCols); !h.empty())
    writeFileAtomically(outDir / "hindsight.csv", h);
}

namespace {

std::string experimentRecord(const Experiment& e) {
  YAML::Emitter em;
  em << YAML::BeginMap;
  em << YAML::Key << "name" << YAML::Value << e.name;
  em << YAML::Key << "command" << YAML::Value << e.command;
  if (e.bases.empty()) {
    em << YAML::Key << "base" << YAML::Value << e.base.string();
  } else {
    em << YAML::Key << "base" << YAML::Value << YAML::BeginMap;
    for (const auto& b : e.bases) {
      em << YAML::Key << b.name << YAML::Value;
      if (b.fixed.empty()) {
        em << b.file.string();
        continue;
      }
      em << YAML::BeginMap << YAML::Key << "scenario" << YAML::Value << b.file.string() << YAML::Key << "fixed"
         << YAML::Value << YAML::BeginMap;
      for (const auto& [k, v] : b.fixed) em << YAML::Key << k << YAML::Value << YAML::Load(v);
      em << YAML::EndMap << YAML::EndMap;
    }
    em << YAML::EndMap;
  }
  em << YAML::Key << "seed_key" << YAML::Value << e.seedKey;
  em << YAML::Key << "seeds" << YAML::Value << YAML::Flow << e.seeds;
  // the bases' axis is base: itself
  const bool onlyBases = e.sweep.size() == 1 && !e.bases.empty();
  if (!e.sweep.empty() && !onlyBases) {
    em << YAML::Key << "sweep" << YAML::Value << YAML::BeginMap;
    for (const auto& a : e.sweep) {
      if (!e.bases.empty() && a.key == kBaseAxis) continue;
      em << YAML::Key << a.key << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const auto& v : a.values) em << YAML::Load(v);
      em << YAML::EndSeq;
    }
    em << YAML::EndMap;
  }
  if (!e.fixed.empty()) {
    em << YAML::Key << "fixed" << YAML::Value << YAML::BeginMap;
    for (const auto& [k, v] : e.fixed) em << YAML::Key << k << YAML::Value << YAML::Load(v);
    em << YAML::EndMap;
  }
  em << YAML::EndMap;
  return std::string(em.c_str()) + "\n";
}

}  // namespace

void checkResumable(const Experiment& e, const fs::path& outDir) {
  const fs::path p = outDir / "experiment.yaml";
  if (!fs::exists(p)) return;
  if (readFile(p) != experimentRecord(e))
    throw ExperimentError(p.string() + ": this folder holds the runs of another experiment (its base, sweep, fixed or "
                          "seeds differ from " + e.file.string() + "); give another --out or remove the folder");
}

void writeExperimentRecord(const Experiment& e, const fs::path& outDir) {
  checkResumable(e, outDir);
  fs::create_directories(outDir);
  writeFileAtomically(outDir / "experiment.yaml", experimentRecord(e));
}

Experiment readExperimentRecord(const fs::path& outDir) {
  const fs::path p = outDir / "experiment.yaml";
  if (!fs::exists(p)) throw ExperimentError(outDir.string() + ": not a stsim batch output folder (no experiment.yaml)");
  // keys were validated when the batch ran; accept them all again
  Experiment e = loadExperiment(p, std::vector<std::string>{"*"});
  return e;
}

std::vector<RunResult> mergeShards(const std::vector<fs::path>& dirs, const fs::path& outDir) {
  if (dirs.empty()) throw std::invalid_argument("merge needs at least one batch output folder");
  const Experiment e = readExperimentRecord(dirs.front());
  const std::string record = readFile(dirs.front() / "experiment.yaml");
  for (const auto& d : dirs)
    if (readFile(d / "experiment.yaml") != record)
      throw ExperimentError(d.string() + ": experiment.yaml differs from " + dirs.front().string() + ": not shards of one experiment");
  fs::create_directories(outDir / "runs");
  // the shards ran this experiment: the limit their --max-runs set admitted it
  const auto runs = expandRuns(e, std::numeric_limits<std::uint64_t>::max());
  std::vector<RunResult> results;
  for (const auto& spec : runs) {
    RunResult best;
    best.spec = spec;
    for (const auto& d : dirs) {
      RunResult r = loadRunResult(d, spec);
      if (r.status == RunStatus::Missing) continue;
      if (best.status == RunStatus::Missing || (best.status == RunStatus::Failed && r.status == RunStatus::Done)) {
        best = r;
        const fs::path dst = runDir(outDir, spec);
        if (fs::weakly_canonical(runDir(d, spec)) != fs::weakly_canonical(dst)) {
          fs::remove_all(dst);
          fs::copy(runDir(d, spec), dst, fs::copy_options::recursive);
        }
      }
    }
    results.push_back(best);
  }
  if (fs::weakly_canonical(dirs.front()) != fs::weakly_canonical(outDir)) writeExperimentRecord(e, outDir);
  writeTables(e, results, outDir);
  return results;
}

bool writePlots(const fs::path& outDir, std::string& why) {
  // installed: share/stsim/plots.py beside bin/stsim; a build in the tree: the source's copy
  const fs::path script = io::dataFile("plots.py", STSIM_BATCH_PLOT_SCRIPT);
  if (!fs::exists("/usr/bin/python3")) {
    why = "/usr/bin/python3 not found (apt-get install python3-matplotlib)";
    return false;
  }
  if (!fs::exists(script)) {
    why = "plot script missing: " + script.string();
    return false;
  }
  const std::string cmd = "/usr/bin/python3 '" + script.string() + "' '" + outDir.string() + "' > '" +
                          (outDir / "plots.log").string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  if (rc != 0) {
    why = "plotting failed: " + lastLine(readFile(outDir / "plots.log"));
    return false;
  }
  return true;
}

}  // namespace st::batch
