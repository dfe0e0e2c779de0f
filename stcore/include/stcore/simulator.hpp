#pragma once
// Event-driven simulator (§2, §2.1) for balls (circles in 2-D, spheres in 3-D) moving at constant
// velocity between events, against walls, segments, points and capture sensors.
//
// Each ball keeps its own local time (the report's mobile::Time) and is advanced only when it
// takes part in an event. Each ball holds its one earliest predicted event in an indexed heap;
// an event remembers the generation of the other ball, and is dropped lazily when that ball has
// changed since. Pair predictions start from the later of the two balls' local times, so the same
// pair yields the same time whichever space found it: every space kind replays the same history.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <stcore/event_calendar.hpp>
#include <stcore/neighbor_lists.hpp>
#include <stcore/shapes.hpp>
#include <stcore/space.hpp>

namespace st {

// Rest: a decelerating ball comes to a stop (only with setDeceleration).
// Model: an event the caller scheduled (scheduleEvent): a timer, a controller tick, a cue strike.
enum class EventKind : std::uint8_t { BallBall, BallWall, BallSegment, BallPoint, Sensor, Boundary, Rest, Model, Count };
const char* toString(EventKind kind);

// A body's handle is its index; generations tell whether a prediction is still current.
template <int D>
struct BallState {
  Vec<D> p;        // position at local time t
  Vec<D> v;
  double t = 0.0;  // local time (s)
  double radius = 0.0;
  double mass = 1.0;
  int type = 0;    // caller's tag (ball number, colour...)
  std::uint32_t gen = 0;
  bool active = true;
  // Rolling resistance (m/s^2): a constant deceleration opposite to v until the ball stops, so
  // the path stays straight and quadratic in time between events. 0: constant velocity.
  double decel = 0.0;
  bool accelerating() const { return decel > 0.0 && (v.array() != 0.0).any(); }
  // Absolute time the ball stops (infinity if it does not decelerate or is at rest).
  double stopTime() const {
    return accelerating() ? t + v.norm() / decel : std::numeric_limits<double>::infinity();
  }
  // Its acceleration vector while moving.
  Vec<D> acceleration() const { return accelerating() ? Vec<D>(-decel * v.normalized()) : Vec<D>::Zero(); }
  Vec<D> positionAt(double time) const {
    if (!accelerating()) return p + v * (time - t);
    const double dt = std::min(time, stopTime()) - t;
    return p + v * dt + (0.5 * dt * dt) * acceleration();
  }
  Vec<D> velocityAt(double time) const {
    if (!accelerating()) return v;
    if (time >= stopTime()) return Vec<D>::Zero();
    return v + (time - t) * acceleration();
  }
};

// Plane n.x == offset with unit normal n; balls bounce off either side.
template <int D>
struct Wall {
  Vec<D> normal;
  double offset = 0.0;
};

// A capture region: a ball whose centre comes within `radius` of `center` leaves the simulation.
template <int D>
struct Sensor {
  Vec<D> center;
  double radius = 0.0;
};

struct EventRecord {
  double t = 0.0;
  EventKind kind = EventKind::BallBall;
  int a = -1;  // ball (-1 for a Model event)
  int b = -1;  // other ball, index of the wall / segment / point / sensor, or a Model event's tag
};

struct SimulatorCounters {
  std::uint64_t pairChecks = 0;    // ball-ball predictions made (the report's collision checks)
  std::uint64_t staticChecks = 0;  // ball-obstacle predictions made
  std::uint64_t staleEvents = 0;   // popped events whose partner had changed
  std::array<std::uint64_t, static_cast<int>(EventKind::Count)> events{};
  std::uint64_t totalEvents() const {
    std::uint64_t s = 0;
    for (auto e : events) s += e;
    return s;
  }
  std::uint64_t collisions() const {
    return events[0] + events[1] + events[2] + events[3];
  }
};

struct SimulatorConfig {
  SpaceKind spaceKind = SpaceKind::Tree;
  SpaceRule rule;
  // Cells: extra room around each ball's box in the grid, as a fraction of its radius: larger
  // means fewer membership events but more candidates. (A tree lists each ball by its box and
  // takes its events from the leaf walls, with tol::kRegionSlop against rounding.)
  double marginFactor = 0.5;
  // Neighbour lists (neighbor_lists.hpp): a ball may move neighborShell * its radius from where its
  // list was built; pairs are predicted from the lists, and the space (its box around the list
  // centre, grown by that much) is searched only when a ball leaves its shell and rebuilds its
  // list (a Boundary event). 0.5 is Smallenburg's shell of 1.5 diameters. 0: no lists, the
  // space's neighbours are the candidates. Not with SpaceKind::Tree.
  double neighborShell = 0.0;
  // The event queue (event_calendar.hpp): 0 sorts every ball's event in one heap; K > 0 an event
  // calendar (Smallenburg's), sorting only the current time block, sized for about K updates per
  // block, later events unsorted in one list per block. The same order either way.
  double eventsPerBlock = 0.0;
};

enum class StopReason { TimeLimit, NothingLeft, EventLimit };

template <int D>
class Simulator {
 public:
  Simulator(const Aabb<D>& bounds, const SimulatorConfig& config);

