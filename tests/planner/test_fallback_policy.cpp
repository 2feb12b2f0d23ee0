// The fallback policy's parts (procs/planner fallback_policy.hpp): the manoeuvre polynomial keeps
// the limits and ends at rest; the score is the smallest predicted gap to the movers' grown
// bodies after the reaction time, with static clearance as a hard rule; the best manoeuvre steps
// aside from a mover coming head-on, away from a wall; detour headings are ranked by the same
// score; the choice between keep, evade and brake.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ucon/planner/fallback_policy.hpp"

using namespace ucon;
using namespace ucon::planner;

namespace {

constexpr int64_t kT0 = 5'000'000;

/// A straight wall: the set y >= wall_y (or x >= wall_x); distance capped at 1 m like the ESDF.
class WallField : public trajopt::DistanceField2D {
 public:
  WallField(bool along_x, double at) : along_x_(along_x), at_(at) {}
  double distance(double x, double y, Eigen::Vector2d* grad) const override {
    if (grad) grad->setZero();
    return std::min(1.0, at_ - (along_x_ ? y : x));
  }

 private:
  bool along_x_;
  double at_;
};

trajopt::PredictedObstacle mover(double x, double y, double vx, double vy, double radius = 0.3, double pos_var = 0.0,
                                 double vel_var = 0.0) {
  trajopt::PredictedObstacle o;
  o.id = 7;
  o.utime = kT0;
  o.state << x, y, 0.8, vx, vy, 0.0;
  o.covariance.setZero();
  o.covariance(0, 0) = o.covariance(1, 1) = pos_var;
  o.covariance(3, 3) = o.covariance(4, 4) = vel_var;
  o.has_covariance = pos_var > 0.0 || vel_var > 0.0;
  o.radius = radius;
  return o;
}

trajectory::PiecewisePolynomial rest(const Eigen::Vector2d& p) {
  trajectory::PiecewisePolynomial pp;
  EXPECT_TRUE(manoeuvrePolynomial(kT0, p, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), 2.0, 1.5, &pp));
  return pp;
}

}  // namespace

TEST(FallbackPolicy, GivenAChangeOfVelocityThenTheManoeuvreReachesItAtTheLimitHoldsItAndBrakesToRest) {
  const Eigen::Vector2d p0(1.0, -2.0), v0(1.0, 0.0), u(0.0, 1.5);
  const double amax = 2.0, run = 1.5;
  trajectory::PiecewisePolynomial pp;
  ASSERT_TRUE(manoeuvrePolynomial(kT0, p0, v0, u, amax, run, &pp));
  const double T1 = (u - v0).norm() / amax;  // 0.90 s
  EXPECT_LT((pp.sampleRelative(T1).velocity.head<2>() - u).norm(), 1e-9);
  EXPECT_LT((pp.sampleRelative(0.5 * (T1 + run)).velocity.head<2>() - u).norm(), 1e-9);  // held
  // Braking at the limit from run on, then at rest for 0.5 s.
  EXPECT_NEAR(pp.duration(), run + u.norm() / amax + 0.5, 1e-9);
  const auto end = pp.sampleRelative(pp.duration());
  EXPECT_LT(end.velocity.norm(), 1e-12);
  const Eigen::Vector2d expected_end =
      p0 + v0 * T1 + 0.5 * (u - v0) / T1 * T1 * T1 + u * (run - T1) + u * (0.5 * u.norm() / amax);
  EXPECT_LT((end.position.head<2>() - expected_end).norm(), 1e-9);
  // Continuous position and velocity, acceleration within the limit throughout.
  Eigen::Vector3d prev_p = pp.sampleRelative(0.0).position, prev_v = pp.sampleRelative(0.0).velocity;
  for (double t = 0.001; t <= pp.duration(); t += 0.001) {
    const auto s = pp.sampleRelative(t);
    EXPECT_LE(s.acceleration.norm(), amax + 1e-9) << t;
    EXPECT_LT((s.position - prev_p).norm(), 0.002) << t;
    EXPECT_LT((s.velocity - prev_v).norm(), 0.0021) << t;
    prev_p = s.position;
    prev_v = s.velocity;
  }
  EXPECT_LT((pp.sampleRelative(0.0).position.head<2>() - p0).norm(), 1e-12);
  EXPECT_LT((pp.sampleRelative(0.0).velocity.head<2>() - v0).norm(), 1e-12);
}

