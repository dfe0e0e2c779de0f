#pragma once
// A scenario written back as YAML: what a recorded game (stsim pool serve's download) is.
#include <iosfwd>

#include <stpool/scenario.hpp>

namespace st::pool {

// Writes the scenario as YAML that parseScenario reads back to the same values bit for bit (every
// ball listed, numbers in their shortest exact form, shots as velocities): a game played through
// the Game API and written out replays through `stsim pool` to the same events.
void writeScenarioYaml(std::ostream& os, const Scenario& s);

}  // namespace st::pool
