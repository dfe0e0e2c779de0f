// Time-of-impact kernels against dense time sampling of the exact clearance.
//
// For every case the test evaluates the clearance g(t) (distance between the surfaces, negative
// when overlapping) straight from the geometry on a uniform grid over a horizon long enough to
// contain every contact, then refines: bisection at the first (or last) sign change, and a
// golden-section search around every grid-local minimum, so a grazing dip between two samples is
// not missed. On straight paths the clearance is convex in t (distance from a point moving on a
// line to a convex set, minus a radius); on the decelerating kernels' quadratic paths it can have
// two minima, so those are sampled on a 16x finer grid.
//
// A reported Hit time must lie in the band where |g| is within a roundoff tolerance of contact
// (1e-12 of the scene's length scale), before the clearance falls below minus that tolerance; a
// Miss must have no contact deeper than the tolerance; touching / overlapping starts are checked
// against the documented slop and the sign of dg/dt. 10^5 cases per kernel, mixing generic,
// aimed, grazing, touching, overlapping, parallel, zero-velocity and slow cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <vector>

#include <stcore/toi.hpp>
#include "test_scale.hpp"
#include <stcore/tolerances.hpp>

namespace st {
namespace {

const int kCases = test::scaledCount(100000);  // fewer under the sanitizers (test_scale.hpp)
constexpr double kSlop = tol::kLinearSlop;
constexpr double kInf = std::numeric_limits<double>::infinity();

const char* name(Outcome o) {
  switch (o) {
    case Outcome::Hit: return "Hit";
    case Outcome::Miss: return "Miss";
    case Outcome::Overlapping: return "Overlapping";
    case Outcome::Separating: return "Separating";
  }
  return "?";
}

// ---- sampling truth ---------------------------------------------------------------------------

// g sampled on Grid intervals of [0, T] and refined around every grid-local minimum, so a
// dip between two samples is not missed even when g has several minima (quadratic paths).
template <class G, int Grid = 128>
class Sampled {
 public:
  static constexpr int kGrid = Grid;

  Sampled(G g, double horizon) : g_(g), T_(horizon) {
    for (int k = 0; k <= kGrid; ++k) s_[k] = g_(at(k));
    for (int k = 0; k <= kGrid; ++k) {
      const bool left = k == 0 || s_[k] < s_[k - 1];
      const bool right = k == kGrid || s_[k] <= s_[k + 1];
      if (left && right) minima_.push_back(refine(k));
    }
    if (minima_.empty()) minima_.push_back(refine(0));  // constant g
    global_ = *std::min_element(minima_.begin(), minima_.end(),
                                [](const Minimum& a, const Minimum& b) { return a.g < b.g; });
  }

  double horizon() const { return T_; }
  double g0() const { return s_[0]; }
  double minimum() const { return global_.g; }
  double argMinimum() const { return global_.t; }
  double operator()(double t) const { return g_(t); }

  // First t in [0, T] with g(t) <= level.
  std::optional<double> firstBelow(double level) const {
    if (s_[0] <= level) return 0.0;
    double best = kInfinity;
    for (int k = 1; k <= kGrid; ++k)
      if (s_[k] <= level) {
        best = bisectDown(level, at(k - 1), at(k));
        break;
      }
    for (const Minimum& m : minima_)  // a dip below level between samples
      if (m.g <= level && m.t < best) best = std::min(best, bisectDown(level, at(std::max(m.k - 1, 0)), m.t));
    if (best == kInfinity) return std::nullopt;
    return best;
  }
  // Last t in [0, T] with g(t) <= level.
  std::optional<double> lastBelow(double level) const {
    if (s_[kGrid] <= level) return T_;
    double best = -kInfinity;
    for (int k = kGrid - 1; k >= 0; --k)
      if (s_[k] <= level) {
        best = bisectUp(level, at(k), at(k + 1));
        break;
      }
    for (const Minimum& m : minima_)
      if (m.g <= level && m.t > best) best = std::max(best, bisectUp(level, m.t, at(std::min(m.k + 1, kGrid))));
    if (best == -kInfinity) return std::nullopt;
    return best;
  }

 private:
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
  struct Minimum {
    int k;  // grid index it was found at
    double t, g;
  };
  double at(int k) const { return T_ * k / kGrid; }
  // golden section on the two grid intervals around grid point k
  Minimum refine(int k) const {
    double a = at(std::max(k - 1, 0)), b = at(std::min(k + 1, kGrid));
    const double r = 0.5 * (std::sqrt(5.0) - 1.0);
    double x1 = b - r * (b - a), x2 = a + r * (b - a);
    double f1 = g_(x1), f2 = g_(x2);
    for (int it = 0; it < 90 && b - a > 0; ++it) {
      if (f1 <= f2) {
        b = x2, x2 = x1, f2 = f1;
        x1 = b - r * (b - a), f1 = g_(x1);
      } else {
        a = x1, x1 = x2, f1 = f2;
        x2 = a + r * (b - a), f2 = g_(x2);
      }
    }
    Minimum m{k, f1 <= f2 ? x1 : x2, std::min(f1, f2)};
    if (s_[k] <= m.g) m.t = at(k), m.g = s_[k];
    return m;
  }
  // g(lo) > level >= g(hi): the crossing, from above
  double bisectDown(double level, double lo, double hi) const {
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (g_(mid) <= level ? hi : lo) = mid;
    }
    return hi;
  }
  // g(lo) <= level < g(hi)
  double bisectUp(double level, double lo, double hi) const {
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (g_(mid) <= level ? lo : hi) = mid;
    }
    return lo;
  }

  G g_;
  double T_;
  std::array<double, kGrid + 1> s_{};
  std::vector<Minimum> minima_;
  Minimum global_{0, 0, 0};
};

// What a kernel run saw; every category that a kernel can produce must be exercised.
struct Tally {
  int hit = 0, hitAtZero = 0, miss = 0, overlapping = 0, separating = 0, band = 0;
  int total() const { return hit + hitAtZero + miss + overlapping + separating + band; }
};

::testing::AssertionResult contractHolds(const Impact& got) {
  switch (got.outcome) {
    case Outcome::Hit:
      if (got.t >= 0.0 && std::isfinite(got.t)) return ::testing::AssertionSuccess();
      break;
    case Outcome::Overlapping:
      if (got.t == 0.0) return ::testing::AssertionSuccess();
      break;
    case Outcome::Miss:
    case Outcome::Separating:
      if (got.t == kInf) return ::testing::AssertionSuccess();
      break;
  }
  return ::testing::AssertionFailure() << name(got.outcome) << " with t = " << got.t;
}

// Every outcome of a first-contact kernel was exercised on kCases cases; the roundoff band (either
// answer right: grazing and tangential families sit there by design) stays a minority.
void expectEveryOutcome(const Tally& tally) {
  EXPECT_GT(tally.hit, kCases / 10);
  EXPECT_GT(tally.miss, kCases / 10);
  EXPECT_GT(tally.hitAtZero, 500);
  EXPECT_GT(tally.overlapping, 1000);
  EXPECT_GT(tally.separating, 1000);
  EXPECT_LT(tally.band, kCases / 5);
  EXPECT_EQ(tally.total(), kCases);
}

// Which start conditions count as contact: Slop for obstacles (touching within the linear slop
// acts at once when approaching; separating contacts are left alone), Boundary for space
// boundaries (any overlap with the line or plane is "already overlapping").
enum class Semantics { Slop, Boundary };

