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

// The links traffic lights control, by the lane they leave (the stop line is its end).
struct SignalLinks {
  struct Link {
    int light = 0;   // index into lights
    int index = 0;   // the link's index in the light's state string
    char dir = 's';  // SUMO's direction: s, l, L, r, R, t
    std::string to;  // the edge it leads onto
  };
  std::vector<std::string> lights;                             // <tlLogic> ids, in order of first appearance
  std::unordered_map<std::string, std::vector<Link>> byLane;   // fromLane id -> its controlled links
  std::unordered_map<std::string, double> laneLength;          // those lanes' lengths (m, SUMO's)
  // "from edge\nto edge" -> the lowest-index link between them (as cosim's SignalBook keys them)
  std::unordered_map<std::string, Link> byEdges;
};
// From a .net.xml's <connection tl=".." linkIndex=".." dir=".."> elements (InputError: file:line).
SignalLinks readSignalLinks(const std::filesystem::path& net);

// SUMO's SaveTLSStates output (<tlsState time id state/> per switch), replayed in time order.
class SignalStates {
 public:
  // Reads every record; a light the network does not have, a state of another length than the
  // light's links need, or times going back are InputErrors naming file:line.
  SignalStates(const std::filesystem::path& file, const SignalLinks& links);
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
// lane ends at no light. With its route known (`edge` the one it is on, `nextEdge` the route's
// next), the link between the two, as the live run reads it (none if no light controls one);
// else the link of its lane its blinker shows.
void nextSignalOf(const SignalLinks& links, const SignalStates& states, const std::string& lane, double pos,
                  int sumoSignals, SumoVehicleRecord& r, const std::string* edge = nullptr,
                  const std::string* nextEdge = nullptr);

}  // namespace st::highway
