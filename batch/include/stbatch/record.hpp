#pragma once
// The experiment as resolved for a batch, recorded in its output folder: what resuming checks,
// what shards are merged by.
#include <filesystem>
#include <vector>

#include <stbatch/experiment.hpp>
#include <stbatch/run_result.hpp>

namespace st::batch {

// The experiment as resolved for this batch (absolute base), stored in the output folder so
// shards can be merged and checked to be of the same experiment.
void writeExperimentRecord(const Experiment& e, const std::filesystem::path& outDir);
// Throws ExperimentError if outDir already records a different experiment (resuming it would mix
// the two experiments' runs in one table). Called by writeExperimentRecord.
void checkResumable(const Experiment& e, const std::filesystem::path& outDir);
Experiment readExperimentRecord(const std::filesystem::path& outDir);

// Merges shard output folders into `outDir`: run folders are copied, tables rebuilt.
std::vector<RunResult> mergeShards(const std::vector<std::filesystem::path>& dirs, const std::filesystem::path& outDir);

}  // namespace st::batch
