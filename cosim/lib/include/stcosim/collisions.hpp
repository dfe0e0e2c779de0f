#pragma once
// SUMO's collisions: counted once per contact, and read from SUMO's --collision-output file.
// The file is the only source over TraCI: SUMO 1.15's libtraci leaves Simulation::getCollisions
// unimplemented (it returns nothing; eclipse-sumo/sumo#12861), while libsumo implements it.
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <stcosim/backend.hpp>

namespace st::cosim {

// With --collision.action warn SUMO reports a touching pair again at every step, so a pair counts
// as a new collision only after a step in which it was not reported.
class CollisionCounter {
 public:
  // The collisions SUMO reported at one step (none is a step too: it ends every contact).
  void step(const std::vector<SumoCollision>& reported);
  std::uint64_t distinct() const { return distinct_; }
  std::uint64_t reports() const { return reports_; }

 private:
  std::set<std::pair<std::string, std::string>> touching_;
  std::uint64_t distinct_ = 0, reports_ = 0;
};

// Replays reports in time order through a counter, one step of `stepLength` seconds at a time, so
// a gap of one step or more between two reports of a pair makes them two collisions.
void countCollisions(CollisionCounter& counter, const std::vector<SumoCollision>& reports, double stepLength);

// The options that make SUMO write its collisions to `file`.
std::vector<std::string> collisionOutputArguments(const std::filesystem::path& file);
// Reads a --collision-output file, in its order (time order). Throws std::runtime_error naming the
// file (and line) if it cannot be read or a record lacks a required attribute.
std::vector<SumoCollision> readCollisionOutput(const std::filesystem::path& file);

}  // namespace st::cosim
