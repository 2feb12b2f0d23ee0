#include <gtest/gtest.h>

#include <cmath>

#include "test_fixtures.hpp"
#include "ucon/config.hpp"
#include "ucon/trajopt/sector_minco.hpp"

using namespace ucon::trajopt;
using trajopt_test::DiscField;

namespace ucon::trajopt {
void PrintTo(PlanStatus s, std::ostream* os) { *os << toString(s); }
}  // namespace ucon::trajopt

namespace {

constexpr int64_t kStart = 10'000'000;

PlanRequest straightRequest(const DistanceField2D* field) {
  PlanRequest r;
  r.start_utime = kStart;
  r.start << 0.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  r.goal << 8.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  for (int i = 1; i < 5; ++i) r.inner_waypoints.push_back(Eigen::Vector2d(1.6 * i, 0.0));
  r.durations.assign(5, 1.4);
  r.field = field;
  return r;
}

PredictedObstacle obstacle(int64_t id, Eigen::Vector2d p, Eigen::Vector2d v, double radius) {
  PredictedObstacle o;
  o.id = id;
  o.utime = kStart;
  o.state << p.x(), p.y(), 0.0, v.x(), v.y(), 0.0;
  o.covariance = ucon::kalman::Cov6::Zero();
  o.covariance.diagonal() << 0.01, 0.01, 0.01, 0.04, 0.04, 0.04;
  o.radius = radius;
  return o;
}

Eigen::Vector2d positionAt(const ucon::trajectory_t& tr, double t) {
  int k = 0;
  while (k + 1 < tr.num_pieces && t > tr.durations[k]) t -= tr.durations[k++];
  t = std::min(t, tr.durations[k]);
  Eigen::Vector2d p;
  for (int d = 0; d < 2; ++d) {
    double v = 0.0;
    for (int j = 5; j >= 0; --j) v = v * t + tr.coeffs[(k * 2 + d) * 6 + j];
    p(d) = v;
  }
  return p;
}

}  // namespace

TEST(Optimizer, GivenAStaticDiscOnTheStraightPathWhenPlannedThenTheResultGoesAroundItAndPassesTheCheck) {
  const DiscField field({{Eigen::Vector2d(4.0, 0.05), 0.6}});
  TrajectoryOptimizer opt;
  const PlanRequest req = straightRequest(&field);
  // The initial guess itself collides.
  EXPECT_LT(field.distance(4.0, 0.0, nullptr), opt.params().robot_radius);
  const PlanOutput out = opt.plan(req);
  ASSERT_EQ(out.status, PlanStatus::kOk) << out.message << " " << out.solver_result;
  EXPECT_GE(out.min_static_clearance, opt.params().robot_radius);
  EXPECT_LE(out.max_speed, opt.params().max_velocity * (1 + opt.params().limit_tolerance));
  EXPECT_GT(out.iterations, 1);
  EXPECT_EQ(out.trajectory.status, ucon::trajectory_t::STATUS_OK);
  EXPECT_EQ(out.trajectory.start_utime, kStart);
  ASSERT_EQ(out.trajectory.num_pieces, 5);
  EXPECT_EQ(out.durations.size(), 5u);
  EXPECT_EQ(out.inner_waypoints.size(), 4u);
  EXPECT_LT((positionAt(out.trajectory, 0.0) - Eigen::Vector2d(0, 0)).norm(), 1e-9);
  double total = 0;
  for (double T : out.trajectory.durations) total += T;
  EXPECT_LT((positionAt(out.trajectory, total) - Eigen::Vector2d(8, 0)).norm(), 1e-8);
  EXPECT_GT(out.cost.energy, 0.0);
}

TEST(Optimizer, GivenAnObstacleCrossingThePathWhenPlannedWithEachModelThenNoPredictedCollision) {
  for (ObstacleModel m : {ObstacleModel::kSector, ObstacleModel::kNoUncertainty, ObstacleModel::kFapp}) {
    OptimizerParams p;
    p.obstacle_model = m;
    TrajectoryOptimizer opt(p);
    PlanRequest req = straightRequest(nullptr);
    // Walks across the straight line so it would meet the robot around x = 4 m at t = 3.5 s.
    req.obstacles.push_back(obstacle(1, {4.0, -3.5}, {0.0, 1.0}, 0.3));
    const SafetyCheck before = checkTrajectory(
        [&] {
          // The straight-line guess with the given durations (plan with no obstacle cost).
          OptimizerParams q = p;
          q.lambda_d = 0.0;
          q.max_iterations = 1;
          TrajectoryOptimizer o(q);
          return o.plan(straightRequest(nullptr)).trajectory;
        }(),
        kStart, nullptr, req.obstacles, [&] {
          OptimizerParams q = p;
          q.check_horizon = 10.0;
          q.limit_tolerance = 100.0;  // only the collision matters here
          return q;
        }());
    EXPECT_EQ(before.status, PlanStatus::kDynamicCollision) << toString(m);
    const PlanOutput out = opt.plan(req);
    EXPECT_EQ(out.status, PlanStatus::kOk) << toString(m) << ": " << out.message;
    EXPECT_EQ(out.obstacles_used, 1);
    EXPECT_GT(out.min_dynamic_clearance, p.robot_radius) << toString(m);
  }
}

