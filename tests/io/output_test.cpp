// The one checked writer: a failed write is an exception naming the file, and what was there or
// what was written before stays whole.
#include <gtest/gtest.h>

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <sstream>

#include <stio/output.hpp>

#include "files.hpp"

namespace st::io {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) { return st::test::freshDir("output", name); }

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(Output, AtomicWriteReplacesTheFileWhole) {
  const fs::path d = freshDir("atomic");
  writeFileAtomically(d / "runs.csv", "a\n1\n");
  EXPECT_EQ(contents(d / "runs.csv"), "a\n1\n");
  writeFileAtomically(d / "runs.csv", "a\n2\n");
  EXPECT_EQ(contents(d / "runs.csv"), "a\n2\n");
  EXPECT_FALSE(fs::exists(d / "runs.csv.tmp"));
  fs::remove_all(d);
}

TEST(Output, AFullDiskIsAnErrorNamingTheFileAndTheOldFileStays) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path d = freshDir("full");
  writeFileAtomically(d / "runs.csv", "a\n1\n");
  ::setenv("STSIM_TEST_FULL_FILE", "runs.csv", 1);
  EXPECT_EQ(errorOf([&] { writeFileAtomically(d / "runs.csv", "a\n2\n"); }), "write failed: " + (d / "runs.csv").string());
  EXPECT_EQ(errorOf([&] { writeTextFile(d / "runs.csv", "x"); }), "write failed: " + (d / "runs.csv").string());
  EXPECT_EQ(errorOf([&] { CsvRowWriter w(d / "runs.csv", "a"); }), "write failed: " + (d / "runs.csv").string());
  // another name is written
  writeFileAtomically(d / "summary.csv", "s\n");
  ::unsetenv("STSIM_TEST_FULL_FILE");
  EXPECT_EQ(contents(d / "runs.csv"), "a\n1\n");
  EXPECT_EQ(contents(d / "summary.csv"), "s\n");
  EXPECT_FALSE(fs::exists(d / "runs.csv.tmp"));
  fs::remove_all(d);
}

TEST(Output, AtomicWriteGoesThroughASymlinkToADevice) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path d = freshDir("symlink");
  fs::create_symlink("/dev/full", d / "runs.csv");
  EXPECT_EQ(errorOf([&] { writeFileAtomically(d / "runs.csv", "a\n"); }), "write failed: " + (d / "runs.csv").string());
  EXPECT_TRUE(fs::is_symlink(d / "runs.csv"));  // not replaced by a file beside the device
  fs::remove_all(d);
}

}  // namespace
}  // namespace st::io
