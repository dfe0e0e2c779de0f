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
