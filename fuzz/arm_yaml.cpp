// Arm scenario reader: a scenario or one InputError.
#include <starm/scenario.hpp>

#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = st::fuzz::asFile(data, size, ".yaml");
  try {
    st::arm::loadScenario(path);
  } catch (const st::arm::InputError&) {
  }
  return 0;
}
