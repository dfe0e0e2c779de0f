// A control loop of your own: each cycle, give the monitor the arms' joint readings, run it,
// and brake the arms it STOPs. Here the readings come from a scenario's scripted motion.
#include <algorithm>
#include <cstdio>
#include <vector>

#include <starm/scenario.hpp>

int main(int argc, char** argv) {
  if (argc != 2) return std::fprintf(stderr, "usage: arm_loop SCENARIO.yaml\n"), 2;
  try {
    const st::arm::Scenario s = st::arm::loadScenario(argv[1]);
    st::arm::Monitor monitor = st::arm::makeMonitor(s);
    auto sensor = st::arm::makeSensor(s);  // your robot's joint states instead
    std::vector<bool> stopped(monitor.armCount(), false);
    st::arm::Reading r;
    bool more = sensor->next(r);
    while (more) {
      const double t = r.t;
      for (; more && r.t == t; more = sensor->next(r))  // the readings of one cycle
        monitor.setJointState(r.arm, r.t, r.q.data(), r.qdot.data());  // checked: throws on NaN
      monitor.cycle(t);
      for (int a = 0; a < monitor.armCount(); ++a)
        if (monitor.stopped(a) && !stopped[a]) {
          stopped[a] = true;  // your brake command here
          std::printf("%.3f s: STOP %s (min TTC %.3f s)\n", t, monitor.arm(a).name.c_str(), monitor.minTtc(a));
        }
    }
    std::printf("arm_loop: %d arms, %zu stopped\n", monitor.armCount(), std::count(stopped.begin(), stopped.end(), true));
  } catch (const std::exception& e) {
    return std::fprintf(stderr, "arm_loop: %s\n", e.what()), 1;
  }
}
