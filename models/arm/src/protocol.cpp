#include <starm/protocol.hpp>

#include <cstring>

namespace st::arm::proto {

namespace {

// Little-endian writer.
struct Writer {
  std::string& out;
  std::uint8_t version = kVersion;
  void u8(std::uint8_t v) { out.push_back(static_cast<char>(v)); }
  void u16(std::uint16_t v) {
    u8(static_cast<std::uint8_t>(v));
    u8(static_cast<std::uint8_t>(v >> 8));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i16(std::int16_t v) { u16(static_cast<std::uint16_t>(v)); }
  void f64(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, 8);
    u64(b);
  }
  void str(const std::string& s) {
    const std::size_t n = std::min<std::size_t>(s.size(), 65535);
    u16(static_cast<std::uint16_t>(n));
    out.append(s.data(), n);
  }
  void ids(const std::vector<std::uint16_t>& v) {
    u16(static_cast<std::uint16_t>(v.size()));
    for (std::uint16_t id : v) u16(id);
  }
  void head(Type t) {
    u8(version);
    u8(static_cast<std::uint8_t>(t));
  }
};

// Little-endian reader over a payload; the first failure names what was being read.
struct Reader {
  std::string_view in;
  std::size_t pos = 0;
  std::string error;
  const char* what = "";

  bool need(std::size_t n) {
    if (!error.empty()) return false;
    if (in.size() - pos < n) {
      error = std::string("truncated at byte ") + std::to_string(in.size()) + " (" + what + ")";
      return false;
    }
    return true;
  }
  std::uint8_t u8() {
    if (!need(1)) return 0;
    return static_cast<std::uint8_t>(in[pos++]);
  }
  std::uint16_t u16() {
    if (!need(2)) return 0;
    const auto v = static_cast<std::uint16_t>(static_cast<unsigned char>(in[pos]) | (static_cast<unsigned char>(in[pos + 1]) << 8));
    pos += 2;
    return v;
  }
  std::uint32_t u32() {
    if (!need(4)) return 0;
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(in[pos + i])) << (8 * i);
    pos += 4;
    return v;
  }
  std::uint64_t u64() {
    if (!need(8)) return 0;
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(in[pos + i])) << (8 * i);
    pos += 8;
    return v;
  }
  std::int16_t i16() { return static_cast<std::int16_t>(u16()); }
  double f64() {
    const std::uint64_t b = u64();
    double v;
    std::memcpy(&v, &b, 8);
    return v;
  }
  std::string str() {
    const std::uint16_t n = u16();
    if (!need(n)) return {};
    std::string s(in.substr(pos, n));
    pos += n;
    return s;
  }
  bool fail(const std::string& e) {
    if (error.empty()) error = e;
    return false;
  }
  // u16 n (at most `max`), then n x u16 ids: CLAIM's and RESET's lists
  void ids(std::vector<std::uint16_t>& out, std::size_t max, const char* noun, const std::string& beyond) {
    what = "count";
    const std::uint16_t n = u16();
    if (error.empty() && n > max) fail(std::to_string(n) + " " + noun + " " + beyond + " (at most " + std::to_string(max) + ")");
    what = noun;
    for (std::uint16_t k = 0; k < n && error.empty(); ++k) out.push_back(u16());
  }
  bool done() {
    if (!error.empty()) return false;
    if (pos != in.size()) return fail(std::to_string(in.size() - pos) + " bytes after the message");
    return true;
  }
};

const char* typeName(Type t) {
  switch (t) {
    case Type::Hello: return "HELLO";
    case Type::Readings: return "READINGS";
    case Type::Obstacles: return "OBSTACLES";
    case Type::Subscribe: return "SUBSCRIBE";
    case Type::Claim: return "CLAIM";
    case Type::Reset: return "RESET";
    case Type::Skeletons: return "SKELETONS";
    case Type::Welcome: return "WELCOME";
    case Type::Verdict: return "VERDICT";
    case Type::Error: return "ERROR";
  }
  return "?";
}

bool knownType(std::uint8_t b) {
  switch (static_cast<Type>(b)) {
    case Type::Hello:
    case Type::Readings:
    case Type::Obstacles:
    case Type::Subscribe:
    case Type::Claim:
    case Type::Reset:
    case Type::Skeletons:
    case Type::Welcome:
    case Type::Verdict:
    case Type::Error: return true;
  }
  return false;
}

