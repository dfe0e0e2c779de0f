#pragma once
// MPI mode: `mpirun -np K stsim batch --mpi EXPERIMENT.yaml`. Runs are dealt to ranks in turn;
// each rank executes its share (one process per run); rank 0 gathers every rank's outcomes and
// writes the tables. The output folder must be on a file system all ranks share.
#include <stbatch/runner.hpp>

namespace st::batch {

// True when this build has MPI support.
bool mpiAvailable();

// Runs the batch under MPI; returns the results on rank 0 (empty on other ranks) and sets isRoot.
std::vector<RunResult> executeRunsMpi(const Experiment& e, const std::vector<RunSpec>& runs,
                                      const BatchOptions& o, bool& isRoot);

}  // namespace st::batch
