#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <sthighway/tolerances.hpp>

#include "lane_prediction.hpp"

using st::Vec2;
using st::highway::detail::QuietLine;
namespace tol = st::highway::tol;

namespace {

// A centre line as the road prediction walks it: lane segments (start, direction, length, scale),
// the line from the foot through each segment's end, and the arcs of both.
struct Walk {
  std::vector<Vec2> start, dir, vertex;  // vertex[k]: the line's k-th point (0: the foot)
  std::vector<double> scale, lineS, laneS;  // lineS[k], laneS[k]: arcs at the k-th segment's end
};

Vec2 turned(const Vec2& d, double angle) {
  return Vec2(std::cos(angle) * d.x() - std::sin(angle) * d.y(), std::sin(angle) * d.x() + std::cos(angle) * d.y());
}

// The line's point at arc S (the prediction's linePoint: on along the last piece past the end).
Vec2 linePoint(const Walk& w, double S) {
  std::size_t k = 1;
  while (k + 1 < w.lineS.size() && w.lineS[k] < S) ++k;
  const double len = w.lineS[k] - w.lineS[k - 1];
  return w.vertex[k - 1] + (len > 0.0 ? (S - w.lineS[k - 1]) / len : 0.0) * (w.vertex[k] - w.vertex[k - 1]);
}

}  // namespace

// Wherever QuietLine says a body's window lies on quiet line, the chord the prediction would lay
// (from the line half a length behind to half ahead) has its middle within kChordOffset of the
// path's point and turns from the lane by at most kMergeBend: the work it skips would have left
// the body square to the lane. Random lines: bends from polyline noise to a few degrees, lanes
// whose shapes are longer than their lengths, joints with small gaps.
TEST(QuietLine, WhereItIsQuietNoBodyIsLaidOnAChord) {
  std::mt19937_64 rng(20261207);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  long windows = 0, lines = 0, quietToTheEnd = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double half = std::vector<double>{1.2, 2.5, 6.0, 9.0}[trial % 4];
    const double bendScale = std::pow(10.0, -6.0 + 5.0 * U(rng));  // 1e-6 .. 0.1 rad
    Walk w;
    Vec2 d = turned(Vec2(1.0, 0.0), 6.283 * U(rng));
    w.vertex.push_back(Vec2(3.0, -2.0));
    w.lineS.push_back(0.0);
    w.laneS.push_back(0.0);
    QuietLine quiet(d, half);
    double scale = 1.0;
    const int pieces = 1 + static_cast<int>(8 * U(rng));
    for (int k = 0; k < pieces; ++k) {
      Vec2 from = w.vertex.back();
      double gap = 0.0;
      if (k > 0) {
        d = turned(d, bendScale * (2.0 * U(rng) - 1.0));
        if (U(rng) < 0.3) {  // a joint between lanes: a new scale, maybe a gap
          scale = U(rng) < 0.5 ? 1.0 : 1.0 + 1e-3 * U(rng);
          const Vec2 g = turned(Vec2(1.0, 0.0), 6.283 * U(rng)) * (U(rng) < 0.5 ? 0.0 : 1e-4 * U(rng));
          from += g;
          gap = g.norm();
        }
      }
      const double length = 0.3 + 30.0 * U(rng);
      const Vec2 end = from + length * d;
      const Vec2 e = end - w.vertex.back();
      const double dS = std::max(0.0, e.dot(d)) / scale;
      if (quiet.open()) quiet.add(e, dS, d, scale, gap);
      w.start.push_back(from);
      w.dir.push_back(d);
      w.scale.push_back(scale);
      w.vertex.push_back(end);
      w.lineS.push_back(w.lineS.back() + dS);
      w.laneS.push_back(w.laneS.back() + length / scale);
    }
    quiet.finish();
    ++lines;
    if (std::isinf(quiet.end())) ++quietToTheEnd;
    // the path's points as the prediction's main loop has them: on each lane segment, at its arcs
    for (std::size_t k = 0; k < w.start.size(); ++k)
      for (double f = 0.0; f <= 1.0; f += 0.05) {
        const double S = w.laneS[k] + f * (w.laneS[k + 1] - w.laneS[k]);
        if (!(S >= half && S + half <= quiet.end())) continue;
        const Vec2 q = w.start[k] + ((S - w.laneS[k]) * w.scale[k]) * w.dir[k];
        const Vec2 ahead = linePoint(w, S + half), behind = linePoint(w, S - half);
        const Vec2 span = ahead - behind, m = 0.5 * (ahead + behind);
        const double angle = std::abs(std::atan2(w.dir[k].x() * span.y() - w.dir[k].y() * span.x(), w.dir[k].dot(span)));
        ASSERT_LE((m - q).norm(), tol::kChordOffset) << "trial " << trial << " S " << S;
        ASSERT_LE(angle, tol::kMergeBend) << "trial " << trial << " S " << S;
        ++windows;
      }
  }
  // the check ran, and most gentle lines are quiet all along: the work is skipped where it counts
  EXPECT_GT(windows, 20000);
  EXPECT_GT(quietToTheEnd, lines / 4);
}

// A line with a bend of a few degrees under the body is not quiet there (the chord is worked out).
TEST(QuietLine, ABendUnderTheBodyEndsTheQuiet) {
  const double half = 5.0;
  QuietLine quiet(Vec2(1.0, 0.0), half);
  quiet.add(Vec2(20.0, 0.0), 20.0, Vec2(1.0, 0.0), 1.0, 0.0);
  EXPECT_TRUE(quiet.open());
  EXPECT_EQ(quiet.end(), 20.0);
  const Vec2 d(std::cos(0.05), std::sin(0.05));
  quiet.add(10.0 * d, 10.0, d, 1.0, 0.0);
  EXPECT_FALSE(quiet.open());
  quiet.finish();
  EXPECT_EQ(quiet.end(), 20.0);  // a body reaching past 20 m is worked out
  QuietLine straight(Vec2(0.0, 1.0), half);
  straight.add(Vec2(0.0, 50.0), 50.0, Vec2(0.0, 1.0), 1.0, 0.0);
  straight.finish();
  EXPECT_TRUE(std::isinf(straight.end()));
}
