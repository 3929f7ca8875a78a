// Rearrangement events, theta grids, ensemble statistics and the avalanche angle, on
// series whose answers are worked out by hand.
#include "cdpile/analysis/series.hpp"
#include "cdpile/analysis/stats.hpp"
#include "cdpile/error.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace cdpile;
using namespace cdpile::analysis;

TEST(Events, LocalMaximumToNextLocalMinimum) {
  std::vector<std::int64_t> n = {10, 11, 12, 12, 9, 8, 8, 10, 11, 7, 7, 7};
  auto ev = rearrangements(n, {});
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].peak, 3u);    // the last sample at the maximum
  EXPECT_EQ(ev[0].trough, 5u);  // the first sample at the minimum
  EXPECT_DOUBLE_EQ(ev[0].loss, 4.0 / 12.0);
  EXPECT_FALSE(ev[0].open);
  EXPECT_EQ(ev[1].peak, 8u);
  EXPECT_EQ(ev[1].trough, 9u);
  EXPECT_DOUBLE_EQ(ev[1].loss, 4.0 / 11.0);
  EXPECT_TRUE(ev[1].open);  // the series ends while N is down
}

TEST(Events, HysteresisMergesSmallRises) {
  std::vector<std::int64_t> n = {20, 15, 16, 10, 12};
  auto ev1 = rearrangements(n, {1, 1});
  ASSERT_EQ(ev1.size(), 2u);
  EXPECT_DOUBLE_EQ(ev1[0].loss, 5.0 / 20.0);
  EXPECT_DOUBLE_EQ(ev1[1].loss, 6.0 / 16.0);
  auto ev2 = rearrangements(n, {2, 1});
  ASSERT_EQ(ev2.size(), 1u);
  EXPECT_EQ(ev2[0].peak, 0u);
  EXPECT_EQ(ev2[0].trough, 3u);
  EXPECT_DOUBLE_EQ(ev2[0].loss, 10.0 / 20.0);
  auto ev3 = rearrangements(n, {1, 6});  // keep drops of >= 6 contacts
  ASSERT_EQ(ev3.size(), 1u);
  EXPECT_DOUBLE_EQ(ev3[0].loss, 6.0 / 16.0);
}

TEST(Events, FlatOrRisingSeriesHasNoEvent) {
  EXPECT_TRUE(rearrangements(std::vector<std::int64_t>{}, {}).empty());
  EXPECT_TRUE(rearrangements(std::vector<std::int64_t>{5, 5, 6, 7}, {}).empty());
  EXPECT_THROW(rearrangements(std::vector<std::int64_t>{1}, {0, 1}), Error);
}

TEST(Grid, BinsAndUpperEnd) {
  Grid g = make_grid(0.0, 0.2, 0.1);
  ASSERT_EQ(g.count, 2u);
  std::vector<double> th = {0.0, 0.05, 0.1, 0.15, 0.2, 0.3, -0.1};
  std::vector<double> v = {1, 2, 3, 4, 5, 100, 100};
  auto mean = bin_mean(th, v, g);
  auto mx = bin_max(th, v, g);
  EXPECT_DOUBLE_EQ(*mean[0], 1.5);
  EXPECT_DOUBLE_EQ(*mean[1], 4.0);
  EXPECT_DOUBLE_EQ(*mx[0], 2.0);
  EXPECT_DOUBLE_EQ(*mx[1], 5.0);
  Grid g2 = make_grid(0.0, 1.0, 0.25);
  auto m2 = bin_mean(th, v, g2);
  EXPECT_FALSE(m2[2]);  // empty bin
  EXPECT_THROW(make_grid(0, 1, 0), Error);
}

TEST(Grid, LowerEndAllowsRoundOff) {
  // 5.5 deg written in radians and read back is 5.499999999999999: it belongs to the
  // first bin of a grid that starts at 5.5, while a clearly lower angle does not.
  const double back = 5.5 * M_PI / 180.0 * 180.0 / M_PI;
  ASSERT_LT(back, 5.5);
  Grid g = make_grid(5.5, 6.5, 0.1);
  ASSERT_TRUE(g.bin(back));
  EXPECT_EQ(*g.bin(back), 0u);
  EXPECT_FALSE(g.bin(5.49));
}

TEST(Ensemble, MeanAndStandardErrorAcrossRuns) {
  std::vector<std::vector<std::optional<double>>> runs = {{1.0, std::nullopt}, {3.0, 5.0}};
  auto s = across_runs(runs, 2);
  EXPECT_EQ(s[0].n, 2);
  EXPECT_DOUBLE_EQ(*s[0].mean, 2.0);
  EXPECT_DOUBLE_EQ(*s[0].se, 1.0);  // sd = sqrt(2), se = sd / sqrt(2)
  EXPECT_EQ(s[1].n, 1);
  EXPECT_DOUBLE_EQ(*s[1].mean, 5.0);
  EXPECT_FALSE(s[1].se);  // one run: no standard error, not NaN
}

TEST(Stats, PooledClusterRobustError) {
  Sums a, b;
  a.add(1.0);
  a.add(1.0);
  b.add(4.0);
  std::vector<Sums> cl = {a, b, Sums{}};
  Pooled p = pooled_mean(cl, SeOver::runs);
  EXPECT_EQ(p.n, 3);
  EXPECT_EQ(p.clusters, 2);
  EXPECT_DOUBLE_EQ(*p.mean, 2.0);
  // residuals: 2 - 2*2 = -2 and 4 - 2 = 2; se = sqrt(2/1 * 8) / 3
  EXPECT_DOUBLE_EQ(*p.se, 4.0 / 3.0);
  EXPECT_EQ(p.over, SeOver::runs);

  std::vector<Sums> one = {a};
  Pooled q = pooled_mean(one, SeOver::runs);
  EXPECT_EQ(q.over, SeOver::contacts);
  EXPECT_DOUBLE_EQ(*q.se, 0.0);
  Pooled none = pooled_mean(std::vector<Sums>{}, SeOver::runs);
  EXPECT_FALSE(none.mean);
  EXPECT_FALSE(none.se);
}

TEST(Avalanche, FirstSustainedCrossing) {
  std::vector<double> th, e;
  for (int k = 0; k <= 10; ++k) th.push_back(0.1 * k);
  e = {0, 0, 2e-3, 0, 0, 2e-3, 2e-3, 2e-3, 2e-3, 2e-3, 2e-3};
  auto k = avalanche_index(th, e, {1e-3, 0.2});
  ASSERT_TRUE(k);
  EXPECT_EQ(*k, 5u);  // the blip at index 2 falls back within 0.2 deg
  e = {0, 0, 0, 0, 0, 0, 0, 0, 0, 2e-3, 3e-3};
  k = avalanche_index(th, e, {1e-3, 5.0});
  ASSERT_TRUE(k);
  EXPECT_EQ(*k, 9u);  // stays above until the run ends
  e.assign(11, 1e-4);
  EXPECT_FALSE(avalanche_index(th, e, {1e-3, 0.2}));
}
