#pragma once
// Who is near whom: the car-car broad phase behind one small interface, with two implementations
// that find the same threats: all pairs (the reference) and the cells with their bins
// (cell_pair_search.cpp). Each tick: prepare() once after the table is updated, then threatsOf()
// for every equipped ego.
#include <memory>
#include <span>
#include <vector>

#include <sthighway/cells.hpp>

#include "pair_test.hpp"

namespace st::highway::detail {

// What the road search needs of a group of cars the pair search keeps together (a bin): bounds
// over their centres, velocities, envelopes and brake ratios, so one list of nearby road features
// serves all of them.
struct CarGroup {
  Aabb<2> centres{Vec2::Zero(), Vec2::Zero()};
  Vec2 vmin = Vec2::Zero(), vmax = Vec2::Zero();
  double amax = 0.0, envMax = 0.0;
  double ratioMax = 0.0;  // largest m / (2 F_brake) of its equipped cars
  int equipped = 0;
  bool stopping = false;  // a car of it brakes to a stop line (its acceleration counts then)
};

class PairSearch {
 public:
  virtual ~PairSearch() = default;
  // This tick's structures, from the table after update() (departed cars still listed there
  // are dropped here).
  virtual void prepare() = 0;
  // Ego e's vehicle threats this tick, appended to out (in no particular order).
  virtual void threatsOf(int e, std::vector<Threat>& out) = 0;
  // The groups this tick and each car's (empty, -1: the search keeps no groups).
  virtual std::span<const CarGroup> groups() const { return {}; }
  virtual int groupOf(int /*slot*/) const { return -1; }
};

// Every other car of the table, each tested against the cheap bound, then exactly.
std::unique_ptr<PairSearch> makeAllPairsSearch(const PairTest& test);
// The cells broad phase: cars placed in their serving cells (CellNetwork, which hands them off),
// grouped per cell in bins and swept along each bin's long axis; divided cells searched through
// their trees.
std::unique_ptr<PairSearch> makeCellPairSearch(const PairTest& test, CellNetwork& cells);

}  // namespace st::highway::detail
