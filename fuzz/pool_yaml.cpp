// Pool scenario reader: any text is a scenario or one ScenarioError; nothing else may escape.
#include <stpool/scenario.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    st::pool::parseScenario(std::string(reinterpret_cast<const char*>(data), size), "f.yaml");
  } catch (const st::pool::ScenarioError&) {
  }
  return 0;
}
