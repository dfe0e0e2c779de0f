#pragma once
// A picture of a run: a self-contained HTML replay of the cell (arm capsules, obstacles, persons)
// in two orthographic views, top (x, y) and side (x, z), with a time slider, each arm's STOP /
// WARN timeline and the cause pair of every STOP highlighted. The recorder watches the monitor
// after each cycle; the page inlines everything it draws (no external URL) and stays bounded:
// poses of at most `maxFrames` cycles (every k-th, k doubling as the run grows, plus the cycle of
// each STOP), while the timeline and the STOP list cover every cycle.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <starm/monitor.hpp>
#include <stio/json.hpp>

namespace st::arm {

class PersonSet;
class SeparationMonitor;

struct ReplayConfig {
  // most cycles whose poses are kept; 0: chosen so that about 60 000 capsule poses fit (200..2000)
  int maxFrames = 0;
  // most STOPs kept with their own frame (more are listed and drawn on the timeline)
  int maxStopFrames = 500;
};

// What a STOP was for: its arm, time and the rule; for collision and separation the pair with the
// arm's smallest time to collision (Monitor::worst) at the STOP's cycle.
struct ReplayStop {
  int arm = -1;
  double t = 0.0;
  std::string cause;          // collision, separation, stale, latched
  std::string body, other;    // the pair: "arm/link" and "arm/link" or "obstacle:name"; empty: none
  int capsule = -1;           // the arm's capsule (Monitor's global index), -1: no pair
  int otherCapsule = -1;      // the other arm capsule, or
  int obstacle = -1;          // the obstacle
  double distance = INFINITY, ttc = INFINITY;  // m, s
};

class ReplayRecorder {
 public:
  // persons may be null (none in the scene)
  ReplayRecorder(const Monitor& m, const PersonSet* persons, ReplayConfig cfg = {});
  // After each cycle: the poses (if this cycle is kept), each arm's level and new STOPs.
  // ssm may be null (no persons).
  void see(const Monitor& m, const PersonSet* persons, const SeparationMonitor* ssm);
  // The page; title names the scenario. Throws std::runtime_error naming the file if it cannot
  // be written (io::writeTextFile).
  void write(const std::filesystem::path& file, const std::string& title) const;

  int frames() const { return static_cast<int>(frameT_.size()); }
  std::uint64_t cycles() const { return cycles_; }
  const std::vector<ReplayStop>& stops() const { return stops_; }

 private:
  struct Segment {
    double t0, t1;
    int level;  // 1 WARN, 2 STOP (collision monitor); 3 SCALE, 4 person STOP (persons' band)
    bool open;  // still growing: the last cycle's level
  };
  void keepFrame(const Monitor& m, const PersonSet* persons, bool forced);
  // the page's data D: the run, the scene, the frames, the timeline's rows and the STOPs
  io::JsonText dataJson(const std::string& title) const;
  static io::JsonText rowsJson(const std::vector<std::vector<Segment>>& rows, double tEnd);
  io::JsonText stopJson(std::size_t k) const;
  void thin();  // halves the regular frames once they exceed the cap
  static void level(std::vector<Segment>& row, int lvl, double t);

  ReplayConfig cfg_;
  double cycleTime_ = 0.0;
  std::string scene_;  // the static part of the page's data (arms, capsules, obstacles)
  int capsules_ = 0, persons_ = 0;
  std::vector<int> first_;  // first global capsule of each arm
  int stride_ = 1;
  std::uint64_t cycles_ = 0;
  double lastT_ = 0.0;
  // frames, struct of arrays: time, cycle index, forced (a STOP's), capsule end points in mm
  std::vector<double> frameT_;
  std::vector<std::uint64_t> frameCycle_;
  std::vector<char> frameForced_;
  std::vector<std::vector<std::int32_t>> frameCaps_;     // 6 per arm capsule
  std::vector<std::vector<std::int32_t>> framePersons_;  // 6 per person capsule, empty: absent
  int forcedFrames_ = 0;
  std::vector<std::vector<Segment>> armRows_, personRows_;
  std::vector<char> wasStopped_;
  std::vector<ReplayStop> stops_;
  std::vector<std::uint64_t> stopCycle_;
};

}  // namespace st::arm
