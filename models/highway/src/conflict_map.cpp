#include <sthighway/conflict_map.hpp>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <stio/data_file.hpp>

namespace st::highway {

namespace {

// a shell word: single-quoted, a quote inside as '\''
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string lastLine(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace

bool writeConflictMap(const ConflictMapRequest& r, std::string& why) {
  // installed: share/stsim/conflict_map.py beside bin/stsim; a build in the tree: the source's copy
  const std::filesystem::path script = io::dataFile("conflict_map.py", STSIM_CONFLICT_MAP_SCRIPT);
  if (!std::filesystem::exists("/usr/bin/python3")) {
    why = "/usr/bin/python3 not found (apt-get install python3-matplotlib)";
    return false;
  }
  if (!std::filesystem::exists(script)) {
    why = "map script missing: " + script.string();
    return false;
  }
  const std::filesystem::path log = r.out.string() + ".log";
  std::ostringstream cmd;
  cmd << "/usr/bin/python3 " << quoted(script.string()) << " --out " << quoted(r.out.string());
  if (!r.net.empty()) cmd << " --net " << quoted(r.net.string());
  if (!r.title.empty()) cmd << " --title " << quoted(r.title);
  for (const auto& w : r.warnings) cmd << ' ' << quoted(w.string());
  cmd << " > " << quoted(log.string()) << " 2>&1";
  if (std::system(cmd.str().c_str()) != 0) {
    why = "conflict map failed: " + lastLine(log);
    return false;
  }
  std::error_code ec;
  std::filesystem::remove(log, ec);  // empty on success
  return true;
}

}  // namespace st::highway
