// Rolling resistance: balls decelerate at a constant rate along straight paths and stop; the
// impact times come from the quartic solver. Checked against the closed-form kinematics.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include <stcore/tolerances.hpp>
#include <stpool/game.hpp>
#include <stpool/rack.hpp>

#include "pool_test_util.hpp"

namespace st::pool {
namespace {

using test::ball;
using test::physical;

constexpr double r = kBallRadius;

struct Played {
  std::vector<PoolEvent> events;
  ShotSummary summary;
};

Played play(Game& g, int number, Vec2 v, double limit) {
  Played p;
  Shot s;
  s.ball = number;
  s.velocity = v;
  p.summary = g.play(s, limit, [&](const PoolEvent& e) { p.events.push_back(e); });
  p.events = physical(p.events);
  return p;
}

// A lone ball stops at t = v0/a after v0^2/(2a), and the rest state ends the shot there.
TEST(PoolFriction, LoneBallStopsAtAnalyticTimeAndPlace) {
  for (SpaceKind kind : {SpaceKind::Single, SpaceKind::Tree}) {
    Scenario s = test::oneTable(true);
    s.friction = 0.5;
    s.balls = {ball(0, {0.6, 0.635})};
    Game g(s, test::config(kind));
    const double v0 = 1.0;
    const Played p = play(g, 0, {v0, 0}, 10.0);
    ASSERT_EQ(p.events.size(), 1u);
    EXPECT_EQ(p.events[0].kind, PoolEventKind::Rest);
    EXPECT_NEAR(p.events[0].t, v0 / s.friction, 1e-15);
    EXPECT_NEAR(p.events[0].p.x(), 0.6 + v0 * v0 / (2 * s.friction), 1e-15);
    EXPECT_EQ(p.events[0].v, Vec2::Zero());
    EXPECT_EQ(p.summary.ending, ShotEnd::Rest);
    EXPECT_NEAR(p.summary.end, v0 / s.friction, 1e-15);
    EXPECT_EQ(p.summary.keEnd, 0.0);
  }
}

// A bank does not change the speed, so the stopping time is still v0/a; the cushion is met when
// v0 t - a t^2/2 covers the distance to it.
TEST(PoolFriction, BankedBallStillStopsAtV0OverA) {
  Scenario s = test::oneTable(false);
  s.friction = 0.4;
  s.balls = {ball(0, {2.0, 0.635})};
  Game g(s, test::config(SpaceKind::Tree));
  const double v0 = 1.5, dist = 2.54 - r - 2.0;
  const Played p = play(g, 0, {v0, 0}, 10.0);
  ASSERT_EQ(p.events.size(), 2u);
  EXPECT_EQ(p.events[0].kind, PoolEventKind::Cushion);
  const double tHit = (v0 - std::sqrt(v0 * v0 - 2 * s.friction * dist)) / s.friction;
  EXPECT_NEAR(p.events[0].t, tHit, 1e-14);
  EXPECT_NEAR(p.events[0].v.x(), -(v0 - s.friction * tHit), 1e-14);
  EXPECT_EQ(p.events[1].kind, PoolEventKind::Rest);
  EXPECT_NEAR(p.events[1].t, v0 / s.friction, 1e-14);
  EXPECT_NEAR(p.events[1].p.x(), 2.54 - r - (v0 * v0 / (2 * s.friction) - dist), 1e-14);
}

// A decelerating ball reaches a resting one when v0 t - a t^2/2 = d - 2r and, the masses being
// equal, hands over all its speed: then the struck ball stops after (v0 - a t)^2 / (2a).
TEST(PoolFriction, DeceleratingHeadOnCollision) {
  Scenario s = test::oneTable(false);
  s.friction = 0.3;
  s.balls = {ball(0, {0.5, 0.635}), ball(1, {1.0, 0.635})};
  Game g(s, test::config(SpaceKind::None));
  const double v0 = 1.0, gap = 0.5 - 2 * r;
  const Played p = play(g, 0, {v0, 0}, 10.0);
  ASSERT_EQ(p.events.size(), 2u);  // the collision; the striker stops dead there, no Rest needed
  ASSERT_EQ(p.events[0].kind, PoolEventKind::Ball);
  const double t = (v0 - std::sqrt(v0 * v0 - 2 * s.friction * gap)) / s.friction;
  const double v1 = v0 - s.friction * t;
  EXPECT_NEAR(p.events[0].t, t, 1e-14);
  const Vec2 vStriker = p.events[0].ball == 0 ? p.events[0].v : p.events[0].otherV;
  const Vec2 vStruck = p.events[0].ball == 0 ? p.events[0].otherV : p.events[0].v;
  EXPECT_NEAR(vStriker.norm(), 0.0, 1e-15);
  EXPECT_NEAR(vStruck.x(), v1, 1e-14);
  EXPECT_EQ(p.events[1].kind, PoolEventKind::Rest);
  EXPECT_EQ(p.events[1].ball, 1);
  EXPECT_NEAR(p.events[1].t, t + v1 / s.friction, 1e-14);
  EXPECT_NEAR(p.events[1].p.x(), 1.0 + v1 * v1 / (2 * s.friction), 1e-14);
}

// A break with friction: every ball comes to rest (the rest state ends the shot well before the
// limit), kinetic energy never rises, no two balls overlap, and version I and II agree exactly.
TEST(PoolFriction, BreakComesToRestIdenticallyInEverySpace) {
  std::vector<PoolEvent> reference;
  for (SpaceKind kind : {SpaceKind::None, SpaceKind::Single, SpaceKind::Tree, SpaceKind::Cells}) {
    Scenario s = test::oneTable(true);
    s.friction = 0.2;
    Rng rng(42);
    RackSpec rack;
    rack.gap = 2e-5;
    s.balls = standardRack(makeTable(s.table), rack, rng);
    s.space.cellSize = 0.15;
    SpaceSpec sp = s.space;
    sp.kind = kind;
    Game g(s, simulatorConfig(sp, s.table, s.balls));
    Shot shot;
    shot.velocity = Vec2(8.0, 0.0);
    double worst = 0.0, lastKe = 1e300;
    bool keRose = false;
    std::vector<PoolEvent> ev;
    const ShotSummary sum = g.play(shot, 60.0, [&](const PoolEvent& e) {
      ev.push_back(e);
      const double ke = g.simulator().kineticEnergy();
      if (e.kind != PoolEventKind::Strike && ke > lastKe * (1 + 1e-12)) keRose = true;
      lastKe = ke;
      const auto& balls = g.simulator().balls();
      for (std::size_t i = 0; i < balls.size(); ++i)
        for (std::size_t j = i + 1; j < balls.size(); ++j) {
          if (!balls[i].active || !balls[j].active) continue;
          worst = std::min(worst, (balls[i].positionAt(e.t) - balls[j].positionAt(e.t)).norm() - 2 * r);
        }
    });
    EXPECT_EQ(sum.ending, ShotEnd::Rest) << toString(kind);
    EXPECT_LT(sum.end, 30.0);
    EXPECT_TRUE(g.atRest());
    EXPECT_EQ(g.simulator().kineticEnergy(), 0.0);
    EXPECT_FALSE(keRose) << toString(kind);
    EXPECT_GE(worst, -tol::kLinearSlop) << toString(kind);
    ev = physical(ev);
    int rests = 0;
    for (const auto& e : ev) rests += e.kind == PoolEventKind::Rest;
    EXPECT_GE(rests + static_cast<int>(g.pocketed().size()), 15);  // nearly every ball moved, then stopped
    if (reference.empty()) {
      reference = ev;
      continue;
    }
    ASSERT_EQ(ev.size(), reference.size()) << toString(kind);
    for (std::size_t i = 0; i < ev.size(); ++i) {
      // a ball-ball event may be held by either ball: compare the unordered pair
      const auto key = [](const PoolEvent& e) {
        return e.kind == PoolEventKind::Ball ? std::make_tuple(e.kind, std::min(e.ball, e.other), std::max(e.ball, e.other))
                                             : std::make_tuple(e.kind, e.ball, e.other);
      };
      ASSERT_EQ(ev[i].t, reference[i].t) << toString(kind) << " event " << i;
      ASSERT_EQ(key(ev[i]), key(reference[i])) << toString(kind) << " event " << i;
    }
  }
}

}  // namespace
}  // namespace st::pool
