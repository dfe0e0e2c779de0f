// Batch experiment reader: an experiment or one ExperimentError (its base resolves next to it).
#include <stbatch/experiment.hpp>

#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = st::fuzz::asFile(data, size, ".yaml");
  try {
    const auto e = st::batch::loadExperiment(path, std::vector<std::string>{"*"});
    double runs = static_cast<double>(e.seeds.size());
    for (const auto& axis : e.sweep) runs *= static_cast<double>(axis.values.size());
    if (runs < 10000) st::batch::expandRuns(e);  // a large cross product is valid, only slow
  } catch (const st::batch::ExperimentError&) {
  }
  return 0;
}