TEST(Optimizer, GivenTheSameRequestTwiceThenByteIdenticalTrajectories) {
  const DiscField field({{Eigen::Vector2d(4.0, 0.3), 0.5}});
  PlanRequest req = straightRequest(&field);
  req.obstacles.push_back(obstacle(1, {6.0, -2.0}, {0.0, 0.8}, 0.3));
  TrajectoryOptimizer a, b;
  const PlanOutput oa = a.plan(req), ob = b.plan(req), oa2 = a.plan(req);
  ASSERT_EQ(oa.trajectory.coeffs.size(), ob.trajectory.coeffs.size());
  EXPECT_TRUE(oa.trajectory.coeffs == ob.trajectory.coeffs);
  EXPECT_TRUE(oa.trajectory.coeffs == oa2.trajectory.coeffs);
  EXPECT_TRUE(oa.trajectory.durations == ob.trajectory.durations);
  EXPECT_EQ(oa.iterations, ob.iterations);
}

TEST(Optimizer, GivenBadInputThenInvalidInputStatusAndNoTrajectoryToFollow) {
  TrajectoryOptimizer opt;
  PlanRequest req = straightRequest(nullptr);
  req.goal(0, 0) = std::nan("");
  PlanOutput out = opt.plan(req);
  EXPECT_EQ(out.status, PlanStatus::kInvalidInput);
  EXPECT_EQ(out.trajectory.status, ucon::trajectory_t::STATUS_INVALID);
  EXPECT_EQ(out.trajectory.num_pieces, 0);
  EXPECT_STREQ(toString(out.status), "invalid_input");
  req = straightRequest(nullptr);
  req.durations.clear();
  EXPECT_EQ(opt.plan(req).status, PlanStatus::kInvalidInput);
  OptimizerParams bad;
  bad.robot_radius = 0.5;
  bad.safe_distance = 0.3;
  EXPECT_EQ(bad.validate(), "safe_distance");
  TrajectoryOptimizer badopt(bad);
  EXPECT_EQ(badopt.plan(straightRequest(nullptr)).status, PlanStatus::kInvalidInput);
  // NaN obstacle state is dropped and counted, a non-PD covariance is used without it.
  req = straightRequest(nullptr);
  req.obstacles.push_back(obstacle(1, {4.0, 0.0}, {std::nan(""), 0.0}, 0.3));
  auto o2 = obstacle(2, {4.0, -3.5}, {0.0, 1.0}, 0.3);
  o2.covariance(0, 0) = -1.0;
  req.obstacles.push_back(o2);
  out = opt.plan(req);
  EXPECT_EQ(out.obstacles_rejected, 1);
  EXPECT_EQ(out.obstacles_without_covariance, 1);
  EXPECT_EQ(out.status, PlanStatus::kOk) << out.message;
  EXPECT_GT(out.min_dynamic_clearance, opt.params().robot_radius);
}

TEST(Optimizer, GivenATrajectoryThroughAnObstacleThenTheCheckReportsIt) {
  const DiscField field({{Eigen::Vector2d(4.0, 0.0), 0.5}});
  OptimizerParams p;
  p.weight_static = 0.0;  // let the optimiser ignore the map: the check must catch it
  p.max_iterations = 3;
  TrajectoryOptimizer opt(p);
  const PlanOutput out = opt.plan(straightRequest(&field));
  EXPECT_EQ(out.status, PlanStatus::kStaticCollision);
  EXPECT_EQ(out.trajectory.status, ucon::trajectory_t::STATUS_INVALID);
  EXPECT_LT(out.min_static_clearance, 0.0);
  ucon::trajectory_t bad = out.trajectory;
  bad.coeffs[3] = std::nan("");
  EXPECT_EQ(checkTrajectory(bad, kStart, &field, {}, p).status, PlanStatus::kInvalidInput);
  // From a later time on, the part behind is no longer checked.
  double total = 0;
  for (double T : out.trajectory.durations) total += T;
  const int64_t late = kStart + static_cast<int64_t>(0.95 * total * 1e6);
  EXPECT_EQ(checkTrajectory(out.trajectory, late, &field, {}, p).status, PlanStatus::kOk);
}

