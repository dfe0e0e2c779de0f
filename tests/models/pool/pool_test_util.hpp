#pragma once
// Helpers for the pool tests: small scenarios built in code, the stsim command run as a user would.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

#include <stpool/game.hpp>
#include <stpool/rack.hpp>
#include <stpool/scenario.hpp>

#include "files.hpp"

namespace st::pool::test {

inline Scenario oneTable(bool pockets) {
  Scenario s;
  s.name = "test";
  s.table.pockets = pockets;
  return s;
}

inline BallSpec ball(int number, Vec2 p, Vec2 v = Vec2::Zero(), double mass = kBallMass) {
  BallSpec b = makeBall(number, p);
  b.velocity = v;
  b.mass = mass;
  return b;
}

inline SimulatorConfig config(SpaceKind kind, int df = 5) {
  SpaceSpec s;
  s.kind = kind;
  s.decompositionFactor = df;
  return simulatorConfig(s, TableSpec{}, {});
}

// Simulator events only (no strikes, stops or space crossings): the shot's physical history.
inline std::vector<PoolEvent> physical(const std::vector<PoolEvent>& all) {
  std::vector<PoolEvent> out;
  for (const auto& e : all)
    if (e.kind != PoolEventKind::Boundary && e.kind != PoolEventKind::Strike && e.kind != PoolEventKind::Stop)
      out.push_back(e);
  return out;
}

// `stsim ARGS` (the built binary), its exit code and its stdout + stderr.
struct Ran {
  int code;
  std::string out;
};

inline Ran runStsim(const std::string& args) {
  const std::string cmd = std::string(STSIM_BINARY) + " " + args + " 2>&1";
  Ran r{-1, ""};
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) r.out += buf;
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

using st::test::slurp;

// A fresh, empty folder name under the system's temp directory.
inline std::filesystem::path tempDir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("stsim_pool_test_" + name);
  std::filesystem::remove_all(d);
  return d;
}

}  // namespace st::pool::test
