#pragma once
// Road-aware prediction (MonitorConfig::prediction == Road): each tick every car (a pedestrian
// never: it walks where no lane leads it, in a straight line) is matched to
// the lane its centre is on (by position and heading; the lane is kept while the centre stays in
// it), described in that lane's frame (arc position s, offset d to the left, lateral speed, yaw
// relative to the lane) and predicted along the lane's centre line, continued through junctions
// along its route (VehicleState::route: SUMO gives it), else into the turn its signal shows, else
// the straightest successor, at its speed along the lane (with its acceleration under the
// constant-acceleration model), keeping its offset and lateral speed relative to the lane. From
// the next vertex on its body is square to the lane, or, where the lane bends under it, laid as
// SUMO lays it: the chord from the centre line half a length behind to half a length ahead.
//
// The prediction is a list of path pieces: between two vertices of the path the car moves in a
// straight line with a fixed heading, so the detectors' straight kernels apply piece by piece.
// The pair searches prune with straight motion (p + v t); every car's deviation from it over the
// longest horizon any pair can ask of it is added to its envelope (extent and radius; the extent
// of a body that turns on its path is first widened to its envelope radius), which
// keeps every prune exact: a path's departure from the straight line is that deviation, bounded
// at the pieces' ends (the distance between two affine motions is convex in time). The path is
// never longer than the straight reach (|p(t) - p(0)| is at most the arc length driven, the
// distance the straight line covers at the same speed) unless a lane's shape is longer than the
// source's length of it (Lane::length: SUMO moves a car shape / length times its speed there);
// the deviation holds that too.
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <stcore/static_grid.hpp>
#include <sthighway/monitor.hpp>

#include "vehicle_table.hpp"

namespace st::highway::detail {

// One piece of a predicted path: from t0 on, the centre moves from p along dir at the path speed
// (speed at t0, changing at the car's acceleration until it stops, under that model) and along
// normal at the lateral speed, the body turned to axis.
struct PathPiece {
  double t0 = 0.0;
  Vec2 p = Vec2::Zero();
  Vec2 dir = Vec2(1.0, 0.0);
  Vec2 normal = Vec2(0.0, 1.0);
  Vec2 axis = Vec2(1.0, 0.0);
  double speed = 0.0;    // along the lane at t0, as the source measures it (m/s)
  double lateral = 0.0;  // along normal (m/s)
  double scale = 1.0;    // metres along dir per metre of that speed (Lane::length)
};

// Where a predicted body may be left square to its lane without working out its chord: fed the
// pieces of the centre line ahead of a car (from the centre's foot, in order), it tells how far the
// line stays too straight for a body of half length `half` centred at arc S (S >= half, S + half
// <= end()) to be laid on a chord: the chord's middle within kChordOffset of the line's point at S
// and turned from the lane's segment there by at most kMergeBend. Most lines are straight, and
// this costs a few operations a piece. The bound: every piece of the line and of the lanes it
// follows turns from the car's lane (dir) by at most a/2 (a tan bounds an angle), the pieces have
// between rMin and rMax metres per unit of arc (sMin: the lanes' least scale), and the lanes'
// joints leave gaps in the line; then the chord's middle is within gaps (1 + rMax / sMin) + h a
// + h a^2 / 4 + half (rMax - rMin) / 2 of the point (h = half rMax, the reach) and turns by at most
// a. Half the thresholds: room for rounding.
class QuietLine {
 public:
  QuietLine(const Vec2& dir, double half) : dir_(dir), half_(half) {}
  // The next piece: the line's vector e over arc dS, the lane segment's direction laneDir it
  // follows, its lane's scale, and the gap between the line and the lane where the piece begins
  // (0 but where the line crosses a joint between lanes).
  void add(const Vec2& e, double dS, const Vec2& laneDir, double scale, double gap);
  // Whether every piece added so far is quiet (more are worth adding).
  bool open() const { return open_; }
  // The line is quiet up to this arc; after finish(), beyond its end too if every piece is (the
  // line runs on along its last piece).
  double end() const { return end_; }
  void finish() {
    if (open_ && arc_ > 0.0) end_ = std::numeric_limits<double>::infinity();
  }