// Checks a first-contact kernel result. rate0 is dg/dt at t = 0+, speed |v|, scale the length
// scale of the case (coordinates, radius, distance travelled) that roundoff is relative to.
template <class G, int Grid>
::testing::AssertionResult checkFirstContact(const Impact& got, const Sampled<G, Grid>& s, double rate0,
                                             double speed, double scale, Semantics sem, Tally& tally) {
  if (auto c = contractHolds(got); !c) return c;
  const double tolG = 1e-12 * scale;
  const double rateTol = 1e-12 * speed;
  const double g0 = s.g0();
  auto fail = [&](const char* why) {
    return ::testing::AssertionFailure()
           << why << ": got " << name(got.outcome) << " t=" << got.t << "; truth g0=" << g0
           << " dg/dt(0)=" << rate0 << " min g=" << s.minimum() << " at t=" << s.argMinimum()
           << " horizon=" << s.horizon() << " tol=" << tolG;
  };
  auto is = [&](Outcome o) { return got.outcome == o; };
  auto ok = [&](int& counter) {
    ++counter;
    return ::testing::AssertionSuccess();
  };

  if (sem == Semantics::Slop) {
    if (std::abs(std::abs(g0) - kSlop) <= tolG) return ok(tally.band);  // on the slop's edge
    if (g0 <= kSlop) {
      const bool deep = g0 < -kSlop;
      const bool acts = deep ? is(Outcome::Overlapping) : (is(Outcome::Hit) && got.t == 0.0);
      if (std::abs(rate0) <= rateTol) {
        if (acts || is(Outcome::Separating)) return ok(tally.band);
        return fail("tangential contact must act now or be left alone");
      }
      if (rate0 < 0.0) {
        if (acts) return ok(deep ? tally.overlapping : tally.hitAtZero);
        return fail(deep ? "overlapping and approaching must be Overlapping"
                         : "touching and approaching must Hit at t = 0");
      }
      if (is(Outcome::Separating)) return ok(tally.separating);
      return fail("touching or overlapping while moving apart must be Separating");
    }
  } else {
    if (g0 < -tolG) {
      if (is(Outcome::Overlapping)) return ok(tally.overlapping);
      return fail("a ball across the boundary must be Overlapping");
    }
    if (g0 <= tolG) {
      // touching within roundoff: already across, about to cross, or never crossing
      const std::optional<double> deep = s.firstBelow(-tolG);
      if (is(Outcome::Overlapping) || (is(Outcome::Hit) && got.t <= deep.value_or(kInf)) ||
          (is(Outcome::Miss) && !deep))
        return ok(tally.band);
      return fail("a ball touching the boundary must be Overlapping, Hit at once, or Miss if it never crosses");
    }
  }

  // clear at t = 0: the first contact
  const std::optional<double> tLo = s.firstBelow(tolG), tHi = s.firstBelow(-tolG);
  auto band = [&] {
    std::ostringstream o;
    o.precision(17);
    o << " band [" << tLo.value_or(-1) << ", " << tHi.value_or(-1) << "]";
    return o.str();
  };
  if (tHi && *tHi >= s.horizon()) return fail("test horizon too short");
  if (is(Outcome::Hit)) {
    if (!tLo) return fail("Hit, but the clearance never comes within tolerance of zero");
    const double upper = tHi ? *tHi : s.lastBelow(tolG).value();
    const double slack = 4e-16 * std::max(1.0, got.t);
    if (got.t < *tLo - slack) return fail("Hit earlier than the first contact") << band();
    if (got.t > upper + slack) return fail("Hit later than the first contact") << band();
    return ok(tHi ? tally.hit : tally.band);
  }
  if (is(Outcome::Miss)) {
    if (tHi) return fail("Miss, but the bodies interpenetrate");
    return ok(tLo ? tally.band : tally.miss);
  }
  return fail("a clear start must give Hit or Miss");
}

// Checks a departure kernel (the time the trailing surface leaves a line / plane): the last
// time the clearance is <= 0. vn is the speed across the line; below `still` it does not move.
template <class G, int Grid>
::testing::AssertionResult checkDeparture(const Impact& got, const Sampled<G, Grid>& s, double vn, double still,
                                          double scale, Tally& tally) {
  if (auto c = contractHolds(got); !c) return c;
  if (got.outcome == Outcome::Overlapping || got.outcome == Outcome::Separating)
    return ::testing::AssertionFailure() << "departure gives only Hit or Miss, got " << name(got.outcome);
  auto fail = [&](const char* why) {
    return ::testing::AssertionFailure() << why << ": got " << name(got.outcome) << " t=" << got.t
                                         << "; truth g0=" << s.g0() << " vn=" << vn << " min g=" << s.minimum()
                                         << " horizon=" << s.horizon();
  };
  if (std::abs(vn) <= still) {
    if (got.outcome == Outcome::Miss) return (++tally.miss, ::testing::AssertionSuccess());
    return fail("no motion across the line: never departs");
  }
  if (std::abs(vn) <= 2 * still) return (++tally.band, ::testing::AssertionSuccess());
  const double tolG = 1e-12 * scale;
  const std::optional<double> tA = s.lastBelow(-tolG), tB = s.lastBelow(tolG);
  if (tB && *tB >= s.horizon()) return fail("test horizon too short");
  if (!tB) {
    if (got.outcome == Outcome::Miss) return (++tally.miss, ::testing::AssertionSuccess());
    return fail("never touches the line, cannot depart");
  }
  const double slack = 4e-16 * std::max(1.0, got.t);
  if (tA) {
    if (got.outcome != Outcome::Hit) return fail("crosses the line, must depart");
    if (got.t < *tA - slack || got.t > *tB + slack) return fail("departure time outside the band");
    return (++(got.t == 0.0 ? tally.hitAtZero : tally.hit), ::testing::AssertionSuccess());
  }
  if (got.outcome == Outcome::Miss || got.t <= *tB + slack) return (++tally.band, ::testing::AssertionSuccess());
  return fail("grazing departure too late");
}

// ---- random cases ----------------------------------------------------------------------------

struct Gen {
  std::mt19937_64 rng;
  explicit Gen(unsigned seed) : rng(seed) {}
  double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  double logUni(double lo, double hi) { return std::pow(10.0, uni(lo, hi)); }
  int pick(int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); }
  bool coin() { return rng() & 1; }
  double sign() { return coin() ? 1.0 : -1.0; }
  template <int D>
  Vec<D> box(double h) {
    Vec<D> v;
    for (int i = 0; i < D; ++i) v[i] = uni(-h, h);
    return v;
  }
  template <int D>
  Vec<D> unit() {
    std::normal_distribution<double> n;
    Vec<D> v;
    do {
      for (int i = 0; i < D; ++i) v[i] = n(rng);
    } while (v.norm() < 1e-3);
    return v.normalized();
  }
  // a unit vector perpendicular to u
  template <int D>
  Vec<D> perpendicular(const Vec<D>& u) {
    if constexpr (D == 2) {
      return Vec2(-u.y(), u.x());
    } else {
      return u.cross(unit<3>()).normalized();
    }
  }
  // a small clearance offset around touching: exactly zero, within the slop, or just beyond it
  double touchOffset() {
    static constexpr double offsets[] = {0.0, 1e-13, 5e-10, 1.5e-9, 1e-6};
    return sign() * offsets[pick(5)];
  }
};

