// ucon-bench-base-controller: cost of one control tick and one plant step (medians), and the
// figure-eight tracking error at several peak speeds, motor lags and odometry latencies /
// noise (fixed seed). Prints a table and writes JSON.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "figure_eight.hpp"
#include "ucon/config.hpp"

namespace {
using Clock = std::chrono::steady_clock;
constexpr int64_t kT0 = 1'700'000'000'000'000;

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

struct Case {
  double peak_speed, motor_tau, latency_s, noise_m;
  std::string heading;
};
struct Result {
  Case c;
  double rms = 0, max = 0, peak = 0, tick_us = 0;
};

Result run(const ucon::base_controller::BaseControllerParams& base, const Case& c) {
  ucon::base_controller::BaseControllerParams p = base;
  p.heading.mode = c.heading;
  test_support::FigureEight fig;
  fig.peak_speed = c.peak_speed;
  const ucon::trajectory_t plan = fig.message(kT0);
  ucon::trajectory::PiecewisePolynomial ref;
  ucon::trajectory::PiecewisePolynomial::fromMessage(plan, &ref);
  ucon::base_controller::BaseController ctrl(p);
  auto pp = test_support::plantParams(p.mecanum);
  pp.motor_time_constant = c.motor_tau;
  ucon::mecanum::MecanumPlant plant(pp);
  const Eigen::Vector3d p0 = ref.position(kT0);
  plant.reset(p0.x(), p0.y(), 0.0);
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, c.noise_m);
  std::deque<ucon::robot_pose_t> in_flight;  // poses on their way (latency)
  const int64_t latency_us = static_cast<int64_t>(std::llround(c.latency_s * 1e6));
  std::vector<double> tick_us;
  double sum2 = 0;
  Result r{c};
  int n = 0;
  for (int64_t t = kT0; t < ref.endUtime(); t += 10000) {
    // Pose measured now (valid at t), delivered after the latency.
    ucon::robot_pose_t m = test_support::poseFrom(plant.state(), t);
    if (c.noise_m > 0) {
      m.x += noise(rng);
      m.y += noise(rng);
    }
    in_flight.push_back(m);
    while (!in_flight.empty() && in_flight.front().utime + latency_us <= t) {
      ctrl.onPose(in_flight.front());
      in_flight.pop_front();
    }
    if ((t - kT0) % 100000 == 0) {
      ucon::trajectory_t msg = plan;
      msg.utime = t;
      ctrl.onTrajectory(msg);
    }
    const auto a = Clock::now();
    const auto out = ctrl.tick(t);
    tick_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - a).count());
    if (out.wheel_cmd) {
      const auto& w = *out.wheel_cmd;
      plant.setCommand({w.w_fl, w.w_fr, w.w_rl, w.w_rr}, w.enable);
    }
    plant.step(0.01);
    const Eigen::Vector3d pr = ref.position(t + 10000);
    const double e = std::hypot(pr.x() - plant.state().x, pr.y() - plant.state().y);
    sum2 += e * e;
    r.max = std::max(r.max, e);
    r.peak = std::max(r.peak, std::hypot(plant.state().vx_world, plant.state().vy_world));
    ++n;
  }
  r.rms = std::sqrt(sum2 / std::max(1, n));
  r.tick_us = median(tick_us);
  return r;
}

double plantStepUs(const ucon::base_controller::BaseControllerParams& p, int reps) {
  ucon::mecanum::MecanumPlant plant(test_support::plantParams(p.mecanum));
  plant.reset(0, 0, 0);
  plant.setCommand({10, 12, 9, 11});
  std::vector<double> us;
  for (int r = 0; r < reps; ++r) {
    const auto a = Clock::now();
    for (int i = 0; i < 1000; ++i) plant.step(0.001);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - a).count() / 1000.0);
  }
  return median(us);
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Base controller benchmark: tick cost and figure-eight tracking error."};
  std::string config = "deploy/config/base_controller.yaml", json;
  bool quick = false;
  double max_wheel_speed = 0;
  app.add_option("--config", config, "controller YAML");
  app.add_option("--json", json, "write results here");
  app.add_flag("--quick", quick, "fewer cases (ctest)");
  app.add_option("--max-wheel-speed", max_wheel_speed, "override mecanum.max_wheel_speed [rad/s] (plant and controller)");
  CLI11_PARSE(app, argc, argv);

  std::ifstream f(config);
  if (!f) {
    std::fprintf(stderr, "cannot open %s (run from the repository root or pass --config)\n", config.c_str());
    return 2;
  }
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::vector<ucon::ConfigError> errors;
  auto params = ucon::loadParams<ucon::base_controller::BaseControllerParams>(text, config, &errors);
  if (!params) {
    for (const auto& e : errors) std::fprintf(stderr, "%s\n", e.toString().c_str());
    return 2;
  }
  if (max_wheel_speed > 0) params->mecanum.max_wheel_speed = max_wheel_speed;
  std::printf("wheel limit %.1f rad/s, wheel radius %.3f m\n", params->mecanum.max_wheel_speed,
              params->mecanum.wheel_radius);

  std::vector<Case> cases = {{1.5, 0.05, 0.0, 0.0, "hold"}, {1.5, 0.05, 0.02, 0.005, "hold"}};
  if (!quick) {
    cases.insert(cases.end(), {{1.0, 0.05, 0.0, 0.0, "hold"},
                               {2.0, 0.05, 0.0, 0.0, "hold"},
                               {1.5, 0.10, 0.0, 0.0, "hold"},
                               {1.5, 0.05, 0.05, 0.0, "hold"},
                               {1.5, 0.05, 0.0, 0.0, "path"},
                               {1.5, 0.05, 0.02, 0.005, "path"}});
  }
  std::printf("%-6s %-8s %-9s %-8s %-6s | %-9s %-9s %-9s %-8s\n", "peak", "tau[s]", "latency", "noise", "yaw",
              "RMS[m]", "max[m]", "v_max", "tick[us]");
  std::vector<Result> results;
  for (const Case& c : cases) {
    const Result r = run(*params, c);
    results.push_back(r);
    std::printf("%-6.2f %-8.3f %-9.3f %-8.3f %-6s | %-9.4f %-9.4f %-9.3f %-8.2f\n", c.peak_speed, c.motor_tau,
                c.latency_s, c.noise_m, c.heading.c_str(), r.rms, r.max, r.peak, r.tick_us);
  }
  const double plant_us = plantStepUs(*params, quick ? 20 : 200);
  std::printf("plant step (1 ms): median %.3f us\n", plant_us);

  if (!json.empty()) {
    std::ofstream o(json);
    o << "{\n  \"plant_step_us_median\": " << plant_us << ",\n  \"cases\": [\n";
    for (std::size_t i = 0; i < results.size(); ++i) {
      const Result& r = results[i];
      o << "    {\"peak_speed\": " << r.c.peak_speed << ", \"motor_tau_s\": " << r.c.motor_tau
        << ", \"latency_s\": " << r.c.latency_s << ", \"noise_m\": " << r.c.noise_m << ", \"heading\": \""
        << r.c.heading << "\", \"rms_m\": " << r.rms << ", \"max_m\": " << r.max << ", \"v_max\": " << r.peak
        << ", \"tick_us_median\": " << r.tick_us << "}" << (i + 1 < results.size() ? "," : "") << "\n";
    }
    o << "  ]\n}\n";
  }
  return 0;
}
