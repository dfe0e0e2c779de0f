#include <sthighway/detector.hpp>

#include <algorithm>
#include <cmath>

#include <stcore/box2.hpp>
#include <stcore/toi.hpp>

#include <sthighway/tolerances.hpp>

#include "car_shape.hpp"
#include "kernels.hpp"

namespace st::highway {

namespace detail {
namespace {

// A point given in a body's frame, as a world offset from its centre.
Vec2 toWorld(const Body& b, double x, double y) { return x * b.axis + y * normalOf(b.axis); }

// A car's own motion as a kernel track: constant velocity, or its longitudinal acceleration
// (motionAcceleration: its own, braking to a stop line) until it stops (it does not reverse).
Track trackOf(const Body& b, MotionModel motion) {
  Track t;
  t.p = b.position;
  t.v = b.velocity;
  const double acc = motionAcceleration(b, motion);
  if (std::abs(acc) <= tol::kAccelerationEpsilon) return t;
  // longitudinal speed u changes at rate acc until it reaches zero; cars do not reverse
  const double u = b.velocity.dot(b.axis);
  if (u * acc < 0.0) {
    t.a = acc * b.axis;
    t.stop = -u / acc;
    t.vAfter = b.velocity - u * b.axis;
  } else if (u >= 0.0 && acc > 0.0) {
    t.a = acc * b.axis;  // speeding up forwards; a negative acceleration at rest does not reverse
  }
  return t;
}

// relativePieces of two bodies' tracks; at constant velocity directly (the one piece it gives).
int bodyPieces(const Body& ego, const Body& foe, MotionModel motion, double horizon, std::array<Piece, 3>& out) {
  if (motion == MotionModel::ConstantVelocity && !(ego.stopAcceleration < 0.0) && !(foe.stopAcceleration < 0.0)) {
    out[0] = Piece{foe.position - ego.position, foe.velocity - ego.velocity, Vec2::Zero(), 0.0, horizon};
    return 1;
  }
  return relativePieces(trackOf(ego, motion), trackOf(foe, motion), horizon, out);
}

}  // namespace
}  // namespace detail

const char* toString(DetectorKind k) {
  switch (k) {
    case DetectorKind::Concentric: return "concentric";
    case DetectorKind::FiveCircle: return "five";
    case DetectorKind::Box: return "box";
  }
  return "five";
}

bool parseDetectorKind(const std::string& text, DetectorKind& out) {
  if (text == "concentric") out = DetectorKind::Concentric;
  else if (text == "five" || text == "five-circle" || text == "fivecircle") out = DetectorKind::FiveCircle;
  else if (text == "box") out = DetectorKind::Box;
  else return false;
  return true;
}

bool parseMotionModel(const std::string& text, MotionModel& out) {
  if (text == "velocity") out = MotionModel::ConstantVelocity;
  else if (text == "acceleration") out = MotionModel::ConstantAcceleration;
  else return false;
  return true;
}

bool parseFiveCircleLayout(const std::string& text, FiveCircleLayout& out) {
  if (text == "a") out = FiveCircleLayout::fig11a();
  else if (text == "b") out = FiveCircleLayout::fig11b();
  else return false;
  return true;
}

const char* toString(Zone z) {
  switch (z) {
    case Zone::Front: return "front";
    case Zone::Rear: return "rear";
    case Zone::Left: return "left";
    case Zone::Right: return "right";
    case Zone::Center: return "center";
    case Zone::Inner: return "inner";
    case Zone::Outer: return "outer";
    case Zone::Body: return "body";
  }
  return "body";
}

FiveCircleLayout FiveCircleLayout::fig11a() {
  FiveCircleLayout l;
  constexpr double third = 1.0 / 3.0;
  l.zones[kFront] = {2.0 * third, 0.0, third, 1.0, 0.0};
  l.zones[kRear] = {-2.0 * third, 0.0, third, 1.0, 0.0};
  l.zones[kLeft] = {0.0, 0.5, third, 0.5, 0.0};
  l.zones[kRight] = {0.0, -0.5, third, 0.5, 0.0};
  l.zones[kCenter] = {0.0, 0.0, 0.0, 1.0, 0.0};
  return l;
}

FiveCircleLayout FiveCircleLayout::fig11b() {
  FiveCircleLayout l;
  l.zones[kFront] = {0.5, 0.0, 0.5, 1.0, 0.0};
  l.zones[kRear] = {-0.5, 0.0, 0.5, 1.0, 0.0};
  l.zones[kLeft] = {0.0, 0.5, 0.5, 0.5, 0.0};
  l.zones[kRight] = {0.0, -0.5, 0.5, 0.5, 0.0};
  l.zones[kCenter] = {0.0, 0.0, 0.0, 1.0, 0.0};
  return l;
}

Body bodyOf(const VehicleState& v) { return bodyOf(v, v.direction()); }

namespace {

// sqrt of a sum of squares: car sizes never overflow, and std::hypot is several times slower
inline double norm2(double a, double b) { return std::sqrt(a * a + b * b); }

struct Circ {
  Vec2 offset;  // body frame (m)
  double radius;
};

Circ zoneCircle(const ZoneCircle& z, double length, double width) {
  const double hl = 0.5 * length, hw = 0.5 * width;
  return {Vec2(z.x * hl, z.y * hw), norm2(z.rx * hl, z.ry * hw) + z.margin};
}

int bodyCircleCount(const DetectorConfig& cfg, double length, double width) {
  if (cfg.bodyCircles > 0) return cfg.bodyCircles;
  return std::max(1, static_cast<int>(std::ceil(length / width - 1e-9)));
}

// Body circles of a foe: n equal circles along the length, each around its slice of the rectangle.
Circ bodyCircle(int i, int n, double length, double width) {
  const double slice = length / n;
  return {Vec2(-0.5 * length + (i + 0.5) * slice, 0.0), norm2(0.5 * slice, 0.5 * width)};
}

double halfDiagonal(double length, double width) { return 0.5 * norm2(length, width); }

double outerRadius(const DetectorConfig& cfg, double l, double w) { return halfDiagonal(l, w) + cfg.concentric.outerMargin; }
double innerRadius(const DetectorConfig& cfg, double w) { return 0.5 * w + cfg.concentric.innerMargin; }

// Radius of a circle about the centre holding the foe's shape as the ego's detector sees it.
double foeEnvelope(const DetectorConfig& cfg, double l, double w) {
  switch (cfg.kind) {
    case DetectorKind::Concentric: return outerRadius(cfg, l, w);
    case DetectorKind::FiveCircle: {
      const int n = bodyCircleCount(cfg, l, w);
      const Circ c = bodyCircle(0, n, l, w);
      return c.offset.norm() + c.radius;
    }
    case DetectorKind::Box: return halfDiagonal(l, w);
  }
  return halfDiagonal(l, w);
}

// The skip constants (tol::kSkip*) are documented in tolerances.hpp.
using tol::kSkipMargin;
using tol::kSkipRadius;
using tol::kSkipRange;
using tol::kSkipSpeed;

// The five-circle pair loop on one piece of steady relative motion (no acceleration): the same
// discEntry per zone circle x body circle in the same order, the same result, but pairs whose
// circles stay apart until the earliest hit so far (they cannot win) are skipped: a zone at once
// when its circle stays apart from the disc holding the foe's body circles (foeEnv about the
// centre), else pair by pair.
Ttc steadyFiveCircle(const detail::Piece& pc, const double* zoneR, const Vec2* egoOff, const Vec2* foeOff, int m,
                     double foeR, double foeEnv) {
  Ttc best;
  double bestT = std::numeric_limits<double>::infinity();  // best's time, kept at hand
  const Vec2 v = pc.v;
  const double a = v.squaredNorm();
  double lim = pc.len;  // hits after this cannot win
  // true if |p + v t| > r + kSkipMargin for t in [0, lim]: entering r takes longer than lim
  auto apart = [&](const Vec2& p, double r) {
    const double q = p.squaredNorm(), b = p.dot(v), rm = r + kSkipMargin;
    if (!(q < kSkipRange * kSkipRange && a * lim * lim < kSkipRange * kSkipRange && r < kSkipRadius)) return false;
    // the closest approach: now if receding, at lim if still closing then, else on the way
    if (b >= 0.0) return q > rm * rm;
    if (-b >= a * lim) return (p + v * lim).squaredNorm() > rm * rm;
    const double cr = p.x() * v.y() - p.y() * v.x();
    return cr * cr > rm * rm * a;
  };
  for (int z = 0; z < 4; ++z) {
    if (apart(pc.p - egoOff[z], zoneR[z] + foeEnv)) continue;
    const double r = zoneR[z] + foeR;
    for (int k = 0; k < m; ++k) {
      const Vec2 p = pc.p + (foeOff[k] - egoOff[z]);  // as discEntry forms it
      Impact hit{Outcome::Overlapping, 0.0};
      if (!(p.squaredNorm() <= r * r)) {
        // receding (toiBalls misses or separates), or not entered by lim
        if (p.dot(v) >= 0.0 || apart(p, r)) continue;
        // discEntry's steady branch
        hit = toiBalls<2>(p, v, r);
        if (!hit.acts() || !(hit.actTime() <= pc.len)) continue;
        if (!(hit.actTime() < bestT)) continue;
      }
      const double s = hit.actTime();
      best = {hit, static_cast<Zone>(static_cast<int>(Zone::Front) + z)};
      bestT = s;
      if (s == 0.0) return best;  // nothing later is strictly earlier
      lim = s;
    }
  }
  return best;
}

// True if discEntry(pc, 0, r) certainly finds an entry for every r >= low, pc steady: the centres
// come within low - kSkipMargin of each other in [0, len].
bool surelyEntered(const detail::Piece& pc, double low) {
  const double in = low - kSkipMargin;
  const Vec2 p = pc.p, v = pc.v;
  const double q = p.squaredNorm(), a = v.squaredNorm(), len = pc.len;
  if (!(in > 0.0 && in < kSkipRadius)) return false;
  if (q <= in * in) return true;
  const double b = p.dot(v);
  const double range2 = kSkipRange * kSkipRange;
  if (!(b < 0.0 && q < range2 && a > kSkipSpeed * kSkipSpeed && a * len * len < range2)) return false;
  // the closest approach on [0, len]: at the end if still closing there, else on the way
  const double cr = p.x() * v.y() - p.y() * v.x();
  return -b >= a * len ? (p + v * len).squaredNorm() < in * in : cr * cr < in * in * a;
}

}  // namespace

double envelopeRadius(const DetectorConfig& cfg, double length, double width) {
  double r = halfDiagonal(length, width);
  switch (cfg.kind) {
    case DetectorKind::Concentric:
      r = std::max({r, outerRadius(cfg, length, width), innerRadius(cfg, width)});
      break;
    case DetectorKind::FiveCircle:
      for (const ZoneCircle& z : cfg.five.zones) {
        const Circ c = zoneCircle(z, length, width);
        r = std::max(r, c.offset.norm() + c.radius);
      }
      r = std::max(r, foeEnvelope(cfg, length, width));
      break;
    case DetectorKind::Box:
      break;
  }
  return r;
}

Vec2 envelopeExtent(const DetectorConfig& cfg, const Body& b) {
  // the rectangle itself
  const Box2 box = b.box();
  Vec2 ext(support(box, Vec2(1.0, 0.0)), support(box, Vec2(0.0, 1.0)));
  auto add = [&](const Circ& c) {
    const Vec2 o = detail::toWorld(b, c.offset.x(), c.offset.y());
    ext = ext.cwiseMax(o.cwiseAbs() + Vec2::Constant(c.radius));
  };
  switch (cfg.kind) {
    case DetectorKind::Concentric:
      add({Vec2::Zero(), outerRadius(cfg, b.length, b.width)});
      add({Vec2::Zero(), innerRadius(cfg, b.width)});
      break;
    case DetectorKind::FiveCircle: {
      for (const ZoneCircle& z : cfg.five.zones) add(zoneCircle(z, b.length, b.width));
      const int m = std::min(bodyCircleCount(cfg, b.length, b.width), 16);
      for (int k = 0; k < m; ++k) add(bodyCircle(k, m, b.length, b.width));
      break;
    }
    case DetectorKind::Box:
      break;
  }
  return ext;
}

double roadSupport(const DetectorConfig& cfg, const Body& ego, const Vec2& n) {
  switch (cfg.kind) {
    case DetectorKind::Concentric: return innerRadius(cfg, ego.width);
    case DetectorKind::FiveCircle: {
      const Circ c = zoneCircle(cfg.five.zones[FiveCircleLayout::kCenter], ego.length, ego.width);
      return std::abs(detail::toWorld(ego, c.offset.x(), c.offset.y()).dot(n)) + c.radius;
    }
    case DetectorKind::Box: return support(ego.box(), n);
  }
  return halfDiagonal(ego.length, ego.width);
}

SupportBound roadSupportBound(const DetectorConfig& cfg, const Body& ego) {
  switch (cfg.kind) {
    case DetectorKind::Concentric: return {innerRadius(cfg, ego.width), 0.0, 0.0};
    case DetectorKind::FiveCircle: {
      // |offset . n| <= |offset| (zero for the presets' centred circle)
      const Circ c = zoneCircle(cfg.five.zones[FiveCircleLayout::kCenter], ego.length, ego.width);
      return {c.offset.norm() + c.radius, 0.0, 0.0};
    }
    case DetectorKind::Box: return {0.0, 0.5 * ego.length, 0.5 * ego.width};
  }
  return {halfDiagonal(ego.length, ego.width), 0.0, 0.0};
}

bool layoutCoversBody(const FiveCircleLayout& layout, double length, double width) {
  // every point of a fine grid over the rectangle (boundary included) lies in a car-checking zone
  const int nx = 64, ny = 32;
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      const Vec2 p((i / double(nx) - 0.5) * length, (j / double(ny) - 0.5) * width);
      bool in = false;
      for (int z = 0; z < 4 && !in; ++z) {
        const Circ c = zoneCircle(layout.zones[z], length, width);
        in = (p - c.offset).norm() <= c.radius * (1.0 + 1e-12) + 1e-12;
      }
      if (!in) return false;
    }
  }
  return true;
}

