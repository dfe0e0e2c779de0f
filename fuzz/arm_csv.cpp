// Arm sensor CSV: readings or one InputError naming file:line.
#include <starm/sensor.hpp>

#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = st::fuzz::asFile(data, size, ".csv");
  try {
    st::arm::CsvSensor s(path, {"a", "b"}, {7, 6});
    st::arm::Reading r;
    for (int i = 0; i < 10000 && s.next(r); ++i) {
    }
  } catch (const st::arm::InputError&) {
  }
  return 0;
}
