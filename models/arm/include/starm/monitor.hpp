#pragma once
// The collision monitor (the report's RACDS, §3.2): arms as capsules in a dynamic octree with
// stationary and moving obstacles. Each cycle: forward kinematics for the arms that reported,
// capsules moved in the space, candidate pairs from shared leaves, exact distance and time to
// collision for each, warnings and STOP per arm.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <stcore/space.hpp>
#include <stcore/toi_advance.hpp>
#include <starm/arm.hpp>

namespace st::arm {

// The time-to-collision rule's terms: warn when a pair's time to collision is at most the time the
// system needs to bring the arm to rest. (Not ISO/TS 15066's protective separation distance S_p:
// that is the persons' check, starm/ssm.hpp.)
struct SafetyConfig {
  double cycleTime = 0.001;     // s, sensor period
  double reactionTime = 0.010;  // s, from warning to the start of braking
  double stoppingTime = 0.200;  // s, braking to rest
  double minSeparation = 0.02;  // m, every object grown by half of it
  double horizon = 0.0;         // s, look-ahead of the time-to-collision search; 0 = safe time
  // A STOP because an arm's sensor fell silent holds until reset(arm), once the arm is current
  // again (ISO 10218: a deliberate restart after a protective stop); false: it clears itself.
  bool latchStale = true;
  double safeTime() const { return cycleTime + reactionTime + stoppingTime; }
  double lookAhead() const { return horizon > 0.0 ? horizon : safeTime(); }
};

struct BroadphaseConfig {
  SpaceKind kind = SpaceKind::Tree;  // None: test all pairs (the reference the octree must match)
  // auto starts fine (SpaceRule::autoStart): the lists are tested every cycle and re-filed about
  // every 25 cycles, so the tuner mostly confirms the finest factor; from 16 it spent 0.4-0.8 ms
  // per halving among panda_clutter's 1 000 obstacles, inside the first 48 cycles
  SpaceRule rule{.decompositionFactor = 4, .subdivide = true, .divisions = 8, .maxDepth = 8, .cellSize = 0.25, .autoStart = 2};
  // rule.maxDepth chosen by the Monitor from the scene (depthFromScene below) instead of the
  // value above; a scenario's octree.max_depth sets it false. A fixed depth of 8 with no key cost
  // p99 200-630 us per cycle on the shipped cells against 4-11 us at depth 4 (bench/arm_cycle).
  bool depthFromScene = true;
  double margin = 0.05;              // m, fat-box margin: a capsule is re-filed only when it leaves it
  std::optional<Aabb3> bounds;       // default: everything the arms can reach plus the obstacles
};

enum class ShapeKind { Sphere, Capsule, Box };

struct Obstacle {
  std::string name;
  ShapeKind kind = ShapeKind::Sphere;
  Sphere sphere;
  Capsule capsule;
  Box box;
  Vec3 velocity = Vec3::Zero();  // m/s, constant; zero for stationary objects
  // a tracker reports its pose (the service's OBSTACLES); an untracked one is where the scenario
  // puts it, and no client may move it
  bool tracked = false;
  bool moving() const { return velocity.squaredNorm() > 0.0; }
};

struct ArmInstance {
  std::string name;
  ArmModel model;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  // Its joint sensor's period and jitter (s): readings come at most period + jitter apart; one
  // older than that is stale and the arm STOPs. Period 0 (undeclared): stale after reaction +
  // cycle time.
  double sensorPeriod = 0.0, sensorJitter = 0.0;
  // The most its clock may run fast or slow against the monitor's (1: 0.02 for 2 %). 0: the
  // clocks agree and a reading's age is the monitor's time less its stamp. Declared, the age is
  // judged on the monitor's clock through SensorClock (below) and the gap between readings may be
  // (period + jitter) (1 + drift).
  double sensorDrift = 0.0;
  // Allowed arm-vs-obstacle pairs: (body, obstacle name), never tested (a base bolted to the
  // table it stands on). A name no obstacle has is refused by the Monitor (invalid_argument).
  std::vector<std::pair<int, std::string>> allowedObstacles{};
};

// A sensor's clock seen from the monitor's: the offset to add to its stamps to get the
// monitor's time of the reading. With no drift declared the clocks agree (offset 0). With drift
// rho declared the offset is the lower envelope of (arrival - stamp) over the readings, allowed
// to rise by at most rho per second of the monitor's clock between arrivals:
//   offset_k = min(arrival_k - stamp_k, offset_{k-1} + rho (arrival_k - arrival_{k-1})).
// The true offset (monitor time of the reading less its stamp) changes by at most rho per second
// and never exceeds arrival - stamp (a reading arrives after it is taken), so offset_k is at least
// the true offset less the smallest transport delay seen: age(t) = t - (stamp + offset) is the
// reading's age on the monitor's clock less that delay. It is never less than t - arrival (the
// watchdog on the monitor's own clock), and a delay that grows (a backlog) still ages readings.
// A sensor whose clock drifts is thus judged by its rate, not by how far its clock has wandered.
struct SensorClock {
  double drift = 0.0;     // declared, 1 (0.02: 2 %)
  double offset = 0.0;    // s, monitor time - stamp
  double arrival = 0.0;   // s, monitor time of the last new reading
  bool known = false;     // a reading arrived since the last reset
  // A new reading (a stamp later than the last) first seen at monitor time t.
  void arrived(double stamp, double t) {
    if (!(drift > 0.0)) return;
    const double o = t - stamp;
    offset = known ? std::min(o, offset + drift * (t - arrival)) : o;
    arrival = t;
    known = true;
  }
  // s, on the monitor's clock at time t (0 drift: t - stamp)
  double age(double stamp, double t) const { return t - (stamp + offset); }
  void reset() { known = false, offset = 0.0; }
};

struct Warning {
  double t = 0.0;        // s, cycle time
  int arm = -1;          // the arm warned
  int body = -1;         // its link (body index)
  int capsule = -1;      // index into its model's capsules
  int otherArm = -1;     // another arm (or the same arm: self-collision), or -1
  int otherBody = -1;
  int otherCapsule = -1;
  int obstacle = -1;     // or an obstacle
  double distance = 0.0; // m, separation now
  double ttc = 0.0;      // s, time until within the minimum separation (0 if already)
  Outcome outcome = Outcome::Overlapping;  // already within it (Overlapping), within it at ttc (Hit), or not (Miss)
  bool stop = false;     // this warning issued STOP for `arm`
};

struct MonitorCounters {
  std::uint64_t cycles = 0;
  std::uint64_t candidatePairs = 0;  // pairs sharing a space leaf (after the allowed-collision matrix)
  std::uint64_t exactPairs = 0;      // candidates whose swept boxes overlap: exact distance + TTC
  std::uint64_t advanceSteps = 0;    // distance evaluations in conservative advancement
  std::uint64_t cappedAdvances = 0;  // advancement step budget exhausted (reported early, never late)
  std::uint64_t warnings = 0;
  std::uint64_t stops = 0;
  std::uint64_t staleStops = 0;      // arm cycles STOPped for want of a current reading
  std::uint64_t refiled = 0;         // space updates (a capsule left its fat box)
};

class Monitor {
 public:
  Monitor(std::vector<ArmInstance> arms, std::vector<Obstacle> obstacles, SafetyConfig safety,
          BroadphaseConfig broad = {});

