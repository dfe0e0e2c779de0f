// Where the tool finds the files it ships (the plot scripts): beside the executable as installed
// (bin/../share/stsim), else the source tree's copy.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <stio/data_file.hpp>

namespace st::io {
namespace {

namespace fs = std::filesystem;

TEST(DataFile, InstalledCopyBesideTheExecutableFirstThenTheSourceTree) {
  const fs::path prefix = fs::temp_directory_path() / ("stsim_data_file_" + std::to_string(::getpid()));
  fs::remove_all(prefix);
  fs::create_directories(prefix / "bin");
  fs::create_directories(prefix / "share/stsim");
  const fs::path exe = prefix / "bin/stsim", source = "/src/batch/plots.py";
  // nothing installed: the source tree's copy
  EXPECT_EQ(dataFile("plots.py", source, exe), source);
  std::ofstream(prefix / "share/stsim/plots.py") << "# installed\n";
  EXPECT_EQ(dataFile("plots.py", source, exe), prefix / "share/stsim/plots.py");
  // another name is not there: the source tree's
  EXPECT_EQ(dataFile("conflict_map.py", "/src/conflict_map.py", exe), fs::path("/src/conflict_map.py"));
  // a directory of that name is not the file
  fs::create_directories(prefix / "share/stsim/dir.py");
  EXPECT_EQ(dataFile("dir.py", source, exe), source);
  // no executable known: the source tree's
  EXPECT_EQ(dataFile("plots.py", source, fs::path()), source);
  // the running test binary is not installed beside a share/stsim
  EXPECT_EQ(dataFile("plots.py", source), source);
  fs::remove_all(prefix);
}

}  // namespace
}  // namespace st::io
