// FCD trace reader: frames or one InputError naming file:line.
#include <sthighway/sumo_files.hpp>

#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = st::fuzz::asFile(data, size, ".fcd.xml");
  try {
    st::highway::FcdChecks checks;
    checks.bounded = true;
    checks.lo = st::Vec2(0, -200);
    checks.hi = st::Vec2(3000, 0);
    st::highway::FcdReader r(path, {}, checks);
    st::highway::FcdFrame f;
    for (int i = 0; i < 10000 && r.next(f); ++i) {
    }
  } catch (const st::highway::InputError&) {
  }
  return 0;
}
