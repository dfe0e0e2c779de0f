#include <sthighway/conflict_map.hpp>

#include <sys/wait.h>

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

ConflictMapOutcome drawConflictMap(const ConflictMapRequest& r) {
  using State = ConflictMapOutcome::State;
  // installed: share/stsim/conflict_map.py beside bin/stsim; a build in the tree: the source's copy
  const std::filesystem::path script = io::dataFile("conflict_map.py", STSIM_CONFLICT_MAP_SCRIPT);
  if (!std::filesystem::exists("/usr/bin/python3"))
    return {State::Unavailable, "/usr/bin/python3 not found (apt-get install python3-matplotlib)"};
  if (!std::filesystem::exists(script)) return {State::Unavailable, "map script missing: " + script.string()};
  const std::filesystem::path log = r.out.string() + ".log";
  std::ostringstream cmd;
  cmd << "/usr/bin/python3 " << quoted(script.string()) << " --out " << quoted(r.out.string());
  if (!r.net.empty()) cmd << " --net " << quoted(r.net.string());
  if (!r.title.empty()) cmd << " --title " << quoted(r.title);
  for (const auto& w : r.conflicts) cmd << ' ' << quoted(w.string());
  cmd << " > " << quoted(log.string()) << " 2>&1";
  const int status = std::system(cmd.str().c_str());
  if (status != 0) {
    std::string last = lastLine(log);
    // the script's code for a missing matplotlib (conflict_map.py)
    if (WIFEXITED(status) && WEXITSTATUS(status) == 3) return {State::Unavailable, last};
    if (last.empty()) last = "the plot script exited with status " + std::to_string(status) + " (its log " + log.string() + " is empty: a full disk?)";
    return {State::Failed, "conflict map failed: " + last};
  }
  std::error_code ec;
  std::filesystem::remove(log, ec);  // empty on success
  return {};
}

bool writeConflictMap(const ConflictMapRequest& r, std::string& why) {
  const ConflictMapOutcome o = drawConflictMap(r);
  why = o.why;
  return o.state == ConflictMapOutcome::State::Drawn;
}

}  // namespace st::highway
