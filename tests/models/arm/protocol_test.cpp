// The arm service protocol: every message round-trips, every truncation and trailing byte is
// named, and random bytes or mutated messages never crash the decoder (fuzzed, ASan in CI).
#include <gtest/gtest.h>

#include <random>

#include <starm/protocol.hpp>

namespace st::arm::proto {
namespace {

std::vector<Message> samples() {
  Readings r;
  r.seq = 77;
  r.t = 1.25;
  r.arms = {{0, {0.1, -0.2, 0.3, -1.4, 0.5, 1.6, 0.7}, {1, 2, 3, 4, 5, 6, 7}}, {1, {0.5, 0.25}, {-1, -2}}};
  Obstacles o;
  o.seq = 3;
  o.t = 0.5;
  o.obstacles = {{2, Vec3(1, 2, 3), Vec3(-0.5, 0, 0.25)}};
  Welcome w;
  w.cycleTime = 0.001;
  w.safeTime = 0.211;
  w.armNames = {"left", "right"};
  w.armDofs = {7, 7};
  w.obstacleNames = {"column", "bin"};
  Verdict v;
  v.ack = 9;
  v.cycle = 123456789012ull;
  v.t = 1.071;
  v.arms = {{Level::Stop, 0.2, Cause::Collision, {0, 8, 1, 8, -1, 0.031, 0.2}},
            {Level::Warn, 0.29, Cause::Lookahead, {1, 3, -1, -1, 1, 0.12, 0.29}}};
  v.nearest = {0, 8, 1, 8, -1, 0.031, 0.2};
  w.personNames = {"visitor"};
  v.arms[1].factor = 0.375;
  v.arms[1].personSeparation = 0.61;
  v.arms[1].required = 0.55;
  v.arms[1].person = 0;
  v.arms[1].part = 7;
  Skeletons sk;
  sk.seq = 5;
  sk.t = 0.75;
  sk.persons = {{0, std::vector<Vec3>(kSkeletonJoints, Vec3(1, 2, 3))}};
  sk.persons[0].joints[16] = Vec3(-1, 0.5, 0.08);
  return {Hello{kVersion, "s3cret"}, r, o, Subscribe{Subscribe::kOwnOnly}, w, v, Error{"bad token"}, Claim{{0, 1}, {3}}, Reset{{1}},
          sk};
}

bool same(const Message& a, const Message& b) { return encode(a) == encode(b); }

TEST(Protocol, AClaimIsBoundedAndNamesItsArmsAndObstacles) {
  const Decoded d = decode(encode(Claim{{1, 0}, {7}}));
  ASSERT_TRUE(d.ok) << d.error;
  EXPECT_EQ(std::get<Claim>(d.message).arms, (std::vector<std::uint16_t>{1, 0}));
  EXPECT_EQ(std::get<Claim>(d.message).obstacles, (std::vector<std::uint16_t>{7}));
  const Decoded big = decode(encode(Claim{std::vector<std::uint16_t>(65, 0), {}}));
  EXPECT_FALSE(big.ok);
  EXPECT_EQ(big.error, "CLAIM: 65 arms claimed (at most 64)");
  std::string cut = encode(Claim{{1, 2}, {}});
  cut.pop_back();
  EXPECT_FALSE(decode(cut).ok);
}

TEST(Protocol, EveryMessageRoundTrips) {
  for (const Message& m : samples()) {
    const Decoded d = decode(encode(m));
    ASSERT_TRUE(d.ok) << d.error;
    EXPECT_EQ(d.message.index(), m.index());
    EXPECT_TRUE(same(d.message, m));
  }
  // field by field for the two hot messages
  const Decoded r = decode(encode(samples()[1]));
  const auto& rd = std::get<Readings>(r.message);
  EXPECT_EQ(rd.seq, 77u);
  EXPECT_EQ(rd.t, 1.25);
  ASSERT_EQ(rd.arms.size(), 2u);
  EXPECT_EQ(rd.arms[0].q[3], -1.4);
  EXPECT_EQ(rd.arms[1].qdot[1], -2.0);
  const Decoded vdd = decode(encode(samples()[5]));
  const auto& vd = std::get<Verdict>(vdd.message);
  EXPECT_EQ(vd.cycle, 123456789012ull);
  EXPECT_EQ(vd.arms[0].level, Level::Stop);
  EXPECT_EQ(vd.nearest.obstacle, -1);
  EXPECT_EQ(vd.nearest.distance, 0.031);
  // the hot-path decoder agrees
  Readings into;
  EXPECT_EQ(decodeReadings(encode(samples()[1]), into), "");
  EXPECT_TRUE(same(into, samples()[1]));
}

TEST(Protocol, VersionOneVerdictsKeepTheirLayoutAndVersionTwoNamesTheCause) {
  const Verdict v = std::get<Verdict>(samples()[5]);
  const std::string one = encode(v, 1), two = encode(v, 2);
  EXPECT_EQ(one[0], 1);
  EXPECT_EQ(two[0], 2);
  // version 1: u32 ack, u64 cycle, f64 t, u16 n, n x 9 bytes, the nearest (5 x i16, 2 x f64)
  EXPECT_EQ(one.size(), 2u + 4 + 8 + 8 + 2 + 2 * 9 + 10 + 16);
  EXPECT_EQ(two.size(), one.size() + 2 * 25);
  const Decoded d1 = decode(one), d2 = decode(two);
  ASSERT_TRUE(d1.ok && d2.ok) << d1.error << d2.error;
  const auto& v1 = std::get<Verdict>(d1.message);
  const auto& v2 = std::get<Verdict>(d2.message);
  EXPECT_EQ(v1.arms[0].level, Level::Stop);
  EXPECT_EQ(v1.arms[0].cause, Cause::None) << "version 1 carries no cause";
  EXPECT_EQ(v2.arms[0].cause, Cause::Collision);
  EXPECT_EQ(v2.arms[0].pair.otherArm, 1);
  EXPECT_EQ(v2.arms[0].pair.distance, 0.031);
  EXPECT_EQ(v2.arms[1].pair.arm, 1);
  EXPECT_EQ(v2.arms[1].pair.obstacle, 1);
  EXPECT_EQ(v2.arms[1].cause, Cause::Lookahead);
  // a cause beyond the last is refused
  std::string bad = two;
  bad[2 + 4 + 8 + 8 + 2 + 9] = 8;
  EXPECT_EQ(decode(bad).error, "VERDICT: verdict cause 8");
  // versions 0 and 5 are not served
  for (const char version : {'\0', '\5'}) {
    std::string m = two;
    m[0] = version;
    EXPECT_NE(decode(m).error.find("not supported (this service speaks 1 to 4)"), std::string::npos) << decode(m).error;
  }
}

TEST(Protocol, VersionThreeCarriesPersonsAndOlderVersionsDoNot) {
  const Verdict v = std::get<Verdict>(samples()[5]);
  const std::string two = encode(v, 2), three = encode(v, 3);
  // version 3: 28 bytes more per arm (3 x f64, 2 x i16)
  EXPECT_EQ(three.size(), two.size() + 2 * 28);
  const Decoded d3 = decode(three), d2 = decode(two);
  ASSERT_TRUE(d3.ok && d2.ok) << d3.error << d2.error;
  const auto& v3 = std::get<Verdict>(d3.message);
  EXPECT_EQ(v3.arms[1].factor, 0.375);
  EXPECT_EQ(v3.arms[1].personSeparation, 0.61);
  EXPECT_EQ(v3.arms[1].person, 0);
  EXPECT_EQ(v3.arms[1].part, 7);
  EXPECT_EQ(std::get<Verdict>(d2.message).arms[1].factor, 1.0) << "version 2 carries no factor";
  // the person cause is told to version 2 as separation, whose decoders know no cause 8
  Verdict p = v;
  p.arms[0].cause = Cause::Person;
  EXPECT_EQ(std::get<Verdict>(decode(encode(p, 2)).message).arms[0].cause, Cause::Separation);
  EXPECT_EQ(std::get<Verdict>(decode(encode(p, 3)).message).arms[0].cause, Cause::Person);
  // WELCOME's persons only from version 3 on
  const Welcome w = std::get<Welcome>(samples()[4]);
  EXPECT_TRUE(std::get<Welcome>(decode(encode(w, 2)).message).personNames.empty());
  EXPECT_EQ(std::get<Welcome>(decode(encode(w, 3)).message).personNames, std::vector<std::string>{"visitor"});
  // SKELETONS: round trip, refused in an older version, bounded before allocating
  const Skeletons sk = std::get<Skeletons>(samples()[9]);
  const Decoded ds = decode(encode(sk));
  ASSERT_TRUE(ds.ok) << ds.error;
  EXPECT_EQ(std::get<Skeletons>(ds.message).persons[0].joints[16], Vec3(-1, 0.5, 0.08));
  EXPECT_EQ(decode(encode(sk, 2)).error, "SKELETONS: needs protocol version 3 (this message says 2)");
  std::string many = encode(sk);
  many[2 + 4 + 8] = static_cast<char>(0xFF);
  many[2 + 4 + 8 + 1] = static_cast<char>(0xFF);
  EXPECT_EQ(decode(many).error, "SKELETONS: 65535 persons in one message (at most 64)");
}

TEST(Protocol, VersionFourClaimsCarryRatesAndOlderClaimsAreByteForByteAsBefore) {
  const Claim c{{0, 1}, {3}, {{SensorRate::Arm, 1, 0.02, 0.003, 0.02}, {SensorRate::Person, 0, 1.0 / 30.0, 0.005, 0.01}}};
  const Decoded d = decode(encode(c, 4));
  ASSERT_TRUE(d.ok) << d.error;
  EXPECT_EQ(std::get<Claim>(d.message).rates, c.rates);
  EXPECT_EQ(std::get<Claim>(d.message).arms, c.arms);
  // versions 1 to 3: the CLAIM of before, written by hand (version, type, 2 arms, 1 obstacle)
  for (const int v : {1, 2, 3}) {
    const auto version = static_cast<std::uint8_t>(v);
    const std::string old = encode(c, version);
    EXPECT_EQ(old, std::string({static_cast<char>(version), 0x05, 2, 0, 0, 0, 1, 0, 1, 0, 3, 0}));
    const Decoded o = decode(old);
    ASSERT_TRUE(o.ok) << o.error;
    EXPECT_TRUE(std::get<Claim>(o.message).rates.empty());
  }
  // bounded, named: a rate cut short, a kind that is neither arm nor person, too many rates
  std::string cut = encode(c, 4);
  cut.pop_back();
  EXPECT_NE(decode(cut).error.find("CLAIM: truncated at byte"), std::string::npos) << decode(cut).error;
  std::string kind = encode(c, 4);
  kind[12 + 2] = 2;  // the first rate's kind (after 2 + 2 + 4 + 2 + 2 bytes and the rates' count)
  EXPECT_EQ(decode(kind).error, "CLAIM: rate kind 2 (0 arm, 1 person)");
  std::string many = encode(Claim{{}, {}, {}}, 4);
  many[many.size() - 2] = static_cast<char>(129);
  EXPECT_EQ(decode(many).error, "CLAIM: 129 rates in one CLAIM (at most 128)");
}

TEST(Protocol, InfinityAndNanSurviveTheWire) {
  Verdict v;
  v.arms = {{Level::Ok, std::numeric_limits<double>::infinity(), Cause::None, {}}};
  v.nearest.distance = std::numeric_limits<double>::infinity();
  const Decoded dd = decode(encode(v));
  const auto& d = std::get<Verdict>(dd.message);
  EXPECT_TRUE(std::isinf(d.arms[0].minTtc));
  Readings r;
  r.arms = {{0, {std::nan("")}, {0.0}}};
  const Decoded rd = decode(encode(r));
  EXPECT_TRUE(std::isnan(std::get<Readings>(rd.message).arms[0].q[0]));
}

TEST(Protocol, EveryTruncationAndTrailingByteIsNamed) {
  for (const Message& m : samples()) {
    const std::string full = encode(m);
    for (std::size_t n = 0; n < full.size(); ++n) {
      const Decoded d = decode(full.substr(0, n));
      ASSERT_FALSE(d.ok) << "prefix " << n << " of " << full.size() << " decoded";
      EXPECT_FALSE(d.error.empty());
      EXPECT_EQ(d.error.find('\n'), std::string::npos);
      if (n >= 2) {
        EXPECT_NE(d.error.find("truncated"), std::string::npos) << d.error;
      }
    }
    const Decoded extra = decode(full + "x");
    EXPECT_FALSE(extra.ok);
    EXPECT_NE(extra.error.find("1 bytes after the message"), std::string::npos) << extra.error;
  }
}

TEST(Protocol, VersionAndTypeAreChecked) {
  std::string m = encode(Subscribe{});
  m[0] = 5;
  EXPECT_NE(decode(m).error.find("protocol version 5 not supported"), std::string::npos);
  m[0] = static_cast<char>(kVersion);
  m[1] = 0x42;
  EXPECT_NE(decode(m).error.find("unknown message type 0x42"), std::string::npos) << decode(m).error;
  EXPECT_NE(decode("").error.find("at least 2"), std::string::npos);
}

TEST(Protocol, LimitsAreEnforcedBeforeAllocating) {
  // a READINGS announcing 65535 arms or 255 joints is refused by its count, not by reading on
  std::string m = encode(Readings{});
  m[2 + 4 + 8] = static_cast<char>(0xff);
  m[2 + 4 + 8 + 1] = static_cast<char>(0xff);
  EXPECT_NE(decode(m).error.find("65535 readings in one message"), std::string::npos) << decode(m).error;
  Readings one;
  one.arms = {{0, {1.0}, {0.0}}};
  std::string j = encode(one);
  j[2 + 4 + 8 + 2 + 2] = static_cast<char>(200);
  EXPECT_NE(decode(j).error.find("200 joints"), std::string::npos) << decode(j).error;
}

TEST(Protocol, FuzzedInputNeverCrashes) {
  std::mt19937_64 g(11);
  int ok = 0, errors = 0;
  const std::vector<Message> base = samples();
  for (int k = 0; k < 30000; ++k) {
    std::string p;
    if (k % 3 == 0) {
      p.resize(g() % 200);
      for (char& c : p) c = static_cast<char>(g());
      if (p.size() >= 2 && k % 2) p[0] = static_cast<char>(kVersion);
    } else {
      // a valid message with a few bytes flipped, inserted or cut
      p = encode(base[g() % base.size()]);
      for (int e = 0; e < 1 + static_cast<int>(g() % 3); ++e) {
        const std::size_t at = p.empty() ? 0 : g() % p.size();
        switch (g() % 3) {
          case 0: if (!p.empty()) p[at] = static_cast<char>(g()); break;
          case 1: p.insert(at, 1, static_cast<char>(g())); break;
          default: p.erase(at, 1 + g() % 4);
        }
      }
    }
    const Decoded d = decode(p);
    if (d.ok) {
      ++ok;
      // what decodes re-encodes to the same bytes
      EXPECT_EQ(encode(d.message, static_cast<std::uint8_t>(p[0])), p);
    } else {
      ++errors;
      ASSERT_FALSE(d.error.empty());
      ASSERT_EQ(d.error.find('\n'), std::string::npos);
    }
  }
  EXPECT_GT(errors, 10000);
  EXPECT_GT(ok, 100);
}

}  // namespace
}  // namespace st::arm::proto