namespace {

// One quintic piece of `T` seconds from the origin at constant velocity (vx, vy).
ucon::trajectory_t straightLine(double vx, double vy, double T) {
  ucon::trajectory_t tr{};
  tr.start_utime = kStart;
  tr.dim = 2;
  tr.order1 = 6;
  tr.num_pieces = 1;
  tr.durations = {T};
  tr.num_coeffs = 12;
  tr.coeffs.assign(12, 0.0);
  tr.coeffs[1] = vx;
  tr.coeffs[6 + 1] = vy;
  tr.status = ucon::trajectory_t::STATUS_OK;
  return tr;
}

}  // namespace

TEST(Optimizer, GivenAStartInsideTheStaticClearanceThenOnlyAPlanLeavingItWithoutComingCloserPassesInTime) {
  // The robot's centre is 0.2 m from a pillar's surface: closer than robot_radius (0.3 m).
  const DiscField field({{Eigen::Vector2d(0.0, -0.5), 0.3}});
  OptimizerParams p;
  ASSERT_NEAR(field.distance(0.0, 0.0, nullptr), 0.2, 1e-9);
  ASSERT_DOUBLE_EQ(p.static_escape_s, 1.0);
  // Away from the pillar, along it: clear of robot_radius after ~0.4 s.
  EXPECT_EQ(checkTrajectory(straightLine(1.0, 0.0, 2.0), kStart, &field, {}, p).status, PlanStatus::kOk);
  EXPECT_EQ(checkTrajectory(straightLine(0.0, 0.5, 2.0), kStart, &field, {}, p).status, PlanStatus::kOk);
  // Towards it: closer than the start.
  EXPECT_EQ(checkTrajectory(straightLine(0.0, -0.2, 2.0), kStart, &field, {}, p).status,
            PlanStatus::kStaticCollision);
  // Too slowly out: still inside after static_escape_s.
  EXPECT_EQ(checkTrajectory(straightLine(0.0, 0.05, 3.0), kStart, &field, {}, p).status,
            PlanStatus::kStaticCollision);
  // Without the allowance, any plan from here fails (the robot could only brake).
  p.static_escape_s = 0.0;
  EXPECT_EQ(checkTrajectory(straightLine(1.0, 0.0, 2.0), kStart, &field, {}, p).status,
            PlanStatus::kStaticCollision);
  // A plan that starts clear gets no allowance: passing as close later fails as before, and so
  // does creeping just inside the clearance from just outside it.
  p.static_escape_s = 1.0;
  const DiscField ahead({{Eigen::Vector2d(1.0, -0.5), 0.3}});
  EXPECT_EQ(checkTrajectory(straightLine(1.0, 0.0, 2.0), kStart, &ahead, {}, p).status,
            PlanStatus::kStaticCollision);
  const DiscField edge({{Eigen::Vector2d(0.0, -0.605), 0.3}});  // 0.305 m: just clear
  EXPECT_EQ(checkTrajectory(straightLine(0.0, -0.01, 1.0), kStart, &edge, {}, p).status,
            PlanStatus::kStaticCollision);
}

TEST(Optimizer, GivenAnUncertainObstacleThenItsPredictedSigmaGrowsAndTheCheckCanKeepThatMargin) {
  // Position variance 0.01 m^2, velocity 0.04 (m/s)^2, no cross terms: sigma(t)^2 = 0.01 + 0.04 t^2.
  PredictedObstacle o = obstacle(1, Eigen::Vector2d(2.0, 1.0), Eigen::Vector2d(0.0, 0.0), 0.3);
  EXPECT_NEAR(predictedPositionSigma(o, kStart), 0.1, 1e-12);
  EXPECT_NEAR(predictedPositionSigma(o, kStart + 1'500'000), std::sqrt(0.01 + 0.04 * 2.25), 1e-12);
  // Correlated position and velocity along x (P_pv = 0.02): 0.01 + 2 t 0.02 + 0.04 t^2 at t = 1.
  o.covariance(0, 3) = o.covariance(3, 0) = 0.02;
  EXPECT_NEAR(predictedPositionSigma(o, kStart + 1'000'000), std::sqrt(0.09), 1e-12);
  o.has_covariance = false;
  EXPECT_EQ(predictedPositionSigma(o, kStart + 1'000'000), 0.0);
  o.has_covariance = true;
  o.covariance(1, 1) = NAN;
  EXPECT_EQ(predictedPositionSigma(o, kStart + 1'000'000), 0.0);

  // A still obstacle 0.65 m beside a straight run along x: its body 0.35 m from the robot's
  // centre at the closest, more than robot_radius (0.3 m). First the prediction as it is.
  OptimizerParams p;
  p.check_uncertainty_k = 0.0;
  p.check_uncertainty_cap = 0.0;
  const std::vector<PredictedObstacle> obs{obstacle(2, Eigen::Vector2d(1.0, 0.65), Eigen::Vector2d::Zero(), 0.3)};
  EXPECT_EQ(checkTrajectory(straightLine(1.0, 0.0, 2.0), kStart, nullptr, obs, p).status, PlanStatus::kOk);
  // Grown by one sigma (0.1 m now, 0.22 m when passing it at 1 s) it is within reach.
  p.check_uncertainty_k = 1.0;
  const SafetyCheck grown = checkTrajectory(straightLine(1.0, 0.0, 2.0), kStart, nullptr, obs, p);
  EXPECT_EQ(grown.status, PlanStatus::kDynamicCollision);
  EXPECT_LE(grown.min_dynamic_clearance, 0.35 - std::sqrt(0.01 + 0.04) + 1e-9);
  // Capped at 0.04 m the growth no longer reaches the robot: 0.35 - 0.04 > 0.3.
  p.check_uncertainty_cap = 0.04;
  const SafetyCheck capped = checkTrajectory(straightLine(1.0, 0.0, 2.0), kStart, nullptr, obs, p);
  EXPECT_EQ(capped.status, PlanStatus::kOk);
  EXPECT_NEAR(capped.min_dynamic_clearance, 0.35 - 0.04, 1e-3);
}

