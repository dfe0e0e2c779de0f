#pragma once
// Road geometry: lanes as centre-line polylines with widths, grouped by edge (a road section).
// From it come the static features a car can hit: lane markers between adjacent lanes of an
// edge, curbs at the edge's outer sides, and point hazards.
#include <cstdint>
#include <string>
#include <vector>

#include <stcore/shapes.hpp>

namespace st::highway {

// SUMO's default lane width (m), the width of a lane whose file gives none.
inline constexpr double kSumoLaneWidth = 3.2;

struct Lane {
  std::string id;
  std::string edge;              // lanes of one edge form one road section
  int index = 0;                 // 0 is the rightmost lane (SUMO's convention)
  std::vector<Vec2> shape;       // centre line, in driving direction (m)
  double width = kSumoLaneWidth;  // m
  bool internal = false;         // inside a junction: no curbs, markers or cell sites
  // Its length as the source measures positions and speeds along it (m; SUMO's `length`, which
  // may differ from the shape's: a car there moves shape / length times its speed); 0: the shape's.
  double length = 0.0;
};

// A point hazard (pothole, debris): a disc on the road.
struct Hazard {
  std::string id;
  Vec2 position = Vec2::Zero();
  double radius = 0.3;  // m
};

struct RoadGeometry {
  std::vector<Lane> lanes;
  std::vector<Hazard> hazards;
};

// The network's edges in order of first appearance among its lanes (junction edges included):
// the index space of VehicleState::route.
std::vector<std::string> edgeIds(const RoadGeometry& road);

enum class FeatureKind : std::uint8_t { Curb, LaneMarker, Hazard };
const char* toString(FeatureKind k);

// One static obstacle. Curbs and markers are segments (radius 0); a hazard is a disc
// (segment.a == segment.b, radius > 0).
struct RoadFeature {
  FeatureKind kind = FeatureKind::Curb;
  Segment segment;
  double radius = 0.0;
  int section = -1;        // index into RoadFeatures::sections (-1 for hazards)
  std::string name;        // curb: "<edge>:right"/"<edge>:left"; marker: "<laneR>|<laneL>"; hazard id
};

struct RoadFeatures {
  std::vector<RoadFeature> features;
  std::vector<std::string> sections;  // edge ids, in order of first appearance
  Aabb<2> bounds{Vec2::Zero(), Vec2::Zero()};  // of all lanes (with their widths) and hazards
};

// Offsets each edge's lane shapes sideways (mitred joints so consecutive segments meet):
// markers at +width/2 of every lane but the leftmost, curbs at -width/2 of lane 0 and at
// +width/2 of the leftmost lane. Internal (junction) lanes contribute no features.
// Throws std::invalid_argument for a lane with fewer than two points or a non-positive width.
RoadFeatures deriveFeatures(const RoadGeometry& road);

// A polyline offset sideways by `offset` (positive to the left of travel), mitred.
std::vector<Vec2> offsetPolyline(const std::vector<Vec2>& line, double offset);

}  // namespace st::highway