  int armCount() const { return static_cast<int>(arms_.size()); }
  const ArmInstance& arm(int i) const { return arms_[i].inst; }
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }
  const SafetyConfig& safety() const { return safety_; }

  // A sensor reading: joint angles and rates of one arm at time t. Checked as the service checks
  // it (validateJointState: counts, finite, limits, rates) and never older than the arm's last;
  // throws InputError naming the arm and time, and a refused reading changes nothing.
  void setJointState(int arm, double t, const double* q, const double* qdot);
  // One detection cycle at time t; the warnings of this cycle replace the previous ones.
  void cycle(double t);

  const std::vector<Warning>& warnings() const { return warnings_; }
  // STOP: a pair within the safe time or the minimum separation, or no current reading.
  bool stopped(int arm) const { return arms_[arm].stopped; }
  // The watchdog: no reading of the arm within staleAfter(arm) of the cycle's time (or none yet).
  bool stale(int arm) const { return arms_[arm].stale; }
  // The arm has no reading from now on (its sensor left): stale, STOP (latched, if it had
  // readings) until the next one, whose time may be any.
  void forget(int arm);
  // Held by the latch: its sensor fell silent (or left) since the last reset.
  bool latched(int arm) const { return arms_[arm].latched; }
  // Releases the latch if the arm was current at the last cycle; false if it stays latched.
  bool reset(int arm);
  double staleAfter(int arm) const;
  // Declares arm's sensor anew (ArmInstance::sensorPeriod, sensorJitter, sensorDrift; period 0:
  // undeclared), its clock's offset forgotten: a sensor that introduces itself (the service's
  // CLAIM). Throws std::invalid_argument for a period beyond [0, 60] s, jitter beyond
  // [0, period) or drift beyond [0, 0.5).
  void setSensorRate(int arm, double period, double jitter, double drift);
  // The cycles' times are the sensors' own stamps (the service: a cycle runs at the newest stamp
  // among its messages), so the cycle a reading is applied in may run at that reading's own
  // stamp, whatever its clock's offset: its arrival is marked at the first cycle later than that
  // one. Off (in process): at the first cycle later than the last one before it was set.
  void setStampedCycles(bool on) { stampedCycles_ = on; }
  bool warned(int arm) const { return arms_[arm].warned; }
  double time() const { return now_; }  // of the last cycle
  // The closest pair of this cycle among those tested exactly (swept boxes overlapping; any
  // other pair is farther apart than the minimum separation): arm, body, other party, distance
  // now and its time to collision (infinity: clear). arm < 0: no pair was close enough to test.
  const Warning& nearest() const { return nearest_; }
  // Smallest time to collision of this cycle over the exactly tested pairs (s; infinity: none),
  // overall and per arm (either side of a pair).
  double minTtc() const { return minTtc_; }
  double minTtc(int arm) const { return armMinTtc_[arm]; }
  // The pair behind minTtc(arm), seen from the arm (`arm` is it; ties: the closer pair): what
  // decided its STOP or WARN, which need not be the nearest pair. arm < 0: none tested.
  const Warning& worst(int arm) const { return armWorst_[arm]; }
  // A pose report for obstacle o (a sensor, the network): its reference point (sphere centre,
  // capsule midpoint, box centre) at `position` at time t, moving at `velocity` from then on.
  void setObstaclePose(int o, double t, const Vec3& position, const Vec3& velocity);
  const MonitorCounters& counters() const { return counters_; }
  // The broadphase, never null: SpaceKind::None is the brute force (every pair a candidate).
  const Space<3>* space() const { return &space_; }
  Aabb3 spaceBounds() const { return bounds_; }

