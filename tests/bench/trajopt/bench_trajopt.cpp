// Planning-time micro-benchmark of the sector-MINCO optimiser (common/trajopt).
//
// World like the paper's benchmark (Sec. V-C, docs/reference.md §8): 50 m x 50 m, 160 static discs, N_d moving
// obstacles with radius 0.2-0.5 m and speed 0.3-1.5 m/s, seeded. Each plan: a 7 m local
// problem from a random free start towards a random direction, straight-line guess with 5
// pieces, obstacles with a typical tracked covariance. The static map is a precomputed 0.1 m grid with bilinear
// interpolation (as cheap as the planner's ESDF lookup). Prints medians per model and N_d, and
// how many results passed the post-check (an open-loop figure, not the paper's η).
//
// --closed-loop R runs R seeded crossings per model and density instead (closed_loop.hpp): a
// tuning aid for the optimiser only; the paper's Table II benchmark belongs to the planner.
//
// Usage: bench_trajopt [--quick] [--plans N] [--seed S] [--model M] [--config optimizer.yaml]
//                      [--accel-psd Q] [--closed-loop R] [--verbose] [--debug]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <fstream>
#include <sstream>
#include <vector>

#include "closed_loop.hpp"
#include "grid_field.hpp"
#include "ucon/config.hpp"
#include "ucon/trajopt/sector_minco.hpp"

using namespace ucon::trajopt;
using trajopt_bench::GridField;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

}  // namespace

