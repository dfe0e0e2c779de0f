#pragma once
// Elastic collision resolution. Obstacles (walls, points) are infinitely massive.
#include <stcore/vec.hpp>

namespace st {

template <int D>
struct VelocityPair {
  Vec<D> a;
  Vec<D> b;
};

// Perfectly elastic impact of two balls with masses ma, mb; n points from a to b along the line
// of centres (need not be unit). Conserves momentum and kinetic energy; tangential parts untouched.
template <int D>
VelocityPair<D> resolveBalls(const Vec<D>& va, double ma, const Vec<D>& vb, double mb,
                             const Vec<D>& n) {
  const Vec<D> u = n.normalized();
  const double approach = (va - vb).dot(u);  // > 0 when closing
  // impulse magnitude for restitution 1: J = 2 * mu * approach, mu the reduced mass
  const double j = 2.0 * approach * (ma * mb) / (ma + mb);
  return {va - (j / ma) * u, vb + (j / mb) * u};
}

// A ball against an infinitely massive obstacle whose contact normal is n (any length, any sign):
// the normal component of v is reversed.
template <int D>
Vec<D> reflect(const Vec<D>& v, const Vec<D>& n) {
  const Vec<D> u = n.normalized();
  return v - 2.0 * v.dot(u) * u;
}

}  // namespace st
