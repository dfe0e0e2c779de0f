#include <gtest/gtest.h>
#include "test_scale.hpp"

#include <cmath>
#include <cstring>
#include <random>

#include <sthighway/detector.hpp>

#include "car_shape.hpp"
#include "reference.hpp"

namespace st::highway {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Body car(Vec2 p, double heading, double speed, double lateral = 0.0, double length = 5.0, double width = 1.8) {
  Body b;
  b.position = p;
  b.axis = Vec2(std::cos(heading), std::sin(heading));
  const Vec2 n(-b.axis.y(), b.axis.x());
  b.velocity = speed * b.axis + lateral * n;
  b.length = length;
  b.width = width;
  return b;
}

DetectorConfig config(DetectorKind k, MotionModel m = MotionModel::ConstantVelocity,
                      FiveCircleLayout layout = FiveCircleLayout::fig11a()) {
  DetectorConfig c;
  c.kind = k;
  c.motion = m;
  c.five = layout;
  return c;
}

TEST(Detector, ClosingOnStoppedCarAnalytic) {
  // 5 m x 1.8 m cars, ego at 20 m/s, stopped car 50 m ahead (centre to centre): bumper gap 45 m
  const Body ego = car({0, 0}, 0.0, 20.0), stopped = car({50, 0}, 0.0, 0.0);
  const double box = vehicleTtc(config(DetectorKind::Box), ego, stopped, 10).t();
  EXPECT_NEAR(box, 45.0 / 20.0, 1e-12);
  // concentric: outer circles of radius hypot(5, 1.8) / 2 meet when the centres are 2r apart
  const double r = 0.5 * std::hypot(5.0, 1.8);
  const Ttc conc = vehicleTtc(config(DetectorKind::Concentric), ego, stopped, 10);
  EXPECT_NEAR(conc.t(), (50.0 - 2 * r) / 20.0, 1e-12);
  EXPECT_EQ(conc.zone, Zone::Outer);
  // five-circle (Fig. 11a): ego's front zone circle, centred L/3 ahead, radius hypot(L/6, W/2),
  // meets the stopped car's rearmost body circle (3 circles, centred L/3 behind its centre)
  const double zr = std::hypot(5.0 / 6.0, 0.9);
  const Ttc five = vehicleTtc(config(DetectorKind::FiveCircle), ego, stopped, 10);
  EXPECT_NEAR(five.t(), ((50.0 - 5.0 / 3.0) - 5.0 / 3.0 - 2 * zr) / 20.0, 1e-12);
  EXPECT_EQ(five.zone, Zone::Front);
  // the stopped car sees the ego coming from behind
  EXPECT_EQ(vehicleTtc(config(DetectorKind::FiveCircle), stopped, ego, 10).zone, Zone::Rear);
  // a horizon shorter than the TTC finds nothing
  EXPECT_FALSE(vehicleTtc(config(DetectorKind::Box), ego, stopped, 2.0).found());
}

TEST(Detector, ConstantAccelerationStopsShortOrHits) {
  // ego at 20 m/s braking at 4 m/s^2 stops in 50 m
  Body ego = car({0, 0}, 0.0, 20.0);
  ego.acceleration = -4.0;
  const DetectorConfig ca = config(DetectorKind::Box, MotionModel::ConstantAcceleration);
  // bumper gap 45 m: 20 t - 2 t^2 = 45
  const double hit = vehicleTtc(ca, ego, car({50, 0}, 0.0, 0.0), 20).t();
  EXPECT_NEAR(hit, (20.0 - std::sqrt(400.0 - 360.0)) / 4.0, 1e-9);
  // bumper gap 55 m: it stops 5 m short, and stays stopped (no reversing)
  EXPECT_FALSE(vehicleTtc(ca, ego, car({60, 0}, 0.0, 0.0), 60).found());
  // constant velocity ignores the braking
  EXPECT_NEAR(vehicleTtc(config(DetectorKind::Box), ego, car({60, 0}, 0.0, 0.0), 60).t(), 55.0 / 20.0, 1e-12);
  // circles under the same motion stop short too, and are earlier than the box when they hit
  for (DetectorKind k : {DetectorKind::Concentric, DetectorKind::FiveCircle}) {
    const Ttc c = vehicleTtc(config(k, MotionModel::ConstantAcceleration), ego, car({50, 0}, 0.0, 0.0), 20);
    ASSERT_TRUE(c.found());
    EXPECT_LE(c.t(), hit);
  }
}

TEST(Detector, DriftOntoCurbAnalytic) {
  // curb along y = -5; car 1.8 m wide drifting right at 0.5 m/s: its side reaches the curb after
  // (5 - 0.9) / 0.5 = 8.2 s whichever model (inner circle, centre circle, rectangle)
  RoadFeature curb;
  curb.kind = FeatureKind::Curb;
  curb.segment = Segment{{-500, -5}, {500, -5}};
  const Body ego = car({0, 0}, 0.0, 30.0, -0.5);
  for (DetectorKind k : {DetectorKind::Concentric, DetectorKind::FiveCircle, DetectorKind::Box})
    for (MotionModel m : {MotionModel::ConstantVelocity, MotionModel::ConstantAcceleration}) {
      const Ttc t = featureTtc(config(k, m), ego, curb, 20);
      ASSERT_TRUE(t.found()) << toString(k);
      EXPECT_NEAR(t.t(), 8.2, 1e-9) << toString(k);
    }
  EXPECT_EQ(featureTtc(config(DetectorKind::Concentric), ego, curb, 20).zone, Zone::Inner);
  EXPECT_EQ(featureTtc(config(DetectorKind::FiveCircle), ego, curb, 20).zone, Zone::Center);
  // drifting away: nothing, even when already touching
  EXPECT_FALSE(featureTtc(config(DetectorKind::FiveCircle), car({0, 0}, 0.0, 30.0, 0.5), curb, 20).found());
  EXPECT_FALSE(featureTtc(config(DetectorKind::FiveCircle), car({0, -4.5}, 0.0, 30.0, 0.5), curb, 20).found());
  EXPECT_EQ(featureTtc(config(DetectorKind::FiveCircle), car({0, -4.5}, 0.0, 30.0, -0.5), curb, 20).t(), 0.0);
}

TEST(Detector, HazardAheadAnalytic) {
  RoadFeature pothole;
  pothole.kind = FeatureKind::Hazard;
  pothole.segment = Segment{{100, 0.3}, {100, 0.3}};
  pothole.radius = 0.4;
  const Body ego = car({0, 0}, 0.0, 25.0);
  // rectangle front face at x = 2.5 meets the disc's leftmost point x = 99.6 (its centre is
  // within the car's width): (99.6 - 2.5) / 25
  EXPECT_NEAR(featureTtc(config(DetectorKind::Box), ego, pothole, 10).t(), 97.1 / 25.0, 1e-9);
  // the inner circle (radius 0.9) meets the disc when the centres are 1.3 m apart
  EXPECT_NEAR(featureTtc(config(DetectorKind::Concentric), ego, pothole, 10).t(),
              (100.0 - std::sqrt(1.3 * 1.3 - 0.3 * 0.3)) / 25.0, 1e-9);
}

TEST(Detector, CutInFromEitherSideNamesTheZone) {
  // ego in its lane; a car alongside in the next lane (3.2 m) steers into it at 1 m/s
  const Body ego = car({0, 0}, 0.0, 25.0);
  const Body fromRight = car({0, -3.2}, 0.0, 25.0, 1.0);
  const Body fromLeft = car({0, 3.2}, 0.0, 25.0, -1.0);
  const DetectorConfig five = config(DetectorKind::FiveCircle);
  const Ttc r = vehicleTtc(five, ego, fromRight, 5);
  const Ttc l = vehicleTtc(five, ego, fromLeft, 5);
  EXPECT_EQ(r.zone, Zone::Right);
  EXPECT_EQ(l.zone, Zone::Left);
  // the sides meet after (3.2 - 1.8) / 1 s; the zones fire no later
  EXPECT_NEAR(vehicleTtc(config(DetectorKind::Box), ego, fromRight, 5).t(), 1.4, 1e-12);
  EXPECT_LE(r.t(), 1.4);
  EXPECT_LE(l.t(), 1.4);
  EXPECT_NEAR(r.t(), l.t(), 1e-12);
  // Fig. 11(b) as well
  EXPECT_EQ(vehicleTtc(config(DetectorKind::FiveCircle, MotionModel::ConstantVelocity, FiveCircleLayout::fig11b()), ego,
                       fromRight, 5).zone,
            Zone::Right);
  // in its own lane beside the ego at the same speed, nothing for the five-circle and box models
  EXPECT_FALSE(vehicleTtc(five, ego, car({0, -3.2}, 0.0, 25.0), 5).found());
  EXPECT_FALSE(vehicleTtc(config(DetectorKind::Box), ego, car({0, -3.2}, 0.0, 25.0), 5).found());
}

TEST(Detector, LayoutsCoverTheCar) {
  for (double l : {2.2, 4.5, 5.0, 12.0, 18.75})
    for (double w : {0.9, 1.8, 2.55}) {
      EXPECT_TRUE(layoutCoversBody(FiveCircleLayout::fig11a(), l, w));
      EXPECT_TRUE(layoutCoversBody(FiveCircleLayout::fig11b(), l, w));
    }
  FiveCircleLayout holes = FiveCircleLayout::fig11a();
  holes.zones[FiveCircleLayout::kLeft].ry = 0.2;
  EXPECT_FALSE(layoutCoversBody(holes, 5.0, 1.8));
}

// Random encounters of cars, trucks and motorcycles in highway-like geometry.
struct Encounter {
  Body ego, foe;
};

Encounter randomEncounter(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto size = [&](Body& b) {
    const double r = U(rng);
    if (r < 0.7) b.length = 4.0 + 1.5 * U(rng), b.width = 1.6 + 0.4 * U(rng);
    else if (r < 0.9) b.length = 10.0 + 8.0 * U(rng), b.width = 2.4 + 0.2 * U(rng);
    else b.length = 2.0 + 0.4 * U(rng), b.width = 0.8 + 0.2 * U(rng);
  };
  while (true) {
    Encounter e;
    const bool anyAngle = U(rng) < 0.2;
    e.ego = car({0, 0}, 0.4 * (U(rng) - 0.5), 35 * U(rng), 3 * (U(rng) - 0.5));
    e.foe = car({90 * (U(rng) - 0.5), 12 * (U(rng) - 0.5)}, anyAngle ? 6.283 * U(rng) : 0.4 * (U(rng) - 0.5),
                U(rng) < 0.1 ? 0.0 : 35 * U(rng), 3 * (U(rng) - 0.5));
    size(e.ego);
    size(e.foe);
    e.ego.acceleration = 8 * (U(rng) - 0.6);
    e.foe.acceleration = 8 * (U(rng) - 0.6);
    if (!ref::overlapAt(e.ego, e.foe, 0.0, false)) return e;
  }
}

TEST(Detector, BoxTtcMatchesSampledReference) {
  std::mt19937_64 rng(20261124);
  int hits = 0;
  const int encounters = test::scaledCount(1500);
  for (int i = 0; i < encounters; ++i) {
    const Encounter e = randomEncounter(rng);
    for (bool accel : {false, true}) {
      const MotionModel m = accel ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
      const Impact hit = boxTtc(e.ego, e.foe, m, 6.0);
      // an entry: overlapping now, a hit, or nothing (no contact that separates)
      ASSERT_NE(hit.outcome, Outcome::Separating) << "pair " << i;
      const double box = hit.actTime();
      const double truth = ref::sampledTtc(e.ego, e.foe, 6.0, accel);
      if (truth < kInf) {
        ++hits;
        ASSERT_LT(box, kInf) << "pair " << i << " accel " << accel;
        EXPECT_NEAR(box, truth, 1e-6) << "pair " << i << " accel " << accel;
      } else if (box < kInf) {
        // a graze shorter than the sampling step: the boxes must touch there
        EXPECT_LT(ref::distanceAt(e.ego, e.foe, box, accel), 1e-6) << "pair " << i;
      }
    }
  }
  EXPECT_GT(hits, encounters / 5);  // the scenes are not all misses
}

// The monitor computes a car's shape once and keeps it while the car's size and heading stay:
// a TTC from shapes made of other snapshots of the same cars (other positions, velocities,
// accelerations) must be the one computed from scratch, bit for bit (the sign of a zero too).
TEST(Detector, CarShapesGiveTheSameTtcBitForBit) {
  DetectorConfig fourCircles = config(DetectorKind::FiveCircle);
  fourCircles.bodyCircles = 4;
  FiveCircleLayout offCentre = FiveCircleLayout::fig11a();
  offCentre.zones[FiveCircleLayout::kCenter] = {0.2, -0.1, 0.0, 1.0, 0.1};
  DetectorConfig concentricMargins = config(DetectorKind::Concentric);
  concentricMargins.concentric = {0.3, 0.5};
  const DetectorConfig configs[] = {config(DetectorKind::Concentric), concentricMargins, config(DetectorKind::Box),
                                    config(DetectorKind::FiveCircle),
                                    config(DetectorKind::FiveCircle, MotionModel::ConstantVelocity, FiveCircleLayout::fig11b()),
                                    config(DetectorKind::FiveCircle, MotionModel::ConstantVelocity, offCentre), fourCircles};
  std::mt19937_64 rng(20261125);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  // another snapshot of b: the same size and heading, elsewhere, moving otherwise
  auto elsewhere = [&](const Body& b) {
    Body o = b;
    o.position = Vec2(1e4 * U(rng), 100.0 * (U(rng) - 0.5));
    o.velocity = Vec2(40.0 * (U(rng) - 0.5), 5.0 * (U(rng) - 0.5));
    o.acceleration = 8.0 * (U(rng) - 0.5);
    return o;
  };
  auto same = [](const Ttc& a, const Ttc& b) {
    const double ta = a.t(), tb = b.t();
    return std::memcmp(&ta, &tb, sizeof(double)) == 0 && a.impact.outcome == b.impact.outcome && a.zone == b.zone;
  };
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    Encounter e = randomEncounter(rng);
    if (i % 3 == 0) e.foe.position = e.ego.position + 0.3 * (e.foe.position - e.ego.position);  // more touching
    const double horizon = i % 50 == 0 ? 0.0 : 6.0 * U(rng);
    for (bool accel : {false, true}) {
      for (DetectorConfig c : configs) {
        c.motion = accel ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
        const CarShape es = carShape(c, elsewhere(e.ego)), fs = carShape(c, elsewhere(e.foe));
        const Ttc fresh = vehicleTtc(c, e.ego, e.foe, horizon);
        const Ttc kept = vehicleTtc(c, e.ego, es, e.foe, fs, horizon);
        ASSERT_TRUE(same(fresh, kept)) << toString(c.kind) << " pair " << i << " accel " << accel << ": " << fresh.t()
                                       << " vs " << kept.t();
        hits += fresh.found();
        const SupportBound sb = roadSupportBound(c, e.ego);
        EXPECT_TRUE(std::memcmp(&sb.base, &es.road.base, sizeof(double)) == 0 && sb.along == es.road.along &&
                    sb.across == es.road.across);
      }
    }
  }
  EXPECT_GT(hits, 3000);  // not all misses
}