int main(int argc, char** argv) {
  int plans = 200;
  unsigned seed = 1;
  OptimizerParams base;
  ucon::kalman::KalmanParams prediction;
  std::string models = "all";
  bool verbose = false;
  bool debug = false;
  int closed_loop_runs = 0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) plans = 10;
    else if (!std::strcmp(argv[i], "--plans") && i + 1 < argc) plans = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) seed = static_cast<unsigned>(std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--model") && i + 1 < argc) models = argv[++i];
    else if (!std::strcmp(argv[i], "--verbose")) verbose = true;
    else if (!std::strcmp(argv[i], "--debug")) debug = true;
    else if (!std::strcmp(argv[i], "--closed-loop") && i + 1 < argc) closed_loop_runs = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--accel-psd") && i + 1 < argc) prediction.accel_psd_xy = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--config") && i + 1 < argc) {
      // YAML with the optimizer keys (the `optimizer:` section of deploy/config/planner.yaml).
      std::ifstream f(argv[++i]);
      std::stringstream ss;
      ss << f.rdbuf();
      std::vector<ucon::ConfigError> errors;
      auto p = ucon::loadParams<OptimizerParams>(ss.str(), argv[i], &errors);
      if (!p) {
        for (const auto& e : errors) std::fprintf(stderr, "%s\n", e.toString().c_str());
        return 2;
      }
      base = *p;
    }
    else {
      std::fprintf(stderr, "usage: bench_trajopt [--quick] [--plans N] [--seed S] [--model M] [--config optimizer.yaml] [--accel-psd Q] [--closed-loop R] [--verbose] [--debug]\n");
      return 2;
    }
  }
  if (closed_loop_runs > 0) {
    // Filter of the experiment: measured differenced velocity at 50 Hz with 5 cm noise.
    ucon::kalman::KalmanParams filter = prediction;
    filter.position_std = 0.05;
    filter.velocity_std = std::sqrt(2.0) * 0.05 / 0.02;
    std::printf("%-15s %5s %6s %6s %6s %8s %8s\n", "model", "N_d", "succ%", "coll", "tout", "med_ms", "fail%");
    for (int nd : {50, 80, 110})
      for (ObstacleModel model : {ObstacleModel::kSector, ObstacleModel::kNoUncertainty, ObstacleModel::kFapp}) {
        if (models != "all" && models != toString(model)) continue;
        OptimizerParams params = base;
        params.obstacle_model = model;
        int succ = 0, coll = 0, tout = 0, plans_total = 0, failed = 0;
        int by_status[6] = {0, 0, 0, 0, 0, 0};
        std::vector<double> med;
        for (int r = 0; r < closed_loop_runs; ++r) {
          const auto res = trajopt_bench::runClosedLoop(seed + r, nd, params, filter, debug);
          succ += res.success;
          coll += res.collision;
          tout += res.timeout;
          plans_total += res.plans;
          failed += res.failed_plans;
          for (int f = 0; f < 6; ++f) by_status[f] += res.fail_by_status[f];
          med.push_back(res.plan_ms_median);
          if (verbose) std::printf("  seed %u: %s t=%.1f\n", seed + r, res.success ? "ok" : res.collision ? "collision" : "timeout", res.time_s);
        }
        std::printf("%-15s %5d %6.1f %6d %6d %8.3f %8.1f\n", toString(model), nd, 100.0 * succ / closed_loop_runs, coll,
                    tout, median(med), 100.0 * failed / std::max(1, plans_total));
        if (verbose) {
          std::printf("   ");
          for (int f = 1; f < 6; ++f) std::printf(" %s=%d", toString(static_cast<PlanStatus>(f)), by_status[f]);
          std::printf("\n");
        }
      }
    return 0;
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double size = 50.0;
  std::vector<Eigen::Vector3d> discs;
  for (int i = 0; i < 160; ++i) discs.emplace_back(size * U(rng), size * U(rng), 0.2 + 0.6 * U(rng));
  const GridField field(discs, size, 0.1);

  std::printf("%-15s %5s %9s %9s %9s %7s %8s %8s\n", "model", "N_d", "med_ms", "p95_ms", "mean_ms", "evals", "ok_%", "used");
  bool all_finite = true;
  for (int nd : {50, 80, 110}) {
    for (ObstacleModel model : {ObstacleModel::kSector, ObstacleModel::kNoUncertainty, ObstacleModel::kFapp}) {
      std::mt19937 r2(seed * 1000 + nd);  // same problems for every model
      if (models != "all" && models != toString(model)) continue;
      OptimizerParams params = base;
      params.obstacle_model = model;
      TrajectoryOptimizer opt(params, prediction);
      std::vector<double> ms, evals, used;
      int ok = 0;
      int fails[6] = {0, 0, 0, 0, 0, 0};
      for (int k = 0; k < plans; ++k) {
        PlanRequest req;
        const int64_t now = 1'000'000 + k * 100'000;
        req.start_utime = now;
        Eigen::Vector2d s;
        do s = Eigen::Vector2d(5 + 40 * U(r2), 5 + 40 * U(r2));
        while (field.distance(s.x(), s.y(), nullptr) < 0.8);
        const double heading = 2 * M_PI * U(r2);
        const Eigen::Vector2d dir(std::cos(heading), std::sin(heading));
        req.start.setZero();
        req.start.col(0) = s;
        req.start.col(1) = 0.8 * dir;
        req.goal.setZero();
        req.goal.col(0) = s + 7.0 * dir;
        if (field.distance(req.goal(0, 0), req.goal(1, 0), nullptr) < 0.8) {
          --k;  // the planner's front end only hands over free goals
          continue;
        }
        const int pieces = 5;
        for (int i = 1; i < pieces; ++i) req.inner_waypoints.push_back(s + 7.0 * i / pieces * dir);
        req.durations.assign(pieces, 7.0 / pieces / 1.2);
        req.field = &field;
        for (int i = 0; i < nd; ++i) {
          PredictedObstacle o;
          o.id = i + 1;
          o.utime = now - 20'000;
          const double sp = 0.3 + 1.2 * U(r2), h = 2 * M_PI * U(r2);
          o.state << size * U(r2), size * U(r2), 0.8, sp * std::cos(h), sp * std::sin(h), 0.0;
          o.covariance.setZero();
          o.covariance.diagonal() << 0.004, 0.004, 0.004, 0.05, 0.05, 0.05;
          o.covariance(0, 3) = o.covariance(3, 0) = 0.006;
          o.covariance(1, 4) = o.covariance(4, 1) = 0.006;
          o.radius = 0.2 + 0.3 * U(r2);
          // Not on top of the robot now: a plan cannot undo an existing overlap.
          if ((o.state.head<2>() - s).norm() < 1.5 + o.radius) continue;
          req.obstacles.push_back(o);
        }
        const auto t0 = std::chrono::steady_clock::now();
        const PlanOutput out = opt.plan(req);
        const auto t1 = std::chrono::steady_clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        evals.push_back(out.iterations);
        used.push_back(out.obstacles_used);
        if (out.status == PlanStatus::kOk) ++ok;
        fails[static_cast<int>(out.status)]++;
        if (verbose && out.status != PlanStatus::kOk)
          std::printf("  plan %d: %s: %s (%s, %d evals, cost %.1f)\n", k, toString(out.status), out.message.c_str(),
                      out.solver_result.c_str(), out.iterations, out.cost.total());
        if (!std::isfinite(out.cost.total())) all_finite = false;
      }
      double mean = 0;
      for (double v : ms) mean += v;
      mean /= ms.size();
      std::printf("%-15s %5d %9.3f %9.3f %9.3f %7.0f %8.1f %8.1f\n", toString(model), nd, median(ms),
                  percentile(ms, 0.95), mean, median(evals), 100.0 * ok / plans, median(used));
      std::printf("   ");
      for (int f = 1; f < 6; ++f) std::printf(" %s=%d", toString(static_cast<PlanStatus>(f)), fails[f]);
      std::printf("\n");
    }
  }
  return all_finite ? 0 : 1;
}
