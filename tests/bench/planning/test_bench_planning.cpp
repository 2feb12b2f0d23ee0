// The pieces of the planning benchmark's open-loop protocol (issue 31): McNemar's test, Wilson
// intervals, line-of-sight occlusion, the track rules of line-of-sight observation and the
// play-back of a plan against the true motion.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "observation.hpp"
#include "paired_stats.hpp"
#include "probe.hpp"
#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/world/world.hpp"

namespace ucon::bench {
namespace {

world::MovingObstacle mover(int64_t id, double x, double y, double vx, double vy, double r) {
  world::MovingObstacle m;
  m.id = id;
  m.radius = r;
  m.motion.kind = world::MotionKind::kConstantVelocity;
  m.motion.position = world::Vec2(x, y);
  m.motion.velocity = world::Vec2(vx, vy);
  return m;
}

world::StaticObstacle pillar(double x, double y, double r) {
  world::StaticObstacle s;
  s.kind = world::ShapeKind::kCylinder;
  s.center = world::Vec2(x, y);
  s.radius = r;
  s.height = 2.0;
  return s;
}

world::Scenario scene(std::vector<world::StaticObstacle> statics, std::vector<world::MovingObstacle> movers) {
  world::Scenario sc;
  sc.name = "test";
  sc.statics = std::move(statics);
  sc.movers = std::move(movers);
  EXPECT_FALSE(world::validate(sc).has_value()) << *world::validate(sc);
  return sc;
}

/// A 2-D linear piece p(t) = p0 + v t over `duration` seconds from `start_utime`.
trajectory::PiecewisePolynomial line(Eigen::Vector2d p0, Eigen::Vector2d v, double duration, int64_t start_utime = 1) {
  trajectory::PiecewisePolynomial pp;
  EXPECT_EQ(trajectory::PiecewisePolynomial::create(start_utime, 2, 2, {duration}, {p0.x(), v.x(), p0.y(), v.y()}, &pp),
            trajectory::TrajectoryStatus::kOk);
  return pp;
}

TEST(PairedStats, McNemarMatchesExactBinomialAndChiSquare) {
  // b = 10, c = 2: 2 * P[Bin(12, 1/2) <= 2] = 2 * 79 / 4096 = 79/2048; chi2 = (8 - 1)^2 / 12.
  const McNemar t = mcnemar(10, 2);
  EXPECT_NEAR(t.exact_p, 79.0 / 2048.0, 1e-12);
  EXPECT_NEAR(t.chi2, 49.0 / 12.0, 1e-12);
  EXPECT_NEAR(t.chi2_p, 0.0433081, 1e-6);
  // Symmetric in b and c.
  EXPECT_NEAR(mcnemar(2, 10).exact_p, t.exact_p, 1e-15);
  // Agresti's approval ratings (150 vs 86 discordant): exact p computed with integers.
  EXPECT_NEAR(mcnemar(150, 86).exact_p, 3.715936e-05, 1e-10);
  EXPECT_NEAR(mcnemar(150, 86).chi2, 63.0 * 63.0 / 236.0, 1e-9);
  // Thousands of pairs (log-space sum).
  EXPECT_NEAR(mcnemar(1200, 1100).exact_p, 0.0389668527, 1e-8);
  // No discordant pairs, or as many each way: no evidence.
  EXPECT_EQ(mcnemar(0, 0).exact_p, 1.0);
  EXPECT_EQ(mcnemar(5, 5).exact_p, 1.0);
  EXPECT_NEAR(mcnemar(5, 5).chi2_p, 1.0, 1e-12);
}

TEST(PairedStats, WilsonAndPairedDifference) {
  const Interval w = wilson(0, 10);
  EXPECT_EQ(w.lo, 0.0);
  EXPECT_NEAR(w.hi, 3.8416 / 13.8416, 1e-12);  // z^2 / (n + z^2), z = 1.96
  const Interval half = wilson(50, 100);
  EXPECT_NEAR(half.lo, 0.403829, 1e-6);
  EXPECT_NEAR(half.hi, 0.596171, 1e-6);
  const PairedDifference d = pairedDifference(30, 10, 1000);
  EXPECT_NEAR(d.diff, 0.02, 1e-15);
  EXPECT_NEAR(d.hi - d.diff, 1.96 * std::sqrt(40.0 - 400.0 / 1000.0) / 1000.0, 1e-15);
  EXPECT_TRUE(std::isnan(pairedDifference(0, 0, 0).diff));
}

TEST(Observation, StaticObstaclesAndOtherMoversOcclude) {
  const world::Scenario sc = scene({pillar(2.5, 0.0, 0.6)},
                                   {mover(1, 5.0, 0.0, 0, 0, 0.3),    // behind the pillar
                                    mover(2, 0.0, 5.0, 0, 0, 0.3),    // in the open
                                    mover(3, 0.0, -5.0, 0, 0, 0.3),   // in the open, in front of 4
                                    mover(4, 0.0, -8.0, 0, 0, 0.4)}); // behind mover 3
  world::World w(sc);
  w.setTime(0.0);
  const Eigen::Vector2d sensor(0.0, 0.0);
  EXPECT_FALSE(lineOfSight(w, sensor, 0.5, 0, 12.0));
  EXPECT_TRUE(lineOfSight(w, sensor, 0.5, 1, 12.0));
  EXPECT_TRUE(lineOfSight(w, sensor, 0.5, 2, 12.0));
  EXPECT_FALSE(lineOfSight(w, sensor, 0.5, 3, 12.0));
  // Out of range.
  EXPECT_FALSE(lineOfSight(w, sensor, 0.5, 1, 4.0));
  // Half hidden: the ray to the centre passes 0.54 m from the pillar's axis (blocked), the ray
  // to the side of the body 0.66 m (free).
  EXPECT_TRUE(lineOfSight(w, Eigen::Vector2d(0.0, 1.1), 0.5, 0, 12.0));
  EXPECT_FALSE(lineOfSight(w, Eigen::Vector2d(0.0, 0.5), 0.5, 0, 12.0));
  // From the other side nothing is in the way.
  EXPECT_TRUE(lineOfSight(w, Eigen::Vector2d(5.0, -3.0), 0.5, 0, 12.0));
}

TEST(Observation, HiddenTrackCoastsThenANewTrackStarts) {
  const world::Scenario sc = scene({pillar(2.5, 0.0, 0.6)}, {mover(7, 5.0, 0.0, 0, 0, 0.3)});
  world::World w(sc);
  ObserveConfig cfg;
  cfg.mode = ObserveMode::kLineOfSight;
  cfg.max_coast = 0.5;
  cfg.kalman.position_std = cfg.noise_std;
  const Eigen::Vector2d seen(5.0, -3.0), hidden(0.0, 0.0);
  Observer obs(w, cfg, 1);
  const double dt = 0.02;
  int k = 0;
  auto frame = [&](const Eigen::Vector2d& sensor) {
    w.setTime(k++ * dt);
    return obs.frame(dt, sensor);
  };
  // A new track: zero velocity, the initial velocity sigma.
  auto out = frame(seen);
  ASSERT_EQ(out.size(), 1u);
  const int64_t first_id = out[0].id;
  EXPECT_EQ(out[0].x.segment<3>(3).norm(), 0.0);
  EXPECT_DOUBLE_EQ(out[0].P(3, 3), cfg.kalman.initial_velocity_std * cfg.kalman.initial_velocity_std);
  for (int i = 0; i < 20; ++i) out = frame(seen);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].id, first_id);
  EXPECT_EQ(out[0].state, tracked_object_t::STATE_CONFIRMED);
  EXPECT_NEAR(obs.trackAge(0).value(), 20 * dt, 1e-9);
  double var = out[0].P(0, 0);
  // Hidden: the same track coasts with a growing covariance, up to the coast time.
  for (int i = 0; i < 24; ++i) {
    out = frame(hidden);
    ASSERT_EQ(out.size(), 1u) << "frame " << i;
    EXPECT_EQ(out[0].id, first_id);
    EXPECT_EQ(out[0].state, tracked_object_t::STATE_COASTING);
    EXPECT_GT(out[0].P(0, 0), var);
    var = out[0].P(0, 0);
  }
  out = frame(hidden);
  out = frame(hidden);
  EXPECT_TRUE(out.empty()) << "a track unseen longer than max_coast is dropped";
  EXPECT_FALSE(obs.trackAge(0).has_value());
  EXPECT_EQ(obs.moverOfTrack(first_id), -1);
  // Seen again: a new track with a new id and the initial uncertainty.
  out = frame(seen);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NE(out[0].id, first_id);
  EXPECT_EQ(obs.moverOfTrack(out[0].id), 0);
  EXPECT_DOUBLE_EQ(out[0].P(3, 3), cfg.kalman.initial_velocity_std * cfg.kalman.initial_velocity_std);
  EXPECT_EQ(obs.tracksStarted(), 2);
}

