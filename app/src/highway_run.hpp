#pragma once
// `stsim highway SCENARIO.yaml|FILE.sumocfg [options]`: runs SUMO with the smart-car plugin and writes
// warnings.csv, collisions.csv, summary.json (and validation.json with --validate-ssm) in --out.
// Options (declared by app/src/highway_command.cpp) override the scenario's settings:
//   --detector --layout --motion --broadphase --penetration --action --end --seed --scale --set
//   (each checked by its key's table), --out --gui
//   --traci HOST:PORT[:ORDER]   attach to a running SUMO as a TraCI client (ORDER: client order,
//                               for a SUMO started with --num-clients N)
//   --validate-ssm              equip every vehicle with SUMO's SSM device and compare
// Returns 0 on a complete run, 130 when interrupted (Ctrl-C; results so far are written). A SUMO
// error or a dropped connection writes everything so far, then throws std::runtime_error with a
// one-line message.
#include <stsim/cli.hpp>

namespace st::cli {

int runHighwayCommand(const Args& args);
// `stsim highway [SCENARIO] --scenario-settings [options]`: the scenario's table
// (stcosim/scenario_settings.hpp) with the values in effect, as docs/scenario_settings.md.
int printScenarioSettings(const Args& args);

}  // namespace st::cli
