#include <gtest/gtest.h>

#include <cmath>

#include <stpool/rack.hpp>
#include <stpool/table.hpp>

namespace st::pool {
namespace {

TEST(Table, PocketedTableHasSixCushionsTwelveJawsSixPockets) {
  const Table t = makeTable(TableSpec{});
  EXPECT_EQ(t.cushions.size(), 6u);
  EXPECT_EQ(t.jaws.size(), 12u);
  EXPECT_EQ(t.pockets.size(), 6u);
  // corner mouths and side mouths as specified (jaw to jaw)
  EXPECT_NEAR((t.cushions[5].b - t.cushions[0].a).norm(), TableSpec{}.cornerMouth, 1e-15);
  EXPECT_NEAR((t.cushions[1].a - t.cushions[0].b).norm(), TableSpec{}.sideMouth, 1e-15);
}

TEST(Table, ClosedBoxIsFourWalls) {
  TableSpec spec;
  spec.pockets = false;
  const Table t = makeTable(spec);
  EXPECT_EQ(t.cushions.size(), 4u);
  EXPECT_TRUE(t.jaws.empty());
  EXPECT_TRUE(t.pockets.empty());
}

// The capture circles' two guarantees (table.cpp): every centre passing between two jaws without
// touching them is captured; a ball touching a jaw from the table side is not.
TEST(Table, PocketCapturesEveryPassageAndNoJawContact) {
  const Table t = makeTable(TableSpec{});
  const double r = kBallRadius;
  // pocket k's jaws: the end of one cushion and the start of the next
  for (int k = 0; k < 6; ++k) {
    const Vec2 j1 = t.cushions[(k + 5) % 6].b, j2 = t.cushions[k].a;
    // find the pocket nearest to this mouth
    const Vec2 mid = 0.5 * (j1 + j2);
    int pk = 0;
    for (int q = 1; q < 6; ++q)
      if ((t.pockets[q].center - mid).norm() < (t.pockets[pk].center - mid).norm()) pk = q;
    const Sensor<2>& p = t.pockets[pk];
    const Vec2 u = (j2 - j1).normalized();
    const double half = 0.5 * (j2 - j1).norm();
    for (int i = 0; i <= 100; ++i) {
      const double off = -(half - r) + 2.0 * (half - r) * i / 100.0;
      EXPECT_LE((mid + off * u - p.center).norm(), p.radius * (1 + 1e-12)) << "pocket " << k;
    }
    // inward normal of the mouth: towards the table centre
    Vec2 in(-u.y(), u.x());
    if (in.dot(Vec2(1.27, 0.635) - mid) < 0) in = -in;
    for (const Vec2& jaw : {j1, j2}) {
      const Vec2 along = (jaw == j1 ? u : Vec2(-u));  // from the jaw into the mouth
      for (int i = 1; i <= 90; ++i) {
        const double a = i * M_PI / 180.0;  // contact angle above the mouth line
        const Vec2 centre = jaw + r * (std::cos(a) * along + std::sin(a) * in);
        EXPECT_GT((centre - p.center).norm(), p.radius) << "pocket " << k << " angle " << i;
      }
    }
  }
}

TEST(Table, RejectsTooSmallTablesAndMouths) {
  TableSpec spec;
  spec.width = 0.2;
  EXPECT_THROW(makeTable(spec), std::invalid_argument);
  spec = TableSpec{};
  spec.sideMouth = 0.05;  // narrower than a ball
  EXPECT_THROW(makeTable(spec), std::invalid_argument);
}

TEST(Rack, StandardRackIsTightAndLegal) {
  const Table t = makeTable(TableSpec{});
  Rng rng(3);
  RackSpec spec;
  spec.gap = 2e-5;
  const auto balls = standardRack(t, spec, rng);
  ASSERT_EQ(balls.size(), 16u);
  EXPECT_EQ(balls[0].number, 0);
  EXPECT_EQ(balls[1].number, 1);  // apex
  std::vector<int> seen(16, 0);
  for (const auto& b : balls) ++seen[b.number];
  for (int n = 0; n < 16; ++n) EXPECT_EQ(seen[n], 1);
  // neighbours are between 2r + gap/2 and 2r + 3 gap/2 apart, never closer
  const double r = kBallRadius;
  int neighbours = 0;
  for (std::size_t i = 1; i < balls.size(); ++i)
    for (std::size_t j = i + 1; j < balls.size(); ++j) {
      const double d = (balls[i].position - balls[j].position).norm();
      EXPECT_GE(d, 2 * r + 0.5 * spec.gap);
      if (d < 2 * r + 1.5 * spec.gap) ++neighbours;
    }
  EXPECT_EQ(neighbours, 30);  // the triangle's 30 contacts
  // the 8 in the middle of the third row, a solid and a stripe in the back corners
  EXPECT_EQ(balls[5].number, 8);
  EXPECT_NE(defaultPattern(balls[11].number), defaultPattern(balls[15].number));
}

TEST(Rack, SameSeedSameRackOtherSeedOtherRack) {
  const Table t = makeTable(TableSpec{});
  RackSpec spec;
  spec.gap = 1e-4;
  Rng a(9), b(9), c(10);
  const auto ra = standardRack(t, spec, a), rb = standardRack(t, spec, b), rc = standardRack(t, spec, c);
  for (std::size_t i = 0; i < ra.size(); ++i) EXPECT_EQ(ra[i].position, rb[i].position);
  EXPECT_NE(ra[3].position, rc[3].position);
}

}  // namespace
}  // namespace st::pool
