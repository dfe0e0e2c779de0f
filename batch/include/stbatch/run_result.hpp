#pragma once
// One run's result as the batch reads it back from runs/<id>: its status, error, wall time and
// the numeric leaves of its summary.json.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <stbatch/experiment.hpp>

namespace st::batch {

enum class RunStatus { Done, Failed, Missing };
const char* toString(RunStatus s);

struct RunResult {
  RunSpec spec;
  RunStatus status = RunStatus::Missing;
  std::string error;          // one line, for failed runs
  double wallSeconds = 0.0;
  bool reused = false;        // finished by an earlier invocation
  std::vector<std::pair<std::string, double>> metrics;  // numeric leaves of summary.json, flattened
};

// Reads the result of one run from outDir/runs/<id>, if there is one.
RunResult loadRunResult(const std::filesystem::path& outDir, const RunSpec& spec);

}  // namespace st::batch
