#include <stcosim/backend.hpp>

#include <algorithm>

namespace st::cosim {

const char* toString(BackendKind k) {
  switch (k) {
    case BackendKind::Libsumo: return "libsumo";
    case BackendKind::Traci: return "libtraci";
  }
  return "?";
}

void Backend::step() {
  advance();
  read();
}

void Backend::setReads(const VehicleReads& reads) {
  if (reads == reads_) return;
  reads_ = reads;
  // what is not read is 0, also for the vehicles read before
  for (SumoVehicle& v : vehicles_) {
    if (!reads_.acceleration) v.acceleration = 0.0;
    if (!reads_.signals) v.signals = 0;
    if (!reads_.route) {
      v.routeIndex = -1;
      v.routeId.clear();
      v.route.clear();
      v.routeVersion = ++routeReads_;
    }
  }
  if (!reads_.persons) applyPersons({});
}

const SumoVehicleType& Backend::vehicleType(const std::string& typeId) {
  return types_[static_cast<std::size_t>(typeIndexOf(typeId))];
}

int Backend::typeIndexOf(const std::string& typeId) {
  const auto it = typeIndex_.find(typeId);
  if (it != typeIndex_.end()) return it->second;
  types_.push_back(readVehicleType(typeId));
  return typeIndex_.emplace(typeId, static_cast<int>(types_.size()) - 1).first->second;
}

void Backend::applyEvents(const StepEvents& e) {
  for (const auto& id : e.departed) appear(id);
  for (const auto& id : e.teleportStarted) leave(id);
  for (const auto& id : e.teleportEnded) appear(id);
  for (const auto& id : e.arrived) {
    leave(id);
    known_.erase(id);
  }
}

void Backend::appear(const std::string& id) {
  auto it = known_.find(id);
  if (it == known_.end()) {
    // a vehicle's type is read once (a type change through TraCI by another client is not seen)
    Known k;
    k.typeIndex = typeIndexOf(readTypeId(id));
    k.serial = nextSerial_++;
    it = known_.emplace(id, k).first;
  }
  Known& k = it->second;
  if (k.onRoad) return;
  k.onRoad = true;
  vehicles_.push_back(record(id, k));
}

SumoVehicle Backend::record(const std::string& id, const Known& k) const {
  SumoVehicle v;
  v.id = id;
  v.typeIndex = k.typeIndex;
  v.type = types_[static_cast<std::size_t>(k.typeIndex)].id;
  v.serial = k.serial;
  return v;
}

void Backend::applyPersons(const std::vector<std::string>& walking) {
  const std::uint64_t call = ++personCalls_;
  for (const std::string& id : walking) {
    auto it = knownPersons_.find(id);
    if (it == knownPersons_.end()) {
      Known k;
      k.typeIndex = typeIndexOf(readPersonTypeId(id));
      k.serial = nextSerial_++;
      it = knownPersons_.emplace(id, k).first;
    }
    Known& k = it->second;
    k.seen = call;
    if (k.onRoad) continue;
    k.onRoad = true;
    persons_.push_back(record(id, k));
  }
  std::erase_if(persons_, [&](const SumoVehicle& p) {
    Known& k = knownPersons_.at(p.id);
    if (k.seen == call) return false;
    k.onRoad = false;
    return true;
  });
}

void Backend::leave(const std::string& id) {
  const auto it = known_.find(id);
  if (it == known_.end() || !it->second.onRoad) return;
  it->second.onRoad = false;
  vehicles_.erase(std::find_if(vehicles_.begin(), vehicles_.end(), [&](const SumoVehicle& v) { return v.id == id; }));
}

}  // namespace st::cosim
