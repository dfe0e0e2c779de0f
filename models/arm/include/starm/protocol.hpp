#pragma once
// The arm service's wire protocol, version 4 (versions 1 to 3 still served): pure encode / decode of
// frame payloads (the length prefix is st::net's). No sockets here, so every message can be
// tested and fuzzed.
//
// Every payload starts with two bytes: the protocol version (1 or 2) and the message type. A
// client's HELLO names its version; the service answers in it. Version 2 gives each arm of a
// VERDICT the cause of its level; version 3 adds persons: SKELETONS, the persons in WELCOME, and
// each arm's speed factor and person separation in VERDICT (causes 8 person and 9 deadline in
// version 3 only; a version 2 client is told `separation` and `stale`). Version 4 lets a CLAIM
// declare the rates of what it reports (each arm's joint sensor, each person's tracker: period,
// jitter, clock drift; starm/monitor.hpp) instead of the scenario's. Numbers are little-endian:
// u8/u16/u32/u64, f64 IEEE 754; a string is u16 length + bytes.
//
//   client -> service
//   0x01 HELLO      u16 version, string token (empty unless the service requires one)
//   0x02 READINGS   u32 seq, f64 t, u16 n, n x {u16 arm, u8 dof, dof x f64 q, dof x f64 qdot}
//   0x03 OBSTACLES  u32 seq, f64 t, u16 n, n x {u16 obstacle, 3 x f64 position, 3 x f64 velocity}
//   0x04 SUBSCRIBE  u8 flags (bit 0: only the cycles holding this client's own readings)
//   0x06 RESET      u16 n, n x u16 arm: release the latch of STOPs held since a sensor fell silent
//                   (each arm current again; one that is not stays latched)
//   0x07 SKELETONS  (version 3) u32 seq, f64 t, u16 n, n x {u16 person, 17 x 3 x f64 joints}
//                   (person.hpp's joint order, cell frame, m)
//   0x05 CLAIM      u16 n, n x u16 arm, u16 m, m x u16 obstacle: what this client reports (once,
//                   before its first READINGS or OBSTACLES; without it a client claims each arm or
//                   obstacle by its first report of it)[, v4: u16 k, k x {u8 kind (0 arm, 1 person),
//                   u16 id, f64 period, f64 jitter, f64 drift}: its sensors' rates (s, s, ratio); a
//                   person named here is claimed too]
//   service -> client
//   0x81 WELCOME    u16 version, f64 cycle time, f64 safe time, u16 arms, arms x {string name, u8 dof},
//                   u16 obstacles, obstacles x {string name}[, v3: u16 persons, persons x {string name}]
//   0x82 VERDICT    u32 ack (last seq of this client's in the cycle, 0: none), u64 cycle, f64 t,
//                   u16 arms, arms x {u8 level, f64 min ttc[, v2: u8 cause, i16 body,
//                   i16 other arm, i16 other body, i16 obstacle, f64 distance, f64 ttc][, v3:
//                   f64 speed factor, f64 person separation, f64 S_p, i16 person, i16 body part]},
//                   nearest {i16 arm, i16 body, i16 other arm, i16 other body, i16 obstacle,
//                   f64 distance, f64 ttc}
//   0xFF ERROR      string message (one line); the service closes the connection after it
//
// Positions are the obstacle's reference point (sphere centre, capsule midpoint, box centre).
// Levels: OK, WARN (a pair within the look-ahead but beyond the safe time), STOP (the monitor's
// STOP for the arm: a pair within the safe time or the minimum separation).
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <stcore/vec.hpp>

