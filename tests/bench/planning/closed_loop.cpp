#include "closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ucon/cpu_time.hpp"
#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/perception/outputs.hpp"
#include "ucon/planner/planner_node.hpp"
#include "ucon/status_report.hpp"
#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/world/bench_generator.hpp"
#include "ucon/world/rng.hpp"
#include "ucon/world/world.hpp"

namespace ucon::bench {

namespace {

constexpr int64_t kUtime0 = 1'000'000;  // simulated t = 0 [us] (utime must be > 0)

/// CPU time of the calling thread [ms]: plan cost without the time other processes on a
/// shared machine take the core away.
double threadCpuMs() { return 1e3 * ucon::threadCpuSeconds(); }

/// Marks the static footprints in the planner's map: every leaf of the height band whose
/// centre is within half a cell of a footprint (so thin walls are not lost between centres).
void buildStaticMap(const world::World& w, planner::EsdfMap& map) {
  const auto& mp = map.params();
  const double res = mp.resolution;
  const auto& statics = w.scenario().statics;
  for (std::size_t i = 0; i < statics.size(); ++i) {
    const auto& s = statics[i];
    const double R = (s.kind == world::ShapeKind::kCylinder ? s.radius : s.half_size.norm()) + res;
    const double x0 = std::floor((s.center.x() - R) / res) * res, x1 = s.center.x() + R;
    const double y0 = std::floor((s.center.y() - R) / res) * res, y1 = s.center.y() + R;
    for (double y = y0 + 0.5 * res; y <= y1; y += res) {
      for (double x = x0 + 0.5 * res; x <= x1; x += res) {
        if (w.staticFootprintDistance(i, world::Vec2(x, y)) > 0.5 * res) continue;
        for (double z = std::floor(mp.band_z_min / res) * res + 0.5 * res; z <= mp.band_z_max + 0.5 * res;
             z += res) {
          if (z > s.height) break;
          map.setCell(Eigen::Vector3d(x, y, z), true);
        }
      }
    }
  }
}

}  // namespace

RunResult runClosedLoop(const planner::PlannerParams& base, const RunConfig& cfg) {
  RunResult res;
  const world::Scenario sc = world::generateBench(cfg.n_dynamic, cfg.seed);
  world::World w(sc);

  planner::PlannerParams params = base;
  if (!trajopt::parseObstacleModel(cfg.method, &params.optimizer.obstacle_model)) return res;
  params.optimizer.robot_radius = sc.robot.radius;
  params.optimizer.max_velocity = sc.robot.max_speed;
  params.optimizer.max_acceleration = sc.robot.max_accel;
  params.optimizer.use_time_budget = false;
  params.workspace = {sc.bounds.xmin, sc.bounds.xmax, sc.bounds.ymin, sc.bounds.ymax};

  StatusReport report("planner");
  planner::PlannerNode node(params, report);
  buildStaticMap(w, node.map());
  node.prepareMap(sc.robot.start);

  // Trackers: one filter per mover, perfect association (ids from the ground truth).
  kalman::KalmanParams tracker = params.prediction.model();
  tracker.position_std = cfg.noise_std;
  tracker.velocity_std = cfg.tracker_velocity_std;
  tracker.initial_velocity_std = cfg.tracker_initial_velocity_std;
  std::vector<kalman::ConstantVelocityKalman> filters(w.numMovers(), kalman::ConstantVelocityKalman(tracker));
  world::Rng noise(world::deriveSeed(cfg.seed, 0x5eed));

  const double dt = 1.0 / cfg.observe_hz;
  const int64_t dt_us = int64_t(std::llround(dt * 1e6));
  const world::Vec2 goal = sc.robot.goals.empty() ? world::Vec2(22.0, 0.0) : sc.robot.goals.front();
  Eigen::Vector2d robot = sc.robot.start;
  Eigen::Vector2d robot_v = Eigen::Vector2d::Zero();
  trajectory::PiecewisePolynomial active, pending;
  bool goal_sent = false;
  double jerk_sum = 0.0;
  int64_t jerk_n = 0;
  const int steps = int(std::ceil((cfg.timeout_s + cfg.warmup_s) / dt));

  for (int k = 0; k <= steps; ++k) {
    const double t = k * dt;
    const int64_t utime = kUtime0 + int64_t(k) * dt_us;
    w.setTime(t);

    // Ideal tracking of the latest trajectory that has started.
    if (pending.valid() && utime >= pending.startUtime()) {
      active = pending;
      pending = trajectory::PiecewisePolynomial();
    }
    if (active.valid()) {
      const auto s = active.sample(utime);
      const Eigen::Vector2d p = s.position.head<2>();
      res.path_length += (p - robot).norm();
      robot = p;
      robot_v = s.velocity.head<2>();
      if (goal_sent) {
        jerk_sum += s.jerk.head<2>().norm();
        ++jerk_n;
      }
    }

    // Collision and success.
    const world::Contact c = w.diskContact(robot, sc.robot.radius);
    if (c.collision()) {
      res.collision = true;
      res.collision_with = c.kind == world::HitKind::kMoving ? "moving" : "static";
      res.time_s = t - cfg.warmup_s;
      break;
    }
    if (goal_sent && (robot - goal).norm() <= cfg.goal_tolerance) {
      res.success = true;
      res.time_s = t - cfg.warmup_s;
      break;
    }

    // Pose.
    robot_pose_t pose{};
    pose.utime = utime;
    pose.valid = true;
    pose.x = robot.x();
    pose.y = robot.y();
    pose.qw = 1.0;
    pose.vx = robot_v.x();
    pose.vy = robot_v.y();
    pose.ax = NAN;
    pose.ay = NAN;
    node.onPose(pose);

    // Obstacles: noisy centroids through the Kalman filter.
    tracked_objects_t objs{};
    objs.utime = utime;
    objs.valid = true;
    objs.frame_seq = k;
    objs.frame_id = "world";
    for (std::size_t i = 0; i < w.numMovers(); ++i) {
      const world::ObstacleState& o = w.movers()[i];
      const Eigen::Vector3d z(o.position.x() + cfg.noise_std * noise.normal(),
                              o.position.y() + cfg.noise_std * noise.normal(), 0.5 * o.height);
      auto& f = filters[i];
      if (!f.initialised()) {
        f.init(z, Eigen::Vector3d::Zero());
      } else {
        f.predict(dt);
        f.updatePosition(z);
      }
      perception::ObjectEstimate e;  // confirmed, measured at object level
      e.id = o.id;
      e.x = f.state();
      e.P = f.covariance();
      e.size << 2.0 * o.radius, 2.0 * o.radius, o.height;
      e.num_points = 50;
      e.age_frames = k + 1;
      objs.objects.push_back(perception::toMessage(e));
    }
    objs.num_objects = int32_t(objs.objects.size());
    node.onObjects(objs);

    if (!goal_sent && t >= cfg.warmup_s) {
      nav_goal_t g{};
      g.utime = utime;
      g.goal_id = 1;
      g.action = nav_goal_t::ACTION_GO;
      g.x = goal.x();
      g.y = goal.y();
      g.yaw = NAN;
      g.tolerance = cfg.goal_tolerance * 0.5;  // the node holds only once well inside
      node.onGoal(g);
      goal_sent = true;
    }

    const double cpu0 = threadCpuMs();
    const planner::PlannerOutputs out = node.tick(utime);
    const double cpu1 = threadCpuMs();
    if (cfg.trace && out.plan && (out.plan->result != planner::PlanResult::kOk || !out.plan->message.empty())) {
      double nearest = 1e9;
      for (const auto& o : w.movers()) nearest = std::min(nearest, (o.position - robot).norm() - o.radius - sc.robot.radius);
      std::printf("  t=%6.2f p=(%6.2f,%6.2f) |v|=%.2f gap=%.2f %s: %s\n", t - cfg.warmup_s, robot.x(), robot.y(),
                  robot_v.norm(), nearest, planner::toString(out.plan->result), out.plan->message.c_str());
    }
    if (out.plan && out.plan->optimize_ms > 0.0) {
      res.plan_ms.push_back(out.plan->total_ms);
      res.plan_cpu_ms.push_back(cpu1 - cpu0);
      res.map_ms.push_back(out.plan->map_ms);
      res.front_end_ms.push_back(out.plan->front_end_ms);
      res.optimize_ms.push_back(out.plan->optimize_ms);
      res.iterations.push_back(out.plan->iterations);
    }
    if (out.trajectory) {
      if (out.trajectory->status == trajectory_t::STATUS_STOP) ++res.stops;
      trajectory::PiecewisePolynomial pp;
      if (trajectory::PiecewisePolynomial::fromMessage(*out.trajectory, &pp) == trajectory::TrajectoryStatus::kOk) {
        pending = pp;
      }
    }
    if (k == steps) {
      res.timeout = true;
      res.time_s = t - cfg.warmup_s;
    }
  }
  res.jerk_mean = jerk_n > 0 ? jerk_sum / double(jerk_n) : 0.0;
  for (const char* name : {"rejected_limit_violation", "rejected_static_collision", "rejected_dynamic_collision",
                           "rejected_optimiser_failed", "rejected_invalid_input", "result_kept_previous",
                           "replans_unsafe", "plan_restarts_from_pose", "goal_unreachable", "escape_attempts",
                           "evasive_plans", "least_bad_plans", "evasive_manoeuvres", "evasion_kept"}) {
    if (report.counter(name) > 0) res.counters += std::string(name) + "=" + std::to_string(report.counter(name)) + " ";
  }
  return res;
}

}  // namespace ucon::bench
