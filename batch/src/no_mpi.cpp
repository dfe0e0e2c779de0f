#include <stdexcept>
#include <stbatch/mpi.hpp>

namespace st::batch {

bool mpiAvailable() { return false; }

std::vector<RunResult> executeRunsMpi(const Experiment&, const std::vector<RunSpec>&, const BatchOptions&, bool&) {
  throw std::runtime_error("built without MPI");
}

}  // namespace st::batch
