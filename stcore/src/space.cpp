#include <stcore/space.hpp>

#include <cmath>
#include <stdexcept>

namespace st {

bool parseSpaceKind(const std::string& text, SpaceKind& out) {
  if (text == "none") out = SpaceKind::None;
  else if (text == "single") out = SpaceKind::Single;
  else if (text == "tree" || text == "quadtree" || text == "octree") out = SpaceKind::Tree;
  else if (text == "cells") out = SpaceKind::Cells;
  else return false;
  return true;
}

const char* toString(SpaceKind kind) {
  switch (kind) {
    case SpaceKind::None: return "none";
    case SpaceKind::Single: return "single";
    case SpaceKind::Tree: return "tree";
    case SpaceKind::Cells: return "cells";
  }
  return "?";
}

double reachTime(double x0, double v, double a, double wall, double horizon) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (v == 0.0) return kInf;
  // along the direction of motion: distance d >= 0 to go at speed s, slowing at rate b >= 0
  const double d = v > 0.0 ? wall - x0 : x0 - wall;
  if (!(d > 0.0)) return 0.0;
  const double s = std::abs(v);
  const double b = std::abs(a);
  double t;
  if (b == 0.0) {
    t = d / s;
  } else {
    // s t - b t^2 / 2 = d: the smaller root, in the form without cancellation
    const double disc = s * s - 2.0 * b * d;
    if (disc < 0.0) return kInf;  // stops short of the wall
    t = 2.0 * d / (s + std::sqrt(disc));
  }
  return t <= horizon ? t : kInf;
}

template <int D>
typename Space<D>::Impl Space<D>::make(SpaceKind kind, const Box& bounds, const SpaceRule& rule) {
  switch (kind) {
    case SpaceKind::Single: return Impl(std::in_place_type<SingleList<D>>, bounds);
    case SpaceKind::Tree: return Impl(std::in_place_type<RegionTree<D>>, bounds, rule);
    case SpaceKind::Cells: return Impl(std::in_place_type<UniformGrid<D>>, bounds, rule.cellSize);
    case SpaceKind::None: break;
  }
  throw std::invalid_argument("a space needs a kind: single, tree or cells");
}

template <int D>
Space<D>::Space(SpaceKind kind, const Box& bounds, const SpaceRule& rule)
    : kind_(kind), bounds_(bounds), rule_(rule), impl_(make(kind, bounds, rule)) {
  if (const auto* t = std::get_if<RegionTree<D>>(&impl_)) rule_ = t->rule();  // divisions resolved
  if (kind_ == SpaceKind::Single) rule_.subdivide = false;
}

template <int D>
bool Space<D>::update(int id, const Box& box, double margin) {
  if (auto* g = std::get_if<UniformGrid<D>>(&impl_)) {
    // the grid's visits change only when a block does
    const std::uint64_t before = g->revision();
    g->update(id, box, margin);
    if (g->revision() == before) return false;
    ++revision_;
    return true;
  }
  ++revision_;
  if (auto* t = std::get_if<RegionTree<D>>(&impl_)) return t->update(id, box, margin);
  std::get<SingleList<D>>(impl_).update(id, box, margin);
  return false;
}

template class Space<2>;
template class Space<3>;

}  // namespace st