namespace st::arm::proto {

inline constexpr std::uint8_t kVersion = 4;     // what this build speaks by default
inline constexpr std::uint8_t kOldestVersion = 1;  // the oldest still served
inline constexpr std::size_t kMaxArms = 64;        // per message
inline constexpr std::size_t kMaxDof = 32;
inline constexpr std::size_t kMaxObstacles = 4096;
inline constexpr std::size_t kMaxPersons = 64;     // per message
inline constexpr std::size_t kSkeletonJoints = 17;  // person.hpp's SkeletonJoint

enum class Type : std::uint8_t {
  Hello = 0x01,
  Readings = 0x02,
  Obstacles = 0x03,
  Subscribe = 0x04,
  Claim = 0x05,
  Reset = 0x06,
  Skeletons = 0x07,  // version 3
  Welcome = 0x81,
  Verdict = 0x82,
  Error = 0xFF,
};

enum class Level : std::uint8_t { Ok = 0, Warn = 1, Stop = 2 };
const char* toString(Level l);
// Why an arm's verdict is what it is (version 2): the rule that decided it.
enum class Cause : std::uint8_t {
  None = 0,          // OK: no pair hits within the look-ahead
  Collision = 1,     // STOP: a pair hits within the safe time
  Separation = 2,    // STOP: a pair is already within the minimum separation
  Lookahead = 3,     // WARN: a pair hits within the look-ahead, beyond the safe time
  Stale = 4,         // STOP: no current reading of the arm
  ObstacleLost = 5,  // STOP: a tracked obstacle has no current pose
  Disputed = 6,      // STOP: the arm, or a tracked obstacle, is reported by two connections
  Latched = 7,       // STOP: held since the arm's sensor fell silent, until a RESET
  Person = 8,        // STOP: a person within S_p at the arm's speed (version 3; version 2: Separation)
  Deadline = 9,      // STOP: the cycle's compute time exceeded its budget (version 3; version 2: Stale)
};
inline constexpr std::uint8_t kLastCause = 9;
// the last cause a version's VERDICT carries
inline std::uint8_t lastCause(std::uint8_t version) { return version >= 3 ? 9 : 7; }
const char* toString(Cause c);

struct Hello {
  std::uint16_t version = kVersion;
  std::string token;
};
struct ArmReading {
  std::uint16_t arm = 0;
  std::vector<double> q, qdot;
};
struct Readings {
  std::uint32_t seq = 0;
  double t = 0.0;
  std::vector<ArmReading> arms;
};
struct ObstaclePose {
  std::uint16_t obstacle = 0;
  Vec3 position = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
};
struct Obstacles {
  std::uint32_t seq = 0;
  double t = 0.0;
  std::vector<ObstaclePose> obstacles;
};
struct PersonPose {
  std::uint16_t person = 0;
  std::vector<Vec3> joints;  // kSkeletonJoints, cell frame
};
struct Skeletons {
  std::uint32_t seq = 0;
  double t = 0.0;
  std::vector<PersonPose> persons;
};
struct Subscribe {
  std::uint8_t flags = 0;
  static constexpr std::uint8_t kOwnOnly = 1;
};
// A sensor's declared rate (version 4): readings at most period + jitter apart (s), its clock
// off the service's by at most drift (a ratio: 0.02 is 2 %).
struct SensorRate {
  enum Kind : std::uint8_t { Arm = 0, Person = 1 };
  std::uint8_t kind = Arm;
  std::uint16_t id = 0;
  double period = 0.0, jitter = 0.0, drift = 0.0;
  bool operator==(const SensorRate&) const = default;
};
inline constexpr std::size_t kMaxRates = 128;  // per CLAIM
struct Claim {
  std::vector<std::uint16_t> arms, obstacles;
  std::vector<SensorRate> rates{};  // version 4; not written in older versions
};
struct Reset {
  std::vector<std::uint16_t> arms;
};
struct Welcome {
  std::uint16_t version = kVersion;
  double cycleTime = 0.0, safeTime = 0.0;
  std::vector<std::string> armNames;
  std::vector<std::uint8_t> armDofs;
  std::vector<std::string> obstacleNames;
  std::vector<std::string> personNames;  // version 3
};
// A pair of bodies: an arm's body and another arm's body or an obstacle (-1: none).
struct Nearest {
  std::int16_t arm = -1, body = -1, otherArm = -1, otherBody = -1, obstacle = -1;
  double distance = std::numeric_limits<double>::infinity();
  double ttc = std::numeric_limits<double>::infinity();
};
struct ArmVerdict {
  Level level = Level::Ok;
  double minTtc = std::numeric_limits<double>::infinity();
  // version 2: the rule, and for Collision / Separation / Lookahead the pair that decided it
  // (the arm's smallest time to collision; `arm` is this arm); on the wire `arm` is implied
  Cause cause = Cause::None;
  Nearest pair;
  // version 3: speed and separation monitoring (factor 1, no person: nothing to slow for)
  double factor = 1.0;
  double personSeparation = std::numeric_limits<double>::infinity();  // m
  double required = 0.0;  // m, S_p of the binding person pair
  std::int16_t person = -1, part = -1;  // the binding person and body part (person.hpp's bodyParts order)
};
struct Verdict {
  std::uint32_t ack = 0;
  std::uint64_t cycle = 0;
  double t = 0.0;
  std::vector<ArmVerdict> arms;
  Nearest nearest;
};
struct Error {
  std::string message;
};

using Message = std::variant<Hello, Readings, Obstacles, Subscribe, Claim, Reset, Welcome, Verdict, Error, Skeletons>;

// In protocol `version` (kOldestVersion..kVersion).
std::string encode(const Message& m, std::uint8_t version = kVersion);
// Appends to out (no allocation once out has grown; the service's hot path).
void encodeInto(std::string& out, const Verdict& v, std::uint8_t version = kVersion);

// A decoded message or why not (one line, e.g. "READINGS: truncated at byte 23 (arm 1 q)").
struct Decoded {
  bool ok = false;
  Message message;
  std::string error;
};
Decoded decode(std::string_view payload);
// Decodes READINGS into `out`, reusing its storage (the service's hot path). Error text or "".
std::string decodeReadings(std::string_view payload, Readings& out);
// The same for SKELETONS (the service's hot path with a person).
std::string decodeSkeletons(std::string_view payload, Skeletons& out);
// The type byte of a payload of a version served, or an error.
bool peekType(std::string_view payload, Type& type, std::string& error);

}  // namespace st::arm::proto
