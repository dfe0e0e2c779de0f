// Highway scenario reader (stcosim/scenario.hpp): a scenario YAML, or a .sumocfg when the input
// starts with '<', read beside the ring network's files (so sumocfg: ring.sumocfg resolves and
// the reader gets past it); the result, or one ScenarioError. SUMO's files themselves are read
// by their own readers (fuzz_net, fuzz_fcd), which may answer with their own one-line error.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <sthighway/sumo_files.hpp>
#include <stcosim/scenario.hpp>

namespace fs = std::filesystem;

namespace {

// A folder of this process's with the ring network linked in.
const fs::path& folder() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("stsim_fuzz_cosim_" + std::to_string(::getpid()));
    fs::create_directories(d);
    for (const char* f : {"ring.sumocfg", "ring.net.xml", "ring.rou.xml"}) {
      std::error_code ec;
      fs::create_symlink(fs::path(STSIM_SOURCE_DIR) / "networks/ring" / f, d / f, ec);
    }
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool sumocfg = size > 0 && data[0] == '<';
  // only this input's file: a YAML naming input.sumocfg must not read an earlier input
  fs::remove(folder() / "input.sumocfg");
  fs::remove(folder() / "input.yaml");
  const fs::path path = folder() / (sumocfg ? "input.sumocfg" : "input.yaml");
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    const st::cosim::Scenario s = st::cosim::loadScenario(path);
    st::cosim::checkSumoConfig(s.sumocfg);
    st::cosim::sumoArguments(s);
  } catch (const st::cosim::ScenarioError&) {
  } catch (const st::highway::InputError&) {  // a SUMO file named by the scenario, by its reader
  }
  return 0;
}
