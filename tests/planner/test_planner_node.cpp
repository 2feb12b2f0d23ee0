// The planner node, called through its handlers: plans around static obstacles, replans at
// the configured rate with continuous p/v/a, replans at once when its plan becomes unsafe,
// stops with a clear status on bad or missing input, is deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "ucon/config.hpp"
#include "ucon/planner/planner_node.hpp"
#include "ucon/planner/planner_params.hpp"

using namespace ucon;
using namespace ucon::planner;

namespace {

constexpr int64_t kT0 = 1'000'000;  // first message time [us]

PlannerParams loadDeployParams() {
  std::ifstream f(std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml");
  std::stringstream ss;
  ss << f.rdbuf();
  std::vector<ConfigError> errors;
  auto p = loadParams<PlannerParams>(ss.str(), "planner.yaml", &errors);
  EXPECT_TRUE(p.has_value()) << (errors.empty() ? "" : errors.front().toString());
  return p.value_or(PlannerParams{});
}

robot_pose_t pose(int64_t utime, double x, double y, double vx = 0.0, double vy = 0.0) {
  robot_pose_t m{};
  m.utime = utime;
  m.valid = true;
  m.x = x;
  m.y = y;
  m.qw = 1.0;
  m.vx = vx;
  m.vy = vy;
  m.ax = NAN;
  m.ay = NAN;
  return m;
}

tracked_object_t object(int64_t id, double x, double y, double vx, double vy, double var = 0.01) {
  tracked_object_t o{};
  o.id = id;
  o.state = tracked_object_t::STATE_CONFIRMED;
  o.x = x;
  o.y = y;
  o.z = 0.8;
  o.vx = vx;
  o.vy = vy;
  o.cov_size = 36;
  o.cov.assign(36, 0.0);
  for (int i = 0; i < 6; ++i) o.cov[i * 7] = var;
  o.size_x = 0.5;
  o.size_y = 0.5;
  o.size_z = 1.7;
  return o;
}

tracked_objects_t objects(int64_t utime, std::vector<tracked_object_t> objs = {}) {
  tracked_objects_t m{};
  m.utime = utime;
  m.valid = true;
  m.frame_id = "world";
  m.num_objects = int32_t(objs.size());
  m.objects = std::move(objs);
  return m;
}

nav_goal_t goal(int64_t utime, double x, double y, int64_t id = 1) {
  nav_goal_t g{};
  g.utime = utime;
  g.goal_id = id;
  g.action = nav_goal_t::ACTION_GO;
  g.x = x;
  g.y = y;
  g.yaw = NAN;
  g.tolerance = 0.3;
  return g;
}

/// A node with a known map: a wall segment across the straight line from (0,0) to (5,0).
struct Fixture {
  PlannerParams params = loadDeployParams();
  StatusReport report{"planner"};
  std::unique_ptr<PlannerNode> node;
  explicit Fixture(bool with_wall = true) {
    node = std::make_unique<PlannerNode>(params, report);
    if (with_wall) node->map().addBox(2.4, -1.0, 2.7, 1.0);
    node->map().addCylinder(50.0, 50.0, 0.3);  // something, so the map is not empty
    node->notifyMapChanged();
  }
  void feed(int64_t t, double x = 0.0, double y = 0.0, std::vector<tracked_object_t> objs = {}) {
    node->onPose(pose(t, x, y));
    node->onObjects(objects(t, std::move(objs)));
  }
};

double minMapDistance(PlannerNode& node, const trajectory::PiecewisePolynomial& pp) {
  double worst = 1e9;
  for (double t = 0; t <= pp.duration(); t += 0.01) {
    const auto p = pp.sampleRelative(t).position;
    worst = std::min(worst, node.map().distance(p.x(), p.y(), nullptr));
  }
  return worst;
}

}  // namespace

TEST(PlannerNode, GivenAWallOnTheWayWhenAGoalArrivesThenTheTrajectoryGoesAroundItFromNowPlusLatency) {
  Fixture f;
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  const auto out = f.node->tick(kT0);
  ASSERT_TRUE(out.trajectory);
  ASSERT_TRUE(out.plan);
  EXPECT_EQ(out.plan->result, PlanResult::kOk) << out.plan->message;
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_OK);
  EXPECT_EQ(out.trajectory->goal_id, 1);
  EXPECT_EQ(out.trajectory->start_utime, kT0 + int64_t(f.params.latency_s * 1e6));
  const auto& pp = f.node->currentTrajectory();
  ASSERT_TRUE(pp.valid());
  EXPECT_NEAR(pp.sampleRelative(0).position.x(), 0.0, 1e-9);
  EXPECT_NEAR(pp.sampleRelative(pp.duration()).position.x(), 5.0, 1e-6);
  EXPECT_NEAR(pp.sampleRelative(pp.duration()).velocity.norm(), 0.0, 1e-6);
  EXPECT_GE(minMapDistance(*f.node, pp), f.params.optimizer.robot_radius);
  EXPECT_GT(out.plan->iterations, 0);
  EXPECT_GT(out.plan->cost_energy, 0.0);
}

