#pragma once
// Neighbour lists with a shell, after Smallenburg's EDMD (EPJE 2022): each ball lists the balls
// whose list centres lie within (1 + shell)(r_i + r_j) of its own, a centre being where the ball
// stood when its list was last built. A ball may move shell * r from its centre; while two balls
// both stay that close to their centres, a pair not listed is more than r_i + r_j apart and cannot
// touch. So the lists are the candidates of every pair prediction, and a ball rebuilds its list
// (one event) only when it leaves its shell, not at every cell face it crosses.
//
// The lists are symmetric: a rebuild takes the ball out of its old neighbours' lists and puts it
// into its new ones'. Storage is one flat array, stride_ ints per ball (count apart), the stride
// doubled for all when a list outgrows it.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <stcore/tolerances.hpp>
#include <stcore/vec.hpp>

namespace st {

template <int D>
class NeighborLists {
 public:
  // shell: how far a ball may move from its list centre, as a fraction of its radius (0: no lists)
  explicit NeighborLists(double shell = 0.0) : shell_(shell) {}

  bool enabled() const { return shell_ > 0.0; }
  // How far the ball may move from its centre (m).
  double skin(double radius) const { return shell_ * radius; }
  // How far from ball i's centre another ball's centre may lie and still be listed: a search of
  // the centres within this distance finds every neighbour.
  double searchRadius(int i) const { return reach_[i] + maxReach_ + tol::kRegionSlop; }

  // Ball i joins with an empty list (link it with rebuild).
  void add(int i, double radius) {
    if (i >= static_cast<int>(count_.size())) {
      count_.resize(static_cast<std::size_t>(i) + 1, 0);
      centre_.resize(static_cast<std::size_t>(i) + 1, Vec<D>::Zero());
      reach_.resize(static_cast<std::size_t>(i) + 1, 0.0);
      data_.resize(count_.size() * static_cast<std::size_t>(stride_), 0);
    }
    count_[i] = 0;
    reach_[i] = (1.0 + shell_) * radius;
    maxReach_ = std::max(maxReach_, reach_[i]);
  }

  // Ball i's list centred at `centre`: out of its old neighbours' lists, then into those of every
  // candidate within reach. forEachCandidate(f) calls f(j) for a superset of them, each once (i
  // itself may be among them).
  template <class Candidates>
  void rebuild(int i, const Vec<D>& centre, Candidates&& forEachCandidate) {
    unlink(i);
    centre_[i] = centre;
    forEachCandidate([&](int j) {
      if (j == i) return;
      // the slop: a pair exactly at reach after rounding in the exit times stays listed
      const double reach = reach_[i] + reach_[j] + tol::kRegionSlop;
      if ((centre_[j] - centre).squaredNorm() < reach * reach) {
        push(i, j);
        push(j, i);
      }
    });
  }

  // Ball i leaves: out of every list.
  void remove(int i) { unlink(i); }

  const int* begin(int i) const { return data_.data() + static_cast<std::ptrdiff_t>(i) * stride_; }
  int count(int i) const { return count_[i]; }
  const Vec<D>& centre(int i) const { return centre_[i]; }

  // Time after which a ball at p moving at v is skin(radius) from its centre (straight path; the
  // later root, so p may lie anywhere inside); infinity if it does not move.
  double exitTime(int i, const Vec<D>& p, const Vec<D>& v, double radius) const {
    const double v2 = v.squaredNorm();
    if (!(v2 > 0.0)) return std::numeric_limits<double>::infinity();
    const Vec<D> d = p - centre_[i];
    const double s = skin(radius);
    const double b = d.dot(v);
    const double disc = std::max(0.0, b * b - v2 * (d.squaredNorm() - s * s));
    // the later root (-b + sqrt(disc)) / v2; when b > 0, as the product of the roots over the
    // earlier one, without cancellation
    const double root = std::sqrt(disc);
    const double t = b > 0.0 ? (s * s - d.squaredNorm()) / (b + root) : (root - b) / v2;
    return std::max(t, 0.0);
  }

 private:
  void push(int i, int j) {
    if (count_[i] == stride_) grow();
    data_[static_cast<std::size_t>(i) * stride_ + count_[i]++] = j;
  }
  void unlink(int i) {
    const int* mine = begin(i);
    for (int k = 0; k < count_[i]; ++k) {
      const int j = mine[k];
      int* theirs = data_.data() + static_cast<std::ptrdiff_t>(j) * stride_;
      int* last = theirs + count_[j] - 1;
      *std::find(theirs, last, i) = *last;  // order within a list carries no meaning
      --count_[j];
    }
    count_[i] = 0;
  }
  void grow() {
    const int wider = 2 * stride_;
    std::vector<int> data(count_.size() * static_cast<std::size_t>(wider), 0);
    for (std::size_t b = 0; b < count_.size(); ++b)
      std::copy_n(data_.begin() + static_cast<std::ptrdiff_t>(b * stride_), count_[b],
                  data.begin() + static_cast<std::ptrdiff_t>(b * wider));
    data_.swap(data);
    stride_ = wider;
  }

  double shell_ = 0.0;
  int stride_ = 16;
  std::vector<int> data_;
  std::vector<int> count_;
  std::vector<Vec<D>> centre_;
  std::vector<double> reach_;  // (1 + shell) r
  double maxReach_ = 0.0;
};

}  // namespace st
