// bench nav's line-of-sight oracle (--oracle-objects --oracle-line-of-sight): what a tracker
// that is perfect on what the sensor sees would publish.
#include "probes.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using ucon::bench::nav::LineOfSightOracle;

ucon::sim_object_t mover(int64_t id, double x, double vx, double visible) {
  ucon::sim_object_t o{};
  o.id = id;
  o.x = x;
  o.y = 0.0;
  o.vx = vx;
  o.vy = 0.0;
  o.radius = 0.25;
  o.height = 1.7;
  o.visible = visible;
  return o;
}

ucon::sim_ground_truth_t groundTruth(int64_t utime, std::vector<ucon::sim_object_t> movers) {
  ucon::sim_ground_truth_t g{};
  g.utime = utime;
  g.objects = std::move(movers);
  g.num_objects = static_cast<int32_t>(g.objects.size());
  return g;
}

const ucon::tracked_object_t* byId(const ucon::tracked_objects_t& m, int64_t id) {
  for (const auto& o : m.objects)
    if (o.id == id) return &o;
  return nullptr;
}

TEST(LineOfSightOracle, GivenMoversInViewHiddenAndNeverSeenThenItPublishesWhatAPerfectTrackerWould) {
  LineOfSightOracle oracle(12.0, 1.5, 0.0);
  // t = 0: mover 1 in view, mover 2 hidden and never seen, mover 3 in view but beyond range,
  // mover 4 with its visibility not computed (NaN: not known to be in view).
  auto m = oracle.objects(groundTruth(0, {mover(1, 3.0, 1.0, 0.8), mover(2, 4.0, 0.0, 0.1),
                                          mover(3, 13.0, 0.0, 1.0), mover(4, 5.0, 0.0, NAN)}),
                          0);
  ASSERT_EQ(m.objects.size(), 1u);
  const auto* o = byId(m, 1);
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->state, ucon::tracked_object_t::STATE_CONFIRMED);
  EXPECT_DOUBLE_EQ(o->x, 3.0);
  EXPECT_DOUBLE_EQ(o->vx, 1.0);
  // t = 0.5 s: mover 1 hidden, having walked on and turned: the oracle coasts it along its last
  // seen velocity with a grown position std, not at its true place.
  m = oracle.objects(groundTruth(500000, {mover(1, 3.2, -1.0, 0.2), mover(2, 4.0, 0.0, 0.29)}), 1);
  ASSERT_EQ(m.objects.size(), 1u);
  o = byId(m, 1);
  ASSERT_NE(o, nullptr);
  EXPECT_EQ(o->state, ucon::tracked_object_t::STATE_COASTING);
  EXPECT_NEAR(o->x, 3.5, 1e-9);
  EXPECT_NEAR(o->vx, 1.0, 1e-9);
  const double std_xy = 0.05 + LineOfSightOracle::kCoastStdPerS * 0.5;
  ASSERT_EQ(o->cov.size(), 36u);
  EXPECT_NEAR(o->cov[0], std_xy * std_xy, 1e-9);
  // t = 2.1 s: hidden longer than the coast time: gone; mover 2 now in view (at the bound).
  m = oracle.objects(groundTruth(2100000, {mover(1, 2.0, -1.0, 0.0), mover(2, 4.0, 0.0, 0.3)}), 2);
  ASSERT_EQ(m.objects.size(), 1u);
  EXPECT_NE(byId(m, 2), nullptr);
}

TEST(LineOfSightOracle, GivenADelayThenAMoverIsGivenOnlyOnceInViewThatLongWithoutABreak) {
  LineOfSightOracle oracle(12.0, 1.5, 0.25);
  const auto at = [&](int64_t t_us, double visible) {
    return oracle.objects(groundTruth(t_us, {mover(1, 3.0, 0.0, visible)}), 0).objects.size();
  };
  EXPECT_EQ(at(0, 1.0), 0u);        // comes into view
  EXPECT_EQ(at(200000, 1.0), 0u);   // 0.2 s in view
  EXPECT_EQ(at(300000, 0.0), 0u);   // hidden before the delay: never given, so not coasted
  EXPECT_EQ(at(400000, 1.0), 0u);   // back in view: the delay starts again
  EXPECT_EQ(at(600000, 1.0), 0u);   // 0.2 s
  EXPECT_EQ(at(700000, 1.0), 1u);   // 0.3 s: given
  EXPECT_EQ(at(800000, 0.0), 1u);   // hidden: coasted
  EXPECT_EQ(at(900000, 1.0), 1u);   // back in view while coasting: its track takes it back
  EXPECT_EQ(at(1000000, 0.0), 1u);  // hidden again: coasted ...
  EXPECT_EQ(at(2600000, 0.0), 0u);  // ... for at most 1.5 s
  EXPECT_EQ(at(2700000, 1.0), 0u);  // back in view with no track: the delay starts again
}

}  // namespace
