#include <sthighway/run_driver.hpp>

#include <exception>

#include <sthighway/run_files.hpp>

namespace st::highway {

namespace {
// summary.json's fields of a driven run (an error's message with it, if any)
RunInfo runInfo(const HighwayMonitor& monitor, const DriveSetup& setup) {
  const MonitorConfig& cfg = monitor.config();
  RunInfo info;
  info.source = setup.source;
  info.detector = toString(cfg.detector.kind);
  info.broadphase = toString(cfg.broadphase);
  info.prediction = toString(cfg.prediction);
  info.hindsight = cfg.hindsight;
  info.conflict = cfg.conflict;
  return info;
}

// the source's frames through the monitor, each tick's results written as they come
struct Span {
  double first = 0.0, last = 0.0;
  bool any = false;
};
void stepFrames(FrameSource& source, HighwayMonitor& monitor, TickFiles& files, const DriveSetup& setup, Span& span) {
  Frame frame;
  while (source.next(frame)) {
    if (setup.end && frame.time > *setup.end) break;
    if (setup.penetration < 1.0)
      for (VehicleState& v : frame.vehicles)
        v.equipped = v.vehicleClass != VehicleClass::Pedestrian && drawnEquipped(setup.seed, v.id, setup.penetration);
    monitor.step(frame.time, frame.vehicles);
    if (!span.any) span.first = frame.time;
    span.any = true;
    span.last = frame.time;
    files.write(monitor);
  }
}

// close the open episodes at the last frame, write what is left, then summary.json
void closeRun(HighwayMonitor& monitor, TickFiles& files, const DriveSetup& setup, const Span& span,
              const std::string& error, RunInfo& info) {
  monitor.finish(span.any ? span.last : 0.0);
  files.write(monitor);
  files.flush();
  info.simulatedSeconds = span.any ? span.last - span.first : 0.0;
  info.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup.wallStart).count();
  if (!error.empty()) info.strings.emplace_back("error", error);
  info.numbers.emplace_back("penetration", setup.penetration);
  info.strings.emplace_back("net", std::filesystem::absolute(setup.net).string());
  writeSummaryJson(setup.out / "summary.json", monitor.counters(), info);
}
}  // namespace

DriveResult driveRun(FrameSource& source, HighwayMonitor& monitor, const DriveSetup& setup) {
  TickFiles files(setup.out, {.trajectories = setup.trajectories});
  if (setup.trajectories) monitor.recordTrajectories(true);
  DriveResult result;
  result.info = runInfo(monitor, setup);
  Span span;
  // on any error: close what is open, write everything so far, then rethrow
  try {
    stepFrames(source, monitor, files, setup, span);
  } catch (const std::exception& e) {
    closeRun(monitor, files, setup, span, e.what(), result.info);
    throw;
  }
  closeRun(monitor, files, setup, span, "", result.info);
  if (setup.map) result.map = drawConflictMap({setup.out / "conflict_map", setup.net, {setup.out / "conflicts.csv"}, *setup.map});
  return result;
}

}  // namespace st::highway
