#pragma once
// Where the plugin's detection runs: in line after each SUMO step, or on a worker thread while
// SUMO advances to the next step (the monitor's work for tick t beside SUMO's step to t+1).
//
//     DetectionStage detection(plugin, overlap, [&] { write(plugin.takeFinished()); });
//     while (backend.running()) { backend.step(); detection.afterStep(); }
//     detection.drain();
//     plugin.finish();
//
// SUMO is only ever touched on the caller's thread: the reads (backend.step()), the conversion
// and incidents (plugin.prepare()) and the actions. The worker runs plugin.detect() alone, which
// reads the converted states and writes only the monitor; the caller touches neither the monitor
// nor states() (beyond reading it) until the detection is done. Results are those of the serial
// run, bit for bit (tests/cosim/detection_test.cpp). Overlap needs an action that does not have to
// reach SUMO before its next step: `none`, or `color`, whose colours for tick t then reach SUMO
// after its step to t+1 (one step late on screen); `brake` changes what SUMO does next.
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

#include <stcosim/plugin.hpp>

namespace st::cosim {

// Whether detection may run beside SUMO's next step with this configuration.
bool detectionCanOverlap(const PluginConfig& config);

class DetectionStage {
 public:
  // overlap: detect on a worker thread (throws std::invalid_argument if the configuration does
  // not allow it). collect: called on the caller's thread after each tick's detection, with the
  // monitor idle: take its finished warnings and events there.
  DetectionStage(HighwayPlugin& plugin, bool overlap, std::function<void()> collect);
  ~DetectionStage();  // waits for a running detection, ends the worker
  DetectionStage(const DetectionStage&) = delete;
  DetectionStage& operator=(const DetectionStage&) = delete;

  // After SUMO's step to t. In line: prepare, detect, act on tick t, collect. Overlapped: wait
  // for tick t-1's detection (rethrowing its error here), collect it and act on it (colour),
  // prepare tick t and start its detection.
  void afterStep();
  // Waits for the running detection, if any, collects it and acts on it; rethrows its error. Call
  // before plugin.finish() and before reading the monitor.
  void drain();
  bool overlapped() const { return worker_.joinable(); }

 private:
  void work();
  void start();
  void wait();

  HighwayPlugin& plugin_;
  std::function<void()> collect_;
  std::thread worker_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  bool job_ = false;      // a detection handed to the worker and not finished
  bool pending_ = false;  // a detection started and not yet collected (caller's thread only)
  bool quit_ = false;
  std::exception_ptr error_;
};

}  // namespace st::cosim
