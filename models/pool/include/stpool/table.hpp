#pragma once
// The pool table (§2.4, §2.5): cushions as segments, pocket jaws as the segments' end points,
// pockets as capture circles. Coordinates: origin at the lower-left corner of the playing
// surface, x along the long side, metres.
#include <vector>

#include <stcore/shapes.hpp>
#include <stcore/simulator.hpp>

namespace st::pool {

struct TableSpec {
  double width = 2.54;          // m, playing surface of a 9-ft table
  double height = 1.27;         // m
  bool pockets = true;          // false: a closed box
  double cornerMouth = 0.116;   // m, jaw-to-jaw opening of a corner pocket (WPA 4.5-4.625 in)
  double sideMouth = 0.129;     // m, jaw-to-jaw opening of a side pocket (WPA 5-5.125 in)
  double designBallRadius = 0.028575;  // m, the ball the pocket capture circles are sized for
};

struct Table {
  TableSpec spec;
  std::vector<Segment> cushions;  // ball edges bounce off these (interior faces)
  std::vector<Vec2> jaws;         // cushion ends at the pocket mouths (a ball can strike them)
  std::vector<Sensor<2>> pockets; // a ball whose centre enters one is pocketed
  Rect surface() const { return {Vec2(0, 0), Vec2(spec.width, spec.height)}; }
  // Region the simulator's space covers: the surface plus the pocket mouths.
  Rect bounds() const;
};

// Builds the table; throws std::invalid_argument for a table too small for its pockets or
// pocket mouths narrower than a ball.
Table makeTable(const TableSpec& spec);

// Why a ball may not be placed at p: "" if it may.
const char* placementProblem(const Table& table, const Vec2& p, double radius);

}  // namespace st::pool
