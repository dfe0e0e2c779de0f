#include <sthighway/sumo_signals.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

#include "xml_scanner.hpp"

namespace st::highway {

using detail::number;
using detail::required;
using detail::XmlScanner;

namespace {
// What one pass over the network gathers: the links (before their wait points are known) and
// what the later steps need to finish them.
struct NetScan {
  SignalLinks links;
  std::unordered_map<std::string, int> lightIndex;           // <tlLogic> id -> index into links.lights
  std::unordered_map<std::string, double> laneLengths;       // every lane's, for the controlled ones
  std::unordered_map<std::string, std::string> viaByEdges;   // byEdges' key -> its link's first internal lane
  std::vector<std::pair<std::string, std::string>> laneVia;  // (from lane, via) of each link in byLane, in order
};

// The light's index in scan.links.lights, added at its first appearance.
int lightOf(NetScan& scan, const std::string& id) {
  const auto [it, fresh] = scan.lightIndex.emplace(id, static_cast<int>(scan.links.lights.size()));
  if (fresh) scan.links.lights.push_back(id);
  return it->second;
}

// One <connection>: a wait point (an internal lane on through a minor link), or a link from a
// lane with a light, a yield or a via (the others are major links straight through).
void addConnection(const XmlScanner& x, const XmlScanner::Tag& t, NetScan& scan) {
  const std::string* from = t.attr("from");
  const std::string* fromLane = t.attr("fromLane");
  if (!from || !fromLane) x.fail(t.line, "<connection> lacks attribute 'from' or 'fromLane'");
  const std::string* state = t.attr("state");
  const std::string* viaLane = t.attr("via");
  const char fixed = state && state->size() == 1 ? (*state)[0] : 0;
  if ((*from)[0] == ':') {
    // an internal lane on to the next part of its turn, through a minor link: a wait point
    if (fixed == 'm' && viaLane) scan.links.waitLength.emplace(*from + "_" + *fromLane, 0.0);
    return;
  }
  const std::string* tl = t.attr("tl");
  // without a light: only where a driver gives way or stops, or may meet a wait point
  if (!tl && !(givesWayAt(fixed) || viaLane)) return;
  SignalLinks::Link link;
  if (tl) {
    const double index = required(x, t, "linkIndex");
    if (!(index >= 0 && index < 1e6 && index == std::floor(index)))
      x.fail(t.line, "<connection> linkIndex is not a link index: " + *t.attr("linkIndex"));
    link.light = lightOf(scan, *tl);
    link.index = static_cast<int>(index);
  } else {
    link.light = -1;
    link.fixed = fixed;
  }
  const std::string* dir = t.attr("dir");
  const std::string* to = t.attr("to");
  if (!to) x.fail(t.line, "<connection> lacks attribute 'to'");
  link.dir = dir && !dir->empty() ? (*dir)[0] : 's';
  link.to = *to;
  const std::string lane = *from + "_" + *fromLane;
  scan.links.byLane[lane].push_back(link);
  scan.laneVia.emplace_back(lane, viaLane ? *viaLane : std::string());
  const std::string key = *from + '\n' + *to;
  const auto [at, fresh] = scan.links.byEdges.try_emplace(key, link);
  if (fresh || link.light < at->second.light || (link.light == at->second.light && link.index < at->second.index)) {
    at->second = link;
    scan.viaByEdges[key] = viaLane ? *viaLane : std::string();
  }
}

// The lights, lanes and connections of the network, in one pass.
NetScan scanNet(const std::filesystem::path& net) {
  XmlScanner x(net);
  XmlScanner::Tag t;
  NetScan scan;
  while (x.next(t)) {
    if (t.closing) continue;
    if (t.name == "tlLogic") {
      if (const std::string* id = t.attr("id")) lightOf(scan, *id);
    } else if (t.name == "lane") {
      const std::string* id = t.attr("id");
      if (id && t.attr("length")) scan.laneLengths[*id] = required(x, t, "length");
    } else if (t.name == "connection") {
      addConnection(x, t, scan);
    }
  }
  return scan;
}

// The wait points' lengths, and each link's from its first internal lane (the internal
// connections come after the ones into them); without `priority` no wait points.
void setWaits(const std::filesystem::path& net, bool priority, NetScan& scan) {
  SignalLinks& out = scan.links;
  for (auto& [lane, length] : out.waitLength) {
    const auto it = scan.laneLengths.find(lane);
    if (it == scan.laneLengths.end())
      throw InputError(net.string() + ": internal lane '" + lane + "' has a connection but no <lane>");
    length = it->second;
  }
  auto waitOf = [&](const std::string& v) {
    const auto it = out.waitLength.find(v);
    return it == out.waitLength.end() ? 0.0 : it->second;
  };
  if (!priority) out.waitLength.clear();
  for (auto& [key, link] : out.byEdges) link.wait = waitOf(scan.viaByEdges[key]);
  std::unordered_map<std::string, std::size_t> nth;
  for (const auto& [lane, v] : scan.laneVia) out.byLane[lane][nth[lane]++].wait = waitOf(v);
}

// Drops the links without a light and with neither a yield nor a wait point (major ones straight
// through; without `priority` every link without a light), and the lanes left with none.
void dropMajorLinks(bool priority, SignalLinks& out) {
  auto major = [&](const SignalLinks::Link& l) {
    return l.light < 0 && (!priority || (l.wait == 0.0 && !givesWayAt(l.fixed)));
  };
  std::erase_if(out.byEdges, [&](const auto& kv) { return major(kv.second); });
  for (auto& [lane, links] : out.byLane) std::erase_if(links, major);
  std::erase_if(out.byLane, [](const auto& kv) { return kv.second.empty(); });
}

// The lengths of the lanes that still have links.
void setLaneLengths(const std::filesystem::path& net, const std::unordered_map<std::string, double>& laneLengths,
                    SignalLinks& out) {
  for (const auto& [lane, links] : out.byLane) {
    const auto it = laneLengths.find(lane);
    if (it == laneLengths.end()) throw InputError(net.string() + ": a light controls lane '" + lane + "', which has no <lane>");
    out.laneLength.emplace(lane, it->second);
  }
}
}  // namespace

SignalLinks readSignalLinks(const std::filesystem::path& net, bool priority) {
  NetScan scan = scanNet(net);
  setWaits(net, priority, scan);
  dropMajorLinks(priority, scan.links);
  setLaneLengths(net, scan.laneLengths, scan.links);
  return std::move(scan.links);
}

SignalStates::SignalStates(const std::filesystem::path& file, const SignalLinks& links) {
  XmlScanner x(file);
  XmlScanner::Tag t;
  std::unordered_map<std::string, int> lightIndex;
  std::vector<int> needs(links.lights.size(), 0);  // the longest link index + 1 per light
  for (std::size_t k = 0; k < links.lights.size(); ++k) lightIndex.emplace(links.lights[k], static_cast<int>(k));
  for (const auto& [lane, ls] : links.byLane)
    for (const SignalLinks::Link& l : ls)
      if (l.light >= 0) needs[static_cast<std::size_t>(l.light)] = std::max(needs[static_cast<std::size_t>(l.light)], l.index + 1);
  bool any = false;
  double last = -1e300;
  while (x.next(t)) {
    if (t.closing || t.name != "tlsState") continue;
    any = true;
    const double time = required(x, t, "time");
    if (time < last) x.fail(t.line, "<tlsState> times must not go back");
    last = time;
    const std::string* id = t.attr("id");
    const std::string* state = t.attr("state");
    if (!id || !state) x.fail(t.line, "<tlsState> lacks attribute 'id' or 'state'");
    const auto it = lightIndex.find(*id);
    if (it == lightIndex.end()) x.fail(t.line, "<tlsState> light '" + *id + "' is not in the network");
    if (static_cast<int>(state->size()) < needs[static_cast<std::size_t>(it->second)])
      x.fail(t.line, "<tlsState id=\"" + *id + "\"> state '" + *state + "' is shorter than the light's " +
                         std::to_string(needs[static_cast<std::size_t>(it->second)]) + " links");
    if (state->find_first_not_of("rRyYgGsuoO") != std::string::npos)
      x.fail(t.line, "<tlsState id=\"" + *id + "\"> state '" + *state + "' is not SUMO's link states (rRyYgGsuoO)");
    records_.push_back({time, it->second, *state});
  }
  if (!any) throw InputError(file.string() + ": holds no <tlsState> (not SUMO's SaveTLSStates output)");
  current_.assign(links.lights.size(), std::string());
}

void SignalStates::advanceTo(double t) {
  while (next_ < records_.size() && records_[next_].time <= t) {
    current_[static_cast<std::size_t>(records_[next_].light)] = records_[next_].state;
    ++next_;
  }
}

namespace {
// The link's state now (0: its light has no record yet), and where the car meets it: a link that
// lets it go on into a wait point has it give way there (m), as the live run reads it.
void setNext(const SignalLinks::Link& l, const SignalStates& states, double toLine, SumoVehicleRecord& r) {
  char state = l.fixed;
  if (l.light >= 0) {
    const std::string& s = states.state(l.light);
    if (static_cast<std::size_t>(l.index) >= s.size()) return;  // before the light's first record
    state = s[static_cast<std::size_t>(l.index)];
  }
  r.nextSignal = state;
  r.nextSignalDistance = std::max(0.0, toLine);
  if (l.wait > 0.0 && entersAt(state)) {
    r.nextSignal = 'm';
    r.nextSignalDistance += l.wait;
  }
}
}  // namespace

void nextSignalOf(const SignalLinks& links, const SignalStates& states, const std::string& lane, double pos,
                  int sumoSignals, SumoVehicleRecord& r, const std::string* edge, const std::string* nextEdge) {
  r.nextSignal = 0;
  r.nextSignalDistance = 0.0;
  if (const auto wait = links.waitLength.find(lane); wait != links.waitLength.end()) {
    r.nextSignal = 'm';  // in the junction, before its wait point
    r.nextSignalDistance = std::max(0.0, wait->second - pos);
    return;
  }
  if (edge && nextEdge) {
    const auto link = links.byEdges.find(*edge + '\n' + *nextEdge);
    const auto len = links.laneLength.find(lane);
    if (link == links.byEdges.end() || len == links.laneLength.end()) return;
    setNext(link->second, states, len->second - pos, r);
    return;
  }
  const auto it = links.byLane.find(lane);
  if (it == links.byLane.end() || it->second.empty()) return;
  const std::vector<SignalLinks::Link>& ls = it->second;
  // the link its blinker shows (the live run knows its route; a trace only this)
  auto wanted = [&](char d) {
    if (sumoSignals & kSumoBlinkerLeft) return d == 'l' || d == 'L' || d == 't';
    if (sumoSignals & kSumoBlinkerRight) return d == 'r' || d == 'R';
    return d == 's';
  };
  const auto pick = std::find_if(ls.begin(), ls.end(), [&](const SignalLinks::Link& l) { return wanted(l.dir); });
  setNext(pick != ls.end() ? *pick : ls.front(), states, links.laneLength.at(lane) - pos, r);
}

}  // namespace st::highway
