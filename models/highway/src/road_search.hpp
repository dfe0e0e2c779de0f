#pragma once
// The road search: which curbs, lane markers and hazards an ego may reach within its road safe
// time, and their threats. The features are indexed once (a uniform grid); each tick every group
// of cars the pair search keeps (a bin) gets the list of features any of its cars could reach,
// with the lines grouped by their normal so an ego's prune reads them cheaply; without groups
// (all pairs) every ego reads the list of all features.
#include <array>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <stcore/space.hpp>
#include <sthighway/monitor.hpp>

#include "index_visit.hpp"
#include "lane_prediction.hpp"
#include "pair_search.hpp"
#include "vehicle_table.hpp"

namespace st::highway::detail {

class RoadSearch {
 public:
  // prediction: a car on a lane, predicted along it, gets its curb and marker threats in the lane
  // frame
  RoadSearch(const RoadGeometry& road, const MonitorConfig& config, const VehicleTable& cars,
             const LanePrediction& prediction, MonitorCounters& counters);

  const RoadFeatures& features() const { return features_; }
  // the name of a feature group (one polyline or hazard): a road threat's foe
  const std::string& groupName(int group) const { return groupName_[group]; }
  // the features of a group (its polyline's segments, or the hazard)
  std::span<const int> groupFeatures(int group) const { return groupFeatures_[group]; }

  // The line (feature group) on a lane's right (side 0) or left (side 1); -1: none (internal lanes).
  int lineOf(int lane, int side) const { return lane >= 0 && lane < static_cast<int>(laneLines_.size()) ? laneLines_[lane][side] : -1; }

  // This tick's per-group lists (groups from the pair search; empty: every ego reads all).
  void prepare(std::span<const CarGroup> groups);
  // Ego e's road threats this tick (group: its group, -1 for none), appended to out.
  void threatsOf(int e, int group, std::vector<Threat>& out);

  // a segment feature's line: its first point and unit normal (left of a -> b); line is 0 for
  // hazards and zero-length segments (no line to prune with)
  struct FeatureLine {
    Vec2 a = Vec2::Zero();
    Vec2 b = Vec2::Zero();  // the other end
    Vec2 n = Vec2::Zero();
    int line = 0;
  };
  // Road features an ego may reach, as its prune reads them: the lines grouped by their normal
  // (up to its sign), so the ego's support, centre and velocity along a normal are computed once
  // per group (a straight road's lines share one), and a line costs a subtraction and a
  // comparison; the features without a line (hazards, zero-length segments) are always checked.
  struct RoadList {
    struct Group {
      Vec2 n;          // unit normal, its sign chosen so the first nonzero component is positive
      int begin, end;  // its lines
    };
    struct Line {
      double c;       // n . (a point of the line)
      double lo, hi;  // the segment along the group's tangent (n.y, -n.x)
      int feature;
    };
    std::vector<Group> groups;
    std::vector<Line> lines;
    std::vector<int> always;
    std::vector<int> source;  // the features it was built from, in the order given
    std::size_t size() const { return lines.size() + always.size(); }
    // from features in any order (scratch: reused storage); kept if they are the last ones
    void build(std::span<const int> features, const std::vector<FeatureLine>& featureLine,
               std::vector<std::pair<Vec2, Line>>& scratch);
  };

 private:
  void checkFeature(int e, int fi, double hMax, std::vector<Threat>& out) const;
  void laneThreats(int e, std::vector<Threat>& out) const;
  int nearestFeature(int group, const Vec2& p) const;

  const MonitorConfig* cfg_;
  const VehicleTable* cars_;
  MonitorCounters* counters_;
  RoadFeatures features_;
  std::vector<int> groupOf_;  // feature -> group (one polyline or hazard)
  std::vector<std::string> groupName_;
  std::vector<std::vector<int>> groupFeatures_;
  std::vector<FeatureLine> featureLine_;
  std::optional<Space<2>> featureIndex_;
  RoadList allRoad_;                         // every feature (all-pairs)
  std::vector<RoadList> roadNear_;           // per car group
  std::vector<IndexVisit> featureVisits_;    // per car group: the feature index's features near it
  std::vector<int> roadFound_;               // scratch: a group's features before grouping
  std::vector<std::pair<Vec2, RoadList::Line>> roadScratch_;
  std::vector<int> featureNear_;             // scratch: the features an ego may reach
  const LanePrediction* prediction_;
  std::vector<std::array<int, 2>> laneLines_;  // per lane: the groups of its right and left lines
  std::vector<int> hazards_;                   // the hazard features
};

}  // namespace st::highway::detail
