#pragma once
// The conflict map (PNG and SVG): the network's lanes and every conflict of conflicts.csv (one
// point per conflict at its conflict point, at TTC*; no warnings), coloured by conflict type, sized
// by MaxDeltaV. TTC* is read from the summary.json beside each conflicts.csv (conflicts.max_ttc_s)
// and said in the title. Drawn by models/highway/conflict_map.py with
// Debian's python3-matplotlib, which the batch report's plots use too.
#include <filesystem>
#include <string>
#include <vector>

namespace st::highway {

struct ConflictMapRequest {
  std::filesystem::path out;                     // prefix: writes out.png and out.svg
  std::filesystem::path net;                     // .net.xml whose lanes are drawn (empty: none)
  std::vector<std::filesystem::path> conflicts;  // conflicts.csv files, drawn together
  std::string title;
};

// What drawing the map came to: drawn; not drawn because python3, matplotlib or the script is
// missing (a tool the run can do without: the caller says so and the run succeeds); or failed
// (the script ran and could not write the map: a full disk, a folder in the way), which fails the
// run as any output that cannot be written does.
struct ConflictMapOutcome {
  enum class State { Drawn, Unavailable, Failed } state = State::Drawn;
  std::string why;  // for Unavailable and Failed
};

// Runs the plot script (its log in out.log).
ConflictMapOutcome drawConflictMap(const ConflictMapRequest& request);
// drawConflictMap, true when drawn (else why).
bool writeConflictMap(const ConflictMapRequest& request, std::string& why);

}  // namespace st::highway
