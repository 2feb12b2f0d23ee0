// Point-level historical re-association (appendix algorithm) on hand-made point sets.
#include <gtest/gtest.h>

#include "ucon/perception/reassociation.hpp"

using namespace ucon::perception;

namespace {
Points blob(float cx, float cy, int n = 10) {
  Points p;
  for (int i = 0; i < n; ++i) p.emplace_back(cx + 0.02f * i, cy, 1.0f);
  return p;
}
}  // namespace

TEST(Reassociation, GivenHistoryDisplacedByVelocityThenTheNearbyCurrentPointsAreRecovered) {
  // P: a wall at x = 5 (indices 0..9) and the object's current points at x = 1.0 (10..19).
  Points P = blob(5.0f, 0.0f);
  const Points now = blob(1.0f, 0.0f);
  P.insert(P.end(), now.begin(), now.end());
  ProximityIndex index;
  index.build(P);
  // History 0.5 s old at x = 0.5, moving at +1 m/s: displaced onto x = 1.0.
  HistoricalObject obj{blob(0.5f, 0.0f), {1.0, 0.0, 0.0}, 0.5};
  const auto r = reassociate({obj}, index, 0.1, 0.35);
  ASSERT_EQ(r.size(), 1u);
  ASSERT_EQ(r[0].size(), 10u);
  EXPECT_EQ(r[0].front(), 10);
  EXPECT_EQ(r[0].back(), 19);
}

TEST(Reassociation, GivenNoPointsWithinD0ThenTheObjectIsNotRecovered) {
  Points P = blob(5.0f, 0.0f);
  ProximityIndex index;
  index.build(P);
  HistoricalObject obj{blob(0.5f, 0.0f), {1.0, 0.0, 0.0}, 0.5};
  EXPECT_TRUE(reassociate({obj}, index, 0.6, 0.35)[0].empty());
  // Without the v*tau displacement the same history would miss by 0.5 m with d0 = 0.1.
  Points Q = blob(1.0f, 0.0f);
  index.build(Q);
  HistoricalObject still{blob(0.5f, 0.0f), {0.0, 0.0, 0.0}, 0.5};
  EXPECT_TRUE(reassociate({still}, index, 0.1, 0.35)[0].empty());
}

TEST(Reassociation, GivenExactlyGammaTimesNMatchesThenItFailsAndOneMoreSucceeds) {
  // History: 10 points; only the first k have a current point nearby (gamma = 0.3 -> need > 3).
  Points hist = blob(0.0f, 0.0f);
  for (int k : {3, 4}) {
    Points P;
    for (int i = 0; i < k; ++i) P.push_back(hist[i]);
    P.emplace_back(9.0f, 9.0f, 1.0f);
    ProximityIndex index;
    index.build(P);
    // Points farther along the history line are > d0 = 0.01 from the matched ones.
    const auto r = reassociate({{hist, {0, 0, 0}, 0.0}}, index, 0.01, 0.3);
    if (k == 3) {
      EXPECT_TRUE(r[0].empty());
    } else {
      EXPECT_EQ(r[0].size(), 4u);
    }
  }
}

TEST(Reassociation, GivenTwoObjectsWantingTheSamePointsThenTheFirstKeepsThem) {
  Points P = blob(1.0f, 0.0f);
  ProximityIndex index;
  index.build(P);
  HistoricalObject a{blob(1.0f, 0.0f), {0, 0, 0}, 0.0};
  HistoricalObject b{blob(1.0f, 0.05f), {0, 0, 0}, 0.0};
  const auto r = reassociate({a, b}, index, 0.2, 0.35);
  EXPECT_EQ(r[0].size(), 10u);
  EXPECT_TRUE(r[1].empty());
}

TEST(Reassociation, GivenAnEmptyIndexOrBadInputThenNothingIsRecoveredAndNothingCrashes) {
  ProximityIndex empty;
  empty.build({});
  EXPECT_TRUE(reassociate({{blob(0, 0), {0, 0, 0}, 0.1}}, empty, 0.6, 0.35)[0].empty());
  Points P = blob(0.0f, 0.0f);
  ProximityIndex index;
  index.build(P);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(reassociate({{blob(0, 0), {nan, 0, 0}, 0.1}}, index, 0.6, 0.35)[0].empty());
  EXPECT_TRUE(reassociate({{{}, {0, 0, 0}, 0.1}}, index, 0.6, 0.35)[0].empty());
}
