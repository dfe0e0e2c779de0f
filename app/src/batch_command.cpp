// stsim batch: parameter sweeps and seeds over a scenario, one process per run, with statistics.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <thread>

#include <stbatch/experiment.hpp>
#include <stbatch/mpi.hpp>
#include <stbatch/plots.hpp>
#include <stbatch/record.hpp>
#include <stbatch/runner.hpp>
#include <stbatch/tables.hpp>
#include <stio/format.hpp>
#ifdef STSIM_HAVE_COSIM
#include <stcosim/scenario.hpp>
#endif
#include <stsim/cli.hpp>
#include <stsim/commands.hpp>

#include "stop_signals.hpp"

namespace st::cli {

namespace fs = std::filesystem;

namespace {


// Scenario keys a command accepts even when the base scenario leaves them out.
std::vector<std::string> optionalKeysFor(const std::string& command) {
  if (command == "pool")
    return {"until", "friction", "seed", "space.kind", "space.decomposition_factor", "space.divisions", "rack_gap"};
#ifdef STSIM_HAVE_COSIM
  if (command == "highway") return st::cosim::scenarioKeys();
#endif
  if (command == "arm") return {};  // arm scenarios have no seed: an experiment names its seed_key
  return {"seed"};
}

std::string formatDuration(double s) {
  char buf[32];
  const int t = static_cast<int>(s + 0.5);
  if (t >= 3600) std::snprintf(buf, sizeof buf, "%dh%02dm", t / 3600, (t / 60) % 60);
  else if (t >= 60) std::snprintf(buf, sizeof buf, "%dm%02ds", t / 60, t % 60);
  else std::snprintf(buf, sizeof buf, "%ds", t);
  return buf;
}

void summarizeResults(const std::vector<batch::RunResult>& results, const fs::path& out) {
  int done = 0, failed = 0, missing = 0;
  for (const auto& r : results) {
    done += r.status == batch::RunStatus::Done;
    failed += r.status == batch::RunStatus::Failed;
    missing += r.status == batch::RunStatus::Missing;
  }
  std::cout << "batch: " << done << " done, " << failed << " failed";
  if (missing) std::cout << ", " << missing << " not run";
  std::cout << " -> " << (out / "runs.csv").string() << ", " << (out / "summary.csv").string() << "\n";
  for (const auto& r : results)
    if (r.status == batch::RunStatus::Failed) std::cout << "  failed " << io::printable(r.spec.id) << ": " << io::printable(r.error) << "\n";
}

int runMerge(int argc, const char* const* argv) {
  Args args("batch merge", "Combines the output folders of shards (--shard I/N) of one experiment into one runs.csv and summary.csv.");
  args.option("out", "DIR", "where the merged tables go", "").flag("no-plots", "skip the PNG plots and report.md");
  args.positional("DIR...", "batch output folders to merge", false);
  // the parser takes one positional; collect the rest here
  std::vector<std::string> dirs;
  std::vector<const char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) == 0 || (!rest.empty() && std::string(rest.back()) == "--out")) rest.push_back(argv[i]);
    else dirs.push_back(a);
  }
  if (!dirs.empty()) rest.push_back(dirs.front().c_str());
  if (!args.parse(static_cast<int>(rest.size()), rest.data())) {
    std::cout << args.help();
    return 0;
  }
  if (dirs.empty()) throw UsageError("merge needs the batch output folders to merge: stsim batch merge DIR... --out DIR");
  if (!args.has("out")) throw UsageError("merge needs --out DIR");
  std::vector<fs::path> paths(dirs.begin(), dirs.end());
  const fs::path out = args.get("out");
  const batch::FolderLock lock(out);
  const auto results = batch::mergeShards(paths, out);
  summarizeResults(results, out);
  std::string why;
  if (!args.has("no-plots") && !batch::writePlots(out, why)) std::cerr << "stsim batch: plots skipped: " << why << "\n";
  for (const auto& r : results)
    if (r.status != batch::RunStatus::Done) return 1;
  return 0;
}

// stsim batch's options
Args batchArgs() {
  Args args("batch",
            "Runs an experiment: the cross product of a sweep over scenario keys and seeds, one process per run,\n"
            "in parallel and resumable; writes runs.csv, summary.csv (mean, sd, 95% CI over seeds), plots and\n"
            "report.md. `stsim batch merge DIR... --out DIR` combines shard outputs.");
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  args.positional("EXPERIMENT.yaml", "the experiment (see networks/experiments/README.md)")
      .option("out", "DIR", "output folder", "out/<experiment name>")
      .option("jobs", "N", "runs at once", std::to_string(cores))
      .option("shard", "I/N", "run only the I-th (1-based) of N disjoint slices, e.g. --shard $SLURM_ARRAY_TASK_ID/4")
      .flag("mpi", "spread runs over MPI ranks (mpirun -np K stsim batch --mpi ...); rank 0 writes the tables")
      .flag("list", "print the runs (id and parameters) and exit")
      .option("max-runs", "N", "refuse an experiment of more runs than this (a runaway sweep)",
              std::to_string(batch::kDefaultMaxRuns))
      .flag("no-plots", "skip the PNG plots and report.md");
  return args;
}