 private:
  double angleBound(const Vec2& unit) const;
  Vec2 dir_;
  double half_;
  bool open_ = true;
  double arc_ = 0.0, end_ = 0.0;
  double angle_ = 0.0, rMin_ = std::numeric_limits<double>::infinity(), rMax_ = 0.0;
  double sMin_ = std::numeric_limits<double>::infinity(), gaps_ = 0.0;
};

// A car in its lane's frame.
struct LaneFrame {
  int lane = -1;         // index into RoadGeometry::lanes; -1: predicted in a straight line
  int seg = 0;           // the segment of the lane's centre line the centre projects on
  double s = 0.0;        // arc position of the centre on the lane (m; < 0 or > length: just beyond an end)
  double d = 0.0;        // offset to the left of the centre line (m), the car's own: less the chord's at a vertex
  double lateral = 0.0;  // lateral speed (m/s, to the left), from d tick to tick in a common frame
  double speed = 0.0;    // along the lane (m/s)
  Vec2 dir = Vec2(1.0, 0.0);  // the lane's direction at s
  double halfBody = 0.0, halfShape = 0.0;  // half widths across the lane (beyondLine)
  // arc from the centre to the end of a dropped lane ahead, in the source's lengths (Lane::length;
  // over speed, a time)
  double endGap = std::numeric_limits<double>::infinity();
  int endLane = -1;      // that lane
};

class LanePrediction {
 public:
  LanePrediction(const RoadGeometry& road, const MonitorConfig& config, VehicleTable& cars, MonitorCounters& counters);

  // The stages ask it, whichever model is configured: with Prediction::Straight every path is
  // the straight line (straight() is true for every car, vehicleTtc is the straight detector).
  // Lane frames are kept in either model (hindsight judges road warnings in them).
  bool alongLanes() const { return alongLanes_; }
  // The width of the lane a car is reported on (SUMO's default where none is known).
  double laneWidth(int slot) const {
    const int l = reportedLane(slot);
    return l >= 0 && l < static_cast<int>(lanes_.size()) ? lanes_[l].width : kSumoLaneWidth;
  }
  // After the vehicle table's update: match lanes, predict paths, grow the envelopes.
  void update(double t);

  const LaneFrame& frame(int slot) const { return frame_[slot]; }
  // The lane a car is reported on: the source's, else the one it was matched to (-1: none).
  int reportedLane(int slot) const { return cars_->lane[slot] >= 0 ? cars_->lane[slot] : matched_[slot]; }
  std::span<const PathPiece> path(int slot) const {
    return {pieces_.data() + pieceBegin_[slot], static_cast<std::size_t>(pieceEnd_[slot] - pieceBegin_[slot])};
  }
  // How far a car lies beyond its lane's line on a side (0 right, 1 left; m, >= 0: touching or
  // across it): its offset towards that side plus its half width across the lane, less the lane's
  // half width. The half width is the body's (W/2: what a crossing is), or the detector's shape
  // that checks road features (shape: W/2 grown by a layout's margin), with the car square to the
  // lane: a rigid body's corners on a polyline's joints (a truck's 12 m on a curve) reach out by
  // its yaw against the joint's segment, which is no lane departure. On a lane only.
  double beyondLine(int slot, int side, bool shape) const;
  // beyondLine(slot, side, false) of the side its centre is off to (the larger of the two, bit for
  // bit), for a caller that skips the bodies reaching across neither line.
  double beyondNearerLine(int slot) const {
    const LaneFrame& f = frame_[slot];
    return std::abs(f.d) + f.halfBody - halfWidth(f.lane);
  }
  // True when the car's body lies along its lane, its rear past the lane's start and its front
  // short of its end: only then do the lane's lines apply (a body straddling a junction, half on
  // the lane it leaves, cuts across where no line is drawn).
  bool alongside(int slot) const;
  // alongside(slot) as update() found it this tick (a car it predicted)
  bool along(int slot) const { return prevAlong_[slot] != 0; }
  double halfWidth(int lane) const { return 0.5 * lanes_[lane].width; }
  // Metres along a lane's shape per metre of the source's length of it (Lane::length).
  double scale(int lane) const { return lanes_[lane].scale; }
  // The longest horizon a pair test may ask of a car this tick (s).
  double horizon(int slot) const { return horizon_[slot]; }
  bool straight(int slot) const { return straight_[slot] != 0; }
  // The car is at a merge: on a junction lane, on an edge one of whose lanes ends while the edge
  // goes on (an acceleration lane's, a lane drop's), headed off its lane by more than
  // tol::kMergeBend (SUMO's chord from its rear to its front across a vertex or a junction), or on
  // a lane its path leaves through a junction or turns by more than tol::kMergeBend within TTC*
  // (an entry lane: a ramp's nose, its curve). Its momentary heading there is the bend's (SUMO heads a body from its rear to its
  // front: 30 degrees and more off the carriageway at a ramp's nose), so conflicts.csv predicts
  // such a car along its path (boxTtcAlong), not in a straight line. Only under road prediction,
  // and only where its path reaches TTC* (horizon >= TTC*).
  bool atMerge(int slot) const { return merge_[slot] != 0; }
  // How far a car's path departs from its straight line (p + v t) within its horizon (m; 0 for a
  // straight path): the pair prunes' growth of its envelope, which bounds any sweep over paths.
  double deviation(int slot) const { return deviation_[slot]; }

