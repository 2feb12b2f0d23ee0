// Min-cost assignment: optimum on small hand-checked matrices, rectangular shapes, and
// forbidden pairs (maximum number of allowed pairs first, then minimum cost).
#include <gtest/gtest.h>

#include <limits>

#include "ucon/mot/hungarian.hpp"

namespace {
constexpr double kX = std::numeric_limits<double>::infinity();

ucon::CostMatrix make(int r, int c, std::initializer_list<double> v) {
  ucon::CostMatrix m(r, c);
  m.values.assign(v.begin(), v.end());
  return m;
}
}  // namespace

TEST(Hungarian, GivenASquareMatrixThenTheOptimalPermutationIsFound) {
  // Greedy picks (0,0)=1 then (1,1)=7 or so; the optimum is 0->1, 1->2, 2->0 with 2+3+1 = 6.
  const auto m = make(3, 3, {1, 2, 9,  //
                             4, 7, 3,  //
                             1, 9, 8});
  const auto a = ucon::solveAssignment(m);
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a[0], 1);
  EXPECT_EQ(a[1], 2);
  EXPECT_EQ(a[2], 0);
}

TEST(Hungarian, GivenMoreRowsThanColumnsThenTheCheapestRowsAreAssigned) {
  const auto m = make(3, 2, {5, 9,  //
                             1, 8,  //
                             6, 2});
  const auto a = ucon::solveAssignment(m);
  EXPECT_EQ(a[0], -1);
  EXPECT_EQ(a[1], 0);
  EXPECT_EQ(a[2], 1);
}

TEST(Hungarian, GivenMoreColumnsThanRowsThenEachRowGetsItsBestFreeColumn) {
  const auto m = make(2, 4, {7, 3, 9, 1,  //
                             8, 2, 9, 2});
  const auto a = ucon::solveAssignment(m);
  EXPECT_EQ(a[0], 3);
  EXPECT_EQ(a[1], 1);
}

TEST(Hungarian, GivenForbiddenPairsThenTheNumberOfAllowedPairsIsMaximisedBeforeTheCost) {
  // 0->0 (1) + 1->1 (100) uses two allowed pairs; 0->1 (2) alone would be cheaper but smaller.
  const auto m = make(2, 2, {1, 2,  //
                             kX, 100});
  const auto a = ucon::solveAssignment(m);
  EXPECT_EQ(a[0], 0);
  EXPECT_EQ(a[1], 1);
}

TEST(Hungarian, GivenARowWithOnlyForbiddenPairsThenItStaysUnassigned) {
  const auto m = make(2, 2, {kX, kX,  //
                             3, 1});
  const auto a = ucon::solveAssignment(m);
  EXPECT_EQ(a[0], -1);
  EXPECT_EQ(a[1], 1);
  const auto nan = make(1, 1, {std::numeric_limits<double>::quiet_NaN()});
  EXPECT_EQ(ucon::solveAssignment(nan)[0], -1);
}

TEST(Hungarian, GivenEmptyMatricesThenNothingIsAssigned) {
  EXPECT_TRUE(ucon::solveAssignment(ucon::CostMatrix(0, 3)).empty());
  const auto a = ucon::solveAssignment(ucon::CostMatrix(2, 0));
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0], -1);
  EXPECT_EQ(a[1], -1);
}

TEST(Hungarian, GivenNegativeCostsThenTheMinimumIsStillFound) {
  const auto m = make(2, 2, {-1, -5,  //
                             -4, -1});
  const auto a = ucon::solveAssignment(m);  // -5 + -4 = -9 beats -2
  EXPECT_EQ(a[0], 1);
  EXPECT_EQ(a[1], 0);
}
