// The avalanche rule (sim/avalanche.hpp; docs/method.md, "Avalanche"): confirmed once the
// agitation stays at or above the threshold for `hold` steps in a row, at the tilt where
// that interval began; a dip (or a NaN) starts the count again.
#include "cdpile/sim/avalanche.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace cdpile;

TEST(Avalanche, ConfirmedAfterHoldStepsAtTheStartOfTheInterval) {
  sim::AvalancheDetector d;
  d.threshold = 1.0;
  d.hold = 3;
  const double a[] = {0.5, 2.0, 2.0, 0.9, 1.0, NAN, 1.5, 1.5, 1.5, 0.0};
  for (int k = 0; k < 10; ++k) d.update(k + 1, 0.1 * (k + 1), a[k]);
  ASSERT_TRUE(d.detected);
  EXPECT_EQ(d.start_step, 7);
  EXPECT_EQ(d.confirmed_step, 9);
  EXPECT_DOUBLE_EQ(d.angle_deg, 0.7);
}

TEST(Avalanche, StepsForRoundsUpButNotTheRoundingOfTheRate) {
  EXPECT_EQ(sim::steps_for(2.0, 0.001), 2000);
  EXPECT_EQ(sim::steps_for(0.0015, 0.001), 2);
}
