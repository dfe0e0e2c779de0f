#include <mpi.h>

#include <sstream>
#include <stbatch/mpi.hpp>

namespace st::batch {

bool mpiAvailable() { return true; }

std::vector<RunResult> executeRunsMpi(const Experiment& e, const std::vector<RunSpec>& runs,
                                      const BatchOptions& o, bool& isRoot) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) MPI_Init(nullptr, nullptr);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  isRoot = rank == 0;
  if (isRoot) std::filesystem::create_directories(o.outDir / "runs");
  MPI_Barrier(MPI_COMM_WORLD);

  std::vector<RunSpec> mine;
  for (const auto& r : runs)
    if (r.index % size == rank) mine.push_back(r);
  BatchOptions local = o;
  if (!isRoot) local.progress = nullptr;  // one progress display: rank 0's share
  const std::vector<RunResult> done = executeRuns(e, mine, local);

  // gather "index status" lines at rank 0
  std::ostringstream os;
  for (const auto& r : done) os << r.spec.index << ' ' << toString(r.status) << '\n';
  const std::string text = os.str();
  const int len = static_cast<int>(text.size());
  std::vector<int> lens(size), displs(size);
  MPI_Gather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string all;
  if (isRoot) {
    int total = 0;
    for (int i = 0; i < size; ++i) {
      displs[i] = total;
      total += lens[i];
    }
    all.resize(total);
  }
  MPI_Gatherv(text.data(), len, MPI_CHAR, all.data(), lens.data(), displs.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  std::vector<RunResult> results;
  if (isRoot) {
    std::vector<bool> reported(runs.size(), false);
    std::istringstream in(all);
    int index;
    std::string status;
    while (in >> index >> status)
      if (index >= 0 && index < static_cast<int>(runs.size())) reported[index] = true;
    for (const auto& r : runs) {
      RunResult res = loadRunResult(o.outDir, r);
      if (!reported[r.index] && res.status == RunStatus::Missing) res.error = "no rank reported this run";
      results.push_back(res);
    }
  }
  MPI_Finalize();
  return results;
}

}  // namespace st::batch
