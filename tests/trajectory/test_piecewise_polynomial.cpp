#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ucon/trajectory/piecewise_polynomial.hpp"

using namespace ucon::trajectory;

namespace {
constexpr int64_t kStart = 1'000'000'000;

// Two 2-D cubic pieces (order1 = 4): piece 0 on [0, 1] s, piece 1 on [1, 3] s.
// Piece 0: x = 1 + 2t + 3t^2 + 4t^3, y = -t^3. Piece 1: x = 10 - t, y = 5 t^2.
ucon::trajectory_t twoPieces() {
  ucon::trajectory_t m{};
  m.utime = kStart;
  m.plan_id = 7;
  m.start_utime = kStart;
  m.dim = 2;
  m.order1 = 4;
  m.num_pieces = 2;
  m.durations = {1.0, 2.0};
  m.coeffs = {1, 2, 3, 4, 0, 0, 0, -1, 10, -1, 0, 0, 0, 0, 5, 0};
  m.num_coeffs = 16;
  m.yaw = std::numeric_limits<double>::quiet_NaN();
  return m;
}
}  // namespace

TEST(PiecewisePolynomial, GivenTwoPiecesWhenSampledThenValueAndDerivativesMatchHandDerivation) {
  PiecewisePolynomial p;
  ASSERT_EQ(PiecewisePolynomial::fromMessage(twoPieces(), &p), TrajectoryStatus::kOk);
  EXPECT_EQ(p.numPieces(), 2);
  EXPECT_DOUBLE_EQ(p.duration(), 3.0);
  EXPECT_EQ(p.endUtime(), kStart + 3'000'000);

  // t = 0.5 in piece 0.
  TrajectorySample s = p.sample(kStart + 500'000);
  EXPECT_NEAR(s.position.x(), 1 + 1 + 0.75 + 0.5, 1e-12);
  EXPECT_NEAR(s.velocity.x(), 2 + 3 + 3, 1e-12);        // 2 + 6t + 12t^2
  EXPECT_NEAR(s.acceleration.x(), 6 + 12, 1e-12);       // 6 + 24t
  EXPECT_NEAR(s.jerk.x(), 24, 1e-12);
  EXPECT_NEAR(s.position.y(), -0.125, 1e-12);
  EXPECT_NEAR(s.velocity.y(), -0.75, 1e-12);
  EXPECT_NEAR(s.acceleration.y(), -3.0, 1e-12);
  EXPECT_NEAR(s.jerk.y(), -6.0, 1e-12);
  EXPECT_EQ(s.position.z(), 0.0);

  // t = 2.0: local time 1.0 in piece 1.
  s = p.sample(kStart + 2'000'000);
  EXPECT_NEAR(s.position.x(), 9.0, 1e-12);
  EXPECT_NEAR(s.velocity.x(), -1.0, 1e-12);
  EXPECT_NEAR(s.position.y(), 5.0, 1e-12);
  EXPECT_NEAR(s.velocity.y(), 10.0, 1e-12);
  EXPECT_NEAR(s.acceleration.y(), 10.0, 1e-12);
  EXPECT_NEAR(s.jerk.y(), 0.0, 1e-12);
}

TEST(PiecewisePolynomial, GivenTimesOutsideThenClampedToTheEnds) {
  PiecewisePolynomial p;
  ASSERT_EQ(PiecewisePolynomial::fromMessage(twoPieces(), &p), TrajectoryStatus::kOk);
  TrajectorySample before = p.sample(kStart - 5'000'000);
  EXPECT_EQ(before.t, 0.0);
  EXPECT_NEAR(before.position.x(), 1.0, 1e-12);
  EXPECT_NEAR(before.velocity.x(), 2.0, 1e-12);
  TrajectorySample after = p.sample(kStart + 50'000'000);
  EXPECT_EQ(after.t, 3.0);
  EXPECT_NEAR(after.position.x(), 8.0, 1e-12);   // 10 - 2
  EXPECT_NEAR(after.position.y(), 20.0, 1e-12);  // 5 * 4
}

TEST(PiecewisePolynomial, GivenAMessageWhenRoundTrippedThenSameArrays) {
  PiecewisePolynomial p;
  ASSERT_EQ(PiecewisePolynomial::fromMessage(twoPieces(), &p), TrajectoryStatus::kOk);
  ucon::trajectory_t m{};
  m.plan_id = 99;
  p.toMessage(&m);
  EXPECT_EQ(m.plan_id, 99);
  EXPECT_EQ(m.start_utime, kStart);
  EXPECT_EQ(m.num_pieces, 2);
  EXPECT_EQ(m.num_coeffs, 16);
  EXPECT_EQ(m.coeffs, twoPieces().coeffs);
  EXPECT_EQ(PiecewisePolynomial::validate(m), TrajectoryStatus::kOk);
}

TEST(PiecewisePolynomial, GivenBadMessagesThenEachRejectedWithItsStatus) {
  struct Case {
    const char* what;
    void (*mutate)(ucon::trajectory_t&);
    TrajectoryStatus expect;
  };
  const Case cases[] = {
      {"NaN coefficient", [](ucon::trajectory_t& m) { m.coeffs[5] = std::nan(""); },
       TrajectoryStatus::kNonFiniteCoefficient},
      {"Inf coefficient",
       [](ucon::trajectory_t& m) { m.coeffs[0] = std::numeric_limits<double>::infinity(); },
       TrajectoryStatus::kNonFiniteCoefficient},
      {"zero duration", [](ucon::trajectory_t& m) { m.durations[1] = 0.0; },
       TrajectoryStatus::kBadDuration},
      {"negative duration", [](ucon::trajectory_t& m) { m.durations[0] = -1.0; },
       TrajectoryStatus::kBadDuration},
      {"tiny duration", [](ucon::trajectory_t& m) { m.durations[0] = 1e-7; },
       TrajectoryStatus::kBadDuration},
      {"NaN duration", [](ucon::trajectory_t& m) { m.durations[0] = std::nan(""); },
       TrajectoryStatus::kBadDuration},
      {"num_pieces disagrees", [](ucon::trajectory_t& m) { m.num_pieces = 3; },
       TrajectoryStatus::kSizeMismatch},
      {"coeff count wrong",
       [](ucon::trajectory_t& m) {
         m.coeffs.pop_back();
         m.num_coeffs = 15;
       },
       TrajectoryStatus::kSizeMismatch},
      {"no pieces",
       [](ucon::trajectory_t& m) {
         m.num_pieces = 0;
         m.durations.clear();
         m.num_coeffs = 0;
         m.coeffs.clear();
       },
       TrajectoryStatus::kNoPieces},
      {"dim 4", [](ucon::trajectory_t& m) { m.dim = 4; }, TrajectoryStatus::kBadDimension},
      {"order1 0", [](ucon::trajectory_t& m) { m.order1 = 0; }, TrajectoryStatus::kBadOrder},
      {"start 0", [](ucon::trajectory_t& m) { m.start_utime = 0; }, TrajectoryStatus::kBadStartTime},
      {"too long", [](ucon::trajectory_t& m) { m.durations[0] = 2e5; }, TrajectoryStatus::kTooLong},
      {"overflows in the piece", [](ucon::trajectory_t& m) { m.coeffs[11] = 1e308; },  // 1e308 * 2^3
       TrajectoryStatus::kOverflow},
  };
  for (const Case& c : cases) {
    ucon::trajectory_t m = twoPieces();
    c.mutate(m);
    PiecewisePolynomial p;
    EXPECT_EQ(PiecewisePolynomial::fromMessage(m, &p), c.expect) << c.what;
    EXPECT_FALSE(p.valid()) << c.what;
    EXPECT_STRNE(toString(c.expect), "unknown");
  }
}

TEST(PiecewisePolynomial, GivenEmptyThenSamplesZeroAndIsInvalid) {
  PiecewisePolynomial p;
  EXPECT_FALSE(p.valid());
  EXPECT_EQ(p.sample(kStart).position.norm(), 0.0);
}
