#pragma once
// Files for the tests: a fresh folder per test process, a whole file read back.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace st::test {

// The folder `name` under <temp>/stsim_<area>_<pid>/: each test process its own, so tests run in
// parallel never share one.
inline std::filesystem::path testDir(const std::string& area, const std::string& name) {
  return std::filesystem::temp_directory_path() / ("stsim_" + area + "_" + std::to_string(::getpid())) / name;
}

// The same, fresh and empty.
inline std::filesystem::path freshDir(const std::string& area, const std::string& name) {
  const auto d = testDir(area, name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// The whole file as text ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace st::test