// A message's sequence number, time and count of what follows.
std::uint16_t readStamp(Reader& r, std::uint32_t& seq, double& t) {
  r.what = "seq";
  seq = r.u32();
  r.what = "t";
  t = r.f64();
  r.what = "count";
  return r.u16();
}

bool readReadings(Reader& r, Readings& out) {
  const std::uint16_t n = readStamp(r, out.seq, out.t);
  if (!r.error.empty()) return false;
  if (n > kMaxArms) return r.fail(std::to_string(n) + " readings in one message (at most " + std::to_string(kMaxArms) + ")");
  out.arms.resize(n);
  for (std::uint16_t k = 0; k < n; ++k) {
    ArmReading& a = out.arms[k];
    r.what = "arm";
    a.arm = r.u16();
    r.what = "dof";
    const std::uint8_t dof = r.u8();
    if (!r.error.empty()) return false;
    if (dof > kMaxDof) return r.fail("reading " + std::to_string(k) + ": " + std::to_string(dof) + " joints (at most " +
                                     std::to_string(kMaxDof) + ")");
    r.what = "q";
    if (!r.need(16u * dof)) return false;
    a.q.resize(dof);
    a.qdot.resize(dof);
    for (auto& v : a.q) v = r.f64();
    for (auto& v : a.qdot) v = r.f64();
  }
  return r.done();
}

// SKELETONS after the type byte, into out (its storage reused: a pose per message allocates
// nothing once out has held as many persons).
bool readSkeletons(Reader& r, std::uint8_t version, Skeletons& out) {
  if (version < 3) return r.fail("needs protocol version 3 (this message says " + std::to_string(version) + ")");
  const std::uint16_t n = readStamp(r, out.seq, out.t);
  if (r.error.empty() && n > kMaxPersons)
    return r.fail(std::to_string(n) + " persons in one message (at most " + std::to_string(kMaxPersons) + ")");
  r.what = "skeleton";
  if (!r.need(static_cast<std::size_t>(n) * (2 + kSkeletonJoints * 24))) return false;
  out.persons.resize(n);
  for (PersonPose& p : out.persons) {
    p.person = r.u16();
    p.joints.resize(kSkeletonJoints);
    for (Vec3& j : p.joints)
      for (int i = 0; i < 3; ++i) j[i] = r.f64();
  }
  return r.done();
}

bool readHello(Reader& r, Hello& h) {
  r.what = "version";
  h.version = r.u16();
  r.what = "token";
  h.token = r.str();
  return r.done();
}

bool readObstacles(Reader& r, Obstacles& x) {
  const std::uint16_t n = readStamp(r, x.seq, x.t);
  if (r.error.empty() && n > kMaxObstacles) r.fail(std::to_string(n) + " obstacles in one message");
  r.what = "pose";
  if (r.error.empty() && r.need(static_cast<std::size_t>(n) * 50)) {
    x.obstacles.resize(n);
    for (ObstaclePose& o : x.obstacles) {
      o.obstacle = r.u16();
      for (int i = 0; i < 3; ++i) o.position[i] = r.f64();
      for (int i = 0; i < 3; ++i) o.velocity[i] = r.f64();
    }
  }
  return r.done();
}

bool readSubscribe(Reader& r, Subscribe& s) {
  r.what = "flags";
  s.flags = r.u8();
  return r.done();
}

// CLAIM's sensor rates (version 4)
void readRates(Reader& r, std::vector<SensorRate>& rates) {
  r.what = "rates";
  const std::uint16_t n = r.u16();
  if (r.error.empty() && n > kMaxRates)
    r.fail(std::to_string(n) + " rates in one CLAIM (at most " + std::to_string(kMaxRates) + ")");
  if (!r.error.empty() || !r.need(static_cast<std::size_t>(n) * 27)) return;
  rates.resize(n);
  for (SensorRate& rate : rates) {
    rate.kind = r.u8();
    rate.id = r.u16();
    rate.period = r.f64();
    rate.jitter = r.f64();
    rate.drift = r.f64();
    if (rate.kind > SensorRate::Person && r.error.empty()) r.fail("rate kind " + std::to_string(rate.kind) + " (0 arm, 1 person)");
  }
}

