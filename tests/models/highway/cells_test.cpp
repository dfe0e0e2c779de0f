#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <stdexcept>

#include <sthighway/cells.hpp>

#include "roads.hpp"

namespace st::highway {
namespace {

// One straight three-lane edge along +x, 2 km, lanes 3.2 m wide centred on y = 0, 3.2, 6.4.
RoadGeometry straightRoad(double length = 2000.0) {
  RoadGeometry r;
  for (int i = 0; i < 3; ++i) r.lanes.push_back(laneOf("road", i, {Vec2(0, 3.2 * i), Vec2(length, 3.2 * i)}));
  return r;
}

Aabb<2> carBox(const Vec2& c) { return {c - Vec2(2.5, 0.9), c + Vec2(2.5, 0.9)}; }

// The layouts below are drawn for sites 200 m apart (ten on the 2 km road), not the default
CellConfig config200() {
  CellConfig c;
  c.cellLength = 200.0;
  c.radioRange = 600.0;
  c.decompositionFactor = 32;
  return c;
}

int cellsHolding(const CellNetwork& net, int v) {
  int n = 0;
  for (int c = 0; c < net.cellCount(); ++c)
    for (int m : net.membersOf(c)) n += m == v;
  return n;
}

TEST(Cells, SitesAlongTheSection) {
  const RoadGeometry road = straightRoad();
  const CellNetwork net(road, deriveFeatures(road), config200());
  ASSERT_EQ(net.cellCount(), 10);
  for (int c = 0; c < 10; ++c) {
    EXPECT_NEAR(net.site(c).position.x(), 100.0 + 200.0 * c, 1e-9);
    EXPECT_NEAR(net.site(c).position.y(), 3.2, 1e-12);  // the middle lane
  }
  // log-distance path loss: 10 n dB per decade of distance
  EXPECT_NEAR(net.signalDbm(0, {100, 13.2}) - net.signalDbm(0, {100, 103.2}), 30.0, 1e-9);
}

TEST(Cells, HandoffInOrderNeverLostNeverTwice) {
  const RoadGeometry road = straightRoad();
  CellConfig cfg = config200();
  CellNetwork net(road, deriveFeatures(road), cfg);
  // handoff where d_old / d_new passes 10^(h / 10n): between sites a and a + 200 at
  // a + 200 rho / (1 + rho) on the sites' line
  const double rho = std::pow(10.0, cfg.hysteresisDb / (10.0 * cfg.pathLossExponent));
  const double at = 200.0 * rho / (1.0 + rho);
  int expected = 0;
  for (int step = 0; step <= 2000; ++step) {
    const Vec2 p(step, 3.2);
    net.place(0, p, carBox(p));
    net.refreshExtents();
    ASSERT_GE(net.servingCell(0), 0) << "lost at x=" << step;
    ASSERT_EQ(cellsHolding(net, 0), 1) << "x=" << step;
    for (const Handoff& h : net.takeHandoffs()) {
      EXPECT_EQ(h.vehicle, 0);
      EXPECT_EQ(h.from, expected);
      EXPECT_EQ(h.to, expected + 1);
      // the first step past the hysteresis point
      const double threshold = 100.0 + 200.0 * h.from + at;
      EXPECT_GT(step, threshold);
      EXPECT_LE(step - 1, threshold);
      ++expected;
    }
  }
  EXPECT_EQ(expected, 9);
  EXPECT_EQ(net.counters().handoffs, 9u);
  net.remove(0);
  EXPECT_EQ(net.servingCell(0), -1);
  EXPECT_EQ(cellsHolding(net, 0), 0);
}

// A car re-measures its sites only when it may have come within the hysteresis margin of
// another site; the serving cells and handoffs are those of measuring at every step (brute force
// over every site), for cars wandering over two opposite carriageways (sites 14.4 m apart across
// the median), with small steps, large jumps and reversals.
TEST(Cells, HandoffsEqualMeasuringEveryStep) {
  RoadGeometry road = straightRoad(1400.0);
  for (int i = 0; i < 3; ++i)
    road.lanes.push_back(laneOf("back", i, {Vec2(1400.0, 20.8 - 3.2 * i), Vec2(0.0, 20.8 - 3.2 * i)}));
  CellConfig cfg = config200();
  CellNetwork net(road, deriveFeatures(road), cfg);
  const double ratioSq = std::pow(10.0, 2.0 * cfg.hysteresisDb / (10.0 * cfg.pathLossExponent));
  auto d2 = [&](int c, const Vec2& p) {
    return std::max((net.site(c).position - p).squaredNorm(), cfg.referenceDistance * cfg.referenceDistance);
  };
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int cars = 40;
  std::vector<Vec2> p(cars);
  std::vector<int> want(cars, -1);
  int handoffs = 0;
  for (int v = 0; v < cars; ++v) p[v] = Vec2(1400.0 * U(rng), 22.0 * U(rng) - 1.0);
  for (int step = 0; step < 3000; ++step) {
    for (int v = 0; v < cars; ++v) {
      const double r = U(rng);
      if (r < 0.01) p[v] = Vec2(1400.0 * U(rng), 22.0 * U(rng) - 1.0);             // a jump
      else p[v] += Vec2((v % 2 ? -1.0 : 1.0) * 3.0 * U(rng), 0.6 * (U(rng) - 0.5));  // a tick
      // the reference: the nearest site (ties: lowest index), handed over past the margin
      int best = 0;
      for (int c = 1; c < net.cellCount(); ++c)
        if (d2(c, p[v]) < d2(best, p[v])) best = c;
      if (want[v] < 0) want[v] = best;
      else if (best != want[v] && d2(want[v], p[v]) > ratioSq * d2(best, p[v])) {
        want[v] = best;
        ++handoffs;
      }
      ASSERT_EQ(net.place(v, p[v], carBox(p[v])), want[v]) << "car " << v << " step " << step;
    }
    net.refreshExtents();
  }
  EXPECT_EQ(net.counters().handoffs, static_cast<std::uint64_t>(handoffs));
  EXPECT_GT(handoffs, 1000);
}

TEST(Cells, HysteresisPreventsPingPong) {
  const RoadGeometry road = straightRoad();
  // a car weaving +-8 m around the boundary between cells 2 and 3 (x = 600)
  auto weave = [&](double hysteresisDb) {
    CellConfig cfg = config200();
    cfg.hysteresisDb = hysteresisDb;
    CellNetwork net(road, deriveFeatures(road), cfg);
    for (int i = 0; i < 200; ++i) {
      const Vec2 p(600.0 + 8.0 * std::sin(0.3 * i), 3.2);
      net.place(0, p, carBox(p));
    }
    return net.counters().handoffs;
  };
  EXPECT_EQ(weave(3.0), 0u);   // within the margin: it stays with its first cell
  EXPECT_GT(weave(0.0), 15u);  // without a margin it flips at every crossing
}

TEST(Cells, CongestedCellSubdividesAndReunites) {
  const RoadGeometry road = straightRoad();
  CellConfig cfg = config200();
  cfg.decompositionFactor = 4;
  CellNetwork net(road, deriveFeatures(road), cfg);
  // a jam: 3 lanes x 25 cars at 7 m spacing inside cell 1 (x in 200..400)
  int v = 0;
  for (int lane = 0; lane < 3; ++lane)
    for (int k = 0; k < 25; ++k) {
      const Vec2 p(215.0 + 7.0 * k, 3.2 * lane);
      EXPECT_EQ(net.place(v++, p, carBox(p)), 1);
    }
  net.refreshExtents();
  EXPECT_GT(net.counters().subdivisions, 0u);
  EXPECT_EQ(net.counters().reunions, 0u);
  EXPECT_EQ(static_cast<int>(net.membersOf(1).size()), 75);
  // every car is found by a box around it
  for (int i = 0; i < v; ++i) {
    const Vec2 p(215.0 + 7.0 * (i % 25), 3.2 * (i / 25));
    bool found = false;
    net.forEachCellInBox(carBox(p), [&](int c) {
      net.forEachInCellBox(c, carBox(p), [&](int o) { found = found || o == i; });
    });
    EXPECT_TRUE(found) << i;
  }
  for (int i = 0; i < v; ++i) net.remove(i);
  net.refreshExtents();
  EXPECT_GT(net.counters().reunions, 0u);
  EXPECT_TRUE(net.membersOf(1).empty());
}

// Deferred placement makes each cell's changes in the order placed, so every space ends as
// place() leaves it: the same trees (leaves, their lists in order), slots, counters, handoffs.
// The changes the cells saw (joins, leaves, fat box renewals): what a cell's tree would see.
std::uint64_t spaceChanges(const CellNetwork& net) { return net.counters().boxChanges; }

TEST(Cells, FatBoxesStretchAlongTheVelocity) {
  // a car cruising at 30 m/s in 0.1 s ticks, then braking to a stop and reversing: with the
  // lookahead its fat box is renewed every dozen ticks or so instead of every third, and its
  // cell's space finds it where it is at every tick
  const RoadGeometry road = straightRoad();
  std::uint64_t changes[2] = {0, 0};
  for (int lookahead = 0; lookahead < 2; ++lookahead) {
    CellConfig cfg = config200();
    cfg.fatLookahead = lookahead ? 1.0 : 0.0;
    CellNetwork net(road, deriveFeatures(road), cfg);
    Vec2 p(50.0, 3.2);
    double speed = 30.0;
    for (int step = 0; step < 700; ++step) {
      if (step >= 500) speed = std::max(-10.0, speed - 1.0);  // 10 m/s^2 braking, then reversing
      const Vec2 velocity(speed, 0.0);
      p += 0.1 * velocity;
      net.place(0, p, carBox(p), velocity);
      net.refreshExtents();
      int found = 0;
      net.forEachInCellBox(net.servingCell(0), carBox(p), [&](int v) { found += v == 0; });
      ASSERT_EQ(found, 1) << "step " << step;
    }
    changes[lookahead] = spaceChanges(net);
  }
  EXPECT_LT(3 * changes[1], changes[0]) << changes[1] << " vs " << changes[0];
  EXPECT_GT(changes[1], 0u);
  CellConfig bad = config200();
  bad.fatLookahead = -1.0;
  EXPECT_THROW(CellNetwork(road, deriveFeatures(road), bad), std::invalid_argument);
  bad.fatLookahead = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(CellNetwork(road, deriveFeatures(road), bad), std::invalid_argument);
}

TEST(Cells, DeferredPlacementMatchesPlace) {
  const RoadGeometry road = straightRoad();
  CellConfig cfg = config200();
  cfg.decompositionFactor = 4;  // jams subdivide and reunite
  CellNetwork now(road, deriveFeatures(road), cfg), later(road, deriveFeatures(road), cfg);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int cars = 120;
  std::vector<Vec2> p(cars);
  std::vector<char> in(cars, 1);
  for (int v = 0; v < cars; ++v) p[v] = Vec2(200.0 + 300.0 * U(rng), 6.4 * U(rng));
  for (int step = 0; step < 300; ++step) {
    for (int v = 0; v < cars; ++v) {
      const double r = U(rng);
      if (r < 0.01) {
        in[v] = !in[v];  // leaves, or comes back
        if (!in[v]) {
          now.remove(v);
          later.remove(v);
        }
      }
      if (!in[v]) continue;
      const Vec2 move((v % 3 ? 1.0 : -1.0) * 12.0 * U(rng), 0.6 * (U(rng) - 0.5));
      p[v] += move;
      if (p[v].x() < 0.0 || p[v].x() > 2000.0) p[v] = Vec2(200.0 + 300.0 * U(rng), 6.4 * U(rng));
      const Vec2 velocity = move / 0.5;  // the fat boxes stretch along it
      ASSERT_EQ(later.placeDeferred(v, p[v], carBox(p[v]), velocity), now.place(v, p[v], carBox(p[v]), velocity))
          << v << " " << step;
      if (v % 17 == 0) {  // placed twice before the commit
        p[v] += Vec2(20.0, 0.0);
        ASSERT_EQ(later.placeDeferred(v, p[v], carBox(p[v])), now.place(v, p[v], carBox(p[v])));
      }
    }
    now.refreshExtents();
    later.refreshExtents();
    const std::vector<Handoff> a = now.takeHandoffs(), b = later.takeHandoffs();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].vehicle, b[i].vehicle);
      EXPECT_EQ(a[i].from, b[i].from);
      EXPECT_EQ(a[i].to, b[i].to);
    }
    for (int c = 0; c < now.cellCount(); ++c) {
      const std::span<const int> sa = now.cellSlots(c), sb = later.cellSlots(c);
      ASSERT_TRUE(std::equal(sa.begin(), sa.end(), sb.begin(), sb.end())) << c;
      ASSERT_EQ(now.cellTree(c) != nullptr, later.cellTree(c) != nullptr) << c;
      if (!now.cellTree(c)) continue;
      const Space<2>& ta = *now.cellTree(c);
      const Space<2>& tb = *later.cellTree(c);
      ASSERT_EQ(ta.leaves(), tb.leaves()) << c;
      for (int leaf : ta.leaves()) {
        const ObjectList la = ta.objectsIn(leaf), lb = tb.objectsIn(leaf);
        ASSERT_TRUE(std::equal(la.begin(), la.end(), lb.begin(), lb.end())) << c << " " << leaf;
      }
      EXPECT_EQ(ta.counters().transfers, tb.counters().transfers);
    }
  }
  const CellCounters& ca = now.counters();
  const CellCounters& cb = later.counters();
  EXPECT_EQ(ca.handoffs, cb.handoffs);
  EXPECT_EQ(ca.attaches, cb.attaches);
  EXPECT_EQ(ca.detaches, cb.detaches);
  EXPECT_EQ(ca.subdivisions, cb.subdivisions);
  EXPECT_EQ(ca.reunions, cb.reunions);
  EXPECT_GT(ca.handoffs, 100u);
  EXPECT_GT(ca.subdivisions, 10u);
  EXPECT_GT(ca.reunions, 10u);
}

}  // namespace
}  // namespace st::highway