  // Introspection (tests, viewers): global capsule i of the arms at the current cycle time.
  int capsuleCount() const { return static_cast<int>(capA_.size()); }
  MovingCapsule movingCapsule(int i) const;
  int capsuleArm(int i) const { return capArm_[i]; }
  int capsuleBody(int i) const { return capBody_[i]; }
  // Box an object (space id) may occupy over the look-ahead, grown by half the minimum separation.
  const Aabb3& sweptBox(int id) const { return swept_[id]; }
  const Aabb3& fatBox(int id) const { return fat_[id]; }
  int objectCount() const { return static_cast<int>(swept_.size()); }
  // The neighbour list the cycle tests for object id (a capsule or a moving obstacle), and when it
  // was last filed (a pair is tested from the list of its more recently filed member).
  const std::vector<int>& neighbours(int id) const { return neighbours_[id]; }
  std::uint64_t filedAt(int id) const { return filedAt_[id]; }

 private:
  struct ArmState {
    ArmInstance inst;
    int firstCapsule = 0;
    std::vector<Eigen::Isometry3d> frames;
    BodyRates rates;
    double t = 0.0;  // time of the last reading (its stamp, on its sensor's clock)
    SensorClock clock;   // that clock against the monitor's
    // A reading with a later stamp than the one before, waiting to be marked as arrived: at the
    // first cycle later than the last cycle before it was set (a cycle's time may lag the
    // reading's arrival: the service stamps cycles with the newest stamp). NaN: none waiting.
    double markStamp = std::numeric_limits<double>::quiet_NaN();
    double markAfter = -std::numeric_limits<double>::infinity();
    bool markApplied = false;  // stampedCycles: the cycle it was applied in has run
    bool read = false;   // any reading yet
    bool stale = false;  // this cycle: no current reading
    bool latched = false;  // a sensor once current fell silent: STOP until reset
    bool fresh = false;
    bool stopped = false;
    bool warned = false;
  };

