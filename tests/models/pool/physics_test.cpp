// Single events against their exact analytic answers, and the conservation laws over a break.
#include <gtest/gtest.h>

#include <cmath>

#include <stcore/tolerances.hpp>
#include <stpool/game.hpp>
#include <stpool/rack.hpp>

#include "pool_test_util.hpp"

namespace st::pool {
namespace {

using test::ball;
using test::oneTable;
using test::physical;

constexpr double r = kBallRadius;

std::vector<PoolEvent> playOne(Game& g, int number, Vec2 v, double limit) {
  std::vector<PoolEvent> ev;
  Shot s;
  s.ball = number;
  s.velocity = v;
  g.play(s, limit, [&](const PoolEvent& e) { ev.push_back(e); });
  return physical(ev);
}

// Equal masses head-on: the striker stops, the struck ball leaves with its velocity.
// Unequal: v1' = (m1 - m2)/(m1 + m2) v, v2' = 2 m1/(m1 + m2) v.
TEST(PoolPhysics, HeadOnCollisionExact) {
  for (const double m2 : {kBallMass, 0.5 * kBallMass, 2.0 * kBallMass}) {
    for (SpaceKind kind : {SpaceKind::None, SpaceKind::Tree}) {
      Scenario s = oneTable(false);
      s.balls = {ball(0, {0.5, 0.635}), ball(1, {1.0, 0.635}, Vec2::Zero(), m2)};
      Game g(s, test::config(kind));
      const double v = 2.0;
      const auto ev = playOne(g, 0, {v, 0}, (1.0 - 2 * r - 0.5) / v + 1e-3);
      ASSERT_GE(ev.size(), 1u);
      const PoolEvent& e = ev[0];
      EXPECT_EQ(e.kind, PoolEventKind::Ball);
      EXPECT_EQ(e.ball + e.other, 1);
      EXPECT_NEAR(e.t, (1.0 - 2 * r - 0.5) / v, 1e-15);
      const double m1 = kBallMass;
      const Vec2 v0 = e.ball == 0 ? e.v : e.otherV, v1 = e.ball == 0 ? e.otherV : e.v;
      EXPECT_NEAR(v0.x(), (m1 - m2) / (m1 + m2) * v, 1e-14);
      EXPECT_NEAR(v1.x(), 2 * m1 / (m1 + m2) * v, 1e-14);
      EXPECT_EQ(v0.y(), 0.0);
      EXPECT_EQ(v1.y(), 0.0);
      const Vec2 p0 = e.ball == 0 ? e.p : e.otherP;
      EXPECT_NEAR(p0.x(), 1.0 - 2 * r, 1e-15);
    }
  }
}

// A bank off the bottom cushion: angle in equals angle out, at the predicted time and place.
TEST(PoolPhysics, BankOffCushionExact) {
  Scenario s = oneTable(true);
  s.balls = {ball(0, {0.635, 0.635})};
  Game g(s, test::config(SpaceKind::Single));
  const Vec2 v(0.6, -0.8);  // 1 m/s
  const auto ev = playOne(g, 0, v, 1.0);
  ASSERT_GE(ev.size(), 1u);
  const double t = (0.635 - r) / 0.8;
  EXPECT_EQ(ev[0].kind, PoolEventKind::Cushion);
  EXPECT_EQ(ev[0].other, 0);  // bottom rail, left half
  EXPECT_NEAR(ev[0].t, t, 1e-15);
  EXPECT_NEAR(ev[0].p.x(), 0.635 + 0.6 * t, 1e-15);
  EXPECT_NEAR(ev[0].p.y(), r, 1e-15);
  // the simulator takes the contact normal from centre minus contact point (|.| = r), so position
  // roundoff (~1e-16 m) tilts it by ~1e-16/r: velocity exact to ~1e-14
  EXPECT_NEAR(ev[0].v.x(), 0.6, 1e-13);
  EXPECT_NEAR(ev[0].v.y(), 0.8, 1e-13);
}

// Straight down into the bottom side pocket: captured where its centre meets the capture circle.
TEST(PoolPhysics, BallIntoSidePocketExact) {
  Scenario s = oneTable(true);
  s.balls = {ball(0, {1.27, 0.5}), ball(3, {0.3, 0.3})};
  Game g(s, test::config(SpaceKind::Tree, 1));
  const auto ev = playOne(g, 0, {0, -2.0}, 5.0);
  ASSERT_EQ(ev.size(), 1u);
  const Sensor<2>& side = g.table().pockets[1];
  const double yCapture = side.center.y() + side.radius;
  EXPECT_EQ(ev[0].kind, PoolEventKind::Pocket);
  EXPECT_EQ(ev[0].other, 1);
  EXPECT_NEAR(ev[0].t, (0.5 - yCapture) / 2.0, 1e-15);
  EXPECT_FALSE(g.simulator().ball(0).active);
  ASSERT_EQ(g.pocketed().size(), 1u);
  EXPECT_EQ(g.pocketed()[0].number, 0);
  EXPECT_TRUE(g.atRest());  // the only moving ball is gone: rest state ends the shot
}

// Down onto the left jaw of the bottom side pocket, the centre r/2 inside the mouth: the contact
// normal is at 60 degrees, so (0, -1) reflects to (sqrt3/2, 1/2).
TEST(PoolPhysics, JawStrikeExact) {
  Scenario s = oneTable(true);
  const Table t = makeTable(s.table);
  const Vec2 jaw = t.cushions[0].b;  // (1.27 - sideMouth/2, 0)
  s.balls = {ball(0, {jaw.x() + 0.5 * r, 0.4})};
  Game g(s, test::config(SpaceKind::None));
  const auto ev = playOne(g, 0, {0, -1.0}, 0.5);
  ASSERT_GE(ev.size(), 1u);
  EXPECT_EQ(ev[0].kind, PoolEventKind::Jaw);
  const double yContact = r * std::sqrt(3.0) / 2.0;
  EXPECT_NEAR(ev[0].t, 0.4 - yContact, 1e-15);
  EXPECT_NEAR(ev[0].p.y(), yContact, 1e-15);
  EXPECT_NEAR(ev[0].v.x(), std::sqrt(3.0) / 2.0, 1e-14);
  EXPECT_NEAR(ev[0].v.y(), 0.5, 1e-14);
}

// A ball rolling along a long rail rides over the side pocket (the capture circle sits behind
// the mouth) but drops into the corner.
TEST(PoolPhysics, RailBallPassesSidePocketDropsInCorner) {
  Scenario s = oneTable(true);
  s.balls = {ball(0, {2.0, r})};
  Game g(s, test::config(SpaceKind::Single));
  const auto ev = playOne(g, 0, {-1.0, 0}, 5.0);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].kind, PoolEventKind::Pocket);
  EXPECT_EQ(ev[0].other, 0);  // lower-left corner
}

