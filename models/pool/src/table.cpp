#include <stpool/table.hpp>

#include <cmath>
#include <stdexcept>

namespace st::pool {

Rect Table::bounds() const {
  // a ball is captured before its centre gets further than depth + R <= mouth beyond a rail
  const double m = std::max(spec.cornerMouth, spec.sideMouth);
  return {Vec2(-m, -m), Vec2(spec.width + m, spec.height + m)};
}

Table makeTable(const TableSpec& spec) {
  if (!(spec.width > 0.0) || !(spec.height > 0.0)) throw std::invalid_argument("table size must be positive");
  Table t;
  t.spec = spec;
  const double w = spec.width, h = spec.height;
  if (!spec.pockets) {
    // a closed box, walls listed counter-clockwise so each interior side is on the left
    t.cushions = {{Vec2(0, 0), Vec2(w, 0)}, {Vec2(w, 0), Vec2(w, h)}, {Vec2(w, h), Vec2(0, h)}, {Vec2(0, h), Vec2(0, 0)}};
    return t;
  }
  // corner jaws sit c from the corner along each rail, so the mouth (jaw to jaw) is c*sqrt2
  const double c = spec.cornerMouth / std::sqrt(2.0);
  const double s = 0.5 * spec.sideMouth;
  if (!(spec.designBallRadius > 0.0) || c < spec.designBallRadius * std::sqrt(2.0) || s < spec.designBallRadius ||
      2.0 * c >= h || 2.0 * (c + s) >= w)
    throw std::invalid_argument("pocket mouths do not fit the table");
  const double xm = 0.5 * w;
  t.cushions = {
      {Vec2(c, 0), Vec2(xm - s, 0)},     {Vec2(xm + s, 0), Vec2(w - c, 0)},  // bottom rail
      {Vec2(w, c), Vec2(w, h - c)},                                          // right (foot) rail
      {Vec2(w - c, h), Vec2(xm + s, h)}, {Vec2(xm - s, h), Vec2(c, h)},      // top rail
      {Vec2(0, h - c), Vec2(0, c)},                                          // left (head) rail
  };
  for (const Segment& seg : t.cushions) {
    t.jaws.push_back(seg.a);
    t.jaws.push_back(seg.b);
  }
  // Each pocket is a capture circle behind its mouth (the line between its two jaws), centred
  // `depth` behind the mouth's midpoint with radius R = sqrt((h - r)^2 + depth^2), h the half-mouth
  // and r the design ball radius. Then (1) every centre that passes between the jaws without
  // touching them is within R, so no ball leaves the table uncaptured, and (2) a ball touching a
  // jaw from the table side is outside R (its distance exceeds R by 2hr(1 - cos a) + 2r depth sin a
  // > 0 for contact angle a), so jaws stay strikeable. depth = r keeps a ball rolling along a
  // long rail from dropping into a side pocket, as on a real table.
  const double r = spec.designBallRadius, depth = r;
  auto pocket = [&](const Vec2& jaw1, const Vec2& jaw2, const Vec2& outward) {
    const double half = 0.5 * (jaw2 - jaw1).norm();
    return Sensor<2>{0.5 * (jaw1 + jaw2) + depth * outward.normalized(), std::hypot(half - r, depth)};
  };
  t.pockets = {pocket(Vec2(c, 0), Vec2(0, c), Vec2(-1, -1)),
               pocket(Vec2(xm - s, 0), Vec2(xm + s, 0), Vec2(0, -1)),
               pocket(Vec2(w - c, 0), Vec2(w, c), Vec2(1, -1)),
               pocket(Vec2(w, h - c), Vec2(w - c, h), Vec2(1, 1)),
               pocket(Vec2(xm + s, h), Vec2(xm - s, h), Vec2(0, 1)),
               pocket(Vec2(0, h - c), Vec2(c, h), Vec2(-1, 1))};
  return t;
}

const char* placementProblem(const Table& table, const Vec2& p, double radius) {
  const TableSpec& s = table.spec;
  if (!(p.x() >= radius && p.x() <= s.width - radius && p.y() >= radius && p.y() <= s.height - radius))
    return "ball is off the table (its edge crosses a cushion)";
  for (const auto& pk : table.pockets)
    if ((p - pk.center).norm() <= pk.radius) return "ball is inside a pocket's capture circle";
  return "";
}

}  // namespace st::pool
