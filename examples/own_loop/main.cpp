// own_loop: a user's own SUMO loop with stsim's smart-car warnings added to it. The program starts
// embedded SUMO (libsumo) and steps it; the plugin reads every vehicle after each step, runs the
// highway monitor and colours warned cars (its default action). Prints one line per finished
// warning episode and a count at the end.
//
// usage: own_loop SCENARIO.sumocfg [END_SECONDS]
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <libsumo/libsumo.h>
#include <stcosim/plugin.hpp>
#include <stsim/version.hpp>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: own_loop SCENARIO.sumocfg [END_SECONDS]\n";
    return 2;
  }
  const double end = argc > 2 ? std::atof(argv[2]) : 60.0;
  try {
    libsumo::Simulation::start({"sumo", "-c", argv[1], "--no-step-log", "true", "--no-warnings", "true"});

    st::cosim::PluginConfig config;  // five-circle detector, cells, colour warned cars
    config.monitor.detector.kind = st::highway::DetectorKind::FiveCircle;
    auto plugin = st::cosim::HighwayPlugin::forLibsumo(config);

    long warnings = 0;
    auto print = [&](const std::vector<st::highway::Warning>& finished) {
      for (const auto& w : finished) {
        ++warnings;
        std::cout << w.begin << " s  " << w.ego << " -> " << w.foe << "  " << st::highway::toString(w.kind)
                  << "  min TTC " << w.minTtc << " s\n";
      }
    };
    while (libsumo::Simulation::getMinExpectedNumber() > 0 && libsumo::Simulation::getTime() < end) {
      libsumo::Simulation::step();
      plugin->step();
      print(plugin->takeFinished());
    }
    plugin->finish();  // closes the episodes still open
    print(plugin->takeFinished());
    libsumo::Simulation::close();
    std::cout << "own_loop (stsim " << STSIM_VERSION_STRING << "): " << plugin->counters().equipped
              << " smart cars, " << warnings << " warnings in " << end << " s\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "own_loop: " << e.what() << "\n";
    return 1;
  }
}
