#pragma once
// Cells and handoff (§4.2). The highway is divided into cells, as in cellular radio: a cell site
// every `cellLength` metres along each road section (edge). Each car measures the signal of the
// sites within radio range (log-distance path loss) and stays with its serving cell until another
// site is stronger by the hysteresis margin; then it tells its old cell, which hands it to the
// new one (no search of siblings). Hierarchy: network > road sections (edges) > cells. A cell
// holds its cars in a stcore tree only while it holds more than the decomposition factor (a jam:
// the tree subdivides; it is dropped when the cell reunites); the pair search sweeps the members
// of the other cells itself. The cells a car's look-ahead reaches are found through a
// network-level index over the cells' extents.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <stcore/space.hpp>
#include <sthighway/road.hpp>

namespace st::highway {

struct CellConfig {
  // A cell is only the broad phase's grouping (the warnings do not depend on it): 800 m measured
  // fastest on the benchmark's free-flow motorway among 200-1200 m (about 60 cars per carriageway
  // per cell; shorter cells mean more cell pairs to walk, longer ones subdivide)
  double cellLength = 800.0;        // m between cell sites along a section
  double txPowerDbm = 40.0;         // site transmit power (dBm)
  double pathLossExponent = 3.0;    // log-distance path loss exponent (2 free space, 3-4 roadside)
  double referenceDistance = 1.0;   // m; path loss is 0 dB at this distance
  double hysteresisDb = 3.0;        // a new site must be this much stronger to take the car
  double radioRange = 1000.0;       // m; sites farther than this are not heard (a section's
                                    // ends lie up to 3/4 cellLength from its nearest site)
  double fatMargin = 8.0;           // m; a car's box in its cell's space is grown by this, so
                                    // small moves do not touch the space
  double fatLookahead = 1.0;        // s; and stretched to where its velocity takes it in this
                                    // time (Box2D's predictive box): a car cruising at 30 m/s
                                    // touches its space every dozen ticks of 0.1 s, not every third
  int decompositionFactor = 128;    // a cell's space subdivides past this many cars (a jam:
                                    // free flow on 3 lanes is ~60 per 800 m, a queue ~340)
  int maxDepth = 8;
};

struct CellSite {
  int section = -1;    // index into the road sections
  Vec2 position = Vec2::Zero();
  double along = 0.0;  // distance of the site along its section's reference lane (m)
};

struct CellCounters {
  std::uint64_t handoffs = 0;
  std::uint64_t attaches = 0;      // cars that entered the network
  std::uint64_t detaches = 0;      // cars that left it
  std::uint64_t subdivisions = 0;  // summed over the cells' trees
  std::uint64_t reunions = 0;
  std::uint64_t boxChanges = 0;    // a car joined or left a cell, or its fat box was renewed
};

// One handoff, for tests and logs.
struct Handoff {
  int vehicle = -1;  // the caller's dense vehicle index
  int from = -1;
  int to = -1;
};

class CellNetwork {
 public:
  CellNetwork(const RoadGeometry& road, const RoadFeatures& features, const CellConfig& config);
  ~CellNetwork();
  CellNetwork(CellNetwork&&) noexcept;
  CellNetwork& operator=(CellNetwork&&) noexcept;

  const CellConfig& config() const;
  int cellCount() const;
  const CellSite& site(int cell) const;
  std::span<const std::string> sections() const;

  // Received power of a cell's site at p (dBm).
  double signalDbm(int cell, const Vec2& p) const;

  // Places or moves vehicle `v` (dense index) with the given body box and velocity (m/s, for its
  // fat box only): measures the sites in range and hands off if another is stronger by the
  // hysteresis margin. Returns the serving cell.
  int place(int v, const Vec2& centre, const Aabb<2>& box, const Vec2& velocity = Vec2::Zero());
  // As place(), but the changes to the cells wait for commitPlacements(), which makes them cell
  // by cell, each cell's in the order placed: every cell sees what place() would show it, so
  // trees, counters and handoffs are the same, while a cell's tree stays in cache for all its
  // cars (cars in input order hop between cells, a cache miss each). The serving cell and
  // handoffs are known at once; the cells (and forEachInCellBox) are stale until the commit.
  int placeDeferred(int v, const Vec2& centre, const Aabb<2>& box, const Vec2& velocity = Vec2::Zero());
  void commitPlacements();
  void remove(int v);
  int servingCell(int v) const;  // -1 if not in the network

  // The two levels of a search: f(cell) for the cells whose extent may meet the box, and
  // f(vehicle) for the cars of a cell that may lie in it (those listed in the leaves of its tree
  // the box touches; every member of an undivided cell). Valid after refreshExtents().
  template <class F>
  void forEachCellInBox(const Aabb<2>& box, F&& f) const {
    networkIndex().forEachInBox(box, f);
  }
  template <class F>
  void forEachInCellBox(int cell, const Aabb<2>& box, F&& f) const;

  // The network level: a space over the cells' extents (ids are cells).
  const Space<2>& networkIndex() const;
  // True while a cell is divided: it holds more cars than the decomposition factor and its tree
  // has subdivided.
  bool divided(int cell) const {
    const Space<2>* tree = cellTree(cell);
    return tree && tree->divided();
  }
  // A cell's tree while it has one (ids are the cell's local slots), else nullptr; and its slot
  // -> vehicle table (-1: free).
  const Space<2>* cellTree(int cell) const;
  std::span<const int> cellSlots(int cell) const;

  // Recomputes the cells' extents from their members (committing deferred placements first)
  // and builds or drops the cells' trees; call once per tick after placing all cars.
  void refreshExtents();

  // Cars currently served by a cell (dense vehicle indices).
  std::vector<int> membersOf(int cell) const;
  // Extent of the region a cell is responsible for (its share of road) and of its members now.
  Aabb<2> cellExtent(int cell) const;

  const CellCounters& counters() const;
  // Handoffs since the last call (in order).
  std::vector<Handoff> takeHandoffs();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

template <class F>
void CellNetwork::forEachInCellBox(int cell, const Aabb<2>& box, F&& f) const {
  const std::span<const int> slots = cellSlots(cell);
  if (const Space<2>* tree = cellTree(cell)) {
    tree->forEachInBox(box, [&](int local) { f(slots[local]); });
    return;
  }
  for (int v : slots)
    if (v >= 0) f(v);
}

}  // namespace st::highway
