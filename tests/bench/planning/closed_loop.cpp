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

bool benchParams(const planner::PlannerParams& base, const world::Scenario& sc, const std::string& method,
                 planner::PlannerParams* out) {
  planner::PlannerParams params = base;
  if (!trajopt::parseObstacleModel(method, &params.optimizer.obstacle_model)) return false;
  params.optimizer.robot_radius = sc.robot.radius;
  params.optimizer.max_velocity = sc.robot.max_speed;
  params.optimizer.max_acceleration = sc.robot.max_accel;
  params.optimizer.use_time_budget = false;
  params.workspace = {sc.bounds.xmin, sc.bounds.xmax, sc.bounds.ymin, sc.bounds.ymax};
  *out = params;
  return true;
}

RunResult runClosedLoop(const planner::PlannerParams& base, const RunConfig& cfg) {
  RunResult res;
  const world::Scenario sc = world::generateBench(cfg.n_dynamic, cfg.seed);
  world::World w(sc);

  planner::PlannerParams params;
  if (!benchParams(base, sc, cfg.method, &params)) return res;

  StatusReport report("planner");
  planner::PlannerNode node(params, report);
  buildStaticMap(w, node.map());
  node.prepareMap(sc.robot.start);

  // Trackers (observation.hpp): perfect association, ids from the ground truth or per track.
  ObserveConfig oc;
  oc.mode = cfg.observe;
  oc.range = cfg.sensing_range;
  oc.noise_std = cfg.noise_std;
  oc.kalman = params.prediction.model();
  oc.kalman.position_std = cfg.noise_std;
  oc.kalman.velocity_std = cfg.tracker_velocity_std;
  oc.kalman.initial_velocity_std = cfg.tracker_initial_velocity_std;
  oc.max_coast = cfg.max_coast;
  oc.coast_velocity_decay = cfg.coast_velocity_decay;
  Observer observer(w, oc, cfg.seed);

  const double dt = 1.0 / cfg.observe_hz;
  const int64_t dt_us = int64_t(std::llround(dt * 1e6));
  world::Vec2 goal = sc.robot.goals.empty() ? world::Vec2(22.0, 0.0) : sc.robot.goals.front();
  const world::Vec2 far_goal = goal;
  int32_t goal_id = 1;
  Eigen::Vector2d robot = sc.robot.start;
  Eigen::Vector2d robot_v = Eigen::Vector2d::Zero();
  trajectory::PiecewisePolynomial active, pending;
  bool goal_sent = false;
  double jerk_sum = 0.0;
  int64_t jerk_n = 0;
  const bool shuttle = cfg.shuttle_s > 0.0;
  const int steps = int(std::ceil(((shuttle ? cfg.shuttle_s : cfg.timeout_s) + cfg.warmup_s) / dt));
  const int64_t probe_first = std::llround((cfg.warmup_s + cfg.probe_start_s) / dt);
  const int64_t probe_every = std::max<int64_t>(1, std::llround(cfg.probe_period_s / dt));

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
      ++res.goals_reached;
      if (!shuttle) {
        res.success = true;
        res.time_s = t - cfg.warmup_s;
        break;
      }
      goal = (goal - far_goal).norm() < 1e-9 ? world::Vec2(sc.robot.start) : far_goal;
      ++goal_id;
      goal_sent = false;  // sent below, this frame
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
    for (const auto& e : observer.frame(dt, robot)) objs.objects.push_back(perception::toMessage(e));
    objs.num_objects = int32_t(objs.objects.size());
    node.onObjects(objs);

    if (!goal_sent && t >= cfg.warmup_s) {
      nav_goal_t g{};
      g.utime = utime;
      g.goal_id = goal_id;
      g.action = nav_goal_t::ACTION_GO;
      g.x = goal.x();
      g.y = goal.y();
      g.yaw = NAN;
      g.tolerance = cfg.goal_tolerance * 0.5;  // the node holds only once well inside
      node.onGoal(g);
      goal_sent = true;
    }

    if (cfg.probe && res.goals_reached + (goal_sent ? 1 : 0) > 0 && k >= probe_first &&
        (k - probe_first) % probe_every == 0) {
      cfg.probe(ProbeContext{node, w, observer, t, utime, robot});
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
  res.measurements = observer.measurements();
  res.coasting_frames = observer.coastingFrames();
  res.tracks_started = observer.tracksStarted();
  for (const char* name : {"rejected_limit_violation", "rejected_static_collision", "rejected_dynamic_collision",
                           "rejected_optimiser_failed", "rejected_invalid_input", "result_kept_previous",
                           "replans_unsafe", "plan_restarts_from_pose", "goal_unreachable", "escape_attempts",
                           "evasive_plans", "least_bad_plans", "evasive_manoeuvres", "evasion_kept"}) {
    if (report.counter(name) > 0) res.counters += std::string(name) + "=" + std::to_string(report.counter(name)) + " ";
  }
  return res;
}

}  // namespace ucon::bench
