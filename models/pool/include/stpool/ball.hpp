#pragma once
// Pool balls (§2.2): a circle with mass, number, colour and pattern.
#include <optional>
#include <string>

#include <stcore/vec.hpp>

namespace st::pool {

// Regulation ball: 2 1/4 in diameter, 6 oz.
inline constexpr double kBallRadius = 0.028575;  // m
inline constexpr double kBallMass = 0.170;       // kg
// Fastest ball a scenario may ask for (m/s). A hard break is about 10 m/s; a speed beyond this
// is a unit mistake, and at absurd speeds (1e300 m/s) positions overflow and balls leave the table.
inline constexpr double kMaxSpeed = 1000.0;

// The report's colours and patterns (§2.2), in its order.
enum class Colour { White, Yellow, Purple, Red, Blue, Orange, Green, Maroon, Black };
enum class Pattern { Solid, Striped };

const char* toString(Colour c);
const char* toString(Pattern p);
std::optional<Colour> parseColour(const std::string& text);
std::optional<Pattern> parsePattern(const std::string& text);
// Display colour as #rrggbb.
const char* hexOf(Colour c);

// The usual set: 0 white cue ball, 1-7 solids, 8 black, 9-15 stripes repeating 1-7's colours.
Colour defaultColour(int number);
Pattern defaultPattern(int number);

struct BallSpec {
  int number = 0;
  Vec2 position = Vec2::Zero();  // m
  Vec2 velocity = Vec2::Zero();  // m/s
  double radius = kBallRadius;
  double mass = kBallMass;
  Colour colour = Colour::White;
  Pattern pattern = Pattern::Solid;
};

// A ball of the usual set at p, at rest.
BallSpec makeBall(int number, const Vec2& p);

}  // namespace st::pool