Impact boxTtc(const Body& a, const Body& b, MotionModel motion, double horizon) {
  const Box2 boxA = a.box(), boxB = b.box();
  if (motion == MotionModel::ConstantVelocity && !(a.stopAcceleration < 0.0) && !(b.stopAcceleration < 0.0))
    return timeOfEntry(boxA, boxB, b.velocity - a.velocity, horizon, tol::kContactSlop);
  // braking cars: the same axes on each piece of their relative motion
  const std::array<SeparatingAxis, 4> axes = separatingAxes(boxA, boxB);
  std::array<detail::Piece, 3> pcs;
  const int n = detail::bodyPieces(a, b, motion, horizon, pcs);
  return detail::firstEntry(std::span(pcs.data(), n), [&](const detail::Piece& pc) { return detail::satEntry(pc, axes); });
}

CarShape carShape(const DetectorConfig& cfg, const Body& b) {
  CarShape s;
  s.road = roadSupportBound(cfg, b);
  switch (cfg.kind) {
    case DetectorKind::Concentric:
      s.outer = outerRadius(cfg, b.length, b.width);
      break;
    case DetectorKind::Box:
      break;
    case DetectorKind::FiveCircle: {
      Circ zones[4];
      for (int z = 0; z < 4; ++z) {
        zones[z] = zoneCircle(cfg.five.zones[z], b.length, b.width);
        s.zoneRadius[z] = zones[z].radius;
        s.zoneOffset[z] = detail::toWorld(b, zones[z].offset.x(), zones[z].offset.y());
      }
      s.egoEnvelope = halfDiagonal(b.length, b.width);
      for (int z = 0; z < 4; ++z) s.egoEnvelope = std::max(s.egoEnvelope, zones[z].offset.norm() + zones[z].radius);
      s.egoLow = 0.0;  // |offset| >= its largest coordinate
      for (int z = 0; z < 4; ++z) s.egoLow = std::max(s.egoLow, zones[z].offset.cwiseAbs().maxCoeff() + zones[z].radius);
      s.circles = std::min(bodyCircleCount(cfg, b.length, b.width), 16);
      const Circ first = bodyCircle(0, s.circles, b.length, b.width);
      s.circleRadius = first.radius;
      s.slice = b.length / s.circles;
      s.firstX = first.offset.x();
      s.foeEnvelope = std::max(first.offset.norm() + first.radius, halfDiagonal(b.length, b.width));
      // |axis| <= (1 + axis^2) / 2
      s.foeDisc = std::abs(first.offset.x()) * (0.5 * (1.0 + b.axis.squaredNorm())) + first.radius;
      break;
    }
  }
  return s;
}

