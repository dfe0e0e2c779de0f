// .net.xml reader: lanes or one InputError.
#include <sthighway/sumo_files.hpp>

#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = st::fuzz::asFile(data, size, ".net.xml");
  try {
    std::vector<std::string> leftOut;
    const auto road = st::highway::readSumoNet(path, &leftOut);
    st::highway::fcdChecksFor(road, leftOut, path);
  } catch (const st::highway::InputError&) {
  }
  return 0;
}