TEST(PlannerNode, GivenTicksEvery20msThenItReplansAt10HzWithContinuousState) {
  Fixture f;
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  std::vector<trajectory_t> plans;
  trajectory::PiecewisePolynomial previous;
  for (int k = 0; k <= 50; ++k) {  // 1 s
    const int64_t t = kT0 + k * 20000;
    // The robot follows its plan exactly.
    Eigen::Vector3d p = f.node->currentTrajectory().valid() ? f.node->currentTrajectory().position(t)
                                                           : Eigen::Vector3d::Zero();
    f.feed(t, p.x(), p.y());
    const auto out = f.node->tick(t);
    if (!out.trajectory) continue;
    ASSERT_EQ(out.trajectory->status, trajectory_t::STATUS_OK) << out.trajectory->message;
    if (previous.valid()) {
      // The new plan starts where the old one is at its start time: p, v, a continuous.
      const auto a = previous.sample(out.trajectory->start_utime);
      const auto b = f.node->currentTrajectory().sampleRelative(0.0);
      EXPECT_LT((a.position - b.position).norm(), 1e-6);
      EXPECT_LT((a.velocity - b.velocity).norm(), 1e-6);
      EXPECT_LT((a.acceleration - b.acceleration).norm(), 1e-6);
    }
    previous = f.node->currentTrajectory();
    plans.push_back(*out.trajectory);
  }
  EXPECT_EQ(plans.size(), 11u);  // t = 0, 0.1, ..., 1.0 s
  for (std::size_t i = 1; i < plans.size(); ++i) EXPECT_EQ(plans[i].plan_id, plans[i - 1].plan_id + 1);
}

TEST(PlannerNode, GivenAnObstacleThatAppearsOnThePlanWhenTickedThenItReplansAtOnce) {
  Fixture f(false);
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 6.0, 0.0));
  ASSERT_TRUE(f.node->tick(kT0).trajectory);
  // 20 ms later an obstacle sits on the path, coming toward the robot.
  const int64_t t = kT0 + 20000;
  const auto p = f.node->currentTrajectory().position(t);
  f.feed(t, p.x(), p.y(), {object(7, 1.5, 0.0, -0.5, 0.0)});
  const auto out = f.node->tick(t);
  ASSERT_TRUE(out.plan);
  EXPECT_TRUE(out.plan->triggered_by_unsafe);
  EXPECT_GE(f.report.counter("replans_unsafe"), 1);
  ASSERT_TRUE(out.trajectory);
  // Whatever it chose (a detour or a stop), the new trajectory passes its own check.
  if (out.trajectory->status == trajectory_t::STATUS_OK) {
    EXPECT_EQ(f.node->check(*out.trajectory, t).status, trajopt::PlanStatus::kOk);
  }
}

TEST(PlannerNode, GivenNoPoseWhenAGoalArrivesThenItSaysSoAndPublishesNothingToFollow) {
  Fixture f;
  f.node->onObjects(objects(kT0));
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  const auto out = f.node->tick(kT0);
  ASSERT_TRUE(out.plan);
  EXPECT_EQ(out.plan->result, PlanResult::kStopNoPose);
  ASSERT_TRUE(out.trajectory);
  EXPECT_NE(out.trajectory->status, trajectory_t::STATUS_OK);
  const auto st = f.report.build(kT0, 0);
  EXPECT_EQ(st.health, process_status_t::HEALTH_ERROR);
  EXPECT_NE(st.message.find("pose"), std::string::npos) << st.message;
}

TEST(PlannerNode, GivenNoMapYetWhenAGoalArrivesThenItStopsWithStatusNoMap) {
  PlannerParams params = loadDeployParams();
  StatusReport report("planner");
  PlannerNode node(params, report);
  node.onPose(pose(kT0, 0, 0));
  node.onObjects(objects(kT0));
  node.onGoal(goal(kT0, 5.0, 0.0));
  const auto out = node.tick(kT0);
  ASSERT_TRUE(out.plan);
  EXPECT_EQ(out.plan->result, PlanResult::kStopNoMap);
  ASSERT_TRUE(out.trajectory);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_STOP);
}

TEST(PlannerNode, GivenANaNGoalOrOneOutsideTheMapThenItIsRejectedWithAReason) {
  Fixture f;
  f.feed(kT0);
  f.node->onGoal(goal(kT0, NAN, 0.0));
  EXPECT_FALSE(f.node->hasGoal());
  auto out = f.node->tick(kT0);
  ASSERT_TRUE(out.trajectory);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_STOP);
  EXPECT_NE(out.trajectory->message.find("not finite"), std::string::npos) << out.trajectory->message;
  f.node->onGoal(goal(kT0, 500.0, 0.0));
  EXPECT_FALSE(f.node->hasGoal());
  out = f.node->tick(kT0 + 1000);
  ASSERT_TRUE(out.trajectory);
  EXPECT_NE(out.trajectory->message.find("outside the map"), std::string::npos) << out.trajectory->message;
  EXPECT_EQ(f.report.counter("goals_rejected"), 2);
  EXPECT_EQ(f.report.build(kT0, 0).health, process_status_t::HEALTH_WARN);
}

TEST(PlannerNode, GivenAGoalInsideAnObstacleThenItHeadsForTheNearestSafePointAndSaysSo) {
  Fixture f;
  f.node->map().addCylinder(4.0, 3.0, 0.8);
  f.node->notifyMapChanged();
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 4.0, 3.0));
  const auto out = f.node->tick(kT0);
  ASSERT_TRUE(out.plan);
  EXPECT_EQ(out.plan->guide, GuideStatus::kGoalInCollision);
  EXPECT_EQ(f.report.counter("goal_in_collision"), 1);
  ASSERT_TRUE(out.trajectory);
  if (out.trajectory->status == trajectory_t::STATUS_OK) {
    const auto& pp = f.node->currentTrajectory();
    const auto end = pp.sampleRelative(pp.duration()).position;
    EXPECT_GE(f.node->map().distance(end.x(), end.y(), nullptr), f.params.optimizer.robot_radius);
    EXPECT_GE(minMapDistance(*f.node, pp), f.params.optimizer.robot_radius);
    EXPECT_NE(out.trajectory->message.find("inside an obstacle"), std::string::npos);
  }
  EXPECT_EQ(f.report.build(kT0, 0).health, process_status_t::HEALTH_WARN);
}

