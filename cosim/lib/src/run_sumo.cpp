#include "run_parts.hpp"

namespace st::cosim {

namespace fs = std::filesystem;

SumoStart startSumo(const Scenario& s, const RunSetup& setup) {
  const fs::path& out = setup.out;
  std::error_code ec;
  SumoStart start;
  std::vector<std::string> args = sumoArguments(s);
  start.ssmFile = fs::absolute(out / "ssm.xml");
  if (s.validateSsm) {
    fs::remove(start.ssmFile, ec);
    // the SSM threshold: above any safe time we expect, so every conflict below a safe time is logged
    const double ssmThreshold = 5.0;
    const auto extra = ssmArguments(start.ssmFile, ssmThreshold);
    args.insert(args.end(), extra.begin(), extra.end());
  }

  // Over TraCI SUMO's collisions come from its --collision-output file, read after the run (SUMO
  // 1.15's libtraci cannot fetch them per step); attached to a SUMO started elsewhere, stsim cannot
  // ask for that file, so the run has no collision figures.
  start.collisionsFromFile = setup.gui;
  start.collisionFile = fs::absolute(out / "sumo_collisions.xml");
  if (start.collisionsFromFile) {
    fs::remove(start.collisionFile, ec);
    const auto extra = collisionOutputArguments(start.collisionFile);
    args.insert(args.end(), extra.begin(), extra.end());
  }

  try {
    if (setup.attach) {
      start.backend = attachTraci(*setup.attach);
    } else if (setup.gui) {
      start.backend = launchTraci(SumoLaunch{args, true, (out / "sumo.log").string(), ""});
    } else {
      start.backend = startLibsumo(SumoLaunch{args, false, "", ""});
    }
  } catch (const std::exception& e) {
    // SUMO never ran: the summary says so (not an earlier run's)
    writeStartFailureSummary(s, setup, e.what());
    throw;
  }
  return start;
}

}  // namespace st::cosim
