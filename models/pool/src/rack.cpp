#include <stpool/rack.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <stcore/hash.hpp>
#include <stcore/uniform_grid.hpp>

namespace st::pool {

std::uint64_t Rng::next() { return splitmixMix(state_ += kSplitmixGamma); }

double Rng::uniform() { return unitInterval(next()); }

std::vector<BallSpec> standardRack(const Table& table, const RackSpec& spec, Rng& rng) {
  const double w = table.spec.width, h = table.spec.height;
  const Vec2 apex = spec.apex.x() < 0 ? Vec2(0.75 * w, 0.5 * h) : spec.apex;
  const Vec2 cue = spec.cueBall.x() < 0 ? Vec2(0.25 * w, 0.5 * h) : spec.cueBall;
  // rows from the apex, each listed from low y to high y
  static constexpr std::array<std::array<int, 5>, 5> kRows = {{
      {1, 0, 0, 0, 0}, {9, 2, 0, 0, 0}, {10, 8, 3, 0, 0}, {4, 14, 7, 11, 0}, {12, 6, 15, 13, 5}}};
  const double pitch = 2.0 * spec.radius + spec.gap;
  std::vector<BallSpec> balls;
  BallSpec c = makeBall(0, cue);
  c.radius = spec.radius;
  c.mass = spec.mass;
  balls.push_back(c);
  for (int row = 0; row < 5; ++row) {
    for (int k = 0; k <= row; ++k) {
      Vec2 p = apex + Vec2(row * pitch * std::sqrt(3.0) / 2.0, (k - 0.5 * row) * pitch);
      if (spec.gap > 0.0) {
        // uniform in the disc of radius gap/4
        const double rr = 0.25 * spec.gap * std::sqrt(rng.uniform());
        const double phi = 2.0 * std::numbers::pi * rng.uniform();
        p += rr * Vec2(std::cos(phi), std::sin(phi));
      }
      BallSpec b = makeBall(kRows[row][k], p);
      b.radius = spec.radius;
      b.mass = spec.mass;
      balls.push_back(b);
    }
  }
  return balls;
}

std::vector<BallSpec> randomBalls(const Table& table, int count, double speed, double radius, double mass,
                                  double clearance, Rng& rng) {
  if (count < 0) throw std::invalid_argument("ball count must not be negative");
  std::vector<BallSpec> balls;
  const double lo = radius + clearance;
  const double w = table.spec.width, h = table.spec.height;
  // which placed balls are near a candidate: stcore's grid (one "who is near whom" in stsim), each
  // ball listed by its box grown by half the clearance; two balls closer than 2 radius + clearance
  // have boxes that overlap with room to spare, so share a cell, and the distance test below decides
  const double reach = radius + 0.5 * clearance;
  UniformGrid<2> placed(Aabb<2>{Vec2(0.0, 0.0), Vec2(w, h)}, 2.0 * reach);
  const long maxTries = 200L * count + 1000;
  long tries = 0;
  while (static_cast<int>(balls.size()) < count) {
    if (++tries > maxTries)
      throw std::invalid_argument("cannot place " + std::to_string(count) + " balls on the table without overlap");
    const Vec2 p(rng.uniform(lo, w - lo), rng.uniform(lo, h - lo));
    if (*placementProblem(table, p, radius) != '\0') continue;
    bool free = true;
    placed.forEachInBox(boundsOf<2>(p, reach), [&](int j) {
      if ((balls[j].position - p).norm() < 2.0 * radius + clearance) free = false;
    });
    if (!free) continue;
    const int number = static_cast<int>(balls.size());
    BallSpec b = makeBall(number, p);
    b.radius = radius;
    b.mass = mass;
    if (number > 15) {  // beyond the usual set: cycle its colours and patterns
      b.colour = defaultColour(1 + (number - 1) % 15);
      b.pattern = defaultPattern(1 + (number - 1) % 15);
    }
    const double phi = 2.0 * std::numbers::pi * rng.uniform();
    b.velocity = speed * Vec2(std::cos(phi), std::sin(phi));
    placed.insert(number, boundsOf<2>(p, reach));
    balls.push_back(b);
  }
  return balls;
}

}  // namespace st::pool
