#include <sthighway/sumo_signals.hpp>

#include <algorithm>
#include <cmath>

#include "xml_scanner.hpp"

namespace st::highway {

using detail::number;
using detail::required;
using detail::XmlScanner;

SignalLinks readSignalLinks(const std::filesystem::path& net) {
  XmlScanner x(net);
  XmlScanner::Tag t;
  SignalLinks out;
  std::unordered_map<std::string, int> lightIndex;
  auto lightOf = [&](const std::string& id) {
    const auto [it, fresh] = lightIndex.emplace(id, static_cast<int>(out.lights.size()));
    if (fresh) out.lights.push_back(id);
    return it->second;
  };
  std::unordered_map<std::string, double> lengths;  // every lane's, for the controlled ones
  while (x.next(t)) {
    if (t.closing) continue;
    if (t.name == "tlLogic") {
      if (const std::string* id = t.attr("id")) lightOf(*id);
    } else if (t.name == "lane") {
      const std::string* id = t.attr("id");
      if (id && t.attr("length")) lengths[*id] = required(x, t, "length");
    } else if (t.name == "connection") {
      const std::string* tl = t.attr("tl");
      if (!tl) continue;
      const std::string* from = t.attr("from");
      const std::string* fromLane = t.attr("fromLane");
      if (!from || !fromLane) x.fail(t.line, "<connection> lacks attribute 'from' or 'fromLane'");
      const double index = required(x, t, "linkIndex");
      if (!(index >= 0 && index < 1e6 && index == std::floor(index)))
        x.fail(t.line, "<connection> linkIndex is not a link index: " + *t.attr("linkIndex"));
      const std::string* dir = t.attr("dir");
      const std::string* to = t.attr("to");
      if (!to) x.fail(t.line, "<connection> lacks attribute 'to'");
      const SignalLinks::Link link{lightOf(*tl), static_cast<int>(index), dir && !dir->empty() ? (*dir)[0] : 's', *to};
      out.byLane[*from + "_" + *fromLane].push_back(link);
      const auto [at, fresh] = out.byEdges.try_emplace(*from + '\n' + *to, link);
      if (!fresh && (link.light < at->second.light || (link.light == at->second.light && link.index < at->second.index)))
        at->second = link;
    }
  }
  for (const auto& [lane, links] : out.byLane) {
    const auto it = lengths.find(lane);
    if (it == lengths.end()) throw InputError(net.string() + ": a light controls lane '" + lane + "', which has no <lane>");
    out.laneLength.emplace(lane, it->second);
  }
  return out;
}

SignalStates::SignalStates(const std::filesystem::path& file, const SignalLinks& links) {
  XmlScanner x(file);
  XmlScanner::Tag t;
  std::unordered_map<std::string, int> lightIndex;
  std::vector<int> needs(links.lights.size(), 0);  // the longest link index + 1 per light
  for (std::size_t k = 0; k < links.lights.size(); ++k) lightIndex.emplace(links.lights[k], static_cast<int>(k));
  for (const auto& [lane, ls] : links.byLane)
    for (const SignalLinks::Link& l : ls) needs[static_cast<std::size_t>(l.light)] = std::max(needs[static_cast<std::size_t>(l.light)], l.index + 1);
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

void nextSignalOf(const SignalLinks& links, const SignalStates& states, const std::string& lane, double pos,
                  int sumoSignals, SumoVehicleRecord& r, const std::string* edge, const std::string* nextEdge) {
  r.nextSignal = 0;
  r.nextSignalDistance = 0.0;
  if (edge && nextEdge) {
    const auto link = links.byEdges.find(*edge + '\n' + *nextEdge);
    const auto len = links.laneLength.find(lane);
    if (link == links.byEdges.end() || len == links.laneLength.end()) return;
    const std::string& state = states.state(link->second.light);
    if (static_cast<std::size_t>(link->second.index) >= state.size()) return;
    r.nextSignal = state[static_cast<std::size_t>(link->second.index)];
    r.nextSignalDistance = std::max(0.0, len->second - pos);
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
  const SignalLinks::Link& l = pick != ls.end() ? *pick : ls.front();
  const std::string& state = states.state(l.light);
  if (static_cast<std::size_t>(l.index) >= state.size()) return;  // before the light's first record
  r.nextSignal = state[static_cast<std::size_t>(l.index)];
  r.nextSignalDistance = std::max(0.0, links.laneLength.at(lane) - pos);
}

}  // namespace st::highway
