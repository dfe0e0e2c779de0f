// The two pair searches against each other: on the same vehicle table, the cells broad phase
// (bins swept once, divided cells through their trees) finds exactly the threats of all pairs,
// the reference, for every ego, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include "lane_prediction.hpp"
#include "pair_search.hpp"
#include "scenes.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {
namespace {

auto keyOf(const Threat& t) { return std::make_tuple(t.key, t.ttc, t.safe, t.zone, t.kind, t.foe); }

std::vector<Threat> sorted(std::vector<Threat> v) {
  std::sort(v.begin(), v.end(), [](const Threat& a, const Threat& b) { return keyOf(a) < keyOf(b); });
  return v;
}

TEST(PairSearch, CellsFindExactlyTheThreatsOfAllPairs) {
  std::mt19937_64 rng(90210);
  const RoadGeometry road = testRoad();
  std::uint64_t threats = 0, dividedScenes = 0, cellCandidates = 0, allCandidates = 0;
  for (int scene = 0; scene < 600; ++scene) {
    MonitorConfig cfg;
    cfg.detector.kind = static_cast<DetectorKind>(scene % 3);
    cfg.detector.motion = (scene / 3) % 2 ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
    cfg.cells.cellLength = 60.0 + 10.0 * (scene % 7);
    cfg.cells.decompositionFactor = scene % 4 == 3 ? 4 : 32;  // divided cells beside undivided ones
    cfg.prediction = Prediction::Straight;
    const auto ticks = randomScene(rng, cfg.cells.cellLength);
    MonitorCounters countersCells, countersAll;
    VehicleTable cars(cfg, countersCells);
    CellNetwork network(road, deriveFeatures(road), cfg.cells);
    LanePrediction paths(road, cfg, cars, countersCells);
    const auto cells = makeCellPairSearch(PairTest{&cfg, &cars, &countersCells, &paths}, network);
    const auto all = makeAllPairsSearch(PairTest{&cfg, &cars, &countersAll, &paths});
    bool anyDivided = false;
    for (std::size_t k = 0; k < ticks.size(); ++k) {
      cars.update(0.2 * static_cast<double>(k), ticks[k]);
      paths.update(0.2 * static_cast<double>(k));
      cells->prepare();
      all->prepare();
      cars.release();
      for (int c = 0; c < network.cellCount(); ++c) anyDivided = anyDivided || network.divided(c);
      for (int e : cars.active) {
        if (!cars.equipped[e]) continue;
        std::vector<Threat> a, b;
        cells->threatsOf(e, a);
        all->threatsOf(e, b);
        const std::vector<Threat> sa = sorted(a), sb = sorted(b);
        ASSERT_EQ(sa.size(), sb.size()) << "scene " << scene << " tick " << k << " ego " << cars.slots[e].id;
        for (std::size_t i = 0; i < sa.size(); ++i)
          ASSERT_EQ(keyOf(sa[i]), keyOf(sb[i])) << "scene " << scene << " tick " << k << " ego " << cars.slots[e].id;
        threats += sa.size();
      }
    }
    dividedScenes += anyDivided;
    cellCandidates += countersCells.candidatePairs;
    allCandidates += countersAll.candidatePairs;
  }
  // the scenes warn, some divide cells, and the cells do prune
  EXPECT_GT(threats, 2000u);
  EXPECT_GT(dividedScenes, 50u);
  EXPECT_LT(cellCandidates * 2, allCandidates);
}

// Handles are the caller's: a vehicle found by its handle keeps its slot while present, a slot is
// reused only the tick after its car left, and a handle given to two ids is an error.
TEST(VehicleTable, HandlesMapToSlotsWithoutIds) {
  MonitorConfig cfg;
  MonitorCounters counters;
  VehicleTable cars(cfg, counters);
  auto at = [](const std::string& id, int handle, double x) {
    VehicleState v;
    v.id = id;
    v.handle = handle;
    v.position = Vec2(x, 0.0);
    return v;
  };
  std::vector<VehicleState> tick = {at("a", 7, 0.0), at("b", 2, 10.0), at("c", -1, 20.0)};
  cars.update(0.0, tick);
  ASSERT_EQ(cars.active.size(), 3u);
  const int slotA = cars.active[0], slotB = cars.active[1];
  cars.release();
  // b leaves, a new car takes handle 2 the tick after: a new slot and serial
  tick = {at("a", 7, 1.0), at("c", -1, 21.0)};
  cars.update(0.1, tick);
  EXPECT_EQ(cars.active[0], slotA);
  ASSERT_EQ(cars.departed.size(), 1u);
  EXPECT_EQ(cars.departed[0], slotB);
  const std::uint64_t serialB = cars.slots[slotB].serial;
  cars.release();
  tick = {at("a", 7, 2.0), at("d", 2, 30.0), at("c", -1, 22.0)};
  cars.update(0.2, tick);
  EXPECT_EQ(cars.slots[cars.active[1]].id, "d");
  EXPECT_GT(cars.slots[cars.active[1]].serial, serialB);
  EXPECT_EQ(counters.vehiclesSeen, 4u);
  cars.release();
  tick = {at("a", 7, 3.0), at("e", 7, 40.0)};
  EXPECT_THROW(cars.update(0.3, tick), std::invalid_argument);
}

}  // namespace
}  // namespace st::highway::detail