// vehicleTtcSymmetric: one evaluation serves both roles and any horizon holding its time (the
// monitor tests a pair's two directions that way); the five-circle zones are not symmetric.
TEST(Detector, SymmetricDetectorGivesOneTtcForBothRolesAndHorizons) {
  DetectorConfig margins = config(DetectorKind::Concentric);
  margins.concentric = {0.3, 0.5};
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto same = [](const Ttc& a, const Ttc& b) {
    const double ta = a.t(), tb = b.t();
    return std::memcmp(&ta, &tb, sizeof(double)) == 0 && a.impact.outcome == b.impact.outcome && a.zone == b.zone;
  };
  auto within = [](const Ttc& t, double h) { return t.found() && t.t() <= h ? t : Ttc{}; };
  int found = 0, asymmetric = 0;
  for (int i = 0; i < 4000; ++i) {
    Encounter e = randomEncounter(rng);
    if (i % 3 == 0) e.foe.position = e.ego.position + 0.3 * (e.foe.position - e.ego.position);
    const double h1 = 6.0 * U(rng), h2 = i % 7 == 0 ? h1 : 6.0 * U(rng);
    for (const DetectorConfig& c : {config(DetectorKind::Concentric), margins}) {
      ASSERT_TRUE(vehicleTtcSymmetric(c));
      const Ttc once = vehicleTtc(c, e.ego, e.foe, std::max(h1, h2));
      ASSERT_TRUE(same(vehicleTtc(c, e.ego, e.foe, h1), within(once, h1))) << "pair " << i;
      ASSERT_TRUE(same(vehicleTtc(c, e.foe, e.ego, h2), within(once, h2))) << "pair " << i;
      found += once.found();
    }
    const DetectorConfig five = config(DetectorKind::FiveCircle);
    asymmetric += !same(vehicleTtc(five, e.ego, e.foe, h1), vehicleTtc(five, e.foe, e.ego, h1));
  }
  EXPECT_GT(found, 2000);
  EXPECT_GT(asymmetric, 100);  // why the five-circle zones are excluded
  EXPECT_FALSE(vehicleTtcSymmetric(config(DetectorKind::FiveCircle)));
  EXPECT_FALSE(vehicleTtcSymmetric(config(DetectorKind::Box)));
  EXPECT_FALSE(vehicleTtcSymmetric(config(DetectorKind::Concentric, MotionModel::ConstantAcceleration)));
}