TEST(PlannerNode, GivenObstaclesWithNaNOrNonPDCovarianceThenNaNIsDroppedAndBadCovarianceWidened) {
  Fixture f(false);
  f.node->onPose(pose(kT0, 0, 0));
  auto nan_obj = object(1, NAN, 0.0, 0.0, 0.0);
  auto bad_cov = object(2, 3.0, 0.0, 0.0, 0.0);
  bad_cov.cov[0] = -1.0;  // not positive definite
  auto nan_cov = object(3, 3.0, 2.0, 0.0, 0.0);
  nan_cov.cov[7] = NAN;
  f.node->onObjects(objects(kT0, {nan_obj, bad_cov, nan_cov, object(4, -3.0, 0.0, 0.0, 0.0)}));
  EXPECT_EQ(f.report.counter("objects_nan_dropped"), 1);
  EXPECT_EQ(f.report.counter("objects_bad_covariance"), 2);
  ASSERT_EQ(f.node->obstacles().size(), 3u);
  EXPECT_NEAR(f.node->obstacles()[0].covariance(0, 0), f.params.objects.fallback_position_std *
                                                             f.params.objects.fallback_position_std, 1e-12);
  // Planning through the static obstacle at (3, 0) is not an option: the trajectory avoids it.
  f.node->onGoal(goal(kT0, 6.0, 0.0));
  const auto out = f.node->tick(kT0);
  ASSERT_TRUE(out.trajectory);
  if (out.trajectory->status == trajectory_t::STATUS_OK) {
    const auto& pp = f.node->currentTrajectory();
    for (double t = 0; t <= 2.0; t += 0.02) {
      const auto p = pp.sampleRelative(t).position;
      EXPECT_GT(std::hypot(p.x() - 3.0, p.y()), f.params.optimizer.robot_radius + 0.35);
    }
  }
}

TEST(PlannerNode, GivenATrackBoxShrunkByPartialViewsThenItsBodyIsAtLeastMinRadius) {
  Fixture f(false);
  ASSERT_DOUBLE_EQ(f.params.objects.min_radius, 0.3);  // deploy/config/planner.yaml
  f.node->onPose(pose(kT0, 0, 0));
  auto sliver = object(1, 3.0, 0.0, 0.0, 0.0);  // a few returns of one side: 0.1 x 0.05 m
  sliver.size_x = 0.1;
  sliver.size_y = 0.05;
  auto large = object(2, -3.0, 0.0, 0.0, 0.0);  // 0.8 x 0.6 m: its own half diagonal, 0.5 m
  large.size_x = 0.8;
  large.size_y = 0.6;
  f.node->onObjects(objects(kT0, {sliver, large}));
  ASSERT_EQ(f.node->obstacles().size(), 2u);
  EXPECT_DOUBLE_EQ(f.node->obstacles()[0].radius, 0.3);
  EXPECT_DOUBLE_EQ(f.node->obstacles()[1].radius, 0.5);
  PlannerParams p = f.params;
  p.objects.min_radius = 0.0;
  PlannerNode plain(p, f.report);
  plain.onPose(pose(kT0, 0, 0));
  plain.onObjects(objects(kT0, {sliver}));
  ASSERT_EQ(plain.obstacles().size(), 1u);
  EXPECT_NEAR(plain.obstacles()[0].radius, 0.5 * std::hypot(0.1, 0.05), 1e-12);
}

TEST(PlannerNode, GivenStaleObstaclesThenItStops) {
  Fixture f;
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  ASSERT_EQ(f.node->tick(kT0).trajectory->status, trajectory_t::STATUS_OK);
  const int64_t t = kT0 + 2'000'000;  // poses keep coming, objects do not
  f.node->onPose(pose(t, 1.0, 0.0));
  const auto out = f.node->tick(t);
  ASSERT_TRUE(out.plan);
  EXPECT_EQ(out.plan->result, PlanResult::kStopStaleObjects);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_STOP);
}

TEST(PlannerNode, GivenThePoseStopsWhilePerceptionSendsInvalidFramesThenItStopsAndSaysSoWithinThePoseTimeout) {
  // The pose source stalls: perception keeps publishing, every frame marked invalid ("ROBOT_POSE
  // stale"), and nothing else arrives. Those frames' times are the planner's only clock: if it
  // ignored them, "now" would stay at the last pose and the planner would never notice.
  Fixture f;
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  ASSERT_EQ(f.node->tick(kT0).trajectory->status, trajectory_t::STATUS_OK);
  const int64_t period = int64_t(std::llround(1e6 / f.params.rate_hz));
  const int64_t timeout = int64_t(std::llround(f.params.pose_timeout_s * 1e6));
  int64_t stop_at = -1;
  for (int64_t t = kT0 + 100'000; t <= kT0 + 2'000'000 && stop_at < 0; t += 100'000) {
    tracked_objects_t m = objects(t);
    m.valid = false;
    f.node->onObjects(m);
    // As the process ticks it (binding.hpp): at the node's own "now", the newest input time.
    const auto out = f.node->tick(f.node->clock().now());
    if (out.plan && out.plan->result == PlanResult::kStopNoPose) {
      stop_at = t;
      ASSERT_TRUE(out.trajectory);
      EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_STOP);
      EXPECT_NE(out.plan->message.find("no valid pose"), std::string::npos) << out.plan->message;
    }
  }
  ASSERT_GT(stop_at, 0) << "the planner never noticed that the pose stopped";
  EXPECT_LE(stop_at - kT0, timeout + period);
  EXPECT_EQ(f.report.counter("result_stop_no_pose"), 1);
  EXPECT_GE(f.report.counter("objects_msgs_rejected"), 1);
  EXPECT_EQ(f.report.build(stop_at, 0).health, process_status_t::HEALTH_ERROR);
}