// 10 s frictionless break: kinetic energy (on the table plus carried into pockets) is conserved
// to 1e-9 relative, and at every event no two balls overlap deeper than the stcore slop.
TEST(PoolPhysics, BreakConservesEnergyAndNeverOverlaps) {
  for (SpaceKind kind : {SpaceKind::None, SpaceKind::Tree}) {
    for (bool pockets : {true, false}) {
      Scenario s = oneTable(pockets);
      Rng rng(42);
      RackSpec rack;
      rack.gap = 2e-5;
      s.balls = standardRack(makeTable(s.table), rack, rng);
      Game g(s, test::config(kind));
      Shot shot;
      shot.velocity = Vec2(8.0, 0.05);
      double worst = 0.0;
      std::size_t collisions = 0;
      const auto summary = g.play(shot, 10.0, [&](const PoolEvent& e) {
        if (e.kind == PoolEventKind::Ball) ++collisions;
        const auto& balls = g.simulator().balls();
        for (std::size_t i = 0; i < balls.size(); ++i) {
          if (!balls[i].active) continue;
          for (std::size_t j = i + 1; j < balls.size(); ++j) {
            if (!balls[j].active) continue;
            const double gap =
                (balls[i].positionAt(e.t) - balls[j].positionAt(e.t)).norm() - balls[i].radius - balls[j].radius;
            worst = std::min(worst, gap);
          }
        }
      });
      EXPECT_GT(collisions, 20u);
      EXPECT_GE(worst, -tol::kLinearSlop) << toString(kind);
      EXPECT_NEAR(summary.energyDrift(), 0.0, 1e-9) << toString(kind);
      if (!pockets) {
        EXPECT_NEAR(summary.keEnd, summary.keStart, 1e-9 * summary.keStart);
        EXPECT_EQ(summary.kePocketed, 0.0);
      }
      EXPECT_NEAR(summary.keStart, 0.5 * kBallMass * shot.velocity.squaredNorm(), 1e-15);
    }
  }
}

// The cushions carry momentum away, but between cushion hits the balls exchange only momentum:
// in a ball-only window (the break's first 0.05 s of contacts, before anything reaches a rail) it is conserved.
TEST(PoolPhysics, MomentumConservedWhileOnlyBallsCollide) {
  Scenario s = oneTable(false);
  Rng rng(5);
  RackSpec rack;
  rack.gap = 2e-5;
  s.balls = standardRack(makeTable(s.table), rack, rng);
  Game g(s, test::config(SpaceKind::Tree));
  Shot shot;
  shot.velocity = Vec2(3.0, 0.0);
  int ballEvents = 0;
  const auto sum = g.play(shot, 0.45, [&](const PoolEvent& e) {
    ASSERT_NE(e.kind, PoolEventKind::Cushion);
    if (e.kind == PoolEventKind::Ball) ++ballEvents;
  });
  EXPECT_GT(ballEvents, 15);
  EXPECT_NEAR((sum.momentumEnd - sum.momentumStart).norm(), 0.0, 1e-14);
}

}  // namespace
}  // namespace st::pool

namespace st::pool {
namespace {

// The integrity check: a speed the clock cannot resolve (the loader refuses it; the library's
// play() takes any finite velocity) overflows positions and the ball leaves the table without a
// cushion event. That must stop the run with an error, never pass as a played shot.
TEST(PoolPhysics, BallLeavingTheTableIsAnError) {
  for (SpaceKind kind : {SpaceKind::None, SpaceKind::Tree}) {
    Scenario s = oneTable(true);
    s.balls = {ball(0, {0.5, 0.5})};
    Game g(s, test::config(kind));
    Shot shot;
    shot.velocity = 1e300 * Vec2(std::cos(0.5236), std::sin(0.5236));
    try {
      g.play(shot, 10.0);
      ADD_FAILURE() << toString(kind) << ": the shot was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("shot 1: ball 0 left the table"), std::string::npos) << e.what();
    }
  }
  // a sane fast shot stays on: 1000 m/s for 0.1 s is ~40 cushions
  Scenario s = oneTable(false);
  s.balls = {ball(0, {0.5, 0.5})};
  Game g(s, test::config(SpaceKind::Tree));
  Shot shot;
  shot.velocity = 1000.0 * Vec2(std::cos(0.5236), std::sin(0.5236));
  EXPECT_NO_THROW(g.play(shot, 0.1));
}

}  // namespace
}  // namespace st::pool