bool vehicleTtcSymmetric(const DetectorConfig& cfg) {
  return cfg.kind == DetectorKind::Concentric && cfg.motion == MotionModel::ConstantVelocity;
}

Ttc vehicleTtc(const DetectorConfig& cfg, const Body& ego, const Body& foe, double horizon) {
  return vehicleTtc(cfg, ego, carShape(cfg, ego), foe, carShape(cfg, foe), horizon);
}

Ttc vehicleTtc(const DetectorConfig& cfg, const Body& ego, const CarShape& es, const Body& foe, const CarShape& fs,
               double horizon) {
  Ttc best;
  if (!(horizon >= 0.0)) return best;
  std::array<detail::Piece, 3> pcs;
  const int n = detail::bodyPieces(ego, foe, cfg.motion, horizon, pcs);
  switch (cfg.kind) {
    case DetectorKind::Concentric: {
      // CheckOuter: outer circle against the other car's outer circle
      const double r = es.outer + fs.outer;
      const Impact hit = detail::firstEntry(std::span(pcs.data(), n), [&](const detail::Piece& pc) {
        return detail::discEntry(pc, Vec2::Zero(), r);
      });
      if (hit.acts()) best = {hit, Zone::Outer};
      return best;
    }
    case DetectorKind::Box: {
      return {boxTtc(ego, foe, cfg.motion, horizon), Zone::Body};
    }
    case DetectorKind::FiveCircle: {
      // prune with the envelopes, then CheckFront, CheckRear, CheckLeft, CheckRight against
      // every body circle of the foe; the earliest names the zone (ties: that order)
      const int m = fs.circles;
      Vec2 foeOff[16];
      const double foeR = fs.circleRadius;
      for (int k = 0; k < m; ++k)  // bodyCircle's offsets
        foeOff[k] = detail::toWorld(foe, -0.5 * foe.length + (k + 0.5) * fs.slice, 0.0);
      const double* zoneR = es.zoneRadius.data();
      const Vec2* egoOff = es.zoneOffset.data();
      if (n == 1 && !pcs[0].accelerating()) {
        // the pairs first: the envelope prune only matters when they find a hit, and then the
        // centres mostly come well inside the envelope (a lower bound of it suffices).
        const Ttc hit = steadyFiveCircle(pcs[0], zoneR, egoOff, foeOff, m, foeR, fs.foeDisc);
        if (!hit.found()) return hit;
        if (surelyEntered(pcs[0], es.egoLow + std::abs(fs.firstX) + foeR) ||
            detail::discEntry(pcs[0], Vec2::Zero(), es.egoEnvelope + fs.foeEnvelope).acts())
          return hit;
        return best;
      }
      const double env = es.egoEnvelope + fs.foeEnvelope;
      bool near = false;
      for (int i = 0; i < n && !near; ++i) near = detail::discEntry(pcs[i], Vec2::Zero(), env).acts();
      if (!near) return best;
      for (int i = 0; i < n; ++i) {
        detail::Piece pc = pcs[i];
        for (int z = 0; z < 4; ++z) {
          for (int k = 0; k < m; ++k) {
            pc.len = best.found() ? std::min(pcs[i].len, best.t() - pcs[i].start) : pcs[i].len;
            const Impact e = detail::discEntry(pc, foeOff[k] - egoOff[z], zoneR[z] + foeR);
            if (e.acts() && (!best.found() || pcs[i].start + e.actTime() < best.t()))
              best = {delayed(e, pcs[i].start), static_cast<Zone>(static_cast<int>(Zone::Front) + z)};
          }
        }
        if (best.found()) return best;
      }
      return best;
    }
  }
  return best;
}