TEST(FallbackPolicy, GivenNonFiniteInputOrNoAccelerationThenNoManoeuvre) {
  trajectory::PiecewisePolynomial pp;
  const Eigen::Vector2d z = Eigen::Vector2d::Zero();
  EXPECT_FALSE(manoeuvrePolynomial(kT0, Eigen::Vector2d(NAN, 0.0), z, z, 2.0, 1.0, &pp));
  EXPECT_FALSE(manoeuvrePolynomial(kT0, z, Eigen::Vector2d(0.0, INFINITY), z, 2.0, 1.0, &pp));
  EXPECT_FALSE(manoeuvrePolynomial(kT0, z, z, Eigen::Vector2d(NAN, 1.0), 2.0, 1.0, &pp));
  EXPECT_FALSE(manoeuvrePolynomial(kT0, z, z, z, 0.0, 1.0, &pp));
  EXPECT_FALSE(manoeuvrePolynomial(kT0, z, z, z, 2.0, NAN, &pp));
  EXPECT_FALSE(pp.valid());
}

TEST(FallbackPolicy, GivenAMoverComingTowardsAStillRobotThenTheScoreIsTheSmallestGapOfTheGrownBody) {
  FallbackParams ep;
  ep.horizon_s = 1.5;  // reaction 0.1 s, cap 1 m, k = 1
  const Eigen::Vector2d goal(10.0, 0.0);
  const auto still = rest(Eigen::Vector2d::Zero());
  // Mover from (3, 0) at -1 m/s: at 1.5 s its centre is 1.5 m away: gap 1.5 - 0.3 - 0.3 = 0.9.
  const std::vector<trajopt::PredictedObstacle> plain{mover(3.0, 0.0, -1.0, 0.0)};
  const FallbackScore s = scoreTrajectory(still, kT0, goal, nullptr, plain, 0.3, ep);
  ASSERT_TRUE(s.static_ok);
  EXPECT_NEAR(s.min_gap, 0.9, 1e-9);
  EXPECT_NEAR(s.progress, 0.0, 1e-12);
  EXPECT_NEAR(s.total, s.min_gap + ep.mean_weight * s.mean_gap, 1e-12);
  EXPECT_LE(s.mean_gap, ep.gap_cap);
  EXPECT_GT(s.mean_gap, s.min_gap);
  // Velocity variance 0.04 (0.2 m/s): after 1.5 s the position's sigma is 0.3 m -> gap 0.6.
  const std::vector<trajopt::PredictedObstacle> uncertain{mover(3.0, 0.0, -1.0, 0.0, 0.3, 0.0, 0.04)};
  EXPECT_NEAR(scoreTrajectory(still, kT0, goal, nullptr, uncertain, 0.3, ep).min_gap, 0.6, 1e-9);
  ep.uncertainty_k = 0.0;
  EXPECT_NEAR(scoreTrajectory(still, kT0, goal, nullptr, uncertain, 0.3, ep).min_gap, 0.9, 1e-9);
  // A non-finite obstacle is skipped: nothing left within the cap.
  const std::vector<trajopt::PredictedObstacle> bad{mover(NAN, 0.0, -1.0, 0.0)};
  EXPECT_NEAR(scoreTrajectory(still, kT0, goal, nullptr, bad, 0.3, ep).min_gap, ep.gap_cap, 1e-12);
}

TEST(FallbackPolicy, GivenAMoverLeavingFastThenGapsBeforeTheReactionTimeAreNotScored) {
  FallbackParams ep;
  const auto still = rest(Eigen::Vector2d::Zero());
  // Overlapping now (gap 0.5 - 0.6 = -0.1), 1 m away 0.1 s later: gap 0.4, then beyond the cap.
  const std::vector<trajopt::PredictedObstacle> leaving{mover(0.5, 0.0, 5.0, 0.0)};
  EXPECT_NEAR(scoreTrajectory(still, kT0, Eigen::Vector2d(5, 0), nullptr, leaving, 0.3, ep).min_gap, 0.4, 1e-9);
  ep.reaction_s = 0.0;
  EXPECT_NEAR(scoreTrajectory(still, kT0, Eigen::Vector2d(5, 0), nullptr, leaving, 0.3, ep).min_gap, -0.1, 1e-9);
}

