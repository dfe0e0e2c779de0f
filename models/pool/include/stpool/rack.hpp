#pragma once
// Ball sets: the standard 15-ball triangle rack with the cue ball, and seeded random fills.
#include <cstdint>
#include <vector>

#include <stpool/ball.hpp>
#include <stpool/table.hpp>

namespace st::pool {

// A small deterministic generator (SplitMix64): same numbers on every platform and standard
// library for a seed, unlike std::uniform_real_distribution.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  double uniform();                          // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  std::uint64_t state_;
};

struct RackSpec {
  // Each ball sits on a lattice of pitch 2r + gap and is then moved by a random offset of at most
  // gap/4, so neighbours are 2r + gap/2 .. 2r + 3gap/2 apart: no two contacts happen at the
  // same instant, yet the rack is tight. gap = 0 gives the exact (degenerate) frozen rack.
  double gap = 0.0;                          // m
  Vec2 apex = Vec2(-1, -1);                  // foot spot (3/4 of the length, centred) if negative
  Vec2 cueBall = Vec2(-1, -1);               // head spot (1/4 of the length, centred) if negative
  double radius = kBallRadius;
  double mass = kBallMass;
};

// Cue ball (number 0) first, then the 15 object balls: 1 at the apex, 8 in the middle of the
// third row, a solid and a stripe in the back corners; the triangle points towards -x.
std::vector<BallSpec> standardRack(const Table& table, const RackSpec& spec, Rng& rng);

// count balls placed uniformly at random on the table without overlap (at least `clearance`
// between edges), each moving at `speed` in a random direction (0: at rest). Throws
// std::invalid_argument if they do not fit after many tries.
std::vector<BallSpec> randomBalls(const Table& table, int count, double speed, double radius, double mass,
                                  double clearance, Rng& rng);

}  // namespace st::pool
