#pragma once
// Bookkeeping shared by the backends, so both see exactly the same vehicles in the same order.
#include <algorithm>
#include <string>
#include <unordered_set>
#include <vector>

#include <stcosim/backend.hpp>

namespace st::cosim::detail {

// The vehicles on the road, in departure order: departures are appended, teleports remove a
// vehicle until it is placed again (appended then), arrivals remove it.
class ActiveVehicles {
 public:
  void apply(const StepEvents& e) {
    for (const auto& id : e.departed) add(id);
    for (const auto& id : e.teleportStarted) remove(id);
    for (const auto& id : e.teleportEnded) add(id);
    for (const auto& id : e.arrived) remove(id);
  }
  const std::vector<std::string>& ids() const { return order_; }

 private:
  void add(const std::string& id) {
    if (present_.insert(id).second) order_.push_back(id);
  }
  void remove(const std::string& id) {
    if (present_.erase(id) == 0) return;
    order_.erase(std::find(order_.begin(), order_.end(), id));
  }
  std::vector<std::string> order_;
  std::unordered_set<std::string> present_;
};

}  // namespace st::cosim::detail
