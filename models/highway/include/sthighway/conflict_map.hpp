#pragma once
// The conflict map (PNG and SVG): the network's lanes and every warning at its position,
// coloured by conflict type, sized by severity. Drawn by models/highway/conflict_map.py with
// Debian's python3-matplotlib, which the batch report's plots use too.
#include <filesystem>
#include <string>
#include <vector>

namespace st::highway {

struct ConflictMapRequest {
  std::filesystem::path out;                     // prefix: writes out.png and out.svg
  std::filesystem::path net;                     // .net.xml whose lanes are drawn (empty: none)
  std::vector<std::filesystem::path> warnings;   // warnings.csv files, drawn together
  std::string title;
};

// Runs the plot script (its log in out.log). False, with why, when python3 or matplotlib is
// missing or the script fails; the caller reports it (a missing map is not a failed run).
bool writeConflictMap(const ConflictMapRequest& request, std::string& why);

}  // namespace st::highway
