#include "closed_loop.hpp"
#include "grid_field.hpp"
#include "ucon/world/bench_generator.hpp"
#include "ucon/world/world.hpp"

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <queue>
#include <random>
#include <vector>

namespace trajopt_bench {

using namespace ucon::trajopt;

namespace {

constexpr double kSize = 50.0;
constexpr double kDt = 0.02;       // perception / simulation step [s]
constexpr int kPlanEvery = 5;      // 10 Hz
constexpr double kRobotRadius = 0.3;

Eigen::Vector2d evalMsg(const ucon::trajectory_t& tr, double t, int order) {
  double tt = std::max(0.0, t);
  int k = 0;
  while (k + 1 < tr.num_pieces && tt > tr.durations[k]) tt -= tr.durations[k++];
  tt = std::min(tt, tr.durations[k]);
  Eigen::Vector2d out;
  for (int d = 0; d < 2; ++d) {
    double v = 0.0;
    for (int j = 5; j >= order; --j) {
      double f = 1.0;
      for (int r = 0; r < order; ++r) f *= (j - r);
      v = v * tt + f * tr.coeffs[(k * 2 + d) * 6 + j];
    }
    out(d) = v;
  }
  return out;
}

// Front end of the experiment: 8-connected A* on a 0.25 m grid of cells with clearance
// >= 0.45 m, start to goal; returns the path in metres (empty if none).
std::vector<Eigen::Vector2d> aStar(const DistanceField2D& field, std::vector<char>& free_cells,
                                   const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  constexpr double res = 0.25;
  const int n = static_cast<int>(kSize / res) + 1;
  auto idx = [n](int i, int j) { return i * n + j; };
  auto cell = [&](const Eigen::Vector2d& p) {
    return std::make_pair(std::clamp(static_cast<int>(std::lround(p.x() / res)), 0, n - 1),
                          std::clamp(static_cast<int>(std::lround(p.y() / res)), 0, n - 1));
  };
  if (free_cells.size() != static_cast<std::size_t>(n * n)) {  // computed once per world
    free_cells.assign(n * n, 0);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) free_cells[idx(i, j)] = field.distance(i * res, j * res, nullptr) >= 0.45;
  }
  const auto [si, sj] = cell(from);
  const auto [gi, gj] = cell(to);
  std::vector<double> g(n * n, 1e18);
  std::vector<int> parent(n * n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  g[idx(si, sj)] = 0;
  open.push({0.0, idx(si, sj)});
  const int goal_id = idx(gi, gj);
  while (!open.empty()) {
    const auto [f, id] = open.top();
    open.pop();
    if (id == goal_id) break;
    const int i = id / n, j = id % n;
    if (f - std::hypot(i - gi, j - gj) > g[id] + 1e-9) continue;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const int a = i + di, b = j + dj;
        if ((!di && !dj) || a < 0 || b < 0 || a >= n || b >= n) continue;
        const int nid = idx(a, b);
        if (!free_cells[nid] && nid != goal_id) continue;
        const double ng = g[id] + std::hypot(di, dj);
        if (ng < g[nid]) {
          g[nid] = ng;
          parent[nid] = id;
          open.push({ng + std::hypot(a - gi, b - gj), nid});
        }
      }
  }
  std::vector<Eigen::Vector2d> path;
  if (parent[goal_id] < 0) return path;
  for (int id = goal_id; id >= 0; id = parent[id]) path.push_back(Eigen::Vector2d((id / n) * res, (id % n) * res));
  std::reverse(path.begin(), path.end());
  path.front() = from;
  path.back() = to;
  return path;
}

double totalDuration(const ucon::trajectory_t& tr) {
  double s = 0;
  for (double T : tr.durations) s += T;
  return s;
}

}  // namespace

