#pragma once
// Traffic lights for an FCD replay: the network's signal links and the states SUMO recorded with
// its SaveTLSStates output, so that a replay reads each car's next light as a live run does
// (cosim's SignalBook, sumo_conversion.hpp's stopDistanceOf). A trace has no routes: the link a
// car takes at its stop line is chosen from its lane's links by its blinker (left: a left turn or
// turnaround, right: a right turn, none: straight on; a lane with one link: that one).
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

#include <sthighway/sumo_conversion.hpp>

namespace st::highway {

// The links traffic lights control and the links of junctions without one where a driver gives
// way or stops (SUMO's fixed states m, =, s, w) or meets a wait point inside the junction, by the
// lane they leave (the stop line is its end); as cosim's SignalBook reads them from SUMO.
struct SignalLinks {
  struct Link {
    int light = 0;    // index into lights; -1: no light, the state is `fixed`
    int index = 0;    // the link's index in the light's state string
    char dir = 's';   // SUMO's direction: s, l, L, r, R, t
    std::string to;   // the edge it leads onto
    char fixed = 0;   // without a light, the link's state (SUMO's letters)
    double wait = 0;  // from the stop line to the wait point inside the junction (m); 0: none
  };
  std::vector<std::string> lights;                             // <tlLogic> ids, in order of first appearance
  std::unordered_map<std::string, std::vector<Link>> byLane;   // fromLane id -> its controlled links
  std::unordered_map<std::string, double> laneLength;          // those lanes' lengths (m, SUMO's)
  // "from edge\nto edge" -> the lowest-index link between them (as cosim's SignalBook keys them)
  std::unordered_map<std::string, Link> byEdges;
  // internal lanes ending at a wait point (their exit link minor: SUMO holds a turner there) ->
  // their length (m)
  std::unordered_map<std::string, double> waitLength;
};
// From a .net.xml's <connection tl=".." linkIndex=".." dir=".." state=".." via=".."> elements
// (InputError: file:line); without `priority` the lights' links only (no yields, no wait points:
// MonitorConfig::priorityRules false).
SignalLinks readSignalLinks(const std::filesystem::path& net, bool priority = true);

// SUMO's SaveTLSStates output (<tlsState time id state/> per switch), replayed in time order.
class SignalStates {
 public:
  // Reads every record; a light the network does not have, a state of another length than the
  // light's links need, or times going back are InputErrors naming file:line.
  SignalStates(const std::filesystem::path& file, const SignalLinks& links);
  // No recorded states: every light's unknown (its links give no state), the junctions without
  // one read from the network alone (a replay without --tls-states).
  explicit SignalStates(const SignalLinks& links) : current_(links.lights.size()) {}
  // The states at time t: each light's last record at or before t (an empty state before its
  // first). Times must not go back.
  void advanceTo(double t);
  const std::string& state(int light) const { return current_[static_cast<std::size_t>(light)]; }

 private:
  struct Record {
    double time;
    int light;
    std::string state;
  };
  std::vector<Record> records_;
  std::size_t next_ = 0;
  std::vector<std::string> current_;
};

// Sets r.nextSignal and r.nextSignalDistance (SumoVehicleRecord) of a car on `lane` whose front is
// `pos` m along it, with SUMO's signal bits `sumoSignals`, from the states now: none (0) when the
// lane ends at no light or yield; a link that lets it go on into a wait point: m, to that point;
// a car in the junction before a wait point: m, to it. With its route known (`edge` the one it is on, `nextEdge` the route's
// next), the link between the two, as the live run reads it (none if no light controls one);
// else the link of its lane its blinker shows.
void nextSignalOf(const SignalLinks& links, const SignalStates& states, const std::string& lane, double pos,
                  int sumoSignals, SumoVehicleRecord& r, const std::string* edge = nullptr,
                  const std::string* nextEdge = nullptr);

}  // namespace st::highway