// The runs this command makes: the experiment's (at most --max-runs), --shard's slice of them.
std::vector<batch::RunSpec> selectRuns(const Args& args, const batch::Experiment& e) {
  const long maxRuns = args.getInt("max-runs");
  if (maxRuns < 1) throw UsageError("--max-runs: expected a count >= 1, got " + args.get("max-runs"));
  std::vector<batch::RunSpec> runs = batch::expandRuns(e, static_cast<std::uint64_t>(maxRuns));
  if (!args.has("shard")) return runs;
  const std::string s = args.get("shard");
  int i = 0, n = 0;
  char tail = 0;
  if (std::sscanf(s.c_str(), "%d/%d%c", &i, &n, &tail) != 2 || n < 1 || i < 1 || i > n)
    throw UsageError("--shard wants I/N with 1 <= I <= N, got '" + s + "'");
  return batch::shardRuns(runs, i, n);
}

// --list: a run a line, its index, id, parameters and seed
void listRuns(const batch::Experiment& e, const std::vector<batch::RunSpec>& runs) {
  for (const auto& r : runs) {
    std::cout << r.index << " " << r.id;
    for (const auto& kv : r.params) std::cout << " " << kv.first << "=" << kv.second;
    std::cout << " " << e.seedKey << "=" << r.seed << "\n";
  }
}

// How the runner reports: a progress bar on a terminal, a line a run otherwise.
batch::BatchOptions runnerOptions(const fs::path& out, long jobs) {
  batch::BatchOptions o;
  o.outDir = out;
  o.stsim = fs::read_symlink("/proc/self/exe");
  o.jobs = static_cast<int>(jobs);
  const bool tty = isatty(STDERR_FILENO);
  if (tty) {
    o.progress = [](int done, int total, double elapsed) {
      const int width = 30;
      const int filled = total ? done * width / total : width;
      std::string eta = "--";
      if (done > 0 && elapsed > 0 && done < total) eta = formatDuration(elapsed / done * (total - done));
      std::fprintf(stderr, "\r[%s%s] %d/%d runs, ETA %s   ", std::string(filled, '#').c_str(),
                   std::string(width - filled, '.').c_str(), done, total, eta.c_str());
      if (done == total) std::fprintf(stderr, "\n");
    };
  } else {
    // a run's error line may quote anything (a scenario name with escape sequences)
    o.log = [](const std::string& line) { std::cerr << "batch: " << io::printable(line) << "\n"; };
  }
  return o;
}

int runBatch(int argc, const char* const* argv) {
  if (argc >= 1 && std::string(argv[0]) == "merge") return runMerge(argc - 1, argv + 1);
  Args args = batchArgs();
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  const batch::Experiment e = batch::loadExperiment(*args.positionalValue(0), optionalKeysFor);
  const std::vector<batch::RunSpec> runs = selectRuns(args, e);
  // the options are checked before --list too: a list is what the same command would run
  const long jobs = args.getInt("jobs");
  if (jobs < 1 || jobs > 1024) throw UsageError("--jobs must be between 1 and 1024");
  if (args.has("list")) {
    listRuns(e, runs);
    return 0;
  }
  const fs::path out = args.has("out") ? fs::path(args.get("out")) : fs::path("out") / e.name;
  batch::BatchOptions o = runnerOptions(out, jobs);
  // the guard installs its handlers without SA_RESTART: a signal wakes the runner's waitpid and
  // the runs are told to stop at once
  const StopSignals stopSignals;
  o.stopRequested = StopSignals::requested;

  // one batch per folder, locked before anything in it is read or written (MPI's ranks share
  // theirs: its launcher owns them all)
  std::optional<batch::FolderLock> lock;
  if (!args.has("mpi")) lock.emplace(out);
  batch::checkResumable(e, out);  // before any run: a folder of another experiment is left alone
  std::vector<batch::RunResult> results;
  bool root = true;
  if (args.has("mpi")) {
    if (!batch::mpiAvailable()) throw std::runtime_error("this stsim was built without MPI (apt-get install libopenmpi-dev, rebuild)");
    results = batch::executeRunsMpi(e, runs, o, root);
    if (!root) return 0;
  } else {
    batch::writeExperimentRecord(e, out);
    results = batch::executeRuns(e, runs, o);
  }
  if (args.has("mpi")) batch::writeExperimentRecord(e, out);
  batch::writeTables(e, results, out);
  summarizeResults(results, out);
  if (StopSignals::requested()) {
    std::cerr << "stsim batch: interrupted; finished runs are kept, re-run the same command to resume\n";
    return StopSignals::exitCode();  // 130 on Ctrl-C, 143 on SIGTERM, 129 on SIGHUP
  }
  std::string why;
  if (!args.has("no-plots") && !batch::writePlots(out, why)) std::cerr << "stsim batch: plots skipped: " << why << "\n";
  for (const auto& r : results)
    if (r.status != batch::RunStatus::Done) return 1;
  return 0;
}

}  // namespace

Command batchCommand() {
  return {"batch", "parameter sweeps and seeds over a scenario, with statistics and plots", runBatch};
}

}  // namespace st::cli