ClosedLoopResult runClosedLoop(unsigned seed, int n_dynamic, const OptimizerParams& params,
                               const ucon::kalman::KalmanParams& filter, bool debug) {
  // The planner benchmark's world (common/world's generator, docs/reference.md §8),
  // shifted by +25 m so that the experiment's grids cover [0, 50]^2.
  const ucon::world::Scenario scenario = ucon::world::generateBench(n_dynamic, seed);
  ucon::world::World world(scenario);
  const Eigen::Vector2d shift(-scenario.bounds.xmin, -scenario.bounds.ymin);
  const Eigen::Vector2d start = scenario.robot.start + shift;
  const Eigen::Vector2d goal = scenario.robot.goals.back() + shift;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  const GridField field(
      [&](double x, double y) {
        double best = 3.0;
        for (std::size_t i = 0; i < scenario.statics.size(); ++i) {
          const auto& st = scenario.statics[i];
          const Eigen::Vector2d p(x - shift.x(), y - shift.y());
          if ((st.center - p).cwiseAbs().maxCoeff() > best + 1.5) continue;
          best = std::min(best, world.staticFootprintDistance(i, p));
        }
        return best;
      },
      kSize, 0.1);
  const std::size_t n_movers = world.numMovers();
  // Perception: one Kalman filter per obstacle (identities known), noisy centroids at 50 Hz.
  std::vector<ucon::kalman::ConstantVelocityKalman> kfs(n_movers, ucon::kalman::ConstantVelocityKalman(filter));
  std::vector<Eigen::Vector3d> last_z(n_movers);
  std::vector<double> radius(n_movers);

  TrajectoryOptimizer opt(params, filter);
  std::vector<char> free_cells;
  ucon::trajectory_t current;
  current.num_pieces = 0;
  Eigen::Vector2d robot = start;
  ClosedLoopResult res;
  std::vector<double> ms;
  const int max_steps = static_cast<int>(scenario.duration_s / kDt);
  for (int step = 0; step < max_steps; ++step) {
    const double t = step * kDt;
    const int64_t now = 1'000'000 + static_cast<int64_t>(step) * 20'000;
    world.setTime(t);
    for (std::size_t i = 0; i < n_movers; ++i) {
      const auto& m = world.movers()[i];
      radius[i] = m.radius;
      const Eigen::Vector3d z(m.position.x() + shift.x() + noise(rng), m.position.y() + shift.y() + noise(rng), 0.8);
      if (step == 0) {
        kfs[i].init(z, Eigen::Vector3d::Zero());
      } else {
        kfs[i].predict(kDt);
        kfs[i].update(z, (z - last_z[i]) / kDt);
      }
      last_z[i] = z;
    }
    // Robot: ideal tracking of the current trajectory.
    if (current.num_pieces > 0) robot = evalMsg(current, 1e-6 * (now - current.start_utime), 0);
    const ucon::world::Contact contact = world.diskContact(robot - shift, kRobotRadius);
    if (contact.collision()) {
      res.collision = true;
      if (debug) {
        const Eigen::Vector2d rv = current.num_pieces ? evalMsg(current, 1e-6 * (now - current.start_utime), 1) : Eigen::Vector2d::Zero();
        std::printf("    COLLISION t=%.2f with %s %d | robot (%.2f %.2f) v(%.2f %.2f)\n", t,
                    contact.kind == ucon::world::HitKind::kMoving ? "mover" : "static", contact.index, robot.x(), robot.y(),
                    rv.x(), rv.y());
      }
    }
    if (res.collision) {
      res.collision_time = t;
      break;
    }
    if ((robot - goal).norm() < 0.5) {
      res.success = true;
      break;
    }
    if (step % kPlanEvery != 0) continue;
    PlanRequest req;
    req.start_utime = now;
    req.start.setZero();
    req.start.col(0) = robot;
    if (current.num_pieces > 0) {
      const double tc = 1e-6 * (now - current.start_utime);
      if (tc < totalDuration(current)) {
        req.start.col(1) = evalMsg(current, tc, 1);
        req.start.col(2) = evalMsg(current, tc, 2);
      }
    }
    // Guide path: A* to the goal, cut at 7 m, resampled into pieces of about 1.2 m.
    const std::vector<Eigen::Vector2d> path = aStar(field, free_cells, robot, goal);
    std::vector<Eigen::Vector2d> pts{robot};
    double along = 0.0;
    for (std::size_t k = 1; k < path.size() && along < 7.0; ++k) {
      along += (path[k] - path[k - 1]).norm();
      pts.push_back(path[k]);
    }
    if (pts.size() < 2) pts.push_back(goal);
    std::vector<Eigen::Vector2d> way{robot};
    double acc = 0.0;
    for (std::size_t k = 1; k < pts.size(); ++k) {
      acc += (pts[k] - pts[k - 1]).norm();
      if (acc >= 1.2 || k + 1 == pts.size()) {
        way.push_back(pts[k]);
        acc = 0.0;
      }
    }
    if (way.size() > 9) way.resize(9);
    req.goal.setZero();
    req.goal.col(0) = way.back();
    for (std::size_t k = 1; k + 1 < way.size(); ++k) req.inner_waypoints.push_back(way[k]);
    for (std::size_t k = 1; k < way.size(); ++k)
      req.durations.push_back(std::max(0.3, (way[k] - way[k - 1]).norm() / 1.2));
    req.field = &field;
    for (std::size_t i = 0; i < n_movers; ++i) {
      PredictedObstacle o;
      o.id = static_cast<int64_t>(i) + 1;
      o.utime = now;
      o.state = kfs[i].state();
      o.covariance = kfs[i].covariance();
      o.radius = radius[i];
      if ((o.state.head<2>() - robot).norm() < 15.0) req.obstacles.push_back(o);
    }
    const auto t0 = std::chrono::steady_clock::now();
    const PlanOutput out = opt.plan(req);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    ++res.plans;
    if (out.status == PlanStatus::kOk) {
      current = out.trajectory;
    } else {
      ++res.failed_plans;
      res.fail_by_status[static_cast<int>(out.status)]++;
      if (debug && res.failed_plans < 15)
        std::printf("    t=%.2f %s %s robot(%.2f %.2f) xi=%.3f cost s=%.1f d=%.1f e=%.1f evals=%d %s\n", t, toString(out.status),
                    out.message.c_str(), robot.x(), robot.y(), field.distance(robot.x(), robot.y(), nullptr),
                    out.cost.static_clearance, out.cost.dynamic, out.cost.energy, out.iterations, out.solver_result.c_str());
      if (current.num_pieces == 0 ||
          checkTrajectory(current, now, &field, req.obstacles, params).status != PlanStatus::kOk) {
        // Nothing safe: brake along a stopping trajectory (one piece, rest at the end).
        PlanRequest stop = req;
        const Eigen::Vector2d v0 = req.start.col(1);
        stop.goal.setZero();
        stop.goal.col(0) = robot + v0 * 0.5;
        stop.inner_waypoints.clear();
        stop.durations.assign(1, 1.0);
        stop.obstacles.clear();
        OptimizerParams sp = params;
        sp.max_iterations = 1;
        TrajectoryOptimizer stopper(sp, filter);
        current = stopper.plan(stop).trajectory;
      }
    }
    res.time_s = t;
  }
  res.timeout = !res.success && !res.collision;
  if (!ms.empty()) {
    std::sort(ms.begin(), ms.end());
    res.plan_ms_median = ms[ms.size() / 2];
  }
  return res;
}

}  // namespace trajopt_bench
