#include <sthighway/run_files.hpp>

#include <stdexcept>
#include <string>

#include <stio/format.hpp>

namespace st::highway {

namespace fs = std::filesystem;

namespace {
fs::path prepared(const fs::path& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + out.string() + ": " + ec.message());
  removeRunOutputs(out);
  return out;
}
}  // namespace

TickFiles::TickFiles(const fs::path& out, TickFileOptions options)
    : warnings_(prepared(out) / "warnings.csv"), conflicts_(out / "conflicts.csv"), events_(out / "events.csv") {
  if (options.trajectories) series_.emplace(out / "trajectories.csv");
  // the exposure up to each tick: what a study's warm-up leaves out (stsim batch's warmup)
  if (options.exposure) exposure_.emplace(out / "exposure.csv", "time,vehicle_km,vehicles");
}

void TickFiles::write(HighwayMonitor& monitor) {
  if (exposure_) {
    const MonitorCounters& c = monitor.counters();
    if (const double t = monitor.lastTime(); t > exposureTime_) {
      exposureTime_ = t;
      // the time as given, in full (it joins the trace on it)
      exposure_->row(io::number(t) + "," + io::number(c.vehicleMeters / 1000.0) + "," + std::to_string(c.vehiclesSeen));
    }
  }
  monitor.takeFinished(finished_);
  warnings_.write(finished_);
  for (const Warning& w : finished_)
    if (w.kind == WarningKind::Vehicle) vehicleWarnings_.push_back(w);
  monitor.takeConflicts(conflictBuffer_);
  conflicts_.write(conflictBuffer_);
  monitor.takeEvents(eventBuffer_);
  events_.write(eventBuffer_);
  if (series_) {
    monitor.takeTrajectories(seriesBuffer_);
    series_->write(seriesBuffer_);
  }
}

void TickFiles::flush() {
  warnings_.flush();
  conflicts_.flush();
  events_.flush();
  if (exposure_) exposure_->flush();
  if (series_) series_->flush();
}

}  // namespace st::highway