  // construction: the arms' capsules, their rest poses, the space and the obstacles filed in it
  void addArm(ArmInstance inst);
  std::vector<int> allowedObstacles(const ArmInstance& inst, int body) const;  // obstacle indices
  void restPoses();
  void buildSpace(double grow);
  Aabb3 sceneBounds(double grow) const;  // what the arms can reach and the obstacles' swept boxes

  void updateArmCapsules(ArmState& a);
  void refile(int id);
  void gather(int id);  // id's neighbour list, from the space
  void tuneSpace();  // decomposition_factor auto: the cycle's visits to the space's tuner
  void regather();   // every list the cycle tests, from the space as it is
  void testPair(int i, int j, double t);
  void testObstacle(int i, int o, double t);
  void addWarning(const Warning& w);
  void noteNearest(int i, int j, int obstacle, const AdvanceImpact& r);
  // capsule i's pair with capsule j (or an obstacle, j < 0), as a record seen from i
  Warning pairRecord(int i, int j, int obstacle, const AdvanceImpact& r) const;
  // Counts the advancement; a Warning for capsule i (ego side filled) if r warns at time t.
  std::optional<Warning> warningFor(int i, const AdvanceImpact& r, double t);

  std::vector<ArmState> arms_;
  std::vector<Obstacle> obstacles_;
  std::vector<Obstacle> obstaclesNow_;  // moving ones advanced to the cycle time
  std::vector<int> moving_;             // indices of the moving obstacles
  SafetyConfig safety_;
  BroadphaseConfig broad_;
  Aabb3 bounds_;
  // assigned its kind, bounds and rule once the constructor has found them
  Space<3> space_{SpaceKind::None, Aabb3{Vec3::Constant(-1.0), Vec3::Constant(1.0)}, SpaceRule{}};
  double now_ = 0.0;
  double t0_ = 0.0;  // time the obstacles are given at
  bool started_ = false;
  bool stampedCycles_ = false;

  // arm capsules, struct of arrays, at their arm's reading time
  std::vector<Vec3> capA_, capB_, capVa_, capVb_;
  std::vector<double> capR_;
  std::vector<int> capArm_, capBody_, capLocal_;
  std::vector<std::vector<int>> capAllowedObstacles_;  // per capsule, the obstacles never tested (few)
  // per space object (capsules first, then obstacles)
  std::vector<Aabb3> swept_, fat_;
  // Neighbours from the space, cached when the object was last filed. A pair's candidacy
  // depends only on the two fat boxes, so the list of the more recently filed of the two is
  // current for that pair: each pair is read from exactly that side.
  std::vector<std::vector<int>> neighbours_;
  std::vector<std::uint64_t> filedAt_;
  std::uint64_t fileClock_ = 0;

  std::vector<Warning> warnings_;
  Warning nearest_;
  double minTtc_ = 0.0;
  std::vector<double> armMinTtc_;
  std::vector<Warning> armWorst_;
  MonitorCounters counters_;
};

// The octree depth for a scene: leaves about as large as the moving objects, so that a cluster of
// overlapping capsules (an arm's own links) does not divide down to cells it can never separate.
// depth = round(log2(longest edge of `bounds` / median of `movingSizes`)) within [2, 8];
// movingSizes are the longest fat-box edges of the arm capsules and moving obstacles (m).
int depthFromScene(const Aabb3& bounds, std::vector<double> movingSizes);

// Name of what a warning's other party is: "left/link5", "obstacle:post3".
std::string otherName(const Monitor& m, const Warning& w);
std::string bodyName(const ArmModel& m, int body);

}  // namespace st::arm