// The most a layout's circles reach beyond the car's rectangle, from the documented geometry.
double egoOvershoot(const DetectorConfig& c, double l, double w) {
  if (c.kind == DetectorKind::Concentric) return ref::overshoot({0, 0}, 0.5 * std::hypot(l, w), l, w);
  double d = 0.0;
  for (int z = 0; z < 4; ++z) {
    const ZoneCircle& zc = c.five.zones[z];
    d = std::max(d, ref::overshoot({zc.x * l / 2, zc.y * w / 2}, std::hypot(zc.rx * l / 2, zc.ry * w / 2) + zc.margin, l, w));
  }
  return d;
}
double foeOvershoot(const DetectorConfig& c, double l, double w) {
  if (c.kind == DetectorKind::Concentric) return ref::overshoot({0, 0}, 0.5 * std::hypot(l, w), l, w);
  const int n = std::max(1, static_cast<int>(std::ceil(l / w)));
  return ref::overshoot({-l / 2 + l / (2 * n), 0}, std::hypot(l / (2 * n), w / 2), l, w);
}

TEST(Detector, CirclesAreNeverLaterThanBoxAndWithinMargin) {
  // Documented margin: when a circle model fires at t_c, the two rectangles are at most
  // overshoot(ego layout) + overshoot(foe shape) apart (how far the circles reach beyond the
  // rectangles: concentric hypot(L, W)/2 - W/2 each; five-circle far less).
  std::mt19937_64 rng(7);
  int hits = 0, falseAlarms = 0, both = 0;
  double worstLead = 0.0;
  const DetectorConfig configs[] = {
      config(DetectorKind::Concentric), config(DetectorKind::FiveCircle),
      config(DetectorKind::FiveCircle, MotionModel::ConstantVelocity, FiveCircleLayout::fig11b())};
  for (int i = 0; i < 4000; ++i) {
    const Encounter e = randomEncounter(rng);
    for (bool accel : {false, true}) {
      const MotionModel m = accel ? MotionModel::ConstantAcceleration : MotionModel::ConstantVelocity;
      const double box = boxTtc(e.ego, e.foe, m, 6.0).actTime();
      for (DetectorConfig c : configs) {
        c.motion = m;
        const Ttc circ = vehicleTtc(c, e.ego, e.foe, 6.0);
        if (box < kInf) {
          ++hits;
          ASSERT_TRUE(circ.found()) << toString(c.kind) << " missed a box hit, pair " << i;
          ASSERT_LE(circ.t(), box + 1e-9) << toString(c.kind) << " later than the box, pair " << i;
          worstLead = std::max(worstLead, box - circ.t());
          ++both;
        } else if (circ.found()) {
          ++falseAlarms;
        }
        if (circ.found()) {
          const double margin = egoOvershoot(c, e.ego.length, e.ego.width) + foeOvershoot(c, e.foe.length, e.foe.width);
          EXPECT_LE(ref::distanceAt(e.ego, e.foe, circ.t(), accel), margin + 1e-6)
              << toString(c.kind) << " pair " << i << " fired too early";
        }
      }
    }
  }
  EXPECT_GT(hits, 1000);
  RecordProperty("circle_hits_with_box_hit", both);
  RecordProperty("circle_hits_without_box_hit", falseAlarms);
}

