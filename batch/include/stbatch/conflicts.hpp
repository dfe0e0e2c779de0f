#pragma once
// SSAM's comparison of designs over an experiment's highway runs: each run's conflicts.csv (one
// row per conflict, a pair and one encounter below TTC*, counted once; not the warnings, which are
// per ego), of a conflict type (rear_end, lane_change, crossing, pedestrian), pooled per parameter combination
// over its seeds.
#include <filesystem>
#include <vector>

#include <stbatch/experiment.hpp>
#include <stbatch/run_result.hpp>

namespace st::batch {

// The SSAM measures compared, as conflicts.csv names them; a column a run's file lacks is skipped.
inline constexpr const char* kConflictMeasures[] = {"min_ttc", "pet", "drac", "max_s", "delta_s",
                                                    "dr", "max_d", "max_delta_v"};

// The conflict types, in the tables' order: SSAM's three and a vehicle with a person on foot.
inline constexpr const char* kConflictTypes[] = {"rear_end", "lane_change", "crossing", "pedestrian"};

// One run's conflicts.csv as the batch counts it: the rows of the conflict types whose encounter
// began at or after `warmup` (s), each with the measures the file has (NaN where empty or not
// finite).
struct RunConflicts {
  std::vector<std::string> measures;  // of kConflictMeasures, those the file's header names
  // the file names the road users' classes (first_class, second_class: every stsim conflicts.csv);
  // without them no row is known to have a bicycle in it
  bool classes = false;
  struct Row {
    std::string type;
    std::vector<double> values;  // by `measures`
    bool withBicycle = false;    // either road user's class is `bicycle`
  };
  std::vector<Row> rows;
};
// Throws std::runtime_error naming the file (and the line) when it is missing, cut short or not a
// table (files.hpp's readCsvTable), when its header lacks `type` or (warmup > 0) `begin`, or when a
// `begin` or measure cell holds text that is not a number: a done highway run always writes it whole.
RunConflicts readRunConflicts(const std::filesystem::path& file, double warmup);

// Writes conflicts.csv (per combination: the conflicts by type, and per measure its n, mean, sd and
// 95 % CI over the pooled conflicts after the experiment's warm-up) and conflicts_compared.csv (each swept key's values against
// its first, the other keys held: per measure the difference of the means with its Welch 95 % CI
// and t, SSAM's t-test of two designs). Nothing is written when no run is done. Throws
// readRunConflicts' errors.
void writeConflictTables(const Experiment& e, const std::vector<RunResult>& results,
                         const std::filesystem::path& outDir);

}  // namespace st::batch
