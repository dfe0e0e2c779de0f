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
    case SpaceKind::Tree: {
      SpaceRule r = rule;
      if (r.autoFactor) r.decompositionFactor = rule.autoStart;
      return Impl(std::in_place_type<RegionTree<D>>, bounds, r);
    }
    case SpaceKind::Cells: return Impl(std::in_place_type<UniformGrid<D>>, bounds, rule.cellSize);
    case SpaceKind::None: return Impl(std::in_place_type<BruteForce<D>>, bounds);
  }
  throw std::invalid_argument("a space needs a kind: none, single, tree or cells");
}

template <int D>
Space<D>::Space(SpaceKind kind, const Box& bounds, const SpaceRule& rule)
    : kind_(kind), bounds_(bounds), rule_(rule), impl_(make(kind, bounds, rule)) {
  if (const auto* t = std::get_if<RegionTree<D>>(&impl_)) rule_ = t->rule();  // divisions resolved
  if (kind_ == SpaceKind::Single || kind_ == SpaceKind::None) rule_.subdivide = false;
  tuning_ = kind_ == SpaceKind::Tree && rule_.autoFactor && rule_.subdivide;
  if (rule_.autoFactor && !(rule_.autoRegionCost > 0.0))
    throw std::invalid_argument("the auto decomposition factor needs a positive region cost");
  if (rule_.autoFactor && rule_.autoStart < 1)
    throw std::invalid_argument("the auto decomposition factor needs a start of at least 1");
}

// auto: one update measured; at the end of a window, the factor for the next (true if it changed).
template <int D>
bool Space<D>::tune(int id, const Box& box, bool changed) {
  // the walls of one division lie half the bounds apart along each axis
  const Vec<D> c = box.center();
  const Vec<D> half = 0.5 * bounds_.extent();
  tuner_.noteUpdate(changed, ((c - centre_[id]).cwiseAbs().array() / half.array()).sum());
  centre_[id] = c;
  return decideIfFull();
}

// auto: at the end of a window, the factor for the next (true if it changed).
template <int D>
bool Space<D>::decideIfFull() {
  if (!tuner_.windowFull(objects_)) return false;
  RegionTree<D>& t = std::get<RegionTree<D>>(impl_);
  const int df = tuner_.decide(rule_.decompositionFactor, t.leafCount() > 1, objects_, D, rule_.autoRegionCost);
  if (df == rule_.decompositionFactor) return false;
  t.setDecompositionFactor(df);
  rule_.decompositionFactor = df;
  return true;
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
  if (auto* t = std::get_if<RegionTree<D>>(&impl_)) {
    const bool changed = t->update(id, box, margin);
    // a new factor re-lists objects, this one perhaps among them
    return tuning_ && tune(id, box, changed) ? true : changed;
  }
  // one region or none: the neighbours never change
  visit([&](auto& s) { s.update(id, box, margin); });
  return false;
}

template class Space<2>;
template class Space<3>;

}  // namespace st
