#pragma once
// Speed and separation monitoring (ISO/TS 15066:2016 §5.5.4): every cycle, per arm and person,
// the protective separation distance
//
//   S_p = S_h + S_r + S_s + C + Z_d + Z_r                                         formula (1)
//
// against the current separation (the smallest exact distance between the person's capsules
// and the arm's), and a verdict: the speed factor (0..1 of the arm's top speed) that keeps S_p,
// or STOP where none does. With constant speeds and the closed loop's path-maintaining stop (the
// program speed falls linearly to 0 over the stopping time T_s, starting T_r after the cycle):
//
//   S_h = v_h (T_r + T_s)   the person's motion while the robot reacts and stops,  formula (2)
//   S_r = v_r T_r           the robot's motion while it reacts,                    formula (3)
//   S_s = v_r T_s / 2       the robot's motion while it stops (linear ramp),        formula (4)
//
// v_h the person's approach speed (ISO 13855: 1.6 m/s walking, 2.0 m/s a hand), v_r the robot's
// speed (the fastest capsule end point of the arm, whatever its direction: an upper bound on the
// speed towards the person), C the intrusion distance (ISO 13855: reach beyond what the sensor
// sees), Z_d the person's position uncertainty (the tracker), Z_r the robot's (its encoders and
// capsule fit). The person's capsules grown by S_h are their reachable set over T_r + T_s.
//
// Power and force limiting (ISO/TS 15066 §5.5.5, Annex A): a transient contact of the robot with
// a body region is allowed up to the relative speed at which the energy the region absorbs,
// E = F^2 / (2 k) (A.5), equals the kinetic energy of the two-body collision, E = mu v_rel^2 / 2
// (A.6), with mu = (1/m_H + 1/m_R)^-1 the reduced mass (A.3) and m_R = M / 2 + m_L the robot's
// effective mass (A.4, M the arm's moving mass, m_L its payload):
//
//   v_rel,max = F_max / sqrt(mu k)                                                 (A.7)
//
// with F_max the region's transient force limit (twice the quasi-static one, Table A.2's
// multiplier) and k, m_H the region's effective spring constant and mass (Table A.3).
//
// Two refinements (Annex A's distinction of contacts and its relative speed):
// - Clamping: a region that can be pinned between the arm and a fixed obstacle (the scenario's
//   untracked, unmoving obstacles: a table, a wall) makes a quasi-static contact: held to the
//   quasi-static F_max (half the transient force), and, backed by the obstacle, it cannot recoil
//   with the impact, so (A.3)'s reduced mass becomes the robot's own (m_H -> infinity, mu = m_R):
//     v_rel,max = F_max / sqrt(m_R k)                                               (A.7), clamped
//   A region counts as pinnable where a fixed obstacle is within the arm's travel after a contact
//   at top speed plus the uncertainties: S_p(v_h = 0, v_r = R) = R (T_r + T_s / 2) + C + Z_d + Z_r.
// - The person's own motion: v_rel is the robot's speed plus the region's speed into the arm (a
//   person moving into the arm), so the robot's limit is v_rel,max less that speed, 0 if that
//   is negative. The region's speed into the arm: the larger of its two end joints' velocities
//   along the line from the region to the nearest arm capsule (closest points), 0 if both move
//   away; touching (no such line), their larger magnitude. Where the tracker cannot tell the
//   velocities, the region moves into the arm at the standard's v_h.
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <starm/person.hpp>
#include <stcore/toi_advance.hpp>