// The monitor prunes road lines with roadSupportBound before it computes roadSupport: the
// bound must hold in every direction (else a feature would be lost), and is never wider than
// the envelope it replaced; for the circles and the rectangle it is the support itself.
TEST(Detector, RoadSupportBoundHoldsInEveryDirection) {
  FiveCircleLayout offCentre = FiveCircleLayout::fig11a();
  offCentre.zones[FiveCircleLayout::kCenter] = {0.2, -0.1, 0.0, 1.0, 0.1};
  const DetectorConfig configs[] = {config(DetectorKind::Concentric), config(DetectorKind::Box),
                                    config(DetectorKind::FiveCircle), config(DetectorKind::FiveCircle, MotionModel::ConstantVelocity, FiveCircleLayout::fig11b()),
                                    config(DetectorKind::FiveCircle, MotionModel::ConstantVelocity, offCentre)};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  for (const DetectorConfig& cfg : configs)
    for (int i = 0; i < 2000; ++i) {
      const Body b = car(Vec2(100.0 * U(rng), 10.0 * U(rng)), 6.3 * U(rng), 30.0 * U(rng), 0.0, 2.0 + 14.0 * U(rng),
                         1.5 + 1.2 * U(rng));
      const double phi = 6.3 * U(rng);
      const Vec2 n(std::cos(phi), std::sin(phi));
      const SupportBound sb = roadSupportBound(cfg, b);
      const Vec2 normal(-b.axis.y(), b.axis.x());
      const double bound = sb.base + sb.along * std::abs(b.axis.dot(n)) + sb.across * std::abs(normal.dot(n));
      const double exact = roadSupport(cfg, b, n);
      EXPECT_LE(exact, bound * (1.0 + 1e-12)) << toString(cfg.kind) << " " << i;
      EXPECT_LE(bound, envelopeRadius(cfg, b.length, b.width) * (1.0 + 1e-12)) << toString(cfg.kind) << " " << i;
      if (&cfg != &configs[4]) {
        EXPECT_NEAR(exact, bound, 1e-12 * bound);  // the off-centre circle's bound is |offset| wider at most
      }
    }
}