TEST(FallbackPolicy, GivenAWallThenTrajectoriesCloserThanTheRadiusAreOutUnlessTheyStartedThereAndDoNotCloseIn) {
  const FallbackParams ep;
  const WallField wall(false, 1.0);  // obstacle x >= 1
  const Eigen::Vector2d goal(0.0, 10.0);
  trajectory::PiecewisePolynomial toward, away;
  ASSERT_TRUE(manoeuvrePolynomial(kT0, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d(1.5, 0.0),
                                  2.0, 1.5, &toward));
  const FallbackScore hit = scoreTrajectory(toward, kT0, goal, &wall, {}, 0.3, ep);
  EXPECT_FALSE(hit.static_ok);
  EXPECT_EQ(hit.total, -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(scoreTrajectory(rest(Eigen::Vector2d::Zero()), kT0, goal, &wall, {}, 0.3, ep).static_ok);
  // Starting 0.2 m from the wall (inside the 0.3 m clearance): holding still or leaving is
  // allowed, closing in is not.
  const Eigen::Vector2d close(0.8, 0.0);
  EXPECT_TRUE(scoreTrajectory(rest(close), kT0, goal, &wall, {}, 0.3, ep).static_ok);
  ASSERT_TRUE(manoeuvrePolynomial(kT0, close, Eigen::Vector2d::Zero(), Eigen::Vector2d(-1.5, 0.0), 2.0, 1.5, &away));
  EXPECT_TRUE(scoreTrajectory(away, kT0, goal, &wall, {}, 0.3, ep).static_ok);
  trajectory::PiecewisePolynomial closer;
  ASSERT_TRUE(manoeuvrePolynomial(kT0, close, Eigen::Vector2d::Zero(), Eigen::Vector2d(0.3, 0.0), 2.0, 1.5, &closer));
  EXPECT_FALSE(scoreTrajectory(closer, kT0, goal, &wall, {}, 0.3, ep).static_ok);
  // Progress toward the goal counts: the same gaps, further along.
  trajectory::PiecewisePolynomial up;
  ASSERT_TRUE(manoeuvrePolynomial(kT0, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1.5),
                                  2.0, 1.5, &up));
  const FallbackScore s = scoreTrajectory(up, kT0, goal, &wall, {}, 0.3, ep);
  EXPECT_GT(s.progress, 1.5);
  EXPECT_GT(s.total, scoreTrajectory(rest(Eigen::Vector2d::Zero()), kT0, goal, &wall, {}, 0.3, ep).total);
}

TEST(FallbackPolicy, GivenAMoverHeadOnThenTheBestManoeuvreStepsAsideAwayFromTheWallAndBeatsBraking) {
  const FallbackParams ep;
  const Eigen::Vector2d goal(10.0, 0.0), p0 = Eigen::Vector2d::Zero(), v0(0.5, 0.0);
  // A mover from 2.5 m ahead at 1.5 m/s straight at the robot: braking is hit.
  const std::vector<trajopt::PredictedObstacle> obs{mover(2.5, 0.0, -1.5, 0.0, 0.3, 0.0025, 0.01)};
  trajectory::PiecewisePolynomial brake;
  ASSERT_TRUE(manoeuvrePolynomial(kT0, p0, v0, Eigen::Vector2d::Zero(), 2.0, 0.0, &brake));
  const FallbackScore braking = scoreTrajectory(brake, kT0, goal, nullptr, obs, 0.3, ep);
  ASSERT_LT(braking.min_gap, 0.0);
  const Manoeuvre m = bestManoeuvre(kT0, p0, v0, goal, 1.5, 2.0, nullptr, obs, 0.3, ep);
  ASSERT_TRUE(m.pp.valid());
  EXPECT_GT(m.score.min_gap, 0.0);
  EXPECT_GT(m.score.total, braking.total);
  EXPECT_GT(std::abs(m.velocity.y()), 0.7) << m.velocity.transpose();  // sideways, not back
  // A wall 0.8 m to the robot's left (y >= 0.8): it steps to the right.
  const WallField wall(true, 0.8);
  const Manoeuvre r = bestManoeuvre(kT0, p0, v0, goal, 1.5, 2.0, &wall, obs, 0.3, ep);
  ASSERT_TRUE(r.pp.valid());
  EXPECT_LT(r.velocity.y(), -0.5) << r.velocity.transpose();
  EXPECT_TRUE(r.score.static_ok);
  // Deterministic.
  const Manoeuvre again = bestManoeuvre(kT0, p0, v0, goal, 1.5, 2.0, &wall, obs, 0.3, ep);
  EXPECT_EQ(again.velocity, r.velocity);
  EXPECT_EQ(again.score.total, r.score.total);
  // Nothing finite to start from: no manoeuvre.
  EXPECT_FALSE(bestManoeuvre(kT0, Eigen::Vector2d(NAN, 0.0), v0, goal, 1.5, 2.0, nullptr, obs, 0.3, ep).pp.valid());
}