namespace st::arm {

class Monitor;
struct Obstacle;
class ArmDrive;

enum class SsmResponse {
  Stop,     // binary: STOP while the separation is below S_p at the arm's top speed
  Scaling,  // graded: the largest speed factor keeping S_p; STOP only where the present speed breaks S_p
  Pfl,      // scaling, and where S_p cannot be kept the arm may go on at the power-and-force limit
            // of the body region it may touch instead of stopping
};
const char* toString(SsmResponse r);

struct SsmConfig {
  double bodySpeed = 1.6;           // v_h of the body, m/s (ISO 13855 §6.2: walking)
  double handSpeed = 2.0;           // v_h of a hand, m/s (ISO 13855: hand and arm approach)
  double cycleTime = 0.001;         // T_c, s: the monitor's cycle
  double reactionTime = 0.011;      // T_r, s: a cycle to see + the reaction until braking starts
  double stoppingTime = 0.2;        // T_s, s: the drive's stopping time (braking.stopping_time)
  double intrusion = 0.0;           // C, m: the body capsules are the person, nothing unseen beyond
  double personUncertainty = 0.05;  // Z_d, m: the skeleton tracker's error
  double robotUncertainty = 0.01;   // Z_r, m: joint encoders and capsule fit
  double robotSpeed = 1.0;          // m/s, the arm's top speed: speed factor 1
  double armMass = 18.0;            // M, kg: the arm's moving mass (Panda: 18 kg, its whole weight, on the safe side)
  double payload = 1.0;             // m_L, kg: what the arm carries (gripper and part)
  SsmResponse response = SsmResponse::Scaling;
};

// ISO/TS 15066:2016 Annex A per body region: Table A.2's maximum permissible quasi-static force
// (the transient limit is twice it: the table's multiplier) and Table A.3's effective spring
// constant and effective mass of the body region.
struct RegionLimits {
  double force;      // N, quasi-static F_max
  double springK;    // N/m (Table A.3 gives N/mm)
  double mass;       // kg, m_H
  bool transient;    // transient contact allowed under the pfl response (never with the head)
};
const RegionLimits& regionLimits(BodyRegion r);
// m_R = M / 2 + m_L                                                                  (A.4)
double robotEffectiveMass(double armMass, double payload);
// mu = (1 / m_H + 1 / m_R)^-1                                                        (A.3)
double reducedMass(double humanMass, double robotMass);
// v_rel,max = F / sqrt(mu k) for a transient contact force limit F (N)               (A.7)
double transientSpeedLimit(double force, double springK, double mu);
// The largest robot speed (m/s) for a transient contact with region r under the config's masses:
// (A.7) with F = 2 x the quasi-static F_max; 0 where the region takes no transient contact. The
// region free (not clamped) and at rest: the form below with (false, 0).
double pflSpeedLimit(const SsmConfig& c, BodyRegion r);
// The largest robot speed (m/s) for a contact with region r moving at personSpeed (m/s) towards
// the arm, clamped (quasi-static: F_max, mu = m_R) or not (transient: 2 F_max, mu of (A.3)):
// max(0, v_rel,max - personSpeed); 0 where the region takes no transient contact.
double pflSpeedLimit(const SsmConfig& c, BodyRegion r, bool clamped, double personSpeed);
// A body part's speed into an arm capsule (m/s): see above; known false: the part's v_h.
double partSpeedInto(const SsmConfig& c, int part, const Capsule& body, const Capsule& arm, bool known,
                     const std::array<Vec3, kSkeletonJoints>& v);
// The distance (m) within which a fixed obstacle can pin a body region against the arm:
// R (T_r + T_s / 2) + C + Z_d + Z_r, the arm's travel after a contact at top speed.
double clampGap(const SsmConfig& c);

// The terms of formula (1), each in metres.
struct SeparationTerms {
  double sh = 0.0, sr = 0.0, ss = 0.0, c = 0.0, zd = 0.0, zr = 0.0;
  double total() const { return sh + sr + ss + c + zd + zr; }
  const char* dominant() const;  // "S_h", "S_r", ... the largest term
};

// Formulae (1)-(4) for a person part at speed vh and the robot at speed vr.
SeparationTerms protectiveSeparation(const SsmConfig& c, double vh, double vr);
// The same with the drive's state known (the closed loop): the program speed s now and s_b, the
// one a STOP now would brake from (ArmDrive::brakingSpeed). The drive brakes at 1 / T_s of
// program speed per second, so from s_b it stops in s_b T_s, not T_s; and until it stands the
// arm is no faster than v_b = s_b R (its path's speed is at most R = robot_speed per unit of
// program speed; the speed seen now, v_r, is no bound: at a turn of the path it is near 0 and
// grows while the arm stops), or v_r + (s_b - s) R where the arm is seen faster than R allows:
//   S_r = v_b T_r,   S_s = v_b s_b T_s / 2                                   (3), (4) with the drive's T_s
// With s = s_b = 1 (following) these are (3) and (4) at the arm's top speed max(R, v_r). Without
// the drive (the service, the binary response) the check uses (3) and (4) at v_r as written.
SeparationTerms protectiveSeparation(const SsmConfig& c, double vh, double vr, double s, double sb);
// The largest robot speed (m/s) that keeps S_p at the next cycle: after one more cycle T_c the
// person may be vh T_c and the robot v T_c closer, so S_p(v) <= d - (vh + v) T_c:
//   v = (d - vh T_c - S_p(vh, 0)) / (T_r + T_s / 2 + T_c).
// Negative: no speed does. The drive slows at its braking rate after T_r, so a person coming on
// fast can still outrun the factor: then S_p at the arm's present speed breaks and the verdict
// is STOP, in time by formula (1).
double allowedRobotSpeed(const SsmConfig& c, double vh, double d);
// The same with the drive's stopping time known: an arm held at speed factor f (speed <= f R)
// stops in f T_s. The factor takes effect only after the drive's reaction, so the person may come
// on for T_r (not one cycle) before S_p(f) holds: with room = d - vh T_r - S_p(vh, 0),
//   R f (T_r + T_c) + R f^2 T_s / 2 <= room,
//   f = 2 room / R / ((T_r + T_c) + sqrt((T_r + T_c)^2 + 2 T_s room / R)),
// returned as the speed f R (negative where room is: no speed keeps S_p).
double allowedDrivenSpeed(const SsmConfig& c, double vh, double d);

struct SsmVerdict {
  double separation = std::numeric_limits<double>::infinity();  // m, nearest person capsule to the arm
  double required = 0.0;      // m, S_p of the binding pair (the pair of smallest distance - S_p)
  double slack = std::numeric_limits<double>::infinity();  // m, that pair's distance - S_p
  SeparationTerms terms;      // of the binding pair
  double robotSpeed = 0.0;    // m/s, v_r now
  double allowedSpeed = std::numeric_limits<double>::infinity();  // m/s
  double factor = 1.0;        // speed factor for the arm (0..1 of SsmConfig::robotSpeed)
  bool stop = false;
  bool violated = false;      // separation < S_p at the arm's present speed (pfl: and above the region's limit)
  bool pflAllowed = false;    // pfl: below S_p, but at or below the power-and-force limit of every region so near
  double pflLimit = std::numeric_limits<double>::infinity();  // m/s, pfl: the limit of the regions below S_p
  bool clamped = false;       // pfl: one of those regions can be pinned against a fixed obstacle (quasi-static limit)
  int person = -1, part = -1, armBody = -1;  // the binding pair (-1: no person present)
};

struct SsmCounters {
  std::uint64_t cycles = 0;
  std::uint64_t stopCycles = 0;    // arm cycles with a STOP verdict
  std::uint64_t scaledCycles = 0;  // arm cycles with 0 < factor < 1
  std::uint64_t violations = 0;    // arm cycles with separation < S_p and no STOP verdict
  std::uint64_t contacts = 0;      // arm cycles with a person capsule touching a moving arm capsule
  std::uint64_t contactsWithinLimit = 0;  // of those, the arm at or below the touched regions' PFL limit
  std::uint64_t contactsAboveLimit = 0;   // of those, the arm faster than a touched region's PFL limit
  std::uint64_t pflCycles = 0;     // arm cycles below S_p allowed by power and force limiting
  double minSeparation = std::numeric_limits<double>::infinity();
};

// The persons of a scenario: their names and where each is at a time.
class PersonSet {
 public:
  void add(std::string name, std::unique_ptr<PersonTrack> track);
  int size() const { return static_cast<int>(names_.size()); }
  const std::string& name(int i) const { return names_[i]; }
  // Poses every person at t; present(i) false when its track has nothing for t. Each joint's
  // velocity is its track's over the window (PersonTrack::velocities; default 1 ms, the cycle).
  void pose(double t);
  const Skeleton& skeleton(int i) const { return skeletons_[i]; }
  bool present(int i) const { return present_[i] != 0; }
  // The joints' velocities (m/s) at the last pose; false where the track could not tell.
  bool velocitiesKnown(int i) const { return velocitiesKnown_[i] != 0; }
  const std::array<Vec3, kSkeletonJoints>& velocities(int i) const { return velocities_[i]; }
  void setVelocityWindow(double h) { velocityWindow_ = h; }