bool readClaim(Reader& r, std::uint8_t version, Claim& x) {
  r.ids(x.arms, kMaxArms, "arms", "claimed");
  r.ids(x.obstacles, kMaxObstacles, "obstacles", "claimed");
  if (version >= 4 && r.error.empty()) readRates(r, x.rates);
  return r.done();
}

bool readReset(Reader& r, Reset& x) {
  r.ids(x.arms, kMaxArms, "arms", "to reset");
  return r.done();
}

bool readWelcome(Reader& r, std::uint8_t version, Welcome& x) {
  r.what = "welcome";
  x.version = r.u16();
  x.cycleTime = r.f64();
  x.safeTime = r.f64();
  const std::uint16_t n = r.u16();
  for (std::uint16_t k = 0; k < n && r.error.empty(); ++k) {
    x.armNames.push_back(r.str());
    x.armDofs.push_back(r.u8());
  }
  const std::uint16_t no = r.u16();
  for (std::uint16_t k = 0; k < no && r.error.empty(); ++k) x.obstacleNames.push_back(r.str());
  if (version >= 3) {
    const std::uint16_t np = r.u16();
    for (std::uint16_t k = 0; k < np && r.error.empty(); ++k) x.personNames.push_back(r.str());
  }
  return r.done();
}

// a pair after its arm: body, other arm and body, obstacle, distance, TTC
void readPair(Reader& r, Nearest& n) {
  n.body = r.i16();
  n.otherArm = r.i16();
  n.otherBody = r.i16();
  n.obstacle = r.i16();
  n.distance = r.f64();
  n.ttc = r.f64();
}

// arm k's verdict: its level and TTC; from version 2 its cause and pair, from 3 the persons' part
void readArmVerdict(Reader& r, std::uint8_t version, std::size_t k, ArmVerdict& a) {
  const std::uint8_t l = r.u8();
  if (l > 2) r.fail("verdict level " + std::to_string(l));
  a.level = static_cast<Level>(l);
  a.minTtc = r.f64();
  if (version < 2) return;
  const std::uint8_t c = r.u8();
  if (c > lastCause(version)) r.fail("verdict cause " + std::to_string(c));
  a.cause = static_cast<Cause>(c);
  a.pair.arm = static_cast<std::int16_t>(k);
  readPair(r, a.pair);
  if (version < 3) return;
  a.factor = r.f64();
  a.personSeparation = r.f64();
  a.required = r.f64();
  a.person = r.i16();
  a.part = r.i16();
}

bool readVerdict(Reader& r, std::uint8_t version, Verdict& v) {
  r.what = "verdict";
  v.ack = r.u32();
  v.cycle = r.u64();
  v.t = r.f64();
  const std::uint16_t n = r.u16();
  const std::size_t armBytes = version >= 3 ? 62 : version >= 2 ? 34 : 9;
  if (r.error.empty() && r.need(static_cast<std::size_t>(n) * armBytes)) {
    v.arms.resize(n);
    for (std::size_t k = 0; k < v.arms.size(); ++k) readArmVerdict(r, version, k, v.arms[k]);
  }
  r.what = "nearest";
  v.nearest.arm = r.i16();
  readPair(r, v.nearest);
  return r.done();
}

bool readError(Reader& r, Error& e) {
  r.what = "message";
  e.message = r.str();
  return r.done();
}

// Each message but VERDICT (encodeInto) after its head; the writer's version decides what an
// older peer is sent.
void writeMessage(Writer& w, const Hello& x) {
  w.head(Type::Hello);
  w.u16(x.version);
  w.str(x.token);
}

void writeMessage(Writer& w, const Readings& x) {
  w.head(Type::Readings);
  w.u32(x.seq);
  w.f64(x.t);
  w.u16(static_cast<std::uint16_t>(x.arms.size()));
  for (const ArmReading& a : x.arms) {
    w.u16(a.arm);
    w.u8(static_cast<std::uint8_t>(a.q.size()));
    for (double v : a.q) w.f64(v);
    for (std::size_t k = 0; k < a.q.size(); ++k) w.f64(k < a.qdot.size() ? a.qdot[k] : 0.0);
  }
}

void writeMessage(Writer& w, const Obstacles& x) {
  w.head(Type::Obstacles);
  w.u32(x.seq);
  w.f64(x.t);
  w.u16(static_cast<std::uint16_t>(x.obstacles.size()));
  for (const ObstaclePose& o : x.obstacles) {
    w.u16(o.obstacle);
    for (int i = 0; i < 3; ++i) w.f64(o.position[i]);
    for (int i = 0; i < 3; ++i) w.f64(o.velocity[i]);
  }
}

