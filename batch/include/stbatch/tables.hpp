#pragma once
// The experiment's tables over its runs' results.
#include <filesystem>
#include <vector>

#include <stbatch/experiment.hpp>
#include <stbatch/run_result.hpp>

namespace st::batch {

// Writes runs.csv, summary.csv and paired.csv (atomically) for the given results, in run-index
// order. paired.csv: each swept key's values against its first value, other keys held, as
// differences run by run on the same seed (mean, sd, 95 % CI of the differences). Highway runs
// also get hindsight.csv: per combination, pooled over its seeds, each warning kind's warnings
// per vehicle-km and confirmed share, the near misses' recall and median lead time (empty where
// nothing was counted). A figure a run's summary gives as null is an empty cell in every table.
void writeTables(const Experiment& e, std::vector<RunResult> results, const std::filesystem::path& outDir);

}  // namespace st::batch
