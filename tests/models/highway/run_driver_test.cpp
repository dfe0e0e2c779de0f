// The highway run driver against the monitor stepped by hand: the same frames give the same
// files; an error of the source leaves everything so far written (summary.json with the error)
// and is rethrown; the end time and the equipped share as set.
#include <gtest/gtest.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <sthighway/report.hpp>
#include <sthighway/run_driver.hpp>

#include "files.hpp"
#include "roads.hpp"

namespace st::highway {
namespace {

// Car a at 20 m/s closes on car b, stopped 40 m ahead on the same lane: a car-car warning
// within the first second. Frames every 0.1 s.
Frame frameAt(int k) {
  Frame f;
  f.time = k / 10.0;
  VehicleState a, b;
  a.id = "a";
  a.speed = 20.0;
  a.position = Vec2(2.0 * k, 0.0);
  b.id = "b";
  b.position = Vec2(40.0, 0.0);
  f.vehicles = {a, b};
  return f;
}

// frames 0 .. frames-1; with throwAt >= 0, throws instead of giving that frame
class Scripted final : public FrameSource {
 public:
  Scripted(int frames, int throwAt = -1) : frames_(frames), throwAt_(throwAt) {}
  bool next(Frame& frame) override {
    if (k_ == throwAt_) throw std::runtime_error("bad record at frame " + std::to_string(k_));
    if (k_ == frames_) return false;
    frame = frameAt(k_++);
    return true;
  }

 private:
  int frames_, throwAt_, k_ = 0;
};

// the files of frames 0 .. frames-1 stepped by hand, each writer fed directly
void byHand(const std::filesystem::path& dir, int frames) {
  std::filesystem::create_directories(dir);
  HighwayMonitor m(oneLaneRoad(), MonitorConfig{});
  WarningsCsvWriter warnings(dir / "warnings.csv");
  ConflictsCsvWriter conflicts(dir / "conflicts.csv");
  EventsCsvWriter events(dir / "events.csv");
  std::vector<Conflict> c;
  std::vector<HindsightEvent> e;
  auto take = [&] {
    warnings.write(m.takeFinished());
    m.takeConflicts(c);
    conflicts.write(c);
    m.takeEvents(e);
    events.write(e);
  };
  for (int k = 0; k < frames; ++k) {
    const Frame f = frameAt(k);
    m.step(f.time, f.vehicles);
    take();
  }
  m.finish(frameAt(frames - 1).time);
  take();
}

void expectSameFiles(const std::filesystem::path& a, const std::filesystem::path& b) {
  for (const char* f : {"warnings.csv", "conflicts.csv", "events.csv"}) {
    SCOPED_TRACE(f);
    EXPECT_EQ(test::slurp(a / f), test::slurp(b / f));
  }
}

DriveSetup setupIn(const std::filesystem::path& out) {
  DriveSetup s;
  s.out = out;
  s.source = "scripted";
  s.net = "road.net.xml";
  return s;
}

TEST(RunDriver, WritesWhatTheMonitorSteppedByHandWrites) {
  const auto dir = test::freshDir("run_driver", "whole");
  HighwayMonitor m(oneLaneRoad(), MonitorConfig{});
  Scripted source(30);
  const DriveResult r = driveRun(source, m, setupIn(dir / "driven"));
  byHand(dir / "hand", 30);
  expectSameFiles(dir / "driven", dir / "hand");
  EXPECT_GT(m.counters().warningsByKind[0], 0u);  // the scene warns
  EXPECT_DOUBLE_EQ(r.info.simulatedSeconds, 2.9);
  EXPECT_FALSE(r.map.has_value());
  const std::string summary = test::slurp(dir / "driven" / "summary.json");
  EXPECT_NE(summary.find("\"penetration\": 1"), std::string::npos);
  EXPECT_EQ(summary.find("\"error\""), std::string::npos);
}

TEST(RunDriver, AnErrorWritesEverythingSoFarThenRethrows) {
  const auto dir = test::freshDir("run_driver", "error");
  HighwayMonitor m(oneLaneRoad(), MonitorConfig{});
  Scripted source(30, 12);
  EXPECT_THROW(driveRun(source, m, setupIn(dir / "driven")), std::runtime_error);
  byHand(dir / "hand", 12);  // the frames before the error, then every episode closed
  expectSameFiles(dir / "driven", dir / "hand");
  EXPECT_NE(test::slurp(dir / "driven" / "warnings.csv").find("\na,b,vehicle"), std::string::npos);
  const std::string summary = test::slurp(dir / "driven" / "summary.json");
  EXPECT_NE(summary.find("\"error\": \"bad record at frame 12\""), std::string::npos) << summary;
}

TEST(RunDriver, EndsBeforeTheFirstFrameAfterTheEnd) {
  const auto dir = test::freshDir("run_driver", "end");
  HighwayMonitor m(oneLaneRoad(), MonitorConfig{});
  Scripted source(30);
  DriveSetup s = setupIn(dir / "driven");
  s.end = 1.0;
  const DriveResult r = driveRun(source, m, s);
  EXPECT_DOUBLE_EQ(r.info.simulatedSeconds, 1.0);
  byHand(dir / "hand", 11);  // 0 .. 1.0 s
  expectSameFiles(dir / "driven", dir / "hand");
}

TEST(RunDriver, NobodyEquippedWarnsNobody) {
  const auto dir = test::freshDir("run_driver", "none");
  HighwayMonitor m(oneLaneRoad(), MonitorConfig{});
  Scripted source(30);
  DriveSetup s = setupIn(dir);
  s.penetration = 0.0;
  driveRun(source, m, s);
  for (auto n : m.counters().warningsByKind) EXPECT_EQ(n, 0u);
  EXPECT_EQ(m.counters().vehiclesSeen, 2u);
}

}  // namespace
}  // namespace st::highway