  // vehicleTtc of ego e against foe f along their paths (slots), at most horizon s ahead: piece
  // by piece where both move straight with fixed headings (one piece each, the straight
  // detector itself, bit for bit).
  Ttc vehicleTtc(int e, int f, double horizon) const;

  // The exact box TTC of two cars (slots) along their paths, each at its speed along the path at
  // constant velocity (conflicts.csv's motion; under the constant-acceleration model the pieces
  // still start where that model puts them), at most horizon s ahead: piece by piece, the box
  // kernel on each stretch where both move straight with fixed headings (two straight paths: the
  // straight box TTC). atE, atF: the two bodies then (unchanged when none is found).
  Impact boxTtcAlong(int e, int f, double horizon, Body& atE, Body& atF) const;

  // The lanes a car drives on and takes next, as its path takes them (its route, else its signal,
  // else straight on), from the one it is reported on until `reach` m past its centre (at most
  // kLanesAhead); empty without a lane. In either prediction model: the lanes are the network's.
  void lanesAhead(int slot, double reach, std::vector<int>& out) const;
  static constexpr int kLanesAhead = 8;
  // A lane's centre line (at least two points but for a degenerate lane), whether it lies inside a
  // junction, and its edge (index into edgeIds(road)).
  std::span<const Vec2> laneShape(int lane) const {
    return {pt_.data() + lanes_[lane].first, static_cast<std::size_t>(lanes_[lane].count)};
  }
  bool internalLane(int lane) const { return lanes_[lane].internal; }
  // The lanes that lead onto a lane (those it is a successor of).
  std::span<const int> predecessors(int lane) const {
    return {pred_.data() + predStart_[lane], static_cast<std::size_t>(predStart_[lane + 1] - predStart_[lane])};
  }
  int laneEdge(int lane) const { return lanes_[lane].edge; }
  // Its edge's id (the road's Lane::edge).
  const std::string& laneEdgeId(int lane) const { return edgeIds_[static_cast<std::size_t>(lanes_[lane].edge)]; }
  // The first of the junction lanes a car on `lane` has driven through its junction (SUMO splits
  // a left turn at its wait point: the second part's predecessor is the first), `lane` itself
  // outside a junction.
  int junctionEntry(int lane) const;
  // The body of a car at time t >= 0 on its path (pieces from path()), moving at
  // motionAcceleration(now, motion) along it.
  static Body bodyAt(std::span<const PathPiece> path, const Body& now, MotionModel motion, double t);

