#pragma once
// What an index's forEachInBox found for a box grown by a tenth of its size, kept while the index
// is unchanged (its revision) and later boxes lie inside the grown one: a superset of each later
// box's visit, which every caller filters by its own box (the cells by their centres, the
// features by the line prune; a hazard is checked exactly per ego). A group of cars' box drifts
// metres a tick: it is recomputed every few hundred metres, or when the index changes.
#include <cstdint>
#include <vector>

#include <stcore/space.hpp>

namespace st::highway::detail {

struct IndexVisit {
  Aabb<2> covered{Vec2::Constant(std::numeric_limits<double>::infinity()),
                  Vec2::Constant(-std::numeric_limits<double>::infinity())};  // empty: nothing kept
  std::uint64_t revision = ~std::uint64_t{0};
  std::vector<int> ids;
};

inline const std::vector<int>& cachedVisit(const Space<2>& index, const Aabb<2>& box, IndexVisit& visit) {
  if (index.revision() != visit.revision || !visit.covered.contains(box.min) || !visit.covered.contains(box.max)) {
    const double margin = 0.1 * box.extent().maxCoeff();
    visit.covered = {box.min.array() - margin, box.max.array() + margin};
    visit.revision = index.revision();
    visit.ids.clear();
    index.forEachInBox(visit.covered, [&](int id) { visit.ids.push_back(id); });
  }
  return visit.ids;
}

}  // namespace st::highway::detail
