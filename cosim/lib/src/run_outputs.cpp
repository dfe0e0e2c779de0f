#include "run_parts.hpp"

#include <cmath>

#include <stio/format.hpp>

namespace st::cosim {

namespace fs = std::filesystem;
namespace hw = st::highway;

namespace {
// Numbers as docs/outputs.md's conventions write them: what SUMO reported (time, position, speeds)
// in full, the shortest text that reads back to the same double, so a row joins the FCD trace and
// warnings.csv on its exact time; what stsim worked out from them (the bodies' gap, a lead time:
// a difference of two times) to 0.001 of the unit, trailing zeros dropped, as report.cpp's
// derivedField, so no rounding noise (0.6000000000000227) is printed.
std::string full(double v) { return io::number(v); }
std::string derived(double v) {
  if (!std::isfinite(v)) return io::number(v);
  std::string s = io::fixed(v, 3);
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}
}  // namespace

RunOutputs::RunOutputs(const fs::path& out, bool trajectories)
    : ticks_(out, {.trajectories = trajectories, .exposure = true}),
      collisions_(out / "collisions.csv", "time,collider,victim,type,lane,pos,collider_speed,victim_speed,gap,contact") {
  collisions_.flush();
}

void RunOutputs::writeDetected(HighwayPlugin& plugin) { ticks_.write(plugin.monitor()); }

void RunOutputs::writeCollisions(HighwayPlugin& plugin) {
  for (const auto& c : plugin.takeCollisions()) writeCollision(c);
}

void RunOutputs::writeCollision(const SumoCollision& c) {
  collisionReports_.push_back(c);
  collisions_.row(full(c.time) + "," + io::csvField(c.collider) + "," + io::csvField(c.victim) + "," +
                  io::csvField(c.type) + "," + io::csvField(c.lane) + "," + full(c.pos) + "," + full(c.colliderSpeed) +
                  "," + full(c.victimSpeed) + "," + (std::isnan(c.gap) ? std::string() : derived(c.gap)) + "," +
                  (c.contact() ? "1" : "0"));
}

void RunOutputs::flush() {
  ticks_.flush();
  collisions_.flush();
}

void writeCollisionWarnings(const fs::path& path, const std::vector<CollisionWarning>& leads) {
  io::writeRowsFile(path, [&](std::ostream& lc) {
    lc << "time,collider,victim,collider_warned,lead_time_s\n";
    for (const CollisionWarning& w : leads)
      lc << full(w.collision.time) << "," << io::csvField(w.collision.collider) << "," << io::csvField(w.collision.victim)
         << "," << (w.leadTime ? 1 : 0) << "," << (w.leadTime ? derived(*w.leadTime) : std::string()) << "\n";
  });
}

}  // namespace st::cosim