 private:
  struct NetLane {
    int first = 0, count = 0;  // its points in pt_/cum_
    double width = 3.2, length = 0.0;
    int next = -1;              // the straightest successor, succ_[succBegin] (-1: the lane ends)
    int nextLeft = -1, nextRight = -1;  // the successors turning furthest left and right (by 20 degrees at least)
    int succBegin = 0, succEnd = 0;     // all successors in succ_, the straightest first
    int edge = -1;                      // index into edgeIds(road)
    int exitEdge = -1;                  // the edge a car on it drives on or reaches next (a junction lane's outgoing edge)
    bool drops = false;         // ends while another lane of its edge goes on (a lane drop)
    bool merge = false;         // a lane of its edge drops: an acceleration lane's edge, a lane drop's
    double scale = 1.0;         // its shape's length over the source's length of it (Lane::length)
    bool internal = false;
  };
  struct Projection {
    int seg = 0;
    double s = 0.0, d = 0.0;
    Vec2 dir = Vec2(1.0, 0.0);
  };
  Projection project(int lane, const Vec2& p, int seg) const;
  bool fits(int lane, const Projection& pr, const Vec2& axis, double slack, double half) const;
  double chordOffset(int lane, const Projection& pr, double half) const;
  int match(int slot, const Vec2& p, const Vec2& axis, Projection& out) const;
  int successor(int slot, int lane, int& routeAt) const;
  void predict(int slot, double horizon);
  // predict's stages and what they pass on: a car's lane and motion in its frame; the plan of its
  // path along the lanes; what the pieces bound (growEnvelopes' input)
  struct LaneMotion {
    int lane = -1;          // -1: none matched
    Projection pr;          // its centre in the lane's frame, the chord's offset taken off d
    double chord = 0.0;     // that offset (m)
    double u = 0.0;         // speed along the lane (m/s)
    double lateral = 0.0;   // lateral speed (m/s, to the left)
    bool bent = false;      // headed by a junction's bend, not by its motion
  };
  struct PathLine {         // the centre line ahead (lineS_, linePt_) as onChord reads it
    Vec2 foot, backLine;    // the centre's foot on it; where the back is now
    double half = 0.0;      // half the body's length (m)
    double quietEnd = 0.0;  // arc up to which no body is laid on a chord
  };
  struct PathPlan {
    int lane = -1, routeAt = -1;
    Projection pr;
    double u = 0.0, acc = 0.0, horizon = 0.0, need = 0.0, lateral = 0.0;
    bool straddles = false, bent = false;
    Vec2 off;               // the centre less its foot and offset (zero up to rounding)
    PathLine line;
  };
  struct PathBound {
    double dev = 0.0, maxScale = 1.0;
    bool turns = false, merge = false;
  };
  LaneMotion matchMotion(int slot, double t);
  void setFrame(int slot, double t, const LaneMotion& m);
  void predictStraight(int slot, int lane);
  double traceLine(int slot, int lane, const Projection& pr, int routeAt, const Vec2& foot, double reach);
  Vec2 linePoint(const PathLine& line, double S) const;
  bool onChord(const PathLine& line, double S, const Vec2& q, const Vec2& dir, Vec2& centre, Vec2& axis) const;
  PathBound layPieces(int slot, const Body& b, const PathPlan& p, LaneFrame& f);
  std::pair<int, int> nextSegment(int slot, int ln, int seg, int& routeAt, double segEnd, LaneFrame& f) const;
  void growEnvelopes(int slot, const PathBound& bound, double u, double acc, double h);
  // the constructor's steps, in order: the lanes' points (lanes_, pt_, cum_); their edges
  // (NetLane::edge; the lanes of each edge returned); successors (succ_, next, nextLeft,
  // nextRight); predecessors (pred_, predStart_); exit edges; lane drops and merges (drops,
  // merge); the segment grid (segments_, pointLane_); the crowded segments (crowded_)
  void addLanes(const RoadGeometry& road);
  std::unordered_map<std::string, std::vector<int>> setEdges(const RoadGeometry& road);
  void findSuccessors();
  void findPredecessors();
  void setExitEdges();
  void markLaneDrops(const std::unordered_map<std::string, std::vector<int>>& byEdge);
  void buildSegmentGrid();
  void markCrowded();

  const MonitorConfig* cfg_;
  VehicleTable* cars_;
  MonitorCounters* counters_;
  bool alongLanes_ = false;
  std::vector<NetLane> lanes_;
  std::vector<int> succ_;
  std::vector<int> pred_, predStart_;  // predecessors(), by lane
  std::vector<std::string> edgeIds_;   // edgeIds(road): laneEdge()'s index space
  std::vector<Vec2> pt_;
  std::vector<double> cum_;  // arc length at each point of its lane
  // the lanes' segments (by their first point), for matching a car not on its last lane
  StaticGrid<2> segments_;
  std::vector<int> pointLane_;  // the lane each point belongs to
  std::vector<char> crowded_;  // per segment (by its first point): another lane's area overlaps it

  std::vector<LaneFrame> frame_;
  std::vector<double> prevD_, prevT_, horizon_;
  std::vector<Vec2> prevPos_;
  std::vector<int> prevLane_, pieceBegin_, pieceEnd_;
  std::vector<int> matched_;    // the lane match() found this tick (-1: none)
  std::vector<char> prevAlong_;  // alongside() at the last tick (after update(): at this one)
  std::vector<char> straight_;  // the path is the straight line (no lane, or slow)
  std::vector<char> merge_;     // atMerge()
  std::vector<char> prevBent_;  // its heading at the last tick was a junction's bend, not its motion (predict)
  std::vector<double> deviation_;  // deviation()
  std::vector<PathPiece> pieces_;
  // predict's scratch: the centre line a path follows, its vertices at arcs from the centre's foot
  // (the source's lengths) and their points
  std::vector<double> lineS_;
  std::vector<Vec2> linePt_;
};

}  // namespace st::highway::detail
