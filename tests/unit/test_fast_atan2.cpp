// ucon::fastAtan2 against std::atan2 over the whole circle.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "ucon/fast_atan2.hpp"

TEST(FastAtan2, GivenDirectionsAllRoundTheCircleThenItAgreesWithStdAtan2ToTwentyMicroradians) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0), scale(-6.0, 6.0);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const double k = std::pow(10.0, scale(rng));  // 1e-6 .. 1e6: the ratio is what matters
    const double x = k * u(rng), y = k * u(rng);
    worst = std::max(worst, std::fabs(ucon::fastAtan2(y, x) - std::atan2(y, x)));
  }
  EXPECT_LT(worst, 2e-5);
  EXPECT_GT(worst, 1e-9) << "an approximation, not libm: the test must be able to tell";
  // The axes, the diagonals and the origin exactly where std::atan2 puts them.
  EXPECT_DOUBLE_EQ(ucon::fastAtan2(0.0, 1.0), 0.0);
  EXPECT_NEAR(ucon::fastAtan2(1.0, 0.0), M_PI / 2, 1e-12);
  EXPECT_NEAR(ucon::fastAtan2(0.0, -1.0), M_PI, 1e-12);
  EXPECT_NEAR(ucon::fastAtan2(-1.0, 0.0), -M_PI / 2, 1e-12);
  EXPECT_NEAR(ucon::fastAtan2(1.0, 1.0), M_PI / 4, 2e-5);
  EXPECT_NEAR(ucon::fastAtan2(-1.0, -1.0), -3 * M_PI / 4, 2e-5);
  EXPECT_EQ(ucon::fastAtan2(0.0, 0.0), 0.0);
  EXPECT_TRUE(std::isnan(ucon::fastAtan2(std::numeric_limits<double>::quiet_NaN(), 1.0)));
}
