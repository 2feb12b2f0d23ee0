#include "open_loop.hpp"

#include <chrono>
#include <memory>

#include "ucon/cpu_time.hpp"
#include "ucon/trajopt/sector_minco.hpp"
#include "ucon/world/bench_generator.hpp"

namespace ucon::bench {

OpenLoopResult runOpenLoop(const planner::PlannerParams& base, const OpenLoopConfig& cfg) {
  OpenLoopResult out;
  const world::Scenario sc = world::generateBench(cfg.run.n_dynamic, cfg.run.seed);
  // One optimiser per horizon and method, with the parameters the node would have.
  std::vector<std::unique_ptr<trajopt::TrajectoryOptimizer>> optimisers;
  double robot_radius = sc.robot.radius;
  for (const double h : cfg.horizons) {
    for (const auto& m : cfg.methods) {
      planner::PlannerParams p;
      if (!benchParams(base, sc, m, &p)) return out;
      p.optimizer.dynamic_horizon = h;
      p.optimizer.check_horizon = h;
      robot_radius = p.optimizer.robot_radius;
      optimisers.push_back(std::make_unique<trajopt::TrajectoryOptimizer>(p.optimizer, p.prediction.model()));
    }
  }
  const std::size_t nm = cfg.methods.size();
  RunConfig rc = cfg.run;
  rc.probe = [&](const ProbeContext& ctx) {
    const auto req = ctx.node.problem(ctx.utime);
    if (!req) {
      ++out.skipped;
      return;
    }
    ProbeRecord rec;
    rec.t = ctx.t;
    rec.obstacles = int(req->obstacles.size());
    double best = 1e18;
    for (std::size_t i = 0; i < ctx.world.numMovers(); ++i) {
      const auto& o = ctx.world.movers()[i];
      const double gap = (o.position - ctx.robot).norm() - o.radius;
      if (gap < best) best = gap, rec.nearest = int(i);
    }
    if (rec.nearest >= 0) {
      rec.nearest_kind = ctx.world.movers()[std::size_t(rec.nearest)].motion;
      rec.nearest_gap = best;
      const auto age = ctx.observer.trackAge(std::size_t(rec.nearest));
      rec.nearest_track_age = age ? *age : -1.0;
    }
    std::vector<char> tracked(ctx.world.numMovers(), 0);
    for (const auto& ob : req->obstacles) {
      const int i = ctx.observer.moverOfTrack(ob.id);
      if (i >= 0) tracked[std::size_t(i)] = 1;
    }
    const double t0 = ctx.t + 1e-6 * double(req->start_utime - ctx.utime);
    for (std::size_t h = 0; h < cfg.horizons.size(); ++h) {
      for (std::size_t m = 0; m < nm; ++m) {
        PlanOutcome oc;
        const auto wall0 = std::chrono::steady_clock::now();
        const double cpu0 = threadCpuSeconds();
        const trajopt::PlanOutput po = optimisers[h * nm + m]->plan(*req);
        oc.plan_cpu_ms = 1e3 * (threadCpuSeconds() - cpu0);
        oc.plan_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
        oc.iterations = po.iterations;
        trajectory::PiecewisePolynomial pp;
        oc.has_plan = po.trajectory.num_pieces > 0 &&
                      trajectory::PiecewisePolynomial::fromMessage(po.trajectory, &pp) == trajectory::TrajectoryStatus::kOk;
        oc.passed_check = oc.has_plan && po.status == trajopt::PlanStatus::kOk;
        oc.status = po.status;
        if (oc.has_plan) {
          oc.play = playPlan(pp, t0, cfg.horizons[h], ctx.world, robot_radius);
          oc.hit_tracked = oc.play.mover >= 0 && tracked[std::size_t(oc.play.mover)];
        }
        rec.outcomes.push_back(oc);
      }
    }
    out.probes.push_back(std::move(rec));
  };
  out.run = runClosedLoop(base, rc);
  return out;
}

}  // namespace ucon::bench
