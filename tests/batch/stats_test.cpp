#include <gtest/gtest.h>

#include <cmath>
#include <stbatch/stats.hpp>

namespace st::batch {
namespace {

TEST(BatchStats, HandComputedExample) {
  // x = 2 4 4 4 5 5 7 9: sum 40, mean 5; squared deviations 9+1+1+1+0+0+4+16 = 32;
  // sd = sqrt(32/7) = 2.138089935; t(0.975, 7) = 2.364624252; ci = t * sd / sqrt(8) = 5.0557793 / 2.8284271 = 1.787488
  const Summary s = summarize({2, 4, 4, 4, 5, 5, 7, 9});
  EXPECT_EQ(s.n, 8);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_NEAR(s.sd, 2.138089935, 1e-9);
  EXPECT_NEAR(s.ci95, 1.787488, 1e-6);
}

TEST(BatchStats, FiveSeeds) {
  // 0.8 1.1 0.9 1.3 0.9: mean 1.0, deviations^2 .04 .01 .01 .09 .01 = .16, sd = 0.2,
  // t(0.975, 4) = 2.776445, ci = 2.776445 * 0.2 / sqrt(5) = 0.248333
  const Summary s = summarize({0.8, 1.1, 0.9, 1.3, 0.9});
  EXPECT_NEAR(s.mean, 1.0, 1e-15);
  EXPECT_NEAR(s.sd, 0.2, 1e-15);
  EXPECT_NEAR(s.ci95, 0.248333, 1e-6);
}

TEST(BatchStats, SingleValueHasNoSpread) {
  const Summary s = summarize({3.5});
  EXPECT_EQ(s.n, 1);
  EXPECT_EQ(s.mean, 3.5);
  EXPECT_EQ(s.sd, 0.0);
  EXPECT_EQ(s.ci95, 0.0);
}

TEST(BatchStats, StudentQuantilesMatchTables) {
  // published two-sided 95% critical values
  EXPECT_NEAR(studentT975(1), 12.7062, 1e-4);
  EXPECT_NEAR(studentT975(10), 2.2281, 1e-4);
  EXPECT_NEAR(studentT975(40), 2.0211, 1e-4);
  EXPECT_NEAR(studentT975(60), 2.0003, 1e-4);
  EXPECT_NEAR(studentT975(120), 1.9799, 1e-4);
  EXPECT_NEAR(studentT975(100000), 1.95998, 1e-4);
}

// The median by hand: odd count the middle value, even the mean of the two middle ones, none NaN.
TEST(BatchStats, MedianByHand) {
  EXPECT_DOUBLE_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_TRUE(std::isnan(median({})));
}

}  // namespace
}  // namespace st::batch