Ttc featureTtc(const DetectorConfig& cfg, const Body& ego, const RoadFeature& f, double horizon) {
  Ttc best;
  if (!(horizon >= 0.0)) return best;
  const bool point = f.kind == FeatureKind::Hazard;
  const Vec2 mid = 0.5 * (f.segment.a + f.segment.b);
  // relative motion of the feature as seen from the ego: the ego's motion reversed
  // (not needed by the circles at constant velocity: they call the stcore kernels directly)
  std::array<detail::Piece, 3> pcs;
  const bool direct =
      cfg.kind != DetectorKind::Box && cfg.motion == MotionModel::ConstantVelocity && !(ego.stopAcceleration < 0.0);
  const int n =
      direct ? 0 : detail::relativePieces(detail::trackOf(ego, cfg.motion), detail::staticTrack(mid), horizon, pcs);
  const std::span<const detail::Piece> pieces(pcs.data(), n);
  Impact hit;  // from now, over the pieces
  Zone zone = Zone::Body;
  if (cfg.kind == DetectorKind::Box) {
    const Vec2 an = detail::normalOf(ego.axis);
    const double hl = 0.5 * ego.length, hw = 0.5 * ego.width;
    if (point) {
      // the rectangle grown by the disc: two crossed rectangles and four corner discs
      const SeparatingAxis ax1[2] = {{ego.axis, hl + f.radius}, {an, hw}};
      const SeparatingAxis ax2[2] = {{ego.axis, hl}, {an, hw + f.radius}};
      hit = detail::firstEntry(pieces, [&](const detail::Piece& pc) {
        Impact e = earliest(detail::satEntry(pc, ax1), detail::satEntry(pc, ax2));
        for (double sx : {-1.0, 1.0})
          for (double sy : {-1.0, 1.0})
            e = earliest(e, detail::discEntry(pc, -(sx * hl * ego.axis + sy * hw * an), f.radius));
        return e;
      });
    } else {
      // segment as a degenerate polygon: axes are the box's two and the segment's normal
      const Vec2 d = f.segment.b - f.segment.a;
      const double hlen = 0.5 * d.norm();
      const Vec2 dn = hlen > 0.0 ? Vec2(d / (2.0 * hlen)) : Vec2(1.0, 0.0);
      const Vec2 sn = detail::normalOf(dn);
      const SeparatingAxis ax[3] = {{ego.axis, hl + hlen * std::abs(dn.dot(ego.axis))},
                                    {an, hw + hlen * std::abs(dn.dot(an))},
                                    {sn, support(ego.box(), sn)}};
      hit = detail::firstEntry(pieces, [&](const detail::Piece& pc) { return detail::satEntry(pc, ax); });
    }
  } else {
    // CheckInner (concentric) or CheckCenter (five-circle)
    const double r = cfg.kind == DetectorKind::Concentric
                         ? innerRadius(cfg, ego.width)
                         : zoneCircle(cfg.five.zones[FiveCircleLayout::kCenter], ego.length, ego.width).radius;
    zone = cfg.kind == DetectorKind::Concentric ? Zone::Inner : Zone::Center;
    if (direct || (n == 1 && !pcs[0].accelerating())) {
      // the stcore kernels for constant velocity
      const Circle c{ego.position, r};
      const Impact now = point ? toiBalls<2>(f.segment.a - ego.position, -ego.velocity, r + f.radius)
                               : toiCircleSegment(c, ego.velocity, f.segment).impact;
      if (now.outcome == Outcome::Separating) return best;
      if (now.acts() && now.actTime() <= horizon) hit = now;
    } else if (point) {
      hit = detail::firstEntry(pieces,
                               [&](const detail::Piece& pc) { return detail::discEntry(pc, Vec2::Zero(), r + f.radius); });
    } else {
      // the capsule around the segment: a rectangle and two end discs
      const Vec2 d = f.segment.b - f.segment.a;
      const double hlen = 0.5 * d.norm();
      const Vec2 dn = hlen > 0.0 ? Vec2(d / (2.0 * hlen)) : Vec2(1.0, 0.0);
      const SeparatingAxis ax[2] = {{dn, hlen}, {detail::normalOf(dn), r}};
      hit = detail::firstEntry(pieces, [&](const detail::Piece& pc) {
        return earliest(earliest(detail::satEntry(pc, ax), detail::discEntry(pc, f.segment.a - mid, r)),
                        detail::discEntry(pc, f.segment.b - mid, r));
      });
    }
  }
  if (!hit.acts()) return best;
  const double t = hit.actTime();
  if (t == 0.0) {
    // already touching: a threat only while the car still moves towards the feature
    const Vec2 closest = point ? f.segment.a : closestPointOnSegment(f.segment, ego.position);
    if (ego.velocity.dot(closest - ego.position) <= 0.0) return best;
  }
  best = {hit, zone};
  return best;
}

}  // namespace st::highway
