#pragma once
// The vehicle table: who is on the road this tick and the hot state every stage reads, struct of
// arrays by slot. A vehicle is found by the dense handle its caller gives (VehicleState::handle),
// or by its id when it has none; slots are reused the tick after their car left, so the arrays
// stay as long as the most cars present at once. String ids are kept only for output.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <sthighway/monitor.hpp>

#include "car_shape.hpp"

namespace st::highway::detail {

// What the exact pair test reads of a car, together: the test meets its two cars in no order,
// and separate arrays would be a cache miss each.
struct PairState {
  Vec2 ext = Vec2::Zero();        // envelopeExtent
  double env = 0.0;               // envelopeRadius
  double mass = 0.0;
  double twiceBrakeForce = 1.0;   // 2 F_brake of its class
  double outer = 0.0;             // concentric: the outer radius
  std::uint64_t serial = 0;
};

struct VehicleTable {
  struct Slot {
    std::string id;
    int handle = -1;
    std::uint64_t serial = 0;  // order of first appearance: the key of episodes against it
    bool present = false;
    Vec2 prev = Vec2::Zero();
    double prevSpeed = 0.0, prevTime = 0.0;  // at its last tick
    double length = -1.0, width = -1.0, heading = 0.0;  // of the cached axis and envelopes
    Vec2 axis = Vec2(1.0, 0.0);                          // (cos, sin) of heading
  };

  // laneIds: the road's lane ids by index (what VehicleState::lane indexes), for what is reported
  VehicleTable(const MonitorConfig& config, MonitorCounters& sink, std::vector<std::string> laneIds = {})
      : cfg(&config), counters(&sink), laneIds_(std::move(laneIds)) {}

  // The id of lane index `index` (VehicleState::lane), empty if unknown.
  std::string laneId(int index) const {
    return index >= 0 && index < static_cast<int>(laneIds_.size()) ? laneIds_[index] : std::string();
  }

  // Maps this tick's vehicles to slots and takes their state; the slots of the cars that left
  // are listed in `departed` (in the order they were active), still holding their ids until
  // release(). Throws std::invalid_argument on a duplicate, a non-finite value, a bad size or a
  // handle given to two ids.
  void update(double t, std::span<const VehicleState> vehicles);
  // Frees the departed slots (after the other stages have closed their business with them).
  void release();

  int slotCount() const { return static_cast<int>(slots.size()); }
  // the middle of the body's front edge (SUMO's position of a vehicle)
  Vec2 front(int s) const { return centre[s] + 0.5 * body[s].length * body[s].axis; }

  const MonitorConfig* cfg;
  MonitorCounters* counters;

  std::vector<Slot> slots;
  std::vector<int> freeSlots;
  std::unordered_map<std::string, int> slotOfId;  // vehicles without a handle
  std::vector<int> slotOfHandle;                  // handle -> slot, -1: none
  std::uint64_t nextSerial = 1;
  std::vector<int> active;    // present slots, in input order
  std::vector<int> departed;  // slots whose cars left at this tick
  std::vector<int> arrived;   // slots new at this tick (their per-slot state elsewhere is fresh)

  // hot state by slot
  std::vector<Body> body;
  std::vector<Vec2> centre;                  // body[].position, compact for the pair tests
  std::vector<Vec2> vel;                     // body[].velocity
  std::vector<double> mass, env, accelAbs;
  std::vector<Vec2> ext;                     // envelopeExtent
  // The envelopes of the car's own shapes; env and ext are these grown by how far the road
  // prediction departs from the straight line (lane_prediction.hpp), which every prune reads.
  std::vector<double> ownEnv;
  std::vector<Vec2> ownExt;
  std::vector<CarShape> shape;               // carShape
  std::vector<double> brakeRatio;            // m / (2 F_brake) (s per m/s)
  std::vector<VehicleClass> vclass;
  std::vector<std::uint8_t> signals;
  std::vector<char> equipped;
  std::vector<PairState> pairState;
  // 1 if the car is not compact (heavy or large, or changing lanes): the cells broad phase keeps
  // such cars in a bin of their own (cell_pair_search.cpp)
  std::vector<int> wide;
  std::vector<int> inputOf;                  // index in the current span, -1 if absent
  std::vector<int> lane;                     // VehicleState::lane (only reported)
  std::vector<std::array<int, kRouteAhead>> route;  // VehicleState::route
  // how hard the car braked since its last tick (m/s^2, >= 0), from its speeds: what it actually
  // did, whether or not the source reports accelerations
  std::vector<double> braking;
  // VehicleState::decel (m/s^2; NaN unknown): braking beyond it is an emergency (hindsight)
  std::vector<double> decel;
  // the same signed (m/s^2, negative: braking), NaN at the car's first tick (SSAM's DR and MaxD)
  std::vector<double> accel;

 private:
  std::vector<std::string> laneIds_;
  std::vector<int> next_;  // scratch: the next tick's active list
  int slotFor(const VehicleState& v, int i, double t);
  int newSlot(const VehicleState& v);
  void ensure(std::size_t n);
  void take(int s, const VehicleState& v, double t);
};

}  // namespace st::highway::detail