TEST(FallbackPolicy, GivenAMoverHeadOnThenDetourHeadingsAwayFromItRankFirstAndThoseIntoAWallAreLeftOut) {
  const FallbackParams fp;
  const Eigen::Vector2d goal(10.0, 0.0), p0 = Eigen::Vector2d::Zero(), v0(0.5, 0.0);
  const std::vector<trajopt::PredictedObstacle> obs{mover(2.5, 0.0, -1.5, 0.0, 0.3, 0.0025, 0.01)};
  const std::vector<int> open = rankHeadings(kT0, p0, v0, goal, 1.2, 2.0, nullptr, obs, 0.3, fp);
  ASSERT_EQ(open.size(), std::size_t(fp.directions));  // no walls: every heading
  // Straight at the mover (heading 0, +x) is the worst; the best ones run sideways or back.
  EXPECT_EQ(open.back(), 0);
  EXPECT_LT(heading(open.front(), fp.directions).x(), 0.5) << open.front();
  // Ranked by the score of each heading's straight run, best first.
  auto runScore = [&](int k, const trajopt::DistanceField2D* field) {
    trajectory::PiecewisePolynomial run;
    EXPECT_TRUE(manoeuvrePolynomial(kT0, p0, v0, 1.2 * heading(k, fp.directions), 2.0, fp.detour_length / 1.2, &run));
    return scoreTrajectory(run, kT0, goal, field, obs, 0.3, fp).total;
  };
  for (std::size_t i = 1; i < open.size(); ++i) EXPECT_GE(runScore(open[i - 1], nullptr), runScore(open[i], nullptr));
  // A wall 0.8 m to the left (y >= 0.8): headings whose run reaches it are left out.
  const WallField wall(true, 0.8);
  const std::vector<int> walled = rankHeadings(kT0, p0, v0, goal, 1.2, 2.0, &wall, obs, 0.3, fp);
  EXPECT_LT(walled.size(), open.size());
  for (int k : walled) EXPECT_LT(heading(k, fp.directions).y(), 0.5) << k;
  EXPECT_EQ(walled, rankHeadings(kT0, p0, v0, goal, 1.2, 2.0, &wall, obs, 0.3, fp));  // deterministic
  EXPECT_TRUE(rankHeadings(kT0, p0, v0, goal, 0.0, 2.0, nullptr, obs, 0.3, fp).empty());  // no speed: none
}

TEST(FallbackPolicy, GivenTheScoresThenItKeepsWithinTheMarginElseEvadesOrBrakesByTheBest) {
  const double none = -std::numeric_limits<double>::infinity();
  // Only braking exists.
  EXPECT_EQ(chooseFallback(0.1, none, none, none, 0.0), FallbackChoice::kBrake);
  // A manoeuvre or the least-bad plan must beat braking.
  EXPECT_EQ(chooseFallback(0.3, none, 0.2, 0.25, 0.0), FallbackChoice::kBrake);
  EXPECT_EQ(chooseFallback(0.1, none, 0.2, 0.3, 0.0), FallbackChoice::kManoeuvre);
  EXPECT_EQ(chooseFallback(0.1, none, 0.3, 0.2, 0.0), FallbackChoice::kLeastBad);
  EXPECT_EQ(chooseFallback(0.1, none, 0.3, 0.3, 0.0), FallbackChoice::kLeastBad);  // tie: the plan, not the manoeuvre
  // The plan being followed: kept when it beats braking and comes within keep_margin of the best.
  EXPECT_EQ(chooseFallback(0.1, 0.3, 0.3, 0.3, 0.0), FallbackChoice::kKeep);       // ties keep it
  EXPECT_EQ(chooseFallback(0.1, 0.25, 0.2, 0.3, 0.0), FallbackChoice::kManoeuvre);
  EXPECT_EQ(chooseFallback(0.1, 0.25, 0.2, 0.3, 0.1), FallbackChoice::kKeep);
  EXPECT_EQ(chooseFallback(0.3, 0.25, none, none, 1.0), FallbackChoice::kBrake);   // never kept below braking
  EXPECT_STREQ(toString(FallbackChoice::kLeastBad), "least_bad");
}
