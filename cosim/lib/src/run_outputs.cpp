#include "run_parts.hpp"

#include <cmath>

#include <stio/format.hpp>

namespace st::cosim {

namespace fs = std::filesystem;
namespace hw = st::highway;

namespace {
fs::path prepared(const fs::path& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + out.string() + ": " + ec.message());
  // every file in out belongs to this run: what an earlier run wrote and this one may not goes first
  hw::removeRunOutputs(out);
  return out;
}
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
    : warnings_(prepared(out) / "warnings.csv"),
      conflicts_(out / "conflicts.csv"),
      events_(out / "events.csv"),
      collisions_(out / "collisions.csv", "time,collider,victim,type,lane,pos,collider_speed,victim_speed,gap,contact"),
      // the exposure up to each tick: what a study's warm-up leaves out (stsim batch's warmup)
      exposure_(out / "exposure.csv", "time,vehicle_km,vehicles") {
  if (trajectories) series_.emplace(out / "trajectories.csv");
  collisions_.flush();
}

void RunOutputs::writeDetected(HighwayPlugin& plugin) {
  const hw::MonitorCounters& c = plugin.monitor().counters();
  if (const double t = plugin.monitor().lastTime(); t > exposureTime_) {
    exposureTime_ = t;
    exposure_.row(full(t) + "," + full(c.vehicleMeters / 1000.0) + "," + std::to_string(c.vehiclesSeen));
  }
  const std::vector<hw::Warning> finished = plugin.takeFinished();
  warnings_.write(finished);
  for (const hw::Warning& w : finished)
    if (w.kind == hw::WarningKind::Vehicle) vehicleWarnings_.push_back(w);
  plugin.takeConflicts(conflictBuffer_);
  conflicts_.write(conflictBuffer_);
  plugin.takeEvents(eventBuffer_);
  events_.write(eventBuffer_);
  if (series_) {
    plugin.takeTrajectories(seriesBuffer_);
    series_->write(seriesBuffer_);
  }
}

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
  warnings_.flush();
  conflicts_.flush();
  events_.flush();
  collisions_.flush();
  exposure_.flush();
  if (series_) series_->flush();
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