void writeMessage(Writer& w, const Subscribe& x) {
  w.head(Type::Subscribe);
  w.u8(x.flags);
}

void writeMessage(Writer& w, const Reset& x) {
  w.head(Type::Reset);
  w.ids(x.arms);
}

void writeMessage(Writer& w, const Claim& x) {
  w.head(Type::Claim);
  w.ids(x.arms);
  w.ids(x.obstacles);
  if (w.version < 4) return;
  w.u16(static_cast<std::uint16_t>(x.rates.size()));
  for (const SensorRate& rate : x.rates) {
    w.u8(rate.kind);
    w.u16(rate.id);
    w.f64(rate.period);
    w.f64(rate.jitter);
    w.f64(rate.drift);
  }
}

void writeMessage(Writer& w, const Welcome& x) {
  w.head(Type::Welcome);
  w.u16(x.version);
  w.f64(x.cycleTime);
  w.f64(x.safeTime);
  w.u16(static_cast<std::uint16_t>(x.armNames.size()));
  for (std::size_t k = 0; k < x.armNames.size(); ++k) {
    w.str(x.armNames[k]);
    w.u8(k < x.armDofs.size() ? x.armDofs[k] : 0);
  }
  w.u16(static_cast<std::uint16_t>(x.obstacleNames.size()));
  for (const std::string& n : x.obstacleNames) w.str(n);
  if (w.version < 3) return;
  w.u16(static_cast<std::uint16_t>(x.personNames.size()));
  for (const std::string& n : x.personNames) w.str(n);
}

void writeMessage(Writer& w, const Skeletons& x) {
  w.head(Type::Skeletons);
  w.u32(x.seq);
  w.f64(x.t);
  w.u16(static_cast<std::uint16_t>(x.persons.size()));
  for (const PersonPose& p : x.persons) {
    w.u16(p.person);
    for (std::size_t j = 0; j < kSkeletonJoints; ++j)
      for (int i = 0; i < 3; ++i) w.f64(j < p.joints.size() ? p.joints[j][i] : 0.0);
  }
}

void writeMessage(Writer& w, const Error& x) {
  w.head(Type::Error);
  w.str(x.message);
}

// a message of type M as read(x) reads it, kept if it passed
template <class M, class Read>
void decodeAs(Decoded& d, Read read) {
  M x;
  if (read(x)) d.message = std::move(x);
}

}  // namespace

const char* toString(Level l) {
  switch (l) {
    case Level::Ok: return "OK";
    case Level::Warn: return "WARN";
    case Level::Stop: return "STOP";
  }
  return "?";
}

const char* toString(Cause c) {
  switch (c) {
    case Cause::None: return "none";
    case Cause::Collision: return "collision";
    case Cause::Separation: return "separation";
    case Cause::Lookahead: return "lookahead";
    case Cause::Stale: return "stale";
    case Cause::ObstacleLost: return "obstacle_lost";
    case Cause::Disputed: return "disputed";
    case Cause::Latched: return "latched";
    case Cause::Person: return "person";
    case Cause::Deadline: return "deadline";
  }
  return "?";
}

void encodeInto(std::string& out, const Verdict& v, std::uint8_t version) {
  Writer w{out, version};
  w.head(Type::Verdict);
  w.u32(v.ack);
  w.u64(v.cycle);
  w.f64(v.t);
  w.u16(static_cast<std::uint16_t>(v.arms.size()));
  for (const ArmVerdict& a : v.arms) {
    w.u8(static_cast<std::uint8_t>(a.level));
    w.f64(a.minTtc);
    if (version < 2) continue;
    // a cause the version does not know is told as its nearest one it does
    const Cause cause = version >= 3 ? a.cause
                        : a.cause == Cause::Person ? Cause::Separation
                        : a.cause == Cause::Deadline ? Cause::Stale
                                                     : a.cause;
    w.u8(static_cast<std::uint8_t>(cause));
    w.i16(a.pair.body);
    w.i16(a.pair.otherArm);
    w.i16(a.pair.otherBody);
    w.i16(a.pair.obstacle);
    w.f64(a.pair.distance);
    w.f64(a.pair.ttc);
    if (version < 3) continue;
    w.f64(a.factor);
    w.f64(a.personSeparation);
    w.f64(a.required);
    w.i16(a.person);
    w.i16(a.part);
  }
  const Nearest& n = v.nearest;
  w.i16(n.arm);
  w.i16(n.body);
  w.i16(n.otherArm);
  w.i16(n.otherBody);
  w.i16(n.obstacle);
  w.f64(n.distance);
  w.f64(n.ttc);
}

