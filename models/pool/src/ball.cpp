#include <stpool/ball.hpp>

#include <array>

namespace st::pool {

namespace {
constexpr std::array<const char*, 9> kColourNames = {"white", "yellow", "purple", "red",   "blue",
                                                     "orange", "green", "maroon", "black"};
// Cloth-friendly approximations of the real ball colours.
constexpr std::array<const char*, 9> kColourHex = {"#f8f8f0", "#f5c518", "#5b2a86", "#d62828", "#1d4ed8",
                                                   "#f77f00", "#2d6a4f", "#7f1d1d", "#111111"};
// Colour of balls 1..7 (and 9..15): yellow, blue, red, purple, orange, green, maroon.
constexpr std::array<Colour, 7> kSetColours = {Colour::Yellow, Colour::Blue,  Colour::Red,   Colour::Purple,
                                               Colour::Orange, Colour::Green, Colour::Maroon};
}  // namespace

const char* toString(Colour c) { return kColourNames[static_cast<int>(c)]; }
const char* toString(Pattern p) { return p == Pattern::Solid ? "solid" : "striped"; }
const char* hexOf(Colour c) { return kColourHex[static_cast<int>(c)]; }

std::optional<Colour> parseColour(const std::string& text) {
  for (int i = 0; i < static_cast<int>(kColourNames.size()); ++i)
    if (text == kColourNames[i]) return static_cast<Colour>(i);
  return std::nullopt;
}

std::optional<Pattern> parsePattern(const std::string& text) {
  if (text == "solid") return Pattern::Solid;
  if (text == "striped" || text == "stripe") return Pattern::Striped;
  return std::nullopt;
}

Colour defaultColour(int number) {
  if (number == 8) return Colour::Black;
  if (number >= 1 && number <= 15) return kSetColours[(number - 1) % 8];
  return Colour::White;
}

Pattern defaultPattern(int number) { return number >= 9 && number <= 15 ? Pattern::Striped : Pattern::Solid; }

BallSpec makeBall(int number, const Vec2& p) {
  BallSpec b;
  b.number = number;
  b.position = p;
  b.colour = defaultColour(number);
  b.pattern = defaultPattern(number);
  return b;
}

}  // namespace st::pool