TEST(PlannerNode, GivenObjectFramesOlderThanTheLatestPoseThenTheyAreUsedNotDroppedAsOutOfOrder) {
  // Perception stamps objects with the LiDAR frame's time; poses (100 Hz) are newer by the time
  // they arrive. Those frames are current, and the planner must keep planning with them.
  Fixture f;
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  ASSERT_EQ(f.node->tick(kT0).trajectory->status, trajectory_t::STATUS_OK);
  int64_t t = kT0;
  for (int k = 1; k <= 20; ++k) {
    t = kT0 + k * 100'000;
    f.node->onPose(pose(t, 0.05 * k, 0.0));
    f.node->onObjects(objects(t - 30'000));  // 30 ms old: the frame time plus latency
  }
  const auto out = f.node->tick(t);
  ASSERT_TRUE(out.trajectory);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_OK);
}

TEST(PlannerNode, GivenTheSameGoalRepeatedThenItDoesNotForceANewPlan) {
  Fixture f;
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  ASSERT_TRUE(f.node->tick(kT0).trajectory);
  f.node->onPose(pose(kT0 + 20'000, 0.0, 0.0));
  f.node->onGoal(goal(kT0 + 20'000, 5.0, 0.0));  // the sender repeats itself
  EXPECT_FALSE(f.node->tick(kT0 + 20'000).trajectory) << "a repeated goal is not a new plan";
  f.node->onGoal(goal(kT0 + 20'000, 6.0, 0.0));  // a different goal is
  EXPECT_TRUE(f.node->tick(kT0 + 20'000).trajectory);
}

TEST(PlannerNode, GivenTheRobotAtTheGoalThenGoalReachedAndACancelStops) {
  Fixture f;
  f.feed(kT0, 4.9, 0.0);
  f.node->onGoal(goal(kT0, 5.0, 0.0));
  auto out = f.node->tick(kT0);
  ASSERT_TRUE(out.trajectory);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_GOAL_REACHED);
  EXPECT_FALSE(f.node->hasGoal());
  f.node->onGoal(goal(kT0, -3.0, 0.0, 2));
  nav_goal_t cancel = goal(kT0, 0, 0, 2);
  cancel.action = nav_goal_t::ACTION_CANCEL;
  f.node->onGoal(cancel);
  out = f.node->tick(kT0 + 1000);
  ASSERT_TRUE(out.trajectory);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_STOP);
  EXPECT_EQ(out.plan->result, PlanResult::kCancelled);
}

TEST(PlannerNode, GivenTheSameInputsTwiceThenTheOutputsAreByteIdentical) {
  auto run = [] {
    Fixture f;
    std::vector<uint8_t> bytes;
    f.node->onGoal(goal(kT0, 5.0, 1.0));
    for (int k = 0; k < 25; ++k) {
      const int64_t t = kT0 + k * 20000;
      Eigen::Vector3d p = f.node->currentTrajectory().valid() ? f.node->currentTrajectory().position(t)
                                                             : Eigen::Vector3d::Zero();
      f.feed(t, p.x(), p.y(), {object(5, 3.0, 2.0, 0.0, -0.6), object(6, 1.0, -2.0, 0.3, 0.5)});
      const auto out = f.node->tick(t);
      if (!out.trajectory) continue;
      std::vector<uint8_t> buf(out.trajectory->getEncodedSize());
      out.trajectory->encode(buf.data(), 0, int(buf.size()));
      bytes.insert(bytes.end(), buf.begin(), buf.end());
    }
    return bytes;
  };
  const auto a = run();
  const auto b = run();
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, b);
}

TEST(PlannerNode, GivenItsProblemAskedBeforeEveryTickThenItPlansByteIdenticallyAndSolvesThatProblem) {
  // problem() is a look-ahead for the benchmark's open-loop protocol: it must not change what
  // the node plans, and its request must be the one the node's first optimiser run solves.
  struct Run {
    std::vector<uint8_t> bytes;
    std::vector<trajectory_t> trajectories;
    int problems = 0;
    trajopt::PlanOutput first;  ///< the first problem solved by an optimiser of the node's parameters
    int64_t first_start = 0;
    std::size_t first_obstacles = 0;
  };
  auto run = [](bool probe) {
    Fixture f;
    Run r;
    EXPECT_FALSE(f.node->problem(kT0).has_value());  // no goal yet
    f.node->onGoal(goal(kT0, 5.0, 1.0));
    trajopt::TrajectoryOptimizer opt(f.params.optimizer, f.params.prediction.model());
    for (int k = 0; k < 25; ++k) {
      const int64_t t = kT0 + k * 20000;
      Eigen::Vector3d p = f.node->currentTrajectory().valid() ? f.node->currentTrajectory().position(t)
                                                             : Eigen::Vector3d::Zero();
      f.feed(t, p.x(), p.y(), {object(5, 3.0, 2.0, 0.0, -0.6), object(6, 1.0, -2.0, 0.3, 0.5)});
      if (probe) {
        const auto req = f.node->problem(t);
        EXPECT_TRUE(req.has_value());
        if (req && r.problems++ == 0) {
          EXPECT_NE(req->field, nullptr);
          r.first_start = req->start_utime;
          r.first_obstacles = req->obstacles.size();
          r.first = opt.plan(*req);  // while the node (and its map) lives
        }
      }
      const auto out = f.node->tick(t);
      if (!out.trajectory) continue;
      r.trajectories.push_back(*out.trajectory);
      std::vector<uint8_t> buf(out.trajectory->getEncodedSize());
      out.trajectory->encode(buf.data(), 0, int(buf.size()));
      r.bytes.insert(r.bytes.end(), buf.begin(), buf.end());
    }
    return r;
  };
  const Run plain = run(false);
  const Run probed = run(true);
  EXPECT_GT(plain.bytes.size(), 1000u);
  EXPECT_EQ(plain.bytes, probed.bytes);
  EXPECT_EQ(probed.problems, 25);
  EXPECT_EQ(probed.first_start, kT0 + int64_t(loadDeployParams().latency_s * 1e6));
  EXPECT_EQ(probed.first_obstacles, 2u);
  ASSERT_EQ(probed.first.status, trajopt::PlanStatus::kOk) << probed.first.message;
  ASSERT_FALSE(plain.trajectories.empty());
  EXPECT_EQ(plain.trajectories.front().coeffs, probed.first.trajectory.coeffs);
  EXPECT_EQ(plain.trajectories.front().durations, probed.first.trajectory.durations);
}

TEST(PlannerNode, GivenAStreamOfMoversAcrossADeadEndThenNothingPassesTheCheckAndItBrakes) {
  // The robot stands in a pocket open towards +x (walls 0.5 m behind it and beside it); a
  // stream of movers passes across the opening, 0.85 m ahead. Every plan and detour out meets
  // them within the check horizon, every manoeuvre runs into the stream or a wall: braking, which
  // stays clear of them, scores best.
  Fixture f(false);
  f.node->map().addBox(-0.8, -0.8, -0.5, 0.8);  // behind
  f.node->map().addBox(-0.8, 0.5, 1.5, 0.8);    // left
  f.node->map().addBox(-0.8, -0.8, 1.5, -0.5);  // right
  f.node->notifyMapChanged();
  std::vector<tracked_object_t> stream;
  for (int k = -10; k <= 10; ++k) stream.push_back(object(110 + k, 0.85, 0.6 * k, 0.0, 1.0));
  f.feed(kT0, 0.0, 0.0, stream);
  f.node->onGoal(goal(kT0, 6.0, 0.0));
  const auto out = f.node->tick(kT0);
  ASSERT_TRUE(out.plan);
  EXPECT_EQ(out.plan->result, PlanResult::kStopNoFeasible) << out.plan->message;
  ASSERT_TRUE(out.trajectory);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_STOP);
  EXPECT_NE(out.trajectory->message.find("no feasible"), std::string::npos) << out.trajectory->message;
  EXPECT_GE(f.report.counter("plans_rejected"), 1);
  EXPECT_GE(f.report.counter("escape_attempts"), 1);
  // The stopping trajectory starts at rest here and stays put.
  const auto& pp = f.node->currentTrajectory();
  EXPECT_LT(pp.sampleRelative(pp.duration()).position.norm(), 1e-9);
}

namespace {
// The robot drives along +x at 1 m/s. A mover crosses just behind it (braking stops the
// robot in its way) and a line of movers comes towards it from ahead (every plan onwards meets
// it before the two-second check ends), so nothing passes the check.
std::vector<tracked_object_t> caughtBetween() {
  std::vector<tracked_object_t> objs{object(100, 0.4, -1.8, 0.0, 1.4)};
  for (int k = -5; k <= 5; ++k) objs.push_back(object(101 + k + 5, 3.9, 0.6 * k, -1.0, 0.0));
  return objs;
}
}  // namespace

// One planning cycle of a robot at the origin driving along +x at 1 m/s among `objs`, goal
// (6, 0), no detours (the plans towards the goal alone).
struct OneCycle {
  Fixture f{false};
  PlannerOutputs out;
  explicit OneCycle(const std::vector<tracked_object_t>& objs) {
    f.params.fallback.detours = 0;
    f.node = std::make_unique<PlannerNode>(f.params, f.report);
    f.node->map().addCylinder(50.0, 50.0, 0.3);
    f.node->notifyMapChanged();
    f.node->onPose(pose(kT0, 0.0, 0.0, 1.0, 0.0));
    f.node->onObjects(objects(kT0, objs));
    f.node->onGoal(goal(kT0, 6.0, 0.0));
    out = f.node->tick(kT0);
  }
};

// The stopping trajectory of a robot at the origin driving along +x at 1 m/s (a cancel
// publishes the same braking as a cycle in which braking scores best).
struct Braking {
  Fixture f{false};
  PlannerOutputs out;
  Braking() {
    f.node->onPose(pose(kT0, 0.0, 0.0, 1.0, 0.0));
    f.node->onObjects(objects(kT0));
    nav_goal_t cancel = goal(kT0, 0.0, 0.0);
    cancel.action = nav_goal_t::ACTION_CANCEL;
    f.node->onGoal(cancel);
    out = f.node->tick(kT0);
  }
};

namespace {
/// Smallest gap between the robot's body following `pp` (at rest after its end) and the movers'
/// bodies (constant velocity, radius half the box diagonal) over [from + t_min, from + horizon].
double smallestGap(const trajectory::PiecewisePolynomial& pp, int64_t from, const std::vector<tracked_object_t>& objs,
                   int64_t objs_utime, double t_min, double horizon, double robot_radius) {
  double worst = INFINITY;
  for (double s = t_min; s <= horizon + 1e-9; s += 0.01) {
    const int64_t t = from + int64_t(std::llround(s * 1e6));
    const auto p = pp.sample(t).position;
    const double dt = 1e-6 * double(t - objs_utime);
    for (const auto& o : objs)
      worst = std::min(worst, std::hypot(p.x() - (o.x + o.vx * dt), p.y() - (o.y + o.vy * dt)) -
                                  0.5 * std::hypot(o.size_x, o.size_y) - robot_radius);
  }
  return worst;
}
}  // namespace

TEST(PlannerNode, GivenNothingPassesTheCheckThenItEvadesWhereBrakingWouldBeHitAndStaysClearOfTheMap) {
  // Driving along +x at 1 m/s; a mover crosses just behind (braking stops the robot in its
  // way), a line of movers comes from ahead: nothing passes the check.
  const auto objs = caughtBetween();
  const Braking brake;
  ASSERT_TRUE(brake.out.trajectory);
  ASSERT_EQ(brake.out.trajectory->status, trajectory_t::STATUS_STOP);

  const OneCycle evade(objs);
  const Fixture& f = evade.f;
  ASSERT_TRUE(evade.out.plan && evade.out.trajectory);
  EXPECT_EQ(evade.out.plan->result, PlanResult::kOk);
  EXPECT_EQ(evade.out.trajectory->status, trajectory_t::STATUS_OK);
  EXPECT_NE(evade.out.trajectory->message.find("evasive manoeuvre"), std::string::npos) << evade.out.trajectory->message;
  EXPECT_EQ(f.report.counter("evasive_manoeuvres"), 1);
  EXPECT_GE(f.report.counter("plans_rejected"), 1) << "the scene must defeat every plan";
  // Braking is hit; the manoeuvre keeps a clearly larger gap to the movers as they are predicted
  // (after the first 0.1 s, over the evasion horizon), and clear of the map, within the limits.
  const int64_t from = kT0 + int64_t(f.params.latency_s * 1e6);
  const double r = f.params.optimizer.robot_radius, h = f.params.fallback.horizon_s;
  const double g_stop = smallestGap(brake.f.node->currentTrajectory(), from, objs, kT0, 0.1, h, r);
  const double g_evade = smallestGap(f.node->currentTrajectory(), from, objs, kT0, 0.1, h, r);
  EXPECT_LT(g_stop, 0.0);
  EXPECT_GT(g_evade, g_stop + 0.2) << g_evade << " vs " << g_stop;
  EXPECT_GE(minMapDistance(*f.node, f.node->currentTrajectory()), r);
  const auto& pp = f.node->currentTrajectory();
  for (double t = 0.0; t <= pp.duration(); t += 0.01)
    EXPECT_LE(pp.sampleRelative(t).acceleration.norm(), f.params.optimizer.max_acceleration + 1e-9);
  // It starts where the robot is expected to be, moving as it does.
  EXPECT_LT((pp.sample(from).velocity - Eigen::Vector3d(1.0, 0.0, 0.0)).norm(), 1e-9);
}

TEST(PlannerNode, GivenAnEvasiveManoeuvreUnderWayWhenStillNothingPassesThenItIsKeptUnlessSomethingScoresBetter) {
  // A ring of movers closing in from every side, one gap in it: nothing passes the check, the
  // robot heads for the gap; 0.1 s later (the ring closer still) a fresh manoeuvre the same way
  // scores a little better (it holds full speed 0.1 s longer), by less than keep_margin.
  std::vector<tracked_object_t> ring;
  for (int k = 1; k < 12; ++k) {
    const double a = k * 2.0 * M_PI / 12.0;
    ring.push_back(object(100 + k, 2.0 * std::cos(a), 2.0 * std::sin(a), -1.0 * std::cos(a), -1.0 * std::sin(a)));
  }
  struct Run {
    PlannerOutputs first, second;
    int64_t kept = 0;
  };
  auto run = [&](double keep_margin) {
    Fixture f(false);
    f.params.fallback.keep_margin = keep_margin;
    f.node = std::make_unique<PlannerNode>(f.params, f.report);
    f.node->map().addCylinder(50.0, 50.0, 0.3);
    f.node->notifyMapChanged();
    f.node->onPose(pose(kT0, 0.0, 0.0));
    f.node->onObjects(objects(kT0, ring));
    f.node->onGoal(goal(kT0, 0.0, 6.0));
    Run r;
    r.first = f.node->tick(kT0);
    const int64_t t1 = kT0 + 100'000;
    const auto s = f.node->currentTrajectory().sample(t1);
    std::vector<tracked_object_t> moved = ring;
    for (auto& o : moved) o.x += 0.1 * o.vx, o.y += 0.1 * o.vy;
    f.node->onPose(pose(t1, s.position.x(), s.position.y(), s.velocity.x(), s.velocity.y()));
    f.node->onObjects(objects(t1, moved));
    r.second = f.node->tick(t1);
    r.kept = f.report.counter("evasion_kept");
    return r;
  };
  const Run keep = run(0.05);
  ASSERT_TRUE(keep.first.trajectory && keep.second.trajectory && keep.second.plan);
  ASSERT_NE(keep.first.trajectory->message.find("evasive manoeuvre"), std::string::npos)
      << keep.first.trajectory->message;
  EXPECT_EQ(keep.second.plan->result, PlanResult::kKeptPrevious);
  EXPECT_NE(keep.second.trajectory->message.find("kept (evasion)"), std::string::npos)
      << keep.second.trajectory->message;
  EXPECT_EQ(keep.second.trajectory->plan_id, keep.first.trajectory->plan_id);  // the same curve, re-sent
  EXPECT_EQ(keep.second.trajectory->utime, kT0 + 100'000);
  EXPECT_EQ(keep.kept, 1);
  // Without the margin the better-scoring fresh manoeuvre replaces it.
  const Run fresh = run(0.0);
  ASSERT_TRUE(fresh.second.trajectory);
  EXPECT_NE(fresh.second.trajectory->message.find("evasive manoeuvre"), std::string::npos)
      << fresh.second.trajectory->message;
  EXPECT_NE(fresh.second.trajectory->plan_id, fresh.first.trajectory->plan_id);
  EXPECT_EQ(fresh.kept, 0);
}

TEST(PlannerNode, GivenARobotDrivingWhenItBrakesThenItStopsAtTheFullAccelerationLimitAlongItsPath) {
  const Braking brake;  // driving along +x at 1 m/s
  ASSERT_TRUE(brake.out.trajectory);
  ASSERT_EQ(brake.out.trajectory->status, trajectory_t::STATUS_STOP);
  const auto& pp = brake.f.node->currentTrajectory();
  const double amax = brake.f.params.optimizer.max_acceleration;
  // v^2 / (2 a): 0.25 m at 1 m/s and 2 m/s^2 (a minimum-jerk stop needs twice that).
  const auto end = pp.sampleRelative(pp.duration());
  EXPECT_NEAR(end.position.x(), 1.0 * 1.0 / (2.0 * amax), 1e-9);
  EXPECT_NEAR(end.position.y(), 0.0, 1e-12);
  EXPECT_LT(end.velocity.norm(), 1e-12);
  EXPECT_NEAR(pp.sampleRelative(0.5 / amax).velocity.x(), 0.5, 1e-9);  // half speed halfway
  for (double t = 0.0; t <= pp.duration(); t += 0.01) {
    const auto s = pp.sampleRelative(t);
    EXPECT_LE(s.acceleration.norm(), amax + 1e-9);
    EXPECT_GE(s.velocity.x(), -1e-12);  // never backs up
  }
  EXPECT_GE(pp.duration(), 0.5 + 1.0 / amax - 1e-9);  // then held at rest
}

namespace {
/// A PERCEPTION_STATIC frame: a ring of points of `radius` around each centre, at height z.
ucon::static_points_t ringsAt(int64_t utime, const std::vector<Eigen::Vector2d>& centres, double radius, double z) {
  ucon::static_points_t m{};
  m.utime = utime;
  m.valid = true;
  m.origin_x = 0.0;
  m.origin_y = 0.0;
  m.origin_z = z;
  m.max_range = 10.0f;
  for (const auto& c : centres)
    for (int k = 0; k < 24; ++k) {
      const double a = 2.0 * M_PI * k / 24.0;
      m.x.push_back(float(c.x() + radius * std::cos(a)));
      m.y.push_back(float(c.y() + radius * std::sin(a)));
      m.z.push_back(float(z));
    }
  m.num_points = int(m.x.size());
  return m;
}
}  // namespace

TEST(PlannerNode, GivenAConfirmedMoverOnGhostCellsThenTheyAreClearedButNotUnderSlowOrTentativeTracks) {
  // Ghost obstacles: a mover's points that leaked into the static map. A confirmed track at
  // least clear_under_speed fast clears the band under its body; a slow or tentative one
  // (maybe a false track on real structure) does not.
  Fixture f(false);
  ASSERT_GT(f.params.objects.clear_under_speed, 0.0);
  const double z = 0.5 * (f.params.map.band_z_min + f.params.map.band_z_max);
  // The three "ghosts" have just been published as static points (young cells).
  f.node->onStatic(ringsAt(kT0 - 100000, {{3.0, 0.0}, {3.0, 3.0}, {3.0, -3.0}}, 0.1, z));
  f.node->map().addCylinder(3.0, 0.0, 0.25);   // ghost under the moving track
  f.node->map().addCylinder(3.0, 3.0, 0.25);   // under a slow track
  f.node->map().addCylinder(3.0, -3.0, 0.25);  // under a tentative track
  f.node->notifyMapChanged();
  auto moving = object(1, 3.0, 0.0, 0.0, 1.0);
  auto slow = object(2, 3.0, 3.0, 0.0, 0.5 * f.params.objects.clear_under_speed);
  auto tentative = object(3, 3.0, -3.0, 0.0, 1.0);
  tentative.state = tracked_object_t::STATE_TENTATIVE;
  f.node->onPose(pose(kT0, 0, 0));
  f.node->onObjects(objects(kT0, {moving, slow, tentative}));
  EXPECT_FALSE(f.node->map().isOccupied(Eigen::Vector3d(3.0, 0.0, z)));
  EXPECT_TRUE(f.node->map().isOccupied(Eigen::Vector3d(3.0, 3.0, z)));
  EXPECT_TRUE(f.node->map().isOccupied(Eigen::Vector3d(3.0, -3.0, z)));
  EXPECT_EQ(f.report.counter("cleared_under_movers"), 1);
}

TEST(PlannerNode, GivenAMoverPassingOldStructureThenOnlyItsYoungGhostIsCleared) {
  // Structure seen for longer than clear_max_age stays when a fast confirmed track passes
  // over it; the ghost the mover left a moment ago, and cells without any static points,
  // are told apart by when their static points began.
  Fixture f(false);
  ASSERT_GT(f.params.objects.clear_max_age, 0.0);
  const double z = 0.5 * (f.params.map.band_z_min + f.params.map.band_z_max);
  const int64_t dt = 100000;  // 10 Hz static frames
  const int64_t old_span = int64_t((f.params.objects.clear_max_age + 1.0) * 1e6);
  const int64_t now = kT0 + old_span;
  for (int64_t t = kT0; t < now; t += dt) {
    std::vector<Eigen::Vector2d> c{{3.0, 0.25}};                  // a pillar edge, seen all along
    if (t >= now - 3 * dt) c.push_back(Eigen::Vector2d(3.0, -0.25));  // the mover's leak, new
    f.node->onStatic(ringsAt(t, c, 0.05, z));
  }
  f.node->map().addCylinder(3.0, 0.25, 0.08);
  f.node->map().addCylinder(3.0, -0.25, 0.08);
  f.node->notifyMapChanged();
  f.node->onPose(pose(now, 0, 0));
  auto mover = object(1, 3.0, 0.0, 0.0, 1.0);
  mover.size_x = mover.size_y = 0.7;  // its body covers both
  f.node->onObjects(objects(now, {mover}));
  EXPECT_TRUE(f.node->map().isOccupied(Eigen::Vector3d(3.0, 0.25, z)));
  EXPECT_FALSE(f.node->map().isOccupied(Eigen::Vector3d(3.0, -0.25, z)));
  EXPECT_EQ(f.report.counter("cleared_under_movers"), 1);
}

TEST(PlannerNode, GivenANewPlanRejectedWhileThePreviousIsStillSafeThenThePreviousGoesOutAgainStampedNow) {
  // The base controller stops on a trajectory older than its watchdog (0.2 s): a kept plan
  // must be re-sent, or two such cycles in a row stop the robot where it stands.
  Fixture f(false);
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 8.0, 0.0));
  const auto first = f.node->tick(kT0);
  ASSERT_TRUE(first.trajectory);
  ASSERT_EQ(first.trajectory->status, trajectory_t::STATUS_OK);
  // The pose now says the robot is 3 m off its plan (replans start from the pose), inside a
  // ring of movers closing in: no plan from there passes the check. The plan itself runs
  // along y = 0, which none of them reaches within the check horizon: it is still safe.
  const int64_t t = kT0 + 100000;
  const auto p = f.node->currentTrajectory().position(t);
  std::vector<tracked_object_t> ring;
  for (int k = 0; k < 12; ++k) {
    const double a = k * 2.0 * M_PI / 12.0;
    ring.push_back(object(100 + k, p.x() + 1.2 * std::cos(a), 3.0 + 1.2 * std::sin(a), -1.0 * std::cos(a),
                          -1.0 * std::sin(a)));
  }
  f.feed(t, p.x(), 3.0, ring);
  ASSERT_EQ(f.node->check(*first.trajectory, t).status, trajopt::PlanStatus::kOk);
  const auto out = f.node->tick(t);
  ASSERT_TRUE(out.plan);
  ASSERT_EQ(out.plan->result, PlanResult::kKeptPrevious) << out.plan->message;
  ASSERT_TRUE(out.trajectory) << "a kept plan must be re-sent";
  EXPECT_EQ(out.trajectory->plan_id, first.trajectory->plan_id);
  EXPECT_EQ(out.trajectory->seq, first.trajectory->seq + 1);
  EXPECT_EQ(out.trajectory->utime, t);
  EXPECT_EQ(out.trajectory->start_utime, first.trajectory->start_utime);
  EXPECT_EQ(out.trajectory->coeffs, first.trajectory->coeffs);
  EXPECT_EQ(out.trajectory->status, trajectory_t::STATUS_OK);
  EXPECT_NE(out.trajectory->message.find("kept previous plan"), std::string::npos) << out.trajectory->message;
  EXPECT_EQ(f.report.counter("result_kept_previous"), 1);
}

namespace {

// The end of the first plan toward a goal inside a pillar: the nearest reachable safe point.
Eigen::Vector2d nearestReachable() {
  Fixture f(false);
  f.node->map().addCylinder(3.0, 0.0, 0.8);
  f.node->notifyMapChanged();
  f.feed(kT0);
  f.node->onGoal(goal(kT0, 3.0, 0.0));
  const auto out = f.node->tick(kT0);
  EXPECT_TRUE(out.trajectory && out.trajectory->status == trajectory_t::STATUS_OK);
  const auto& pp = f.node->currentTrajectory();
  return pp.sampleRelative(pp.duration()).position.head<2>();
}

// One cycle of a robot standing at `at` with that goal, and `objs`.
struct Holding {
  Fixture f{false};
  PlannerOutputs out;
  Holding(const Eigen::Vector2d& at, const std::vector<tracked_object_t>& objs) {
    f.node->map().addCylinder(3.0, 0.0, 0.8);
    f.node->notifyMapChanged();
    f.feed(kT0, at.x(), at.y(), objs);
    f.node->onGoal(goal(kT0, 3.0, 0.0));
    out = f.node->tick(kT0);
  }
};

}  // namespace

TEST(PlannerNode, GivenTheRobotHoldingAtTheNearestReachablePointWhenAMoverWalksAtItThenItEvades) {
  const Eigen::Vector2d at = nearestReachable();
  // Nothing around: it holds there (the goal is kept; the map may open).
  const Holding quiet(at, {});
  ASSERT_TRUE(quiet.out.trajectory);
  EXPECT_EQ(quiet.out.trajectory->status, trajectory_t::STATUS_STOP) << quiet.out.trajectory->message;
  EXPECT_NE(quiet.out.trajectory->message.find("inside an obstacle"), std::string::npos) << quiet.out.trajectory->message;
  EXPECT_EQ(quiet.f.report.counter("hold_evasions"), 0);
  // A mover 2.5 m to the side walking straight at the robot at 1 m/s: standing still is hit.
  const std::vector<tracked_object_t> objs{object(7, at.x(), at.y() + 2.5, 0.0, -1.0)};
  const Holding hit(at, objs);
  ASSERT_TRUE(hit.out.trajectory && hit.out.plan);
  EXPECT_EQ(hit.f.report.counter("hold_evasions"), 1);
  EXPECT_EQ(hit.out.trajectory->status, trajectory_t::STATUS_OK) << hit.out.trajectory->message;
  const int64_t from = kT0 + int64_t(hit.f.params.latency_s * 1e6);
  const double r = hit.f.params.optimizer.robot_radius, h = hit.f.params.fallback.horizon_s;
  const double g_hold = smallestGap(quiet.f.node->currentTrajectory(), from, objs, kT0, 0.1, h, r);
  const double g_evade = smallestGap(hit.f.node->currentTrajectory(), from, objs, kT0, 0.1, h, r);
  EXPECT_LT(g_hold, 0.0);
  EXPECT_GT(g_evade, g_hold + 0.3) << g_evade << " vs " << g_hold;
  EXPECT_GE(minMapDistance(*hit.f.node, hit.f.node->currentTrajectory()), r);
}