 private:
  std::vector<std::string> names_;
  std::vector<std::unique_ptr<PersonTrack>> tracks_;
  std::vector<Skeleton> skeletons_;
  std::vector<char> present_;
  std::vector<std::array<Vec3, kSkeletonJoints>> velocities_;
  std::vector<char> velocitiesKnown_;
  double velocityWindow_ = 0.001;  // s
};

class SeparationMonitor {
 public:
  SeparationMonitor(SsmConfig cfg, int arms);
  // The cycle's verdicts from the monitor's arm capsules (at its cycle time) and the posed persons.
  void cycle(const Monitor& m, const PersonSet& persons);
  // The arm's drive, when this process runs it (the closed loop): its program speed sets the
  // stopping time in S_p and the allowed speed (scaling, pfl). Unknown (null, the default): the
  // drive is taken at full program speed, formulae (3) and (4) as written.
  void setDrive(int arm, const ArmDrive* drive) { drives_[arm] = drive; }
  const SsmVerdict& verdict(int arm) const { return verdicts_[arm]; }
  const SsmConfig& config() const { return cfg_; }
  const SsmCounters& counters() const { return counters_; }

 private:
  SsmConfig cfg_;
  std::vector<SsmVerdict> verdicts_;
  std::vector<const ArmDrive*> drives_;
  SsmCounters counters_;
  // the cycle's working state, kept so that a cycle allocates nothing once it has grown
  struct Bound {  // a sphere holding a capsule
    Vec3 centre;
    double reach;  // m
  };
  std::vector<MovingCapsule> caps_;      // the arms' capsules at the cycle time
  std::vector<Bound> capBound_;          // a sphere around each
  std::vector<double> speed_;            // per arm, m/s
  std::vector<int> armFirst_, armCaps_, fill_;  // capsule indices by arm: armCaps_[armFirst_[a] ..armFirst_[a+1])
  std::vector<std::array<Capsule, kBodyParts>> body_;  // per person
  std::vector<std::array<Bound, kBodyParts>> bodyBound_;
  // per person and part, its sphere's distance to each of an arm's capsule spheres, m (a lower
  // bound of their distance): lows_[(p * kBodyParts + k) * n + j], j the arm's j-th capsule
  std::vector<double> lows_;
  std::vector<double> partLow_;  // per person and part, the smallest of its lows_
  std::vector<const Obstacle*> fixed_;  // the untracked, unmoving obstacles (pfl: clamping)
  double gap_ = 0.0;                    // m: a part this near a fixed obstacle is clamped

  // the cycle's stages: place the arms and the persons, then per arm scan the persons' parts for
  // its verdict and count it
  struct ArmScan;
  struct Nearest {
    double d;     // m
    int capsule;  // -1: the arm has none
  };
  void placeArms(const Monitor& m);
  void placePersons(const Monitor& m, const PersonSet& persons);
  SsmVerdict armVerdict(const Monitor& m, const PersonSet& persons, int arm, ArmScan& scan);
  void boundParts(int arm, const PersonSet& persons);
  Nearest nearestCapsule(int arm, int person, int part);
  void judgePart(const Monitor& m, const PersonSet& persons, int arm, int person, int part, Nearest nearest,
                 SsmVerdict& v, ArmScan& scan) const;
  double partLimit(const PersonSet& persons, int person, int part, int armCapsule, bool& clamped) const;
  void respond(SsmVerdict& v, const ArmScan& scan) const;
  void count(const SsmVerdict& v, const ArmScan& scan, double speed);
};

}  // namespace st::arm