std::string encode(const Message& m, std::uint8_t version) {
  std::string out;
  std::visit(
      [&](const auto& x) {
        if constexpr (std::is_same_v<std::decay_t<decltype(x)>, Verdict>) {
          encodeInto(out, x, version);
        } else {
          Writer w{out, version};
          writeMessage(w, x);
        }
      },
      m);
  return out;
}

bool peekType(std::string_view payload, Type& type, std::string& error) {
  if (payload.size() < 2) {
    error = "message of " + std::to_string(payload.size()) + " bytes (at least 2: version, type)";
    return false;
  }
  const auto version = static_cast<std::uint8_t>(payload[0]);
  if (version < kOldestVersion || version > kVersion) {
    error = "protocol version " + std::to_string(version) + " not supported (this service speaks " +
            std::to_string(kOldestVersion) + " to " + std::to_string(kVersion) + ")";
    return false;
  }
  const auto t = static_cast<std::uint8_t>(payload[1]);
  if (!knownType(t)) {
    error = "unknown message type 0x" + std::string(1, "0123456789abcdef"[t >> 4]) + "0123456789abcdef"[t & 15];
    return false;
  }
  type = static_cast<Type>(t);
  return true;
}

std::string decodeReadings(std::string_view payload, Readings& out) {
  Type t;
  std::string err;
  if (!peekType(payload, t, err)) return err;
  if (t != Type::Readings) return std::string("expected READINGS, got ") + typeName(t);
  Reader r{payload, 2, {}, ""};
  if (!readReadings(r, out)) return std::string("READINGS: ") + r.error;
  return "";
}

std::string decodeSkeletons(std::string_view payload, Skeletons& out) {
  Type t;
  std::string err;
  if (!peekType(payload, t, err)) return err;
  if (t != Type::Skeletons) return std::string("expected SKELETONS, got ") + typeName(t);
  Reader r{payload, 2, {}, ""};
  if (!readSkeletons(r, static_cast<std::uint8_t>(payload[0]), out)) return std::string("SKELETONS: ") + r.error;
  return "";
}

Decoded decode(std::string_view payload) {
  Decoded d;
  Type t;
  if (!peekType(payload, t, d.error)) return d;
  Reader r{payload, 2, {}, ""};
  const auto version = static_cast<std::uint8_t>(payload[0]);
  // each type's reader reads its fields and the payload's end
  switch (t) {
    case Type::Hello: decodeAs<Hello>(d, [&](Hello& x) { return readHello(r, x); }); break;
    case Type::Readings: decodeAs<Readings>(d, [&](Readings& x) { return readReadings(r, x); }); break;
    case Type::Obstacles: decodeAs<Obstacles>(d, [&](Obstacles& x) { return readObstacles(r, x); }); break;
    case Type::Subscribe: decodeAs<Subscribe>(d, [&](Subscribe& x) { return readSubscribe(r, x); }); break;
    case Type::Claim: decodeAs<Claim>(d, [&](Claim& x) { return readClaim(r, version, x); }); break;
    case Type::Reset: decodeAs<Reset>(d, [&](Reset& x) { return readReset(r, x); }); break;
    case Type::Welcome: decodeAs<Welcome>(d, [&](Welcome& x) { return readWelcome(r, version, x); }); break;
    case Type::Verdict: decodeAs<Verdict>(d, [&](Verdict& x) { return readVerdict(r, version, x); }); break;
    case Type::Skeletons: decodeAs<Skeletons>(d, [&](Skeletons& x) { return readSkeletons(r, version, x); }); break;
    case Type::Error: decodeAs<Error>(d, [&](Error& x) { return readError(r, x); }); break;
  }
  if (!r.error.empty()) {
    d.error = std::string(typeName(t)) + ": " + r.error;
    return d;
  }
  d.ok = true;
  return d;
}

}  // namespace st::arm::proto