TEST(Observation, AllModeTracksEveryMoverUnderItsOwnId) {
  const world::Scenario sc = scene({pillar(2.5, 0.0, 0.6)}, {mover(7, 5.0, 0.0, 0, 0, 0.3), mover(9, 0, 5, 0, 0, 0.3)});
  world::World w(sc);
  ObserveConfig cfg;
  Observer obs(w, cfg, 1);
  for (int k = 0; k < 10; ++k) {
    w.setTime(k * 0.02);
    const auto out = obs.frame(0.02, Eigen::Vector2d::Zero());
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].id, 7);
    EXPECT_EQ(out[1].id, 9);
    EXPECT_EQ(out[0].age_frames, k + 1);
  }
}

TEST(Probe, AStandingRobotInAMoversPathIsHit) {
  // The mover comes at 1 m/s from 3 m: bodies (0.3 + 0.3) touch after 2.4 s.
  const world::Scenario sc = scene({}, {mover(1, 3.0, 0.0, -1.0, 0.0, 0.3)});
  world::World w(sc);
  const auto pp = line(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), 1.0);
  const PlayResult late = playPlan(pp, 0.0, 3.0, w, 0.3);
  EXPECT_TRUE(late.mover_contact);
  EXPECT_FALSE(late.static_contact);
  EXPECT_EQ(late.mover, 0);
  EXPECT_NEAR(late.contact_s, 2.4, 0.03);
  EXPECT_FALSE(late.contactFree());
  // Not within a 2 s horizon; and not when the plan starts 1 s later in world time.
  EXPECT_TRUE(playPlan(pp, 0.0, 2.0, w, 0.3).contactFree());
  EXPECT_NEAR(playPlan(pp, 1.0, 3.0, w, 0.3).contact_s, 1.4, 0.03);
  // Stepping aside in time avoids it.
  const auto aside = line(Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1.0), 1.5);
  EXPECT_TRUE(playPlan(aside, 0.0, 5.0, w, 0.3).contactFree());
}

TEST(Probe, DrivingIntoAPillarIsAStaticContact) {
  const world::Scenario sc = scene({pillar(0.0, 2.0, 0.5)}, {mover(1, 10.0, 10.0, 0.0, 0.0, 0.3)});
  world::World w(sc);
  const auto pp = line(Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1.0), 3.0);
  const PlayResult r = playPlan(pp, 0.0, 3.0, w, 0.3);
  EXPECT_TRUE(r.static_contact);
  EXPECT_FALSE(r.mover_contact);
  EXPECT_NEAR(r.contact_s, 1.2, 0.03);  // 2.0 - 0.5 - 0.3 at 1 m/s
  EXPECT_NEAR(r.jerk_mean, 0.0, 1e-12);
}

}  // namespace
}  // namespace ucon::bench
