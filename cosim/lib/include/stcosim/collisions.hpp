#pragma once
// SUMO's collisions: counted once per contact, and read from SUMO's --collision-output file.
// The file is the only source over TraCI: SUMO 1.15's libtraci leaves Simulation::getCollisions
// unimplemented (it returns nothing; eclipse-sumo/sumo#12861), while libsumo implements it.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <sthighway/monitor.hpp>
#include <stcosim/backend.hpp>

namespace st::cosim {

// A SUMO collision is a contact when the two bodies (their rectangles from the step's states) are
// at most this far apart (m): SUMO's front positions and our rectangles agree to well under it;
// a minGap violation (collision.mingap-factor 1) leaves the bodies apart by up to the minGap (2.5 m).
inline constexpr double kContactGap = 0.05;

// With --collision.action warn SUMO reports a touching pair again at every step, so a pair counts
// as a new collision only after a step in which it was not reported.
class CollisionCounter {
 public:
  // The collisions SUMO reported at one step (none is a step too: it ends every contact).
  // Returns the indices into `reported` of the contacts that begin at this step.
  std::vector<std::size_t> step(const std::vector<SumoCollision>& reported);
  std::uint64_t distinct() const { return distinct_; }
  std::uint64_t reports() const { return reports_; }

 private:
  std::set<std::pair<std::string, std::string>> touching_;
  std::uint64_t distinct_ = 0, reports_ = 0;
};

// Replays reports in time order through a counter, one step of `stepLength` seconds at a time, so
// a gap of one step or more between two reports of a pair makes them two collisions. Returns the
// first report of each collision.
std::vector<SumoCollision> countCollisions(CollisionCounter& counter, const std::vector<SumoCollision>& reports,
                                           double stepLength);

// A collision and whether the collider had been warned of it: the collider's vehicle warning about
// the victim that is on at the collision (an episode ending no earlier than one step before it),
// counted from its begin, with episodes less than `kWarningGapMerge` apart taken as one warning.
struct CollisionWarning {
  SumoCollision collision;         // its first report
  std::optional<double> leadTime;  // s; none if the collider was not warning about the victim
};
inline constexpr double kWarningGapMerge = 1.0;  // s
std::vector<CollisionWarning> collisionWarnings(const std::vector<SumoCollision>& firstReports, double stepLength,
                                                const std::vector<highway::Warning>& warnings);

// The options that make SUMO write its collisions to `file`.
std::vector<std::string> collisionOutputArguments(const std::filesystem::path& file);
// Reads a --collision-output file, in its order (time order), on stsim's timeline: SUMO stamps a
// step's collisions with the time the step began, libsumo's getCollisions (and stsim's vehicle
// states) with the step's end, so each time is moved on by `stepLength`. Throws
// std::runtime_error naming the file (and line) if it cannot be read or a record lacks a required
// attribute.
std::vector<SumoCollision> readCollisionOutput(const std::filesystem::path& file, double stepLength);

}  // namespace st::cosim
