#include "run_parts.hpp"

#include <stcosim/detection.hpp>

namespace st::cosim {

using Clock = std::chrono::steady_clock;

LoopOutcome stepLoop(Backend& backend, HighwayPlugin& plugin, SsmValidator* validator, RunOutputs& outputs,
                     double endTime, bool overlap, const RunObserver& observer) {
  LoopOutcome o;
  // the monitor's counters are read only with the monitor idle, when a tick's detection is collected
  std::uint64_t warnings = 0;
  DetectionStage detection(plugin, overlap, [&] {
    outputs.writeDetected(plugin);
    warnings = 0;
    for (auto n : plugin.monitor().counters().warningsByKind) warnings += n;
  });
  auto lastProgress = Clock::now();
  auto stopped = [&](const std::exception& e) {
    if (observer.stopRequested && observer.stopRequested()) {
      // Ctrl-C reaches an attached SUMO in the same terminal too: its lost connection is the stop
      o.stopReason = "interrupted";
    } else {
      o.error = e.what();
      o.stopReason = "error";
    }
  };
  try {
    while (backend.running()) {
      if (observer.stopRequested && observer.stopRequested()) {
        o.stopReason = "interrupted";
        break;
      }
      if (endTime >= 0.0 && backend.time() >= endTime - 0.5 * backend.deltaT()) break;
      const auto t0 = Clock::now();
      backend.step();  // overlapped: beside the previous tick's detection
      const auto t1 = Clock::now();
      detection.afterStep();
      const auto t2 = Clock::now();
      o.sumoSeconds += std::chrono::duration<double>(t1 - t0).count();
      // stsim's time on SUMO's thread: what it holds SUMO up
      o.stsimSeconds += std::chrono::duration<double>(t2 - t1).count();
      if (validator) {
        validator->record(backend.time(), plugin.states());
        o.validationSeconds += std::chrono::duration<double>(Clock::now() - t2).count();
      }
      outputs.writeCollisions(plugin);
      if (observer.progress && t2 - lastProgress > observer.progressInterval) {
        lastProgress = t2;
        RunProgress p;
        p.time = backend.time();
        p.endTime = endTime;
        p.vehicles = backend.vehicles().size();
        p.warnings = warnings;
        p.sumoSeconds = o.sumoSeconds;
        p.stsimSeconds = o.stsimSeconds;
        observer.progress(p);
      }
    }
    detection.drain();
  } catch (const std::exception& e) {
    stopped(e);
  }
  // an error in SUMO's step leaves the previous tick's detection running: it is written too
  try {
    detection.drain();
  } catch (const std::exception& e) {
    if (o.error.empty()) stopped(e);
  }
  return o;
}

double closeRun(Backend& backend, HighwayPlugin& plugin, SsmValidator* validator, RunOutputs& outputs) {
  plugin.finish();
  outputs.writeDetected(plugin);
  outputs.writeCollisions(plugin);
  outputs.flush();
  if (validator) validator->finish(backend.time());
  const double simEnd = backend.time();
  backend.close();
  return simEnd;
}

}  // namespace st::cosim