  int addBall(const Vec<D>& p, const Vec<D>& v, double radius, double mass, int type = 0);
  int addWall(const Wall<D>& w);
  int addPoint(const Vec<D>& p);
  int addSegment(const Segment& s);  // 2-D only
  int addSensor(const Sensor<D>& s);

  // Changes a ball's velocity at the current time (a cue strike); re-predicts it.
  void setVelocity(int ball, const Vec<D>& v);
  // Takes a ball out of the simulation at the current time.
  void deactivate(int ball);
  // Gives a ball a rolling-resistance deceleration (m/s^2, >= 0) from the current time on: it
  // slows along its path and stops (a Rest event). 0 (the default) leaves the frictionless
  // simulation bit-identical.
  void setDeceleration(int ball, double decel);

  // Schedules a model-defined event at absolute time t (>= now): run() hands it to the observer as
  // EventKind::Model with b = tag, in time order with the physical events. At equal times model
  // events come first (in the order they were scheduled), so a controller acting at t sees the
  // state just before t's collisions. The observer may change velocities or schedule more events.
  // Returns a handle for cancelEvent.
  int scheduleEvent(double t, int tag);
  // Drops a scheduled model event that has not happened yet (no effect otherwise).
  void cancelEvent(int handle);

  // Processes events up to `until` (inclusive) or `maxEvents`, calling observer(const EventRecord&)
  // after each. Then the clock stands at the last event's time (or `until` if it was reached).
  template <class Observer>
  StopReason run(double until, Observer&& observer,
                 std::uint64_t maxEvents = std::numeric_limits<std::uint64_t>::max());
  StopReason run(double until) {
    return run(until, [](const EventRecord&) {});
  }

  // Advances every active ball to time t (>= now) without changing its path.
  void synchronize(double t);

  double now() const { return now_; }
  const std::vector<BallState<D>>& balls() const { return balls_; }
  const BallState<D>& ball(int i) const { return balls_[i]; }
  const std::vector<Wall<D>>& walls() const { return walls_; }
  const std::vector<Vec<D>>& points() const { return points_; }
  const std::vector<Segment>& segments() const { return segments_; }
  const std::vector<Sensor<D>>& sensors() const { return sensors_; }
  // The broadphase, never null: SpaceKind::None is the brute force, every ball a candidate of
  // every other.
  const Space<D>* space() const { return &space_; }
  const SimulatorCounters& counters() const { return counters_; }
  // The neighbour lists (enabled() with SimulatorConfig::neighborShell > 0).
  const NeighborLists<D>& neighborLists() const { return lists_; }
  // Time of the next event, or infinity.
  double nextEventTime() const;

  double kineticEnergy() const;
  Vec<D> momentum() const;

 private:
  // A ball's next event: its earliest physical event (kind Count if none) and, apart, the time its
  // path may first touch a cell it is not listed in, so that a Boundary event keeps the
  // physical prediction and checks only the neighbours gained.
  struct Next {
    double t = std::numeric_limits<double>::infinity();
    double exit = std::numeric_limits<double>::infinity();
    int other = -1;
    std::uint32_t otherGen = 0;
    EventKind kind = EventKind::Count;
    // Boundary orders after the contacts and before Rest at equal times
    bool boundaryFirst() const { return exit < t || (exit == t && kind > EventKind::Boundary); }
    double due() const { return exit < t ? exit : t; }
  };
  // The part of a ball's state that pair predictions read, packed apart from the rest (48 bytes in
  // 2-D, one aligned line in 3-D, against BallState's 80/96); a copy of balls_[i]'s fields, written
  // wherever those change.
  struct alignas(D == 3 ? 64 : 16) Motion {
    Vec<D> p;
    Vec<D> v;
    double t;
    double radius;
  };

