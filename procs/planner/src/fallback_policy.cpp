#include "ucon/planner/fallback_policy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ucon/config.hpp"

namespace ucon::planner {

namespace {
constexpr double kStaticSlack = 0.02;  // [m] a start inside the clearance may wobble this much
constexpr double kHoldS = 0.5;         // [s] rest held at the end of a manoeuvre
}  // namespace

void FallbackParams::read(ConfigReader& r) {
  r.read("detours", detours, 0, 16);
  r.read("detour_length", detour_length, 0.5, 10.0);
  r.read("directions", directions, 4, 64);
  r.read("run_s", run_s, 0.0, 5.0);
  r.read("horizon_s", horizon_s, 0.2, 5.0);
  r.read("step_s", step_s, 0.005, 0.5);
  r.read("reaction_s", reaction_s, 0.0, 1.0);
  r.read("gap_cap", gap_cap, 0.05, 10.0);
  r.read("uncertainty_k", uncertainty_k, 0.0, 5.0);
  r.read("mean_weight", mean_weight, 0.0, 10.0);
  r.read("goal_weight", goal_weight, 0.0, 10.0);
  r.read("keep_margin", keep_margin, 0.0, 10.0);
  if (step_s > horizon_s) r.fail("step_s", "must be <= horizon_s");
  if (reaction_s >= horizon_s) r.fail("reaction_s", "must be < horizon_s");
}

FallbackScore scoreTrajectory(const trajectory::PiecewisePolynomial& pp, int64_t from_utime,
                             const Eigen::Vector2d& goal, const trajopt::DistanceField2D* field,
                             const std::vector<trajopt::PredictedObstacle>& obstacles, double robot_radius,
                             const FallbackParams& params) {
  FallbackScore out;
  out.total = -std::numeric_limits<double>::infinity();
  if (!pp.valid() || !goal.allFinite()) return out;
  const int steps = static_cast<int>(std::floor(params.horizon_s / params.step_s + 1e-9));
  double allowed = robot_radius;  // static clearance the trajectory must keep
  double min_gap = params.gap_cap, gap_sum = 0.0;
  int scored = 0;
  Eigen::Vector2d first = Eigen::Vector2d::Zero(), last = Eigen::Vector2d::Zero();
  for (int s = 0; s <= steps; ++s) {
    const double t = s * params.step_s;
    const int64_t t_abs = from_utime + static_cast<int64_t>(std::llround(t * 1e6));
    const Eigen::Vector2d p = pp.sample(t_abs).position.head<2>();
    if (!p.allFinite()) return out;
    if (s == 0) first = p;
    last = p;
    if (field) {
      const double xi = field->distance(p.x(), p.y(), nullptr);
      if (s == 0) allowed = std::min(robot_radius, xi - kStaticSlack);
      if (!(xi >= allowed)) return out;  // NaN distance is a collision too
    }
    if (t < params.reaction_s - 1e-9) continue;
    double nearest = params.gap_cap;
    for (const auto& o : obstacles) {
      if (!o.state.allFinite() || !std::isfinite(o.radius)) continue;
      nearest = std::min(nearest, trajopt::grownBodyGap(o, p, t_abs, params.uncertainty_k, 0.0) - robot_radius);
    }
    min_gap = std::min(min_gap, nearest);
    gap_sum += nearest;
    ++scored;
  }
  out.static_ok = true;
  out.min_gap = min_gap;
  out.mean_gap = scored > 0 ? gap_sum / scored : params.gap_cap;
  out.progress = (first - goal).norm() - (last - goal).norm();
  out.total = out.min_gap + params.mean_weight * out.mean_gap + params.goal_weight * out.progress;
  return out;
}

bool manoeuvrePolynomial(int64_t t0, const Eigen::Vector2d& p0, const Eigen::Vector2d& v0,
                         const Eigen::Vector2d& u, double amax, double run_s,
                         trajectory::PiecewisePolynomial* out) {
  if (!out || !p0.allFinite() || !v0.allFinite() || !u.allFinite() || !(amax > 0.0) || !std::isfinite(amax) ||
      !std::isfinite(run_s))
    return false;
  std::vector<double> durations, coeffs;
  // Each piece: p + v t + 0.5 a t^2 per axis (order1 = 6, the rest zero).
  auto piece = [&](double T, const Eigen::Vector2d& p, const Eigen::Vector2d& v, const Eigen::Vector2d& a) {
    durations.push_back(T);
    for (int d = 0; d < 2; ++d) coeffs.insert(coeffs.end(), {p(d), v(d), 0.5 * a(d), 0.0, 0.0, 0.0});
  };
  Eigen::Vector2d p = p0;
  const Eigen::Vector2d dv = u - v0;
  const double T1 = dv.norm() / amax;
  if (T1 > 1e-6) {
    const Eigen::Vector2d a = dv / T1;
    piece(T1, p, v0, a);
    p += v0 * T1 + 0.5 * a * T1 * T1;
  }
  const double T2 = run_s - T1;
  if (T2 > 1e-6 && u.norm() > 1e-9) {
    piece(T2, p, u, Eigen::Vector2d::Zero());
    p += u * T2;
  }
  const double speed = u.norm();
  const double Tb = speed / amax;
  if (Tb > 1e-6) {
    piece(Tb, p, u, -u * (amax / speed));
    p += u * (0.5 * Tb);
  }
  piece(kHoldS, p, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
  return trajectory::PiecewisePolynomial::create(t0, 2, 6, durations, coeffs, out) == trajectory::TrajectoryStatus::kOk;
}

Eigen::Vector2d heading(int k, int directions) {
  const double a = k * (2.0 * M_PI / directions);
  return Eigen::Vector2d(std::cos(a), std::sin(a));
}

std::vector<int> rankHeadings(int64_t t0, const Eigen::Vector2d& p0, const Eigen::Vector2d& v0,
                              const Eigen::Vector2d& goal, double speed, double amax,
                              const trajopt::DistanceField2D* field,
                              const std::vector<trajopt::PredictedObstacle>& obstacles, double robot_radius,
                              const FallbackParams& params) {
  struct Ranked {
    double total;
    int k;
  };
  std::vector<Ranked> ranked;
  if (!(speed > 0.0) || !std::isfinite(speed)) return {};
  for (int k = 0; k < params.directions; ++k) {
    trajectory::PiecewisePolynomial run;
    if (!manoeuvrePolynomial(t0, p0, v0, speed * heading(k, params.directions), amax, params.detour_length / speed,
                             &run))
      return {};
    const FallbackScore s = scoreTrajectory(run, t0, goal, field, obstacles, robot_radius, params);
    if (s.static_ok) ranked.push_back({s.total, k});
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) { return a.total > b.total; });
  std::vector<int> out;
  out.reserve(ranked.size());
  for (const Ranked& r : ranked) out.push_back(r.k);
  return out;
}

Manoeuvre bestManoeuvre(int64_t t0, const Eigen::Vector2d& p0, const Eigen::Vector2d& v0, const Eigen::Vector2d& goal,
                        double vmax, double amax, const trajopt::DistanceField2D* field,
                        const std::vector<trajopt::PredictedObstacle>& obstacles, double robot_radius,
                        const FallbackParams& params) {
  Manoeuvre best;
  best.score.total = -std::numeric_limits<double>::infinity();
  if (!(vmax > 0.0) || !std::isfinite(vmax)) return best;
  for (int k = 0; k < params.directions; ++k) {
    const Eigen::Vector2d dir = heading(k, params.directions);
    for (const double speed : {vmax, 0.5 * vmax}) {
      trajectory::PiecewisePolynomial pp;
      if (!manoeuvrePolynomial(t0, p0, v0, speed * dir, amax, params.run_s, &pp)) return Manoeuvre{};
      const FallbackScore s = scoreTrajectory(pp, t0, goal, field, obstacles, robot_radius, params);
      if (s.static_ok && s.total > best.score.total) {
        best.pp = std::move(pp);
        best.score = s;
        best.velocity = speed * dir;
      }
    }
  }
  return best;
}

const char* toString(FallbackChoice c) {
  switch (c) {
    case FallbackChoice::kBrake: return "brake";
    case FallbackChoice::kKeep: return "keep";
    case FallbackChoice::kLeastBad: return "least_bad";
    case FallbackChoice::kManoeuvre: return "manoeuvre";
  }
  return "unknown";
}

FallbackChoice chooseFallback(double braking, double kept, double least_bad, double manoeuvre, double keep_margin) {
  if (kept > braking && kept + keep_margin >= least_bad && kept + keep_margin >= manoeuvre) return FallbackChoice::kKeep;
  if (manoeuvre > braking && manoeuvre > least_bad) return FallbackChoice::kManoeuvre;
  if (least_bad > braking) return FallbackChoice::kLeastBad;
  return FallbackChoice::kBrake;
}

}  // namespace ucon::planner
