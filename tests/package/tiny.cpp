// The smallest user of the installed headers and libraries (built with pkg-config by
// check_install.sh): two cars closing head-on with no road; the monitor must warn.
#include <cstdio>
#include <vector>

#include <sthighway/monitor.hpp>
#include <stsim/version.hpp>

int main() {
  static_assert(STSIM_VERSION >= 100, "version macro from the installed header");
  st::highway::HighwayMonitor monitor(st::highway::RoadGeometry{}, st::highway::MonitorConfig{});
  std::vector<st::highway::VehicleState> cars(2);
  cars[0].id = "a";
  cars[0].speed = 20.0;
  cars[1].id = "b";
  cars[1].heading = 3.14159265358979323846;
  cars[1].speed = 20.0;
  for (int k = 0; k < 10; ++k) {
    cars[0].position = {0.1 * 20.0 * k, 0.0};
    cars[1].position = {100.0 - 0.1 * 20.0 * k, 0.0};
    monitor.step(0.1 * k, cars);
  }
  monitor.finish(1.0);
  const auto warnings = monitor.takeFinished();
  std::printf("stsim %s: %zu warnings\n", STSIM_VERSION_STRING, warnings.size());
  return warnings.empty() ? 1 : 0;
}
