// bench nav's tracking figures: CLEAR-MOT of perception's output against the ground truth, as
// the mission adapter in the loop sees both.
#include "metrics.hpp"

#include <gtest/gtest.h>

#include <string>

#include "ucon/channels.hpp"

namespace {

using ucon::bench::nav::MissionAdapter;

template <typename M>
std::vector<uint8_t> encode(const M& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

ucon::sim_ground_truth_t groundTruth(int64_t t, std::vector<std::pair<int64_t, double>> movers) {
  ucon::sim_ground_truth_t g{};
  g.utime = t;
  for (const auto& [id, x] : movers) {
    ucon::sim_object_t o{};
    o.id = id;
    o.x = x;
    o.y = 0.0;
    o.radius = 0.25;
    o.visible = 1.0;
    g.objects.push_back(o);
  }
  g.num_objects = static_cast<int32_t>(g.objects.size());
  return g;
}

ucon::tracked_objects_t tracks(int64_t t, std::vector<std::pair<int64_t, double>> xs) {
  ucon::tracked_objects_t m{};
  m.utime = t;
  m.valid = true;
  for (const auto& [id, x] : xs) {
    ucon::tracked_object_t o{};
    o.id = id;
    o.x = x;
    o.state = ucon::tracked_object_t::STATE_CONFIRMED;
    m.objects.push_back(o);
  }
  m.num_objects = static_cast<int32_t>(m.objects.size());
  return m;
}

void feed(MissionAdapter& a, const std::string& channel, const std::vector<uint8_t>& b) {
  std::vector<ucon::replay::OutputMessage> out;
  ASSERT_EQ(a.feed(channel, b.data(), b.size(), &out), ucon::replay::FeedResult::kHandled);
}

}  // namespace

TEST(NavTracking, GivenTracksOnSomeMoversThenClearMotCountsMissesFalsePositivesAndRange) {
  MissionAdapter a(ucon::mission::MissionParams{}, {Eigen::Vector2d(30.0, 0.0)}, 60.0);
  // Ten frames: movers at 3 m and 6 m (scored) and 20 m (beyond the 15 m scored); one track
  // 0.2 m off the first mover, one 3 m from everything (a false positive). The ground truth
  // comes 10 ms before each frame's objects.
  for (int f = 0; f < 10; ++f) {
    const int64_t t = 1'000'000 + f * 20'000;
    feed(a, ucon::channels::kSimGroundTruth, encode(groundTruth(t - 10'000, {{1, 3.0}, {2, 6.0}, {3, 20.0}})));
    feed(a, ucon::channels::kPerceptionObjects, encode(tracks(t, {{7, 3.2}, {8, 9.0}})));
  }
  const auto s = a.clearMot();
  EXPECT_EQ(s.num_frames, 10);
  EXPECT_EQ(s.num_objects, 20);
  EXPECT_EQ(s.num_matches, 10);
  EXPECT_EQ(s.num_misses, 10);
  EXPECT_EQ(s.num_false_positives, 10);
  EXPECT_EQ(s.num_switches, 0);
  EXPECT_NEAR(s.mota, 0.0, 1e-12);  // 1 - (10 + 10) / 20
  EXPECT_NEAR(s.motp, 0.2, 1e-9);

  // Objects with no ground truth within 50 ms are not scored.
  MissionAdapter b(ucon::mission::MissionParams{}, {Eigen::Vector2d(30.0, 0.0)}, 60.0);
  feed(b, ucon::channels::kSimGroundTruth, encode(groundTruth(1'000'000, {{1, 3.0}})));
  feed(b, ucon::channels::kPerceptionObjects, encode(tracks(1'100'000, {{7, 3.0}})));
  EXPECT_EQ(b.clearMot().num_frames, 0);
}

// The velocity tallies of tracked movers within 5 m: every track in the overall sums, those at
// most kYoungFrames frames old also in the young tracks' sums.
TEST(NavTracking, GivenAYoungAndAnOldTrackThenTheYoungTracksVelocityFiguresAreTalliedApart) {
  MissionAdapter a(ucon::mission::MissionParams{}, {Eigen::Vector2d(30.0, 0.0)}, 60.0);
  constexpr int kYoung = ucon::bench::nav::TrackingTally::kYoungFrames;
  for (int f = 0; f < 10; ++f) {
    const int64_t t = 1'000'000 + f * 20'000;
    auto g = groundTruth(t, {{1, 3.0}, {2, 4.0}, {3, 8.0}});
    for (auto& o : g.objects) o.vx = 1.0;
    auto m = tracks(t, {{7, 3.0}, {8, 4.0}, {9, 8.0}});
    for (auto& o : m.objects) {
      o.cov_size = 36;
      o.cov.assign(36, 0.0);
      for (int i = 0; i < 6; ++i) o.cov[static_cast<std::size_t>(7 * i)] = 0.125;  // velocity trace 0.25
    }
    m.objects[0].age_frames = kYoung;  // young, standing: error 1 m/s
    m.objects[1].age_frames = kYoung + 1;  // old, exact
    m.objects[1].vx = 1.0;
    m.objects[2].age_frames = 1;  // young but 8 m away: not tallied
    feed(a, ucon::channels::kPerceptionObjects, encode(m));
    feed(a, ucon::channels::kSimGroundTruth, encode(g));
  }
  const auto& tt = a.tracking();
  EXPECT_EQ(tt.young.n, 10);
  EXPECT_NEAR(tt.young.err2_sum, 10.0, 1e-9);
  EXPECT_NEAR(tt.young.var_sum, 2.5, 1e-9);
  EXPECT_EQ(tt.verr_n, 20);
  EXPECT_NEAR(tt.verr2_sum, 10.0, 1e-9);
  ucon::bench::nav::Row row;
  ucon::bench::nav::RunResult r;
  r.young = tt.young;
  row.add(r);
  row.add(r);
  EXPECT_EQ(row.young.n, 20);
  EXPECT_NEAR(row.young.rmsError(), 1.0, 1e-9);
  EXPECT_NEAR(row.young.errorOverStd(), 2.0, 1e-9);  // 1 m/s against a stated 0.5 m/s
}

TEST(NavCollisions, GivenTheMoverHitsSamplesThenItIsHiddenUntrackedTrackedPoorlyOrTrackedWell) {
  using ucon::bench::nav::classifyHitTracking;
  using ucon::bench::nav::HitSample;
  using ucon::bench::nav::HitTracking;
  const HitSample none{}, good{true, 0.05, 0.1}, off{true, 0.45, 0.1}, fast{true, 0.05, 0.8};
  EXPECT_EQ(classifyHitTracking({}), HitTracking::kNone);
  EXPECT_EQ(classifyHitTracking({none, none, none}), HitTracking::kUntracked);
  EXPECT_EQ(classifyHitTracking({good, good, good}), HitTracking::kTrackedWell);
  // Late (no track at first), off, or with a wrong velocity at any sample: poorly.
  EXPECT_EQ(classifyHitTracking({none, good, good}), HitTracking::kTrackedPoorly);
  EXPECT_EQ(classifyHitTracking({good, off, good}), HitTracking::kTrackedPoorly);
  EXPECT_EQ(classifyHitTracking({good, good, fast}), HitTracking::kTrackedPoorly);
  // A sample with the mover hidden from the sensor makes it hidden, however it was tracked;
  // visibility not computed (NaN) and a mover in view leave the tracking classes.
  HitSample hidden = good, seen = good;
  hidden.visible = 0.1;
  seen.visible = 0.9;
  EXPECT_EQ(classifyHitTracking({good, hidden, good}), HitTracking::kHidden);
  EXPECT_EQ(classifyHitTracking({none, none, hidden}), HitTracking::kHidden);
  EXPECT_EQ(classifyHitTracking({seen, seen, seen}), HitTracking::kTrackedWell);
  seen.visible = ucon::bench::nav::kHiddenVisibility;  // at the bound: in view
  EXPECT_EQ(classifyHitTracking({seen, off}), HitTracking::kTrackedPoorly);
}

// The collision report says whether the mover hit came out of a static obstacle (the bench
// worlds' movers walk through them) within the 2 s of ground truth kept before the hit.
TEST(NavCollisions, GivenAMoverThatCameOutOfAStaticObstacleThenTheHitSaysSo) {
  ucon::world::Scenario sc;
  ucon::world::StaticObstacle pillar;
  pillar.center = ucon::world::Vec2(2.0, 0.0);
  pillar.radius = 0.5;
  sc.statics.push_back(pillar);
  const ucon::world::World world(sc);
  EXPECT_NEAR(ucon::bench::nav::staticGap(world, 1.2, 0.0, 0.25), 0.05, 1e-9);
  EXPECT_NEAR(ucon::bench::nav::staticGap(world, 2.0, 0.0, 0.25), -0.75, 1e-9);
  // Mover 1 walks from `x0` to the robot (at the origin) in 1 s, 50 steps, and hits it.
  const auto run = [](MissionAdapter& a, double x0) {
    for (int k = 0; k <= 50; ++k) {
      auto g = groundTruth(1'000'000 + k * 20'000, {{1, x0 + (0.28 - x0) * k / 50.0}});
      g.objects[0].vx = 0.28 - x0;  // [m/s]: closing in on the robot
      g.collision = k == 50;
      feed(a, ucon::channels::kSimGroundTruth, encode(g));
    }
  };
  MissionAdapter out_of_it(ucon::mission::MissionParams{}, {Eigen::Vector2d(30.0, 0.0)}, 60.0, &world);
  run(out_of_it, 2.0);  // starts inside the pillar; its body is last on the footprint at step 21 (x > 1.25)
  ASSERT_TRUE(out_of_it.collided());
  EXPECT_TRUE(out_of_it.hitMover());
  EXPECT_TRUE(out_of_it.hitThroughStatic());
  EXPECT_NE(out_of_it.collisionWith().find("inside a static obstacle 0.58 s before"), std::string::npos)
      << out_of_it.collisionWith();
  // Every step was a close encounter (within 3 m, closing), each within 2 s of the pillar.
  EXPECT_EQ(out_of_it.tracking().close_total, 51);
  EXPECT_EQ(out_of_it.tracking().close_through_static, 51);
  MissionAdapter beside_it(ucon::mission::MissionParams{}, {Eigen::Vector2d(30.0, 0.0)}, 60.0, &world);
  run(beside_it, 1.2);  // starts 5 cm off the pillar
  ASSERT_TRUE(beside_it.collided());
  EXPECT_FALSE(beside_it.hitThroughStatic());
  EXPECT_EQ(beside_it.collisionWith().find("inside a static obstacle"), std::string::npos);
  EXPECT_EQ(beside_it.tracking().close_total, 51);
  EXPECT_EQ(beside_it.tracking().close_through_static, 0);
  MissionAdapter no_world(ucon::mission::MissionParams{}, {Eigen::Vector2d(30.0, 0.0)}, 60.0);
  run(no_world, 2.0);
  EXPECT_FALSE(no_world.hitThroughStatic());
  EXPECT_EQ(no_world.tracking().close_total, 0);  // not counted without a world
}

TEST(NavAcquisition, GivenMoversComingIntoViewThenTheDelayToTheirFirstTrackIsRecordedOrTheMiss) {
  ucon::bench::nav::AcquisitionTally a;
  // Mover 1 comes into view untracked at 1.0 s and is tracked at 1.3 s: one delay of 0.3 s.
  a.step(900000, 1, false, false);
  a.step(1000000, 1, true, false);
  a.step(1100000, 1, true, false);
  a.step(1300000, 1, true, true);
  a.step(1400000, 1, true, false);  // losing the track later is not a new arrival
  // Mover 2 comes into view, then hides again untracked: a miss.
  a.step(1000000, 2, true, false);
  a.step(1200000, 2, false, false);
  // Mover 3 comes into view already held (a coasting track): no arrival.
  a.step(1000000, 3, true, true);
  a.step(1100000, 3, true, true);
  // Mover 4 comes into view, hides, comes back and is tracked: one miss, then one delay.
  a.step(1000000, 4, true, false);
  a.step(1100000, 4, false, false);
  a.step(2000000, 4, true, false);
  a.step(2100000, 4, true, true);
  // Mover 5 still open at the end: not counted.
  a.step(3000000, 5, true, false);
  ASSERT_EQ(a.delays().size(), 2u);
  EXPECT_NEAR(a.delays()[0], 0.3, 1e-12);
  EXPECT_NEAR(a.delays()[1], 0.1, 1e-12);
  EXPECT_EQ(a.missed(), 2);
}

// The pipeline check fails a run whose robot never drove, not one that detoured and was hit
// before it got closer to its goal (bench:110:66 on seeds 1-120).
TEST(NavPipeline, GivenARobotThatDroveAwayFromItsGoalThenThePipelineIsNotBroken) {
  using ucon::bench::nav::RunResult;
  RunResult r;
  r.ok = true;
  r.messages = {{ucon::channels::kLidarPoints, 10}, {ucon::channels::kPerceptionObjects, 10},
                {ucon::channels::kPlannerTrajectory, 10}};
  r.wheel_cmds_applied = 10;
  r.dist_start_goal = 48.0;
  std::string why;
  // Never moved: broken.
  r.dist_left = 48.0;
  r.dist_from_start = 0.2;
  EXPECT_TRUE(r.pipelineBroken(&why));
  EXPECT_NE(why.find("1 m closer"), std::string::npos);
  // 3 m sideways and back, 0.1 m closer: it drove.
  r.dist_left = 47.9;
  r.dist_from_start = 3.0;
  EXPECT_FALSE(r.pipelineBroken(&why));
  // 1.5 m closer: it drove.
  r.dist_left = 46.5;
  r.dist_from_start = 1.5;
  EXPECT_FALSE(r.pipelineBroken(&why));
  // No wheel command reached the plant: broken whatever the distances.
  r.wheel_cmds_applied = 0;
  EXPECT_TRUE(r.pipelineBroken(&why));
}