TEST(Detector, FollowingMarginInTime) {
  // rear-end approach in one lane: the circle TTC leads the box TTC by exactly the circles'
  // reach along the axis divided by the closing speed
  const Body ego = car({0, 0}, 0.0, 30.0);
  for (double v : {1.0, 5.0, 20.0}) {
    const Body lead = car({40, 0}, 0.0, 30.0 - v);
    const double box = vehicleTtc(config(DetectorKind::Box), ego, lead, 100).t();
    const double five = vehicleTtc(config(DetectorKind::FiveCircle), ego, lead, 100).t();
    const double conc = vehicleTtc(config(DetectorKind::Concentric), ego, lead, 100).t();
    const double zr = std::hypot(5.0 / 6.0, 0.9);
    EXPECT_NEAR((box - five) * v, 2 * (5.0 / 3.0 + zr - 2.5), 1e-9);
    EXPECT_NEAR((box - conc) * v, std::hypot(5.0, 1.8) - 5.0, 1e-9);
  }
}

TEST(Vehicle, EquipmentDrawIsDeterministicAndUniform) {
  EXPECT_EQ(equipmentDraw(42, "main0.17"), equipmentDraw(42, "main0.17"));
  EXPECT_NE(equipmentDraw(42, "main0.17"), equipmentDraw(43, "main0.17"));
  int below = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double u = equipmentDraw(7, "veh" + std::to_string(i));
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    below += u < 0.3;
  }
  // binomial(20000, 0.3): sd = 65; 5 sd
  EXPECT_NEAR(below, 0.3 * n, 5 * 65);
}

TEST(Vehicle, DrawnEquippedFollowsThePenetration) {
  EXPECT_TRUE(drawnEquipped(7, "any", 1.0));
  EXPECT_FALSE(drawnEquipped(7, "any", 0.0));
  for (int i = 0; i < 100; ++i) {
    const std::string id = "veh" + std::to_string(i);
    EXPECT_EQ(drawnEquipped(7, id, 0.4), equipmentDraw(7, id) < 0.4);
  }
}

}  // namespace
}  // namespace st::highway
