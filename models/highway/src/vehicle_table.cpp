#include "vehicle_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <sthighway/tolerances.hpp>

namespace st::highway::detail {

namespace {

void checkFinite(const VehicleState& v) {
  auto bad = [&](const char* field) {
    return std::invalid_argument("vehicle '" + v.id + "': " + field + " must be finite" +
                                 (std::string(field) == "length" || std::string(field) == "width" || std::string(field) == "mass"
                                      ? " and positive" : ""));
  };
  if (!v.position.allFinite()) throw bad("position");
  if (!std::isfinite(v.heading)) throw bad("heading");
  if (!std::isfinite(v.speed)) throw bad("speed");
  if (!std::isfinite(v.lateralSpeed)) throw bad("lateralSpeed");
  if (!std::isfinite(v.acceleration)) throw bad("acceleration");
  if (!(v.length > 0.0) || !std::isfinite(v.length)) throw bad("length");
  if (!(v.width > 0.0) || !std::isfinite(v.width)) throw bad("width");
  if (!(v.mass > 0.0) || !std::isfinite(v.mass)) throw bad("mass");
  if (!std::isnan(v.decel) && !(v.decel > 0.0 && std::isfinite(v.decel))) throw bad("decel");
  if (!(v.stopDistance >= 0.0))
    throw std::invalid_argument("vehicle '" + v.id + "': stopDistance must be >= 0 (infinity: none)");
}

}  // namespace

void VehicleTable::ensure(std::size_t n) {
  if (body.size() >= n) return;
  body.resize(n);
  centre.resize(n);
  vel.resize(n);
  mass.resize(n);
  decel.resize(n);
  env.resize(n);
  ext.resize(n);
  ownEnv.resize(n);
  ownExt.resize(n);
  shape.resize(n);
  brakeRatio.resize(n);
  accelAbs.resize(n);
  vclass.resize(n);
  signals.resize(n);
  equipped.resize(n);
  pairState.resize(n);
  wide.resize(n);
  inputOf.resize(n, -1);
  lane.resize(n, -1);
  route.resize(n);
  braking.resize(n);
  accel.resize(n);
}

int VehicleTable::newSlot(const VehicleState& v) {
  int s;
  if (!freeSlots.empty()) {
    s = freeSlots.back();
    freeSlots.pop_back();
  } else {
    s = static_cast<int>(slots.size());
    slots.emplace_back();
  }
  Slot& sl = slots[s];
  sl = Slot{};
  sl.id = v.id;
  sl.handle = v.handle;
  sl.serial = nextSerial++;
  sl.prev = v.position;
  ensure(slots.size());
  arrived.push_back(s);
  ++(v.vehicleClass == VehicleClass::Pedestrian ? counters->personsSeen : counters->vehiclesSeen);
  return s;
}

// The slot of vehicles[i] (a new one for a vehicle not present at the last tick).
int VehicleTable::slotFor(const VehicleState& v, int i, double t) {
  if (v.handle >= 0) {
    if (v.handle >= static_cast<int>(slotOfHandle.size())) slotOfHandle.resize(v.handle + 1, -1);
    int& s = slotOfHandle[v.handle];
    if (s < 0) s = newSlot(v);
    else if (slots[s].id != v.id)
      throw std::invalid_argument("vehicle handle " + std::to_string(v.handle) + " given to '" + slots[s].id + "' and '" +
                                  v.id + "' at t=" + std::to_string(t));
    return s;
  }
  if (i < static_cast<int>(active.size())) {
    // the common case: the same vehicle at the same place in the input as at the last tick (no
    // hash of its id); a duplicate id falls through to the lookup, which reports it
    const int s = active[i];
    if (inputOf[s] < 0 && slots[s].handle < 0 && slots[s].id == v.id) return s;
  }
  auto [it, inserted] = slotOfId.try_emplace(v.id, -1);  // no node built for a known id
  if (inserted) it->second = newSlot(v);
  return it->second;
}

void VehicleTable::update(double t, std::span<const VehicleState> vehicles) {
  for (int s : active) inputOf[s] = -1;
  arrived.clear();
  next_.resize(vehicles.size());  // next_[i]: the slot of vehicles[i]
  for (int i = 0; i < static_cast<int>(vehicles.size()); ++i) {
    const VehicleState& v = vehicles[i];
    checkFinite(v);
    const int s = slotFor(v, i, t);
    if (inputOf[s] >= 0) throw std::invalid_argument("vehicle '" + v.id + "' appears twice at t=" + std::to_string(t));
    inputOf[s] = i;
    next_[i] = s;
    take(s, v, t);
  }
  departed.clear();
  for (int s : active)
    if (inputOf[s] < 0) departed.push_back(s);
  std::swap(active, next_);
  counters->vehicleUpdates += active.size();
}

void VehicleTable::release() {
  for (int s : departed) {
    Slot& sl = slots[s];
    sl.present = false;
    if (sl.handle >= 0) slotOfHandle[sl.handle] = -1;
    else slotOfId.erase(sl.id);
    freeSlots.push_back(s);
  }
  departed.clear();
}

// Slot s's hot state from its vehicle this tick. Sizes rarely change, headings only on curves
// and lane changes: the axis (cos, sin) and the envelopes are kept until they do.
void VehicleTable::take(int s, const VehicleState& v, double t) {
  Slot& sl = slots[s];
  const DetectorConfig& dc = cfg->detector;
  const bool reshaped = v.length != sl.length || v.width != sl.width || v.heading != sl.heading;
  if (reshaped) sl.axis = v.direction();
  body[s] = bodyOf(v, sl.axis);
  centre[s] = v.position;
  vel[s] = body[s].velocity;
  mass[s] = v.mass;
  decel[s] = v.decel;
  if (reshaped) {
    ownEnv[s] = envelopeRadius(dc, v.length, v.width);
    ownExt[s] = envelopeExtent(dc, body[s]);
    shape[s] = carShape(dc, body[s]);
    sl.length = v.length;
    sl.width = v.width;
    sl.heading = v.heading;
  }
  env[s] = ownEnv[s];
  ext[s] = ownExt[s];
  const double twiceBrake = 2.0 * cfg->safeTime.brakeForce[static_cast<int>(v.vehicleClass)];
  brakeRatio[s] = cfg->safeTime.brakeRatio(v.mass, v.vehicleClass);
  wide[s] = static_cast<int>(!(brakeRatio[s] <= tol::kCompactBrakeRatio && ownExt[s].maxCoeff() <= tol::kCompactExtent &&
                               std::abs(v.lateralSpeed) <= tol::kCompactLateralSpeed));
  // what the kernels move it with (motionAcceleration): its own under ConstantAcceleration, and
  // under either model the braking to its stop line
  const bool own = cfg->detector.motion == MotionModel::ConstantAcceleration;
  accelAbs[s] = std::max(own ? std::abs(v.acceleration) : 0.0, -body[s].stopAcceleration);
  vclass[s] = v.vehicleClass;
  pairState[s] = {ext[s], env[s], v.mass, twiceBrake, shape[s].outer, sl.serial};
  signals[s] = v.signals;
  equipped[s] = v.equipped ? 1 : 0;
  lane[s] = v.lane;
  route[s] = v.route;
  if (sl.present && v.vehicleClass != VehicleClass::Pedestrian) counters->vehicleMeters += (v.position - sl.prev).norm();
  braking[s] = sl.present && t > sl.prevTime ? std::max(0.0, (sl.prevSpeed - v.speed) / (t - sl.prevTime)) : 0.0;
  accel[s] = sl.present && t > sl.prevTime ? (v.speed - sl.prevSpeed) / (t - sl.prevTime)
                                           : std::numeric_limits<double>::quiet_NaN();
  sl.prev = v.position;
  sl.prevSpeed = v.speed;
  sl.prevTime = t;
  sl.present = true;
}

}  // namespace st::highway::detail
