#pragma once
// decomposition_factor: auto. The report leaves the best decomposition factor to "empirical
// measurement" (§5.1); the tuner makes that measurement as the space runs and moves the factor
// to where the two costs a factor trades balance.
//
// What it measures, in windows of the space's own updates (see windowFull):
//   - candidate visits V and neighbour queries Q: each visit is a pair check the caller makes;
//     V / Q is the occupancy n a query meets (the objects sharing a leaf);
//   - region events M: updates that changed an object's leaves (entering or leaving a leaf);
//     while the space is undivided, the events one division would cause, from the distance the
//     objects' boxes moved: 2 per wall crossed, walls half the bounds apart along each axis.
// How it decides: per window the cost is C(n) = V + c M, with c = SpaceRule::autoRegionCost the
// cost of a region event in pair checks. V grows as n (a leaf's occupancy), M as n^(-1/D) (the
// leaves' edge grows as n^(1/D), their walls are crossed that much less often). C is least where
// V = c M / D, at n* = n (c M / (D V))^(D / (D + 1)). The tuner goes half the way there (in the
// log: the exponents are a model and a window is a sample), at most halving (quartering while
// undivided) or doubling per window, and sets the factor to 2 n*: a leaf of k objects divides iff
// k > df, so leaves hold df / 2^D to df objects and 2 n* puts them at the level nearest n*.
// Within -20 % / +25 % of the factor in force it stays put, so it does not hunt on noise.
// It starts at SpaceRule::autoStart (16: scenes of a few objects start as one leaf, large ones as
// a moderate tree; a caller keeping lists starts fine).
// A caller that keeps neighbour lists (re-filing an object only when it leaves its fat box) makes
// its pair checks from the lists, not through the space: it reports them per round (noteRound),
// the rounds close windows (16 of them), and the factor moves from the one in force by the same
// step, since a list is the union of many leaves and says little of one leaf's occupancy.
// Everything it reads is a count: the same run makes the same choices (deterministic for a seed;
// a clock would make the space's counters, and so the outputs that print them, vary run to run).
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace st {

class FactorTuner {
 public:
  static constexpr std::uint64_t kRounds = 16;

  // One neighbour query that visited `visits` objects.
  void noteQuery(std::uint64_t visits) {
    ++queries_;
    visits_ += visits;
  }
  // A round of queries a caller answered from neighbour lists it keeps (the arm's monitor tests
  // every capsule's list each cycle): the visits are pair checks the factor trades, though the
  // space does not make them. Rounds close windows too (see windowFull).
  void noteRound(std::uint64_t queries, std::uint64_t visits) {
    ++rounds_;
    queries_ += queries;
    visits_ += visits;
  }
  // One update: whether the object's leaves changed, and how far its box moved along each axis
  // in units of half the bounds' edge on that axis (the spacing of one division's walls).
  void noteUpdate(bool changedLeaves, double crossings) {
    ++updates_;
    changes_ += changedLeaves ? 1 : 0;
    crossings_ += crossings;
  }
  // A window closes after 64 updates once either every object had about two, or the queries
  // visited 64 objects per object (a scene far from its factor decides soon); or after kRounds
  // rounds (a caller that keeps lists updates rarely: the arm re-files a capsule every ~25 cycles).
  bool windowFull(int objects) const {
    const auto n = static_cast<std::uint64_t>(std::max(objects, 1));
    return rounds_ >= kRounds || (updates_ >= 64 && (updates_ >= 2 * n || visits_ >= 64 * n));
  }

  // The factor for the next window, from the one in force (`df`), whether the space is divided,
  // the objects in it and the dimension; resets the window.
  int decide(int df, bool divided, int objects, int dim, double regionCost) {
    int next = df;
    const int top = std::max(2, objects);  // at or above: one leaf
    const int current = std::min(df, top);
    if (queries_ > 0 && visits_ > 0) {
      const double n = static_cast<double>(visits_) / static_cast<double>(queries_);
      const double events = divided ? static_cast<double>(changes_) : 2.0 * crossings_;
      const double ratio = regionCost * events / (dim * static_cast<double>(visits_));
      // half the way there (in the log): the exponents are a model, and the window a sample
      double step = std::pow(ratio, 0.5 * dim / (dim + 1.0));
      step = std::clamp(step, divided ? 0.5 : 0.25, 2.0);
      if (!divided && step >= 1.0) step = 1.0;
      // a leaf of k objects divides iff k > df, so leaves hold between df / 2^D and df: the
      // factor twice the occupancy wanted puts the leaves at the level nearest it
      // (lists kept by the caller: its objects are large and each list is the union of many
      // leaves, so n says little of a leaf's occupancy: move from the factor in force instead)
      const double want = divided && rounds_ == 0 ? 2.0 * n * step : current * step;
      if (want < 0.8 * current || want > 1.25 * current)
        next = std::clamp(static_cast<int>(std::lround(want)), 2, top);
    }
    ++decisions_;
    if (next != df) ++changesOfFactor_;
    queries_ = visits_ = updates_ = changes_ = rounds_ = 0;
    crossings_ = 0.0;
    return next;
  }

  std::uint64_t decisions() const { return decisions_; }
  std::uint64_t factorChanges() const { return changesOfFactor_; }

 private:
  std::uint64_t queries_ = 0;
  std::uint64_t visits_ = 0;
  std::uint64_t updates_ = 0;
  std::uint64_t changes_ = 0;
  std::uint64_t rounds_ = 0;
  double crossings_ = 0.0;
  std::uint64_t decisions_ = 0;
  std::uint64_t changesOfFactor_ = 0;
};

}  // namespace st
