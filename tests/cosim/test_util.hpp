#pragma once
// Helpers for the cosim tests: run the stsim binary, read its outputs.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sthighway/report.hpp>

#include "files.hpp"
#include "process.hpp"

namespace st::cosim::test {

inline std::filesystem::path sourceDir() { return STSIM_SOURCE_DIR; }
inline std::filesystem::path motorway() { return sourceDir() / "networks/motorway/scenario.yaml"; }

// A fresh directory under the build's temp area.
inline std::filesystem::path freshDir(const std::string& name) { return st::test::freshDir("cosim_test", name); }
inline std::filesystem::path testDir(const std::string& name) { return st::test::testDir("cosim_test", name); }

using st::test::slurp;

inline std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  std::string l;
  while (std::getline(in, l))
    if (!l.empty()) out.push_back(l);
  return out;
}

// The fields of a CSV line without quoting (ids and numbers).
inline std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (c == ',') out.emplace_back();
    else out.back() += c;
  }
  return out;
}

// A number after "key": in a JSON text (first occurrence); NaN if absent.
inline double jsonNumber(const std::string& json, const std::string& key, std::size_t from = 0) {
  const auto k = json.find("\"" + key + "\":", from);
  if (k == std::string::npos) return std::nan("");
  return std::stod(json.substr(k + key.size() + 3));
}
inline std::string jsonString(const std::string& json, const std::string& key) {
  std::smatch m;
  const std::regex re("\"" + key + "\": \"([^\"]*)\"");
  return std::regex_search(json, m, re) ? m[1].str() : std::string();
}

// stsim started as a child process; stdout/stderr go to files in `dir`.
class StsimProcess : public st::test::Process {
 public:
  // `launcher` runs stsim (e.g. {"xvfb-run", "-a"}), found on PATH.
  StsimProcess(const std::vector<std::string>& args, const std::filesystem::path& dir,
               const std::vector<std::string>& launcher = {})
      : Process(argvOf(args, launcher), dir) {}

 private:
  static std::vector<std::string> argvOf(const std::vector<std::string>& args, const std::vector<std::string>& launcher) {
    std::vector<std::string> argv = launcher;
    argv.push_back(STSIM_BINARY);
    argv.insert(argv.end(), args.begin(), args.end());
    return argv;
  }
};

// Waits until `csv` holds at least one warning row (the run has stepped and finished an
// episode); false if the process exits first, or after 10 minutes (a run that hangs fails the
// test instead of blocking it; no working run comes near that). The caller's scenario must
// produce warnings early and not end on its own.
inline bool waitForWarningRows(const std::filesystem::path& csv, StsimProcess& p) {
  const auto giveUp = std::chrono::steady_clock::now() + std::chrono::minutes(10);
  while (std::chrono::steady_clock::now() < giveUp) {
    if (lines(slurp(csv)).size() >= 2) return true;
    if (!p.running()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

struct RunResult {
  int code;
  std::string out, err;
};
inline RunResult runStsim(const std::vector<std::string>& args, const std::filesystem::path& dir,
                          const std::vector<std::string>& launcher = {}) {
  StsimProcess p(args, dir, launcher);
  const int code = p.wait();
  return {code, p.out(), p.err()};
}

// The full path of an executable on PATH, or "".
inline std::string onPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string d;
  while (std::getline(dirs, d, ':')) {
    const auto f = std::filesystem::path(d.empty() ? "." : d) / name;
    if (::access(f.c_str(), X_OK) == 0) return f.string();
  }
  return {};
}

// warnings.csv must be the header plus rows of as many fields.
inline bool validWarningsCsv(const std::filesystem::path& p, std::size_t* rows = nullptr) {
  const auto ls = lines(slurp(p));
  if (ls.empty() || ls[0] != st::highway::warningsCsvHeader()) return false;
  const auto fields = std::count(ls[0].begin(), ls[0].end(), ',');
  for (std::size_t i = 1; i < ls.size(); ++i)
    if (std::count(ls[i].begin(), ls[i].end(), ',') != fields) return false;
  if (rows) *rows = ls.size() - 1;
  return true;
}

}  // namespace st::cosim::test
