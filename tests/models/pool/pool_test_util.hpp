#pragma once
// Helpers for the pool tests: small scenarios built in code.
#include <stpool/game.hpp>
#include <stpool/rack.hpp>
#include <stpool/scenario.hpp>

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

}  // namespace st::pool::test
