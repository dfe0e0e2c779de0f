#pragma once
// A source of frames of vehicle states (an FCD trace, a test, Python): what a highway run
// (run_driver.hpp) steps through the monitor.
#include <vector>

#include <sthighway/vehicle.hpp>

namespace st::highway {

// The vehicles on the road at one time.
struct Frame {
  double time = 0.0;  // s, strictly increasing from frame to frame
  std::vector<VehicleState> vehicles;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Fills the next frame; false at the end. May throw (a bad record): the run writes what it has.
  virtual bool next(Frame& frame) = 0;
};

}  // namespace st::highway