  void predict(int i);
  void predictGained(int i);
  void pairCandidate(int i, int j, Next& best);
  void pairStraight(int i, int j, Next& best, double limit = std::numeric_limits<double>::infinity()) const;
  void pairCandidateAccelerated(int i, int j, Next& best);
  void predictObstacles(int i, Next& best);
  void predictObstaclesAccelerated(int i, Next& best);
  void consider(Next& best, double t, EventKind kind, int other) const;
  double exitTime(int i) const;
  void schedule(int i, const Next& best);
  void schedule(int i, const Next& best, double exit);
  void process(int i);
  void advance(int i, double t);
  void redirect(int i, const Vec<D>& v);
  void syncMotion(int i) { motion_[i] = Motion{balls_[i].p, balls_[i].v, balls_[i].t, balls_[i].radius}; }
  bool accelerating(int i) const { return decelerating_ > 0 && balls_[i].accelerating(); }
  Aabb<D> boxOf(int i, double t) const;
  double spaceMargin(int i) const;
  void spaceUpdate(int i);
  void refileGained(int i);
  void settleSpace();
  void rebuildList(int i, double t);

  // model events: a min-heap on (time, scheduling order); cancelled ones are skipped when they surface
  struct ModelEvent {
    double t;
    int handle;  // scheduling order, also the index into modelTags_ / modelCancelled_
    bool operator>(const ModelEvent& o) const { return t > o.t || (t == o.t && handle > o.handle); }
  };
  void dropCancelledModelEvents();  // keeps modelHeap_'s front live
  bool modelEventDue() const;  // the earliest event overall is a model event
  void processModelEvent();

  SimulatorConfig config_;
  Aabb<D> bounds_;
  Space<D> space_;
  std::vector<BallState<D>> balls_;
  std::vector<Motion> motion_;
  std::vector<Next> next_;
  NeighborLists<D> lists_;  // enabled with config_.neighborShell > 0
  // with lists: per ball, bit w set if wall w (< 32) may be within reach before its list expires
  std::vector<std::uint32_t> nearWalls_;
  EventCalendar heap_;  // balls by next event
  std::vector<Wall<D>> walls_;
  std::vector<Vec<D>> points_;
  std::vector<Segment> segments_;
  std::vector<Sensor<D>> sensors_;
  int decelerating_ = 0;  // balls given a deceleration: none, and every path is a straight line
  double now_ = 0.0;
  std::vector<ModelEvent> modelHeap_;
  std::vector<int> modelTags_;
  std::vector<bool> modelCancelled_;
  SimulatorCounters counters_;
  EventRecord last_;
  // refileGained: a ball's leaves before its update, and its neighbours then
  std::vector<int> oldLeaves_;
  std::vector<std::uint32_t> mark_;
  std::uint32_t markNow_ = 0;
  // settleSpace: the balls a restructure re-listed and widened (kept for their storage)
  std::vector<int> relisted_;
  std::vector<int> widened_;
};

template <int D>
template <class Observer>
StopReason Simulator<D>::run(double until, Observer&& observer, std::uint64_t maxEvents) {
  std::uint64_t done = 0;
  while (true) {
    const double next = nextEventTime();
    if (!(next < std::numeric_limits<double>::infinity())) return StopReason::NothingLeft;
    if (next > until) {
      now_ = std::max(now_, until);
      return StopReason::TimeLimit;
    }
    if (done >= maxEvents) return StopReason::EventLimit;
    last_.kind = EventKind::Count;
    if (modelEventDue()) processModelEvent();
    else process(heap_.top());
    if (last_.kind != EventKind::Count) {
      ++done;
      observer(static_cast<const EventRecord&>(last_));
    }
  }
}

extern template class Simulator<2>;
extern template class Simulator<3>;

}  // namespace st
