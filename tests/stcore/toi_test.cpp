#include <gtest/gtest.h>

#include <stcore/toi.hpp>

namespace st {
namespace {

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

TEST(ToiLine, IntersectAndDepart) {
  const Segment line{{0, 0}, {0, 1}};  // the y axis
  const Circle c{{-3, 0}, 1};
  EXPECT_NEAR(toiCircleLineIntersect(c, {1, 0}, line).t, 2.0, 1e-15);
  EXPECT_NEAR(toiCircleLineDepart(c, {1, 0}, line).t, 4.0, 1e-15);
  EXPECT_EQ(toiCircleLineIntersect(c, {-1, 0}, line).outcome, Outcome::Miss);
}

TEST(ToiPlane, SphereAxisPlane) {
  const Ball<3> b{{0, 0, 0}, 0.5};
  EXPECT_NEAR(toiBallAxisPlaneEnter<3>(b, {0, 0, 2}, 2, 1.5).t, 0.5, 1e-15);
  EXPECT_NEAR(toiBallAxisPlaneLeave<3>(b, {0, 0, 2}, 2, 1.5).t, 1.0, 1e-15);
}

}  // namespace
}  // namespace st