// Velocity for a touching start: radial in, radial out, tangential, or random.
template <int D>
Vec<D> touchVelocity(Gen& gen, const Vec<D>& outward) {
  const double s = gen.uni(0.1, 5);
  switch (gen.pick(4)) {
    case 0: return -s * outward;
    case 1: return s * outward;
    case 2: return s * gen.perpendicular<D>(outward);
    default: return gen.box<D>(5);
  }
}

// ---- balls ---------------------------------------------------------------------------------------

template <int D>
void ballsKernel(unsigned seed, bool throughPointWrapper) {
  Gen gen(seed);
  Tally tally;
  for (int k = 0; k < kCases; ++k) {
    double R = gen.uni(0.01, 3);
    Vec<D> p, v;
    const Vec<D> u = gen.unit<D>(), w = gen.perpendicular<D>(u);
    const int family = k % 9;
    switch (family) {
      case 0:  // generic
        p = gen.box<D>(10), v = gen.box<D>(5);
        break;
      case 1:  // aimed with an impact parameter around R
        p = gen.uni(R, 10 + R) * u + gen.uni(0, 1.5 * R) * w, v = -gen.uni(0.1, 5) * u;
        break;
      case 2:  // grazing: impact parameter R (1 +- 10^-k), or exactly R
        p = gen.uni(R, 10 + R) * u + R * (1.0 + (gen.pick(5) ? gen.sign() * gen.logUni(-15, -2) : 0.0)) * w;
        v = -gen.uni(0.1, 5) * u;
        break;
      case 3:  // touching
        p = (R + gen.touchOffset()) * u, v = touchVelocity<D>(gen, u);
        break;
      case 4:  // overlapping, centres possibly coincident
        p = (gen.pick(10) ? gen.uni(0, 0.999) * R : 0.0) * u, v = gen.box<D>(5);
        break;
      case 5:  // at rest relative to each other
        p = gen.box<D>(3), v.setZero();
        break;
      case 6:  // slow: 1e-10 to 1e-3 m/s, aimed
        p = gen.uni(R, 5 + R) * u + gen.uni(0, 1.5 * R) * w, v = -gen.logUni(-10, -3) * u;
        break;
      case 7:  // large coordinates
        R = gen.uni(0.5, 5);
        p = gen.uni(R, 1000) * u + gen.uni(0, 1.5 * R) * w, v = -gen.uni(1, 50) * u + gen.box<D>(1);
        break;
      default:  // tiny radii
        R = gen.logUni(-6, -2);
        p = gen.uni(R, 2) * u + gen.uni(0, 1.5 * R) * w, v = -gen.uni(0.1, 5) * u;
        break;
    }
    Impact got;
    if constexpr (D == 2) {
      if (throughPointWrapper) {
        // circle at c moving with v against a fixed point q: relative position q - c
        const Vec2 c = gen.box<2>(5);
        got = toiCirclePoint(Circle{c, R}, -v, c + p);
        // same geometry: q - c = p, and the point moves at +v relative to the circle
      } else {
        got = toiBalls<2>(p, v, R);
      }
    } else {
      got = toiBalls<D>(p, v, R);
    }
    const double speed = v.norm();
    auto g = [p, v, R](double t) { return (p + v * t).norm() - R; };
    const double T = speed > 0 ? 2.0 * (p.norm() + R + 1.0) / speed : 1.0;
    const Sampled<decltype(g)> s(g, T);
    const double rate0 = p.norm() > 0 ? p.dot(v) / p.norm() : speed;
    const double scale = p.norm() + R + speed * s.argMinimum();
    ::testing::AssertionResult r = ::testing::AssertionSuccess();
    if (speed * speed <= tol::kSpeedSqEpsilon && s.g0() > kSlop) {
      // documented: below the speed epsilon a clear pair is at rest
      r = got.outcome == Outcome::Miss ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << "at rest";
      ++tally.miss;
    } else {
      r = checkFirstContact(got, s, rate0, speed, scale, Semantics::Slop, tally);
    }
    ASSERT_TRUE(r) << "case " << k << " family " << family << std::hexfloat << " p=" << p.transpose()
                   << " v=" << v.transpose() << " R=" << R;
  }
  expectEveryOutcome(tally);
}

TEST(ToiBallsSampled, Circles) { ballsKernel<2>(101, false); }
TEST(ToiBallsSampled, Spheres) { ballsKernel<3>(102, false); }
TEST(ToiBallsSampled, CirclePoint) { ballsKernel<2>(103, true); }

// ---- circle against segment ----------------------------------------------------------------------