TEST(Optimizer, GivenYamlThenParamsReadOneToOneAndTyposRejected) {
  const std::string yaml = R"(
obstacle_model: fapp
safe_distance: 0.45
max_velocity: 1.5
max_acceleration: 2.0
rho: 10.0
lambda_d: 5000.0
weight_static: 10000.0
weight_velocity: 1000.0
weight_acceleration: 1000.0
samples_per_piece: 10
dynamic_horizon: 3.0
obstacle_corridor: 3.0
max_iterations: 150
relative_tolerance: 1.0e-5
use_time_budget: false
time_budget_ms: 5.0
robot_radius: 0.3
check_step: 0.02
check_horizon: 2.0
limit_tolerance: 0.1
check_uncertainty_k: 0.5
check_uncertainty_cap: 0.2
static_escape_s: 1.0
sector:
  h: 0.02
  k: 2.0
  kappa: 0.05
  alpha: 15.0
  beta: 25.0
  min_speed: 0.05
  fapp_margin: 0.2
)";
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<OptimizerParams>(yaml, "trajopt.yaml", &errors);
  ASSERT_TRUE(p.has_value()) << (errors.empty() ? "" : errors[0].toString());
  EXPECT_EQ(p->obstacle_model, ObstacleModel::kFapp);
  EXPECT_EQ(p->samples_per_piece, 10);
  EXPECT_DOUBLE_EQ(p->sector.beta, 25.0);
  EXPECT_DOUBLE_EQ(p->safe_distance, 0.45);
  EXPECT_DOUBLE_EQ(p->check_uncertainty_k, 0.5);
  EXPECT_DOUBLE_EQ(p->check_uncertainty_cap, 0.2);
  EXPECT_FALSE(ucon::loadParams<OptimizerParams>(yaml + "lamda_d: 1\n", "t.yaml", &errors).has_value());
  std::string wrong = yaml;
  wrong.replace(wrong.find("fapp"), 4, "ellipse");
  EXPECT_FALSE(ucon::loadParams<OptimizerParams>(wrong, "t.yaml", &errors).has_value());
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].key, "obstacle_model");
  ObstacleModel m;
  EXPECT_TRUE(parseObstacleModel("no_uncertainty", &m));
  EXPECT_EQ(m, ObstacleModel::kNoUncertainty);
  EXPECT_FALSE(parseObstacleModel("Sector", &m));
}

TEST(Optimizer, GivenATrackedObjectMessageThenObstacleHasRadiusAndCovariance) {
  ucon::tracked_object_t o{};
  o.id = 5;
  o.x = 1;
  o.y = 2;
  o.vx = 0.5;
  o.size_x = 0.6;
  o.size_y = 0.8;
  o.cov_size = 36;
  o.cov.assign(36, 0.0);
  for (int i = 0; i < 6; ++i) o.cov[i * 7] = 0.1 * (i + 1);
  o.cov[1] = o.cov[6] = 0.01;
  const PredictedObstacle p = obstacleFromMessage(o, 777);
  EXPECT_EQ(p.utime, 777);
  EXPECT_NEAR(p.radius, 0.5, 1e-12);
  EXPECT_TRUE(p.has_covariance);
  EXPECT_DOUBLE_EQ(p.covariance(0, 1), 0.01);
  EXPECT_DOUBLE_EQ(p.covariance(5, 5), 0.6);
  EXPECT_DOUBLE_EQ(p.state(3), 0.5);
  o.cov_size = 0;
  o.cov.clear();
  EXPECT_FALSE(obstacleFromMessage(o, 777).has_covariance);
}
