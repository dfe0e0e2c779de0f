#pragma once
// Box helpers the space tests share, written apart from stcore's own so that the tests do not
// check stcore against itself.
#include <stcore/shapes.hpp>

namespace st::test {

template <int D>
Aabb<D> clampTo(const Aabb<D>& b, const Aabb<D>& bounds) {
  return {b.min.cwiseMax(bounds.min).cwiseMin(bounds.max), b.max.cwiseMin(bounds.max).cwiseMax(bounds.min)};
}

// Open overlap: the boxes share interior (for a grid's half-open cells).
template <int D>
bool overlapsOpen(const Aabb<D>& a, const Aabb<D>& b) {
  return (a.min.array() < b.max.array()).all() && (b.min.array() < a.max.array()).all();
}

}  // namespace st::test
