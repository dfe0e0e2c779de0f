#include "run_parts.hpp"

namespace st::cosim {

using Clock = std::chrono::steady_clock;

LoopOutcome stepLoop(Backend& backend, HighwayPlugin& plugin, SsmValidator* validator, RunOutputs& outputs,
                     double endTime, const RunObserver& observer) {
  LoopOutcome o;
  auto lastProgress = Clock::now();
  try {
    while (backend.running()) {
      if (observer.stopRequested && observer.stopRequested()) {
        o.stopReason = "interrupted";
        break;
      }
      if (endTime >= 0.0 && backend.time() >= endTime - 0.5 * backend.deltaT()) break;
      const auto t0 = Clock::now();
      backend.step();
      const auto t1 = Clock::now();
      plugin.update();
      const auto t2 = Clock::now();
      o.sumoSeconds += std::chrono::duration<double>(t1 - t0).count();
      o.stsimSeconds += std::chrono::duration<double>(t2 - t1).count();
      if (validator) {
        validator->record(backend.time(), plugin.states());
        o.validationSeconds += std::chrono::duration<double>(Clock::now() - t2).count();
      }
      outputs.writeDetected(plugin);
      outputs.writeCollisions(plugin);
      if (observer.progress && t2 - lastProgress > observer.progressInterval) {
        lastProgress = t2;
        RunProgress p;
        p.time = backend.time();
        p.endTime = endTime;
        p.vehicles = backend.vehicles().size();
        for (auto n : plugin.monitor().counters().warningsByKind) p.warnings += n;
        p.sumoSeconds = o.sumoSeconds;
        p.stsimSeconds = o.stsimSeconds;
        observer.progress(p);
      }
    }
  } catch (const std::exception& e) {
    if (observer.stopRequested && observer.stopRequested()) {
      // Ctrl-C reaches an attached SUMO in the same terminal too: its lost connection is the stop
      o.stopReason = "interrupted";
    } else {
      o.error = e.what();
      o.stopReason = "error";
    }
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
