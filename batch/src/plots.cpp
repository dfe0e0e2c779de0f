#include <stbatch/plots.hpp>

#include <cstdlib>

#include <stio/data_file.hpp>

#include "files.hpp"

namespace st::batch {

namespace fs = std::filesystem;
using namespace detail;

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
    why = "plotting failed: " + lastLogLine(outDir / "plots.log");
    return false;
  }
  return true;
}

}  // namespace st::batch