double distanceToSegment(const Vec2& x, const Vec2& a, const Vec2& b, Vec2* closest = nullptr) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double u = len2 > 0 ? std::clamp((x - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  const Vec2 q = a + u * d;
  if (closest) *closest = q;
  return (x - q).norm();
}

// A random segment (now and then a degenerate point) and ball radius.
struct SegmentCase {
  Vec2 a, b, dirUnit, nrm;
  double len = 0, r = 0;
};

SegmentCase randomSegment(Gen& gen) {
  SegmentCase sc;
  sc.a = gen.box<2>(5);
  sc.len = gen.pick(20) ? gen.uni(0.1, 6) : 0.0;
  sc.dirUnit = gen.unit<2>();
  sc.b = sc.a + sc.len * sc.dirUnit;
  sc.nrm = Vec2(-sc.dirUnit.y(), sc.dirUnit.x());
  sc.r = gen.uni(0.05, 2);
  return sc;
}

// Aimed near a point on or beyond the segment, or grazing its end points.
void aimAtSegment(Gen& gen, const SegmentCase& sc, bool grazeEnds, Vec2& c, Vec2& v) {
  const Vec2 target = !grazeEnds ? Vec2(sc.a + gen.uni(-0.3, 1.3) * (sc.b - sc.a)) : (gen.coin() ? sc.a : sc.b);
  const Vec2 d = gen.unit<2>();
  const double h = !grazeEnds ? gen.uni(-1.5, 1.5) * sc.r
                              : gen.sign() * sc.r * (1.0 + (gen.pick(5) ? gen.sign() * gen.logUni(-15, -2) : 0.0));
  c = target - gen.uni(sc.r + 0.1, 8) * d + h * Vec2(-d.y(), d.x());
  v = gen.uni(0.1, 5) * d;
}

// The feature reported is the one touched: the circle's centre x at contact projects inside the
// segment for Face, beyond the named end for EndA / EndB (unless at the junction).
::testing::AssertionResult touchedFeature(const SegmentImpact& got, const SegmentCase& sc, const Vec2& x,
                                          int& faceHits, int& endHits) {
  const double u = (x - sc.a).dot(sc.b - sc.a) / (sc.len * sc.len);
  const double margin = 1e-6;
  const SegmentFeature want = u < -margin ? SegmentFeature::EndA : u > 1 + margin ? SegmentFeature::EndB
                                                                                  : SegmentFeature::Face;
  if (std::abs(u) <= margin || std::abs(u - 1) <= margin) return ::testing::AssertionSuccess();
  if (got.feature != want)
    return ::testing::AssertionFailure() << "feature " << static_cast<int>(got.feature) << " but u=" << u;
  ++(want == SegmentFeature::Face ? faceHits : endHits);
  return ::testing::AssertionSuccess();
}

TEST(ToiSegmentSampled, AgainstDenseSampling) {
  Gen gen(201);
  Tally tally;
  int faceHits = 0, endHits = 0;
  for (int k = 0; k < kCases; ++k) {
    const SegmentCase sc = randomSegment(gen);
    const Vec2 a = sc.a, b = sc.b, dirUnit = sc.dirUnit, nrm = sc.nrm;
    const double len = sc.len, r = sc.r;
    Vec2 c, v;
    const int family = k % 9;
    switch (family) {
      case 0:  // generic
        c = gen.box<2>(10), v = gen.box<2>(5);
        break;
      case 1:
      case 2:  // aimed near a point on or beyond the segment; grazing the end points in family 2
        aimAtSegment(gen, sc, family == 2, c, v);
        break;
      case 3: {  // sliding parallel to the segment, at or near clearance r from its line
        static constexpr double offsets[] = {0.0, 1e-12, -1e-12, 1e-6, -1e-6, -0.5, -1.0};
        const double off = offsets[gen.pick(7)];
        c = a - gen.uni(r + 0.1, 3) * dirUnit + gen.sign() * (r * (1.0 + off)) * nrm;
        v = gen.uni(0.1, 5) * dirUnit * (gen.pick(4) ? 1.0 : -1.0);
        break;
      }
      case 4: {  // touching the face
        const Vec2 q = a + gen.uni(0.05, 0.95) * (b - a);
        const Vec2 out = gen.sign() * nrm;
        c = q + (r + gen.touchOffset()) * out;
        v = touchVelocity<2>(gen, out);
        if (gen.pick(4) == 0) v = gen.uni(0.1, 5) * gen.sign() * dirUnit;  // sliding along it
        break;
      }
      case 5: {  // touching an end point from outside the face's slab
        const Vec2 e = gen.coin() ? a : b;
        const Vec2 away = (e == a ? -1.0 : 1.0) * dirUnit;
        Vec2 out = gen.unit<2>();
        if (out.dot(away) < 0) out = -out;
        c = e + (r + gen.touchOffset()) * out;
        v = touchVelocity<2>(gen, out);
        break;
      }
      case 6:  // overlapping
        c = a + gen.uni(0, 1) * (b - a) + gen.uni(0, 0.999) * r * gen.unit<2>(), v = gen.box<2>(5);
        break;
      case 7:  // at rest
        c = gen.box<2>(6), v.setZero();
        break;
      default:  // slow
        c = a + gen.uni(0, 1) * (b - a) + gen.uni(r, 3 + r) * gen.unit<2>();
        v = gen.logUni(-10, -3) * (a + gen.uni(0, 1) * (b - a) - c).normalized();
        break;
    }
    const Segment seg{a, b};
    const SegmentImpact got = toiCircleSegment(Circle{c, r}, v, seg);
    const double speed = v.norm();
    auto g = [a, b, c, v, r](double t) { return distanceToSegment(c + v * t, a, b) - r; };
    const double T = speed > 0 ? 2.0 * ((c - a).norm() + len + r + 1.0) / speed : 1.0;
    const Sampled<decltype(g)> s(g, T);
    Vec2 q0;
    const double d0 = distanceToSegment(c, a, b, &q0);
    const double rate0 = d0 > 0 ? (c - q0).dot(v) / d0 : 0.0;  // centre on the segment: undefined
    const double scale = c.norm() + a.norm() + len + r + speed * s.argMinimum();
    ::testing::AssertionResult res = ::testing::AssertionSuccess();
    if (speed * speed <= tol::kSpeedSqEpsilon && s.g0() > kSlop) {
      res = got.impact.outcome == Outcome::Miss ? res : ::testing::AssertionFailure() << "at rest";
      ++tally.miss;
    } else {
      res = checkFirstContact(got.impact, s, rate0, speed, scale, Semantics::Slop, tally);
    }
    if (res && got.impact.outcome == Outcome::Hit && got.impact.t > 0 && len > 0)
      res = touchedFeature(got, sc, c + v * got.impact.t, faceHits, endHits);
    ASSERT_TRUE(res) << "case " << k << " family " << family << std::hexfloat << " a=" << a.transpose()
                     << " b=" << b.transpose() << " c=" << c.transpose() << " v=" << v.transpose() << " r=" << r;
  }
  expectEveryOutcome(tally);
  EXPECT_GT(faceHits, kCases / 20);
  EXPECT_GT(endHits, kCases / 20);
}

// ---- lines and planes ------------------------------------------------------------------------------

// A random plane-like setup shared by the line, axis-plane and plane kernels, in terms of the
// signed distance d(t) = d0 + vn t of the centre from the plane, plus a ball and its motion.
template <int D>
struct PlaneCase {
  Vec<D> c, v, n;  // centre, velocity, unit normal
  double offset = 0, r = 0;
};

// Builds a case for a plane with unit normal n through offset (n.x == offset).
template <int D>
PlaneCase<D> planeCase(Gen& gen, int family, const Vec<D>& n, double offset) {
  PlaneCase<D> pc;
  pc.n = n, pc.offset = offset;
  pc.r = gen.uni(0.01, 2);
  const Vec<D> onPlane = n * offset + [&] {
    Vec<D> t = gen.box<D>(5);
    return Vec<D>(t - n * n.dot(t));
  }();
  const Vec<D> side = gen.sign() * n;
  switch (family) {
    case 0:  // generic
      pc.c = onPlane + gen.uni(-8, 8) * n, pc.v = gen.box<D>(5);
      break;
    case 1:  // moving parallel to the plane
      pc.c = onPlane + gen.uni(-3, 3) * n, pc.v = gen.uni(0.1, 5) * gen.perpendicular<D>(n);
      break;
    case 2:  // touching
      pc.c = onPlane + (pc.r + gen.touchOffset()) * side, pc.v = touchVelocity<D>(gen, side);
      break;
    case 3:  // overlapping; centre on the plane now and then
      pc.c = onPlane + (gen.pick(8) ? gen.uni(0, 0.999) * pc.r : 0.0) * side, pc.v = gen.box<D>(5);
      break;
    case 4:  // at rest
      pc.c = onPlane + gen.uni(-3, 3) * n, pc.v.setZero();
      break;
    case 5:  // slow, towards the plane
      pc.c = onPlane + gen.uni(pc.r, 3) * side, pc.v = -gen.logUni(-10, -3) * side + gen.logUni(-12, -4) * gen.box<D>(1);
      break;
    default:  // approaching at an angle
      pc.c = onPlane + gen.uni(pc.r, 8) * side, pc.v = -gen.uni(0.1, 5) * side + gen.box<D>(3);
      break;
  }
  return pc;
}

// A plane kernel against the sampled clearance |n.x(t) - offset| - r.
enum class PlaneKernel { Plane, LineIntersect, LineDepart, AxisEnter, AxisLeave };

template <int D>
void planeKernel(PlaneKernel kind, unsigned seed) {
  Gen gen(seed);
  Tally tally;
  for (int k = 0; k < kCases; ++k) {
    const int family = k % 7;
    Vec<D> n;
    int axis = 0;
    double offset = gen.uni(-5, 5);
    Segment line{};
    if (kind == PlaneKernel::AxisEnter || kind == PlaneKernel::AxisLeave) {
      axis = gen.pick(D);
      n = Vec<D>::Unit(axis);
    } else if (kind == PlaneKernel::Plane) {
      n = gen.pick(4) ? gen.unit<D>() : Vec<D>::Unit(gen.pick(D));  // axis-aligned now and then
    }
    if constexpr (D == 2) {
      if (kind == PlaneKernel::LineIntersect || kind == PlaneKernel::LineDepart) {
        // the kernels take the line through a segment; its normal is computed from it
        line.a = gen.box<2>(5);
        line.b = line.a + gen.uni(0.1, 6) * gen.unit<2>();
        n = leftNormal(line.b - line.a);
        offset = n.dot(line.a);
      }
    }
    PlaneCase<D> pc = planeCase<D>(gen, family, n, offset);
    if constexpr (D == 2) {
      if ((kind == PlaneKernel::LineIntersect || kind == PlaneKernel::LineDepart) && family == 1)
        pc.v = gen.uni(0.1, 5) * (line.b - line.a).normalized();  // parallel as the caller would build it
    }
    Impact got;
    const Ball<D> ball{pc.c, pc.r};
    switch (kind) {
      case PlaneKernel::Plane: got = toiBallPlane<D>(ball, pc.v, n, offset); break;
      case PlaneKernel::AxisEnter: got = toiBallAxisPlaneEnter<D>(ball, pc.v, axis, offset); break;
      case PlaneKernel::AxisLeave: got = toiBallAxisPlaneLeave<D>(ball, pc.v, axis, offset); break;
      case PlaneKernel::LineIntersect:
      case PlaneKernel::LineDepart:
        if constexpr (D == 2) {
          got = kind == PlaneKernel::LineIntersect ? toiCircleLineIntersect(Circle{pc.c, pc.r}, pc.v, line)
                                                   : toiCircleLineDepart(Circle{pc.c, pc.r}, pc.v, line);
        }
        break;
    }
    const Vec<D> c = pc.c, v = pc.v;
    const double r = pc.r;
    auto g = [c, v, n, offset, r](double t) { return std::abs(n.dot(c + v * t) - offset) - r; };
    const double d0 = n.dot(c) - offset, vn = n.dot(v), speed = v.norm();
    // every contact and departure happens while the centre is within r + |d0| + 1 of the plane
    // Motion parallel up to the rounding of n.v (|vn| <= 1e-12 |v|) would put a crossing ~1e12 s
    // out, where the sampled positions themselves are meaningless: sample a horizon of 1000
    // crossing-free lengths instead, and accept a Miss or a hit beyond every horizon.
    const bool parallel = speed > 0 && std::abs(vn) <= 1e-12 * speed;
    const double T = parallel ? 1e3 * (std::abs(d0) + r + 1.0) / speed
                     : std::abs(vn) > 0 ? 2.0 * (std::abs(d0) + r + 1.0) / std::abs(vn) : 1.0;
    const Sampled<decltype(g)> s(g, T);
    ::testing::AssertionResult res = ::testing::AssertionSuccess();
    if (kind == PlaneKernel::LineDepart || kind == PlaneKernel::AxisLeave) {
      const double tLast = s.lastBelow(0.0).value_or(0.0);
      const double scale = c.norm() + std::abs(offset) + r + speed * tLast;
      // LineDepart documents the speed epsilon; the axis kernel stops only at exactly zero
      const double still = kind == PlaneKernel::LineDepart ? std::sqrt(tol::kSpeedSqEpsilon) : 0.0;
      res = checkDeparture(got, s, vn, still, scale, tally);
    } else {
      // centre exactly on the plane: which way is "approaching" is undefined
      const double rate0 = d0 > 0 ? vn : d0 < 0 ? -vn : 0.0;
      const double scale = c.norm() + std::abs(offset) + r + (parallel ? 0.0 : speed * s.argMinimum());
      const Semantics sem = kind == PlaneKernel::Plane ? Semantics::Slop : Semantics::Boundary;
      const double clear = sem == Semantics::Slop ? kSlop : 1e-12 * scale;
      if (parallel && s.g0() > clear) {
        if (got.outcome != Outcome::Miss && !(got.outcome == Outcome::Hit && got.t * speed >= 1e6 * (std::abs(d0) + r)))
          res = ::testing::AssertionFailure() << "parallel motion: " << name(got.outcome) << " at t=" << got.t;
        ++tally.miss;
      } else {
        res = checkFirstContact(got, s, rate0, speed, scale, sem, tally);
      }
    }
    ASSERT_TRUE(res) << "case " << k << " family " << family << std::hexfloat << " c=" << c.transpose()
                     << " v=" << v.transpose() << " n=" << n.transpose() << " offset=" << offset << " r=" << r;
  }
  const bool departure = kind == PlaneKernel::LineDepart || kind == PlaneKernel::AxisLeave;
  EXPECT_GT(tally.hit, kCases / 10);
  EXPECT_GT(tally.miss, kCases / 10);
  if (!departure) {
    EXPECT_GT(tally.overlapping, 1000);
  }
  if (kind == PlaneKernel::Plane) {
    EXPECT_GT(tally.hitAtZero, 500);
    EXPECT_GT(tally.separating, 1000);
  }
  EXPECT_LT(tally.band, kCases / 5);  // grazing and tangential families sit in the band by design
  EXPECT_EQ(tally.total(), kCases);
}

TEST(ToiPlaneSampled, BallPlane2D) { planeKernel<2>(PlaneKernel::Plane, 301); }
TEST(ToiPlaneSampled, BallPlane3D) { planeKernel<3>(PlaneKernel::Plane, 302); }
TEST(ToiPlaneSampled, LineIntersect) { planeKernel<2>(PlaneKernel::LineIntersect, 303); }
TEST(ToiPlaneSampled, LineDepart) { planeKernel<2>(PlaneKernel::LineDepart, 304); }
TEST(ToiPlaneSampled, AxisPlaneEnter2D) { planeKernel<2>(PlaneKernel::AxisEnter, 305); }
TEST(ToiPlaneSampled, AxisPlaneEnter3D) { planeKernel<3>(PlaneKernel::AxisEnter, 306); }
TEST(ToiPlaneSampled, AxisPlaneLeave2D) { planeKernel<2>(PlaneKernel::AxisLeave, 307); }
TEST(ToiPlaneSampled, AxisPlaneLeave3D) { planeKernel<3>(PlaneKernel::AxisLeave, 308); }

// ---- decelerating (quadratic) paths ---------------------------------------------------------------
//
// The same truth on p(t) = p + v t + a t^2 / 2 over [0, tMax]. The clearance is no longer convex
// (a curving path can pass a ball, turn and come back), so it is sampled on a finer grid and every
// local minimum is refined. Most cases are what the simulator builds: each ball decelerating
// against its own velocity, until the first of them stops; some take an arbitrary acceleration.

constexpr int kFineGrid = 2048;

// A ball's deceleration: none now and then, else a rolling resistance of 0.01 to 3 m/s^2.
template <int D>
Vec<D> decelerationOf(Gen& gen, const Vec<D>& v, double& stop) {
  const double mu = gen.pick(4) ? gen.logUni(-2, 0.5) : 0.0;
  const double speed = v.norm();
  if (mu == 0.0 || speed == 0.0) return Vec<D>::Zero();
  stop = std::min(stop, speed / mu);
  return -mu * v / speed;
}

// Relative motion of ball B seen from ball A, both decelerating: v_rel and a_rel from the two
// balls' own velocities; tMax is the first stop (or a random horizon if neither decelerates).
template <int D>
void twoDeceleratingBalls(Gen& gen, const Vec<D>& vRel, Vec<D>& a, double& tMax) {
  const Vec<D> va = gen.box<D>(3), vb = va + vRel;
  double stop = std::numeric_limits<double>::infinity();
  a = decelerationOf<D>(gen, vb, stop) - decelerationOf<D>(gen, va, stop);
  tMax = stop < std::numeric_limits<double>::infinity() ? stop : gen.uni(0.5, 20);
}

// Collision (toiBallsAccelerated, slop semantics) or entry into the closed ball
// (toiBallsEntryAccelerated, boundary semantics: inside now is Overlapping, a graze is a Hit).
enum class BallsAccelerated { Collision, Entry };

template <int D>
void ballsAcceleratedKernel(unsigned seed, BallsAccelerated kernel = BallsAccelerated::Collision) {
  Gen gen(seed);
  Tally tally;
  for (int k = 0; k < kCases; ++k) {
    double R = gen.uni(0.01, 3);
    Vec<D> p, v, a = Vec<D>::Zero();
    double tMax = 1.0;
    const Vec<D> u = gen.unit<D>(), w = gen.perpendicular<D>(u);
    const int family = k % 8;
    switch (family) {
      case 0:  // generic
        p = gen.box<D>(10), v = gen.box<D>(5);
        twoDeceleratingBalls<D>(gen, v, a, tMax);
        break;
      case 1:  // aimed with an impact parameter around R
        p = gen.uni(R, 10 + R) * u + gen.uni(0, 1.5 * R) * w, v = -gen.uni(0.1, 5) * u;
        twoDeceleratingBalls<D>(gen, v, a, tMax);
        break;
      case 2:  // grazing aim
        p = gen.uni(R, 10 + R) * u + R * (1.0 + (gen.pick(5) ? gen.sign() * gen.logUni(-15, -2) : 0.0)) * w;
        v = -gen.uni(0.1, 5) * u;
        twoDeceleratingBalls<D>(gen, v, a, tMax);
        break;
      case 3:  // touching
        p = (R + gen.touchOffset()) * u, v = touchVelocity<D>(gen, u);
        twoDeceleratingBalls<D>(gen, v, a, tMax);
        break;
      case 4:  // overlapping
        p = (gen.pick(10) ? gen.uni(0, 0.999) * R : 0.0) * u, v = gen.box<D>(5);
        twoDeceleratingBalls<D>(gen, v, a, tMax);
        break;
      case 5: {  // head-on at a ball at rest, stopping just short of it or just reaching it
        const double gap = gen.uni(0.1, 8), speed = gen.uni(0.1, 5);
        const double reach = gap * (1.0 + (gen.pick(5) ? gen.sign() * gen.logUni(-12, -1) : 0.0));
        const double mu = speed * speed / (2.0 * reach);
        p = (gap + R) * u + gen.uni(0, 0.5 * R) * w * (gen.pick(2) ? 1.0 : 0.0);
        v = -speed * u, a = mu * u;  // the moving ball's deceleration, seen from it: B accelerates towards +u
        tMax = speed / mu;
        break;
      }
      case 6:  // any acceleration: curving paths that pass, turn and come back
        p = gen.box<D>(6), v = gen.box<D>(4), a = gen.box<D>(4), tMax = gen.uni(0.1, 10);
        break;
      default:  // tiny radii, slow starts
        R = gen.logUni(-6, -2);
        p = gen.uni(R, 2) * u + gen.uni(0, 1.5 * R) * w, v = -gen.logUni(-4, 0.5) * u;
        twoDeceleratingBalls<D>(gen, v, a, tMax);
        break;
    }
    const bool entry = kernel == BallsAccelerated::Entry;
    const Impact got =
        entry ? toiBallsEntryAccelerated<D>(p, v, a, R, tMax) : toiBallsAccelerated<D>(p, v, a, R, tMax);
    auto g = [p, v, a, R](double t) { return (p + v * t + (0.5 * t * t) * a).norm() - R; };
    const Sampled<decltype(g), kFineGrid> s(g, tMax);
    const double speed = v.norm();
    const double rate0 = p.norm() > 0 ? p.dot(v) / p.norm() : speed;
    const double scale = p.norm() + R + speed * tMax + a.norm() * tMax * tMax;
    // entry counts a graze: a path whose closest approach is within this of the surface may go
    // either way (the entry time moves with the square root of the depth; as the highway's
    // kernels_test), and a hit must then come that close
    const double graze = 1e-9 * scale;
    if (entry && s.g0() > graze && std::abs(s.minimum()) <= graze) {
      ++tally.band;
      const bool ok = got.outcome == Outcome::Miss || (got.outcome == Outcome::Hit && g(got.t) <= graze);
      ASSERT_TRUE(ok) << "a graze must Miss or Hit within " << graze << ": got " << name(got.outcome)
                      << " t=" << got.t << " case " << k << " family " << family;
      continue;
    }
    const ::testing::AssertionResult r =
        checkFirstContact(got, s, rate0, speed, scale, entry ? Semantics::Boundary : Semantics::Slop, tally);
    ASSERT_TRUE(r) << "case " << k << " family " << family << std::hexfloat << " p=" << p.transpose()
                   << " v=" << v.transpose() << " a=" << a.transpose() << " R=" << R << " tMax=" << tMax;
  }
  if (kernel == BallsAccelerated::Collision) return expectEveryOutcome(tally);
  // entry knows no Separating and no touching Hit at 0: inside the closed ball is Overlapping
  EXPECT_GT(tally.hit, kCases / 10);
  EXPECT_GT(tally.miss, kCases / 10);
  EXPECT_GT(tally.overlapping, 1000);
  EXPECT_LT(tally.band, kCases / 5);
  EXPECT_EQ(tally.total(), kCases);
}

TEST(ToiAcceleratedSampled, Circles) { ballsAcceleratedKernel<2>(401); }
TEST(ToiAcceleratedSampled, Spheres) { ballsAcceleratedKernel<3>(402); }
TEST(ToiAcceleratedSampled, CircleEntry) { ballsAcceleratedKernel<2>(405, BallsAccelerated::Entry); }
TEST(ToiAcceleratedSampled, SphereEntry) { ballsAcceleratedKernel<3>(406, BallsAccelerated::Entry); }

template <int D>
void planeAcceleratedKernel(unsigned seed) {
  Gen gen(seed);
  Tally tally;
  for (int k = 0; k < kCases; ++k) {
    const int family = k % 8;
    const Vec<D> n = gen.pick(4) ? gen.unit<D>() : Vec<D>::Unit(gen.pick(D));
    const double offset = gen.uni(-5, 5);
    PlaneCase<D> pc = planeCase<D>(gen, std::min(family, 6), n, offset);
    Vec<D> a = Vec<D>::Zero();
    double stop = std::numeric_limits<double>::infinity();
    if (family == 7) {  // towards the plane, stopping just short of it or just reaching it
      const double side = (pc.c.dot(n) - offset) >= 0 ? 1.0 : -1.0;
      pc.c = pc.c + (gen.uni(pc.r + 0.1, 8) - std::abs(pc.c.dot(n) - offset)) * side * n;
      const double gap = std::abs(pc.c.dot(n) - offset) - pc.r, speed = gen.uni(0.1, 5);
      const double reach = gap * (1.0 + (gen.pick(5) ? gen.sign() * gen.logUni(-12, -1) : 0.0));
      pc.v = -speed * side * n;
      a = (speed * speed / (2.0 * reach)) * side * n;
      stop = 2.0 * reach / speed;
    } else if (family == 6 && gen.coin()) {  // any acceleration
      a = gen.box<D>(4), stop = gen.uni(0.1, 10);
    } else {
      a = decelerationOf<D>(gen, pc.v, stop);
    }
    const double tMax = stop < std::numeric_limits<double>::infinity() ? stop : gen.uni(0.5, 20);
    const Vec<D> c = pc.c, v = pc.v;
    const double r = pc.r;
    const Impact got = toiBallPlaneAccelerated<D>(Ball<D>{c, r}, v, a, n, offset, tMax);
    auto g = [c, v, a, n, offset, r](double t) { return std::abs(n.dot(c + v * t + (0.5 * t * t) * a) - offset) - r; };
    const Sampled<decltype(g), kFineGrid> s(g, tMax);
    const double d0 = n.dot(c) - offset, vn = n.dot(v), speed = v.norm();
    const double rate0 = d0 > 0 ? vn : d0 < 0 ? -vn : 0.0;
    const double scale = c.norm() + std::abs(offset) + r + speed * tMax + a.norm() * tMax * tMax;
    const ::testing::AssertionResult res = checkFirstContact(got, s, rate0, speed, scale, Semantics::Slop, tally);
    ASSERT_TRUE(res) << "case " << k << " family " << family << std::hexfloat << " c=" << c.transpose()
                     << " v=" << v.transpose() << " a=" << a.transpose() << " n=" << n.transpose()
                     << " offset=" << offset << " r=" << r << " tMax=" << tMax;
  }
  expectEveryOutcome(tally);
}

TEST(ToiAcceleratedSampled, BallPlane2D) { planeAcceleratedKernel<2>(403); }
TEST(ToiAcceleratedSampled, BallPlane3D) { planeAcceleratedKernel<3>(404); }

TEST(ToiAcceleratedSampled, CircleSegment) {
  Gen gen(405);
  Tally tally;
  int faceHits = 0, endHits = 0;
  for (int k = 0; k < kCases; ++k) {
    const SegmentCase sc = randomSegment(gen);
    const Vec2 a = sc.a, b = sc.b, dirUnit = sc.dirUnit, nrm = sc.nrm;
    const double len = sc.len, r = sc.r;
    Vec2 c, v, acc = Vec2::Zero();
    double stop = std::numeric_limits<double>::infinity();
    const int family = k % 8;
    switch (family) {
      case 0:  // generic
        c = gen.box<2>(10), v = gen.box<2>(5);
        break;
      case 1:
      case 2:  // aimed near a point on or beyond the segment; grazing the end points in family 2
        aimAtSegment(gen, sc, family == 2, c, v);
        break;
      case 3: {  // touching the face or an end
        const bool face = gen.coin();
        const Vec2 q = face ? Vec2(a + gen.uni(0.05, 0.95) * (b - a)) : (gen.coin() ? a : b);
        Vec2 out = face ? Vec2(gen.sign() * nrm) : gen.unit<2>();
        if (!face && out.dot((q == a ? -1.0 : 1.0) * dirUnit) < 0) out = -out;
        c = q + (r + gen.touchOffset()) * out;
        v = touchVelocity<2>(gen, out);
        break;
      }
      case 4:  // overlapping
        c = a + gen.uni(0, 1) * (b - a) + gen.uni(0, 0.999) * r * gen.unit<2>(), v = gen.box<2>(5);
        break;
      case 5: {  // straight at the face, stopping just short of it or just reaching it
        const Vec2 q = a + gen.uni(0.05, 0.95) * (b - a);
        const Vec2 out = gen.sign() * (len > 0 ? nrm : gen.unit<2>());
        const double gap = gen.uni(0.1, 8), speed = gen.uni(0.1, 5);
        const double reach = gap * (1.0 + (gen.pick(5) ? gen.sign() * gen.logUni(-12, -1) : 0.0));
        c = q + (r + gap) * out, v = -speed * out;
        acc = (speed * speed / (2.0 * reach)) * out;
        stop = 2.0 * reach / speed;
        break;
      }
      case 6:  // any acceleration
        c = gen.box<2>(8), v = gen.box<2>(4), acc = gen.box<2>(4), stop = gen.uni(0.1, 10);
        break;
      default:  // sliding along the segment's line at about clearance r, decelerating
        c = a - gen.uni(r + 0.1, 3) * dirUnit + gen.sign() * (r * (1.0 + gen.uni(-0.5, 0.01))) * nrm;
        v = gen.uni(0.1, 5) * dirUnit;
        break;
    }
    if (family != 5 && family != 6) acc = decelerationOf<2>(gen, v, stop);
    const double tMax = stop < std::numeric_limits<double>::infinity() ? stop : gen.uni(0.5, 20);
    const Segment seg{a, b};
    const SegmentImpact got = toiCircleSegmentAccelerated(Circle{c, r}, v, acc, seg, tMax);
    auto g = [a, b, c, v, acc, r](double t) { return distanceToSegment(c + v * t + (0.5 * t * t) * acc, a, b) - r; };
    const Sampled<decltype(g), kFineGrid> s(g, tMax);
    Vec2 q0;
    const double d0 = distanceToSegment(c, a, b, &q0);
    const double speed = v.norm();
    const double rate0 = d0 > 0 ? (c - q0).dot(v) / d0 : 0.0;
    const double scale = c.norm() + a.norm() + len + r + speed * tMax + acc.norm() * tMax * tMax;
    ::testing::AssertionResult res = checkFirstContact(got.impact, s, rate0, speed, scale, Semantics::Slop, tally);
    if (res && got.impact.outcome == Outcome::Hit && got.impact.t > 0 && len > 0) {
      const double t = got.impact.t;
      res = touchedFeature(got, sc, c + v * t + (0.5 * t * t) * acc, faceHits, endHits);
    }
    ASSERT_TRUE(res) << "case " << k << " family " << family << std::hexfloat << " a=" << a.transpose()
                     << " b=" << b.transpose() << " c=" << c.transpose() << " v=" << v.transpose()
                     << " acc=" << acc.transpose() << " r=" << r << " tMax=" << tMax;
  }
  expectEveryOutcome(tally);
  EXPECT_GT(faceHits, kCases / 20);
  EXPECT_GT(endHits, kCases / 20);
}

// ---- hand-checked cases (analytic) ---------------------------------------------------------------

TEST(Impact, EarliestActsFirst) {
  const Impact now{Outcome::Overlapping, 0.0}, at0{Outcome::Hit, 0.0}, at1{Outcome::Hit, 1.0}, at2{Outcome::Hit, 2.0};
  const Impact apart{Outcome::Separating, kInf}, none{};
  // an overlap acts at once, before a hit at 0; hits by time; a miss or separation never acts
  EXPECT_EQ(earliest(at0, now).outcome, Outcome::Overlapping);
  EXPECT_EQ(earliest(at2, at1).t, 1.0);
  EXPECT_EQ(earliest(at1, at2).t, 1.0);
  EXPECT_EQ(earliest(none, at2).t, 2.0);
  EXPECT_EQ(earliest(at2, apart).t, 2.0);
  EXPECT_EQ(earliest(none, apart).outcome, Outcome::Separating);
  EXPECT_EQ(earliest(none, none).outcome, Outcome::Miss);
  // a tie keeps the first
  const Impact at1b{Outcome::Hit, 1.0};
  EXPECT_FALSE(actsBefore(at1b, at1));
  EXPECT_FALSE(actsBefore(at1, at1b));
}

TEST(Impact, DelayedToALaterPiece) {
  // a piece starting 2 s from now: its hit 1 s in is 3 s from now, its overlap at the start a hit at 2 s
  const Impact hit = delayed({Outcome::Hit, 1.0}, 2.0), now = delayed({Outcome::Overlapping, 0.0}, 2.0);
  EXPECT_EQ(hit.outcome, Outcome::Hit);
  EXPECT_EQ(hit.t, 3.0);
  EXPECT_EQ(now.outcome, Outcome::Hit);
  EXPECT_EQ(now.t, 2.0);
  // the first piece's overlap is one now; what does not act stays as it is
  EXPECT_EQ(delayed({Outcome::Overlapping, 0.0}, 0.0).outcome, Outcome::Overlapping);
  EXPECT_EQ(delayed(Impact{}, 2.0).outcome, Outcome::Miss);
  EXPECT_EQ(delayed(Impact{}, 2.0).t, kInf);
}

TEST(ToiBalls, HeadOnAnalytic) {
  // two unit circles 10 m apart closing at 2 m/s: gap 8 m -> t = 4 s
  const Impact i = toiCircleCircle({{0, 0}, 1}, {1, 0}, {{10, 0}, 1}, {-1, 0});
  ASSERT_EQ(i.outcome, Outcome::Hit);
  EXPECT_NEAR(i.t, 4.0, 1e-15);
}

TEST(ToiBalls, SeparatingAndOverlapping) {
  EXPECT_EQ(toiCircleCircle({{0, 0}, 1}, {-1, 0}, {{1.5, 0}, 1}, {1, 0}).outcome, Outcome::Separating);
  EXPECT_EQ(toiCircleCircle({{0, 0}, 1}, {1, 0}, {{1.5, 0}, 1}, {-1, 0}).outcome, Outcome::Overlapping);
  EXPECT_EQ(toiCircleCircle({{0, 0}, 1}, {0, 1}, {{5, 0}, 1}, {0, 1}).outcome, Outcome::Miss);
}

TEST(ToiBalls, SphereOffsetAnalytic) {
  // relative path along x at height 1 towards a sphere pair with radius sum 2: contact when
  // (5 - t)^2 + 1 = 4, t = 5 - sqrt(3)
  const Impact i = toiSphereSphere({{0, 0, 0}, 1.5}, {0, 0, 0}, {{5, 1, 0}, 0.5}, {-1, 0, 0});
  ASSERT_EQ(i.outcome, Outcome::Hit);
  EXPECT_NEAR(i.t, 5.0 - std::sqrt(3.0), 1e-14);
}

TEST(ToiBalls, FarApartSmallRadiiKeepFullPrecision) {
  // Regression: the discriminant as b^2 - a c cancelled b^2 against a |p|^2, so a pair 1e5 radii
  // apart lost ~10 digits of the hit time (contact placed 1e-8 m off here). Truths from 50-digit
  // arithmetic on the same double inputs.
  Impact i = toiBalls<2>(Vec2(1000.0, 0.0005), Vec2(-3.0, 0.0), 0.001);
  ASSERT_EQ(i.outcome, Outcome::Hit);
  EXPECT_NEAR(i.t, 333.33304465819873852, 1e-15 * 333.3);
  i = toiBalls<2>(Vec2(0x1.7c269e75abb38p-1, -0x1.08c616c830acp+0), Vec2(-0x1.af9cfa0f22403p+0, 0x1.2c9ed1a970c46p+1),
                  0x1.17afaadb15abap-17);
  ASSERT_EQ(i.outcome, Outcome::Hit);
  EXPECT_NEAR(i.t, 0.44037879353478084415, 4e-16);
}

TEST(ToiSegment, EmbeddedBallMovingOutOfTheFaceIsSeparating) {
  // Regression: with the ball overlapping the face, the end point it moves towards was reported
  // as Overlapping (resolve now), or as struck later, though the ball is leaving the segment.
  const Segment s{{0, 0}, {1, 0}};
  // the end point b lies inside the circle and the centre moves towards it, but away from the face
  SegmentImpact r = toiCircleSegment({{0.9, 0.3}, 0.5}, {1.0, 0.2}, s);
  EXPECT_EQ(r.impact.outcome, Outcome::Separating);
  EXPECT_EQ(r.feature, SegmentFeature::Face);
  // end point b outside the circle now, reached later, while the ball leaves the face it overlaps
  r = toiCircleSegment({{0.2, 0.3}, 0.5}, {2.0, 0.1}, s);
  EXPECT_EQ(r.impact.outcome, Outcome::Separating);
  // the same ball approaching the face is overlapping
  r = toiCircleSegment({{0.2, 0.3}, 0.5}, {2.0, -0.1}, s);
  EXPECT_EQ(r.impact.outcome, Outcome::Overlapping);
  EXPECT_EQ(r.feature, SegmentFeature::Face);
}

TEST(ToiSegment, EndpointStrikeIsPredicted) {
  // the report's Limitation 1: a ball passing beyond the segment's end strikes the end point
  const Segment s{{0, 0}, {1, 0}};
  const SegmentImpact r = toiCircleSegment({{1.5, 2}, 1}, {0, -1}, s);
  ASSERT_EQ(r.impact.outcome, Outcome::Hit);
  EXPECT_EQ(r.feature, SegmentFeature::EndB);
  // contact when the distance from (1.5, 2 - t) to (1, 0) is 1: (2 - t)^2 = 0.75
  EXPECT_NEAR(r.impact.t, 2.0 - std::sqrt(0.75), 1e-14);
}

TEST(ToiSegment, FaceHit) {
  const SegmentImpact r = toiCircleSegment({{0.5, 3}, 0.5}, {0, -2}, Segment{{0, 0}, {1, 0}});
  ASSERT_EQ(r.impact.outcome, Outcome::Hit);
  EXPECT_EQ(r.feature, SegmentFeature::Face);
  EXPECT_NEAR(r.impact.t, 1.25, 1e-15);
}

TEST(ToiSegment, SlidingAlongTheLineHitsTheEndHeadOn) {
  const SegmentImpact r = toiCircleSegment({{-3, 0}, 0.5}, {2, 0}, Segment{{0, 0}, {1, 0}});
  ASSERT_EQ(r.impact.outcome, Outcome::Hit);
  EXPECT_EQ(r.feature, SegmentFeature::EndA);
  EXPECT_NEAR(r.impact.t, 1.25, 1e-15);
}

TEST(ToiLine, IntersectAndDepart) {
  const Segment line{{0, 0}, {0, 1}};  // the y axis
  const Circle c{{-3, 0}, 1};
  EXPECT_NEAR(toiCircleLineIntersect(c, {1, 0}, line).t, 2.0, 1e-15);
  EXPECT_NEAR(toiCircleLineDepart(c, {1, 0}, line).t, 4.0, 1e-15);
  EXPECT_EQ(toiCircleLineIntersect(c, {-1, 0}, line).outcome, Outcome::Miss);
  EXPECT_EQ(toiCircleLineIntersect(c, {0, 1}, line).outcome, Outcome::Miss);  // parallel
  EXPECT_EQ(toiCircleLineDepart(c, {0, 1}, line).outcome, Outcome::Miss);
}

TEST(ToiPlane, SphereAxisPlane) {
  const Ball<3> b{{0, 0, 0}, 0.5};
  EXPECT_NEAR(toiBallAxisPlaneEnter<3>(b, {0, 0, 2}, 2, 1.5).t, 0.5, 1e-15);
  EXPECT_NEAR(toiBallAxisPlaneLeave<3>(b, {0, 0, 2}, 2, 1.5).t, 1.0, 1e-15);
}

}  // namespace
}  // namespace st
