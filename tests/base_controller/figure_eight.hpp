#pragma once
// Test fixtures: a figure-eight reference as a quintic piecewise polynomial in trajectory_t
// format, and a closed loop of BaseController + MecanumPlant stepped in message time.

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "ucon/base_controller/controller.hpp"
#include "ucon/mecanum/plant.hpp"
#include "ucon/trajectory/quintic_hermite.hpp"

namespace test_support {

constexpr double kPi = 3.14159265358979323846;

/// Lemniscate of Gerono p(s) = (A sin(w s), B/2 sin(2 w s)) traversed once, with the speed
/// ramped up over `ramp_s` from rest and back down to rest (a time warp s(t) with
/// s' = sin^2(pi t / (2 ramp_s)) during the ramps, so p, v, a are continuous). It starts and
/// ends at the tip (A, 0), where the curve is slowest, so that both centre crossings, where
/// the speed peaks at w sqrt(A^2 + B^2), fall into the cruise at full speed.
struct FigureEight {
  double A = 3.0, B = 2.0;
  double peak_speed = 1.5;
  double ramp_s = 2.0;

  double w() const { return peak_speed / std::sqrt(A * A + B * B); }
  double period() const { return 2.0 * kPi / w(); }
  double cruise() const { return period() - ramp_s; }  // s covers ramp/2 + cruise + ramp/2
  double duration() const { return 2.0 * ramp_s + cruise(); }

  /// s, s', s'' at time t.
  void warp(double t, double* s, double* ds, double* dds) const {
    const double R = ramp_s;
    if (t <= R) {
      *s = t / 2 - R / (2 * kPi) * std::sin(kPi * t / R);
      *ds = std::pow(std::sin(kPi * t / (2 * R)), 2);
      *dds = kPi / (2 * R) * std::sin(kPi * t / R);
    } else if (t <= R + cruise()) {
      *s = t - R / 2;
      *ds = 1.0;
      *dds = 0.0;
    } else {
      const double u = std::min(duration() - t, R);  // time left
      *s = period() - (u / 2 - R / (2 * kPi) * std::sin(kPi * u / R));
      *ds = std::pow(std::sin(kPi * u / (2 * R)), 2);
      *dds = -kPi / (2 * R) * std::sin(kPi * u / R);
    }
  }

  ucon::trajectory::KnotState state(double t) const {
    double s, ds, dds;
    warp(t, &s, &ds, &dds);
    const double W = w();
    s += kPi / (2 * W);  // start at the tip
    const Eigen::Vector3d p(A * std::sin(W * s), 0.5 * B * std::sin(2 * W * s), 0);
    const Eigen::Vector3d dp(A * W * std::cos(W * s), B * W * std::cos(2 * W * s), 0);
    const Eigen::Vector3d ddp(-A * W * W * std::sin(W * s), -2 * B * W * W * std::sin(2 * W * s), 0);
    ucon::trajectory::KnotState k;
    k.t = t;
    k.position = p;
    k.velocity = dp * ds;
    k.acceleration = ddp * ds * ds + dp * dds;
    return k;
  }

  /// Knots every ~`h` s, with knots on the ramp/cruise joints.
  ucon::trajectory_t message(int64_t start_utime, double h = 0.25) const {
    std::vector<ucon::trajectory::KnotState> knots;
    auto segment = [&](double t0, double t1, bool include_end) {
      const int n = std::max(1, static_cast<int>(std::ceil((t1 - t0) / h - 1e-9)));
      for (int i = 0; i < n + (include_end ? 1 : 0); ++i) knots.push_back(state(t0 + (t1 - t0) * i / n));
    };
    segment(0.0, ramp_s, false);
    segment(ramp_s, ramp_s + cruise(), false);
    segment(ramp_s + cruise(), duration(), true);
    ucon::trajectory::PiecewisePolynomial pp;
    ucon::trajectory::buildQuinticHermite(start_utime, knots, 2, &pp);
    ucon::trajectory_t m{};
    m.utime = start_utime;
    m.plan_id = 1;
    m.status = ucon::trajectory_t::STATUS_OK;
    m.yaw = std::numeric_limits<double>::quiet_NaN();
    pp.toMessage(&m);
    return m;
  }
};

/// Pose message from the plant state at `utime`.
inline ucon::robot_pose_t poseFrom(const ucon::mecanum::PlantState& s, int64_t utime) {
  ucon::robot_pose_t p{};
  p.utime = utime;
  p.valid = true;
  p.x = s.x;
  p.y = s.y;
  p.qw = std::cos(s.yaw / 2);
  p.qz = std::sin(s.yaw / 2);
  p.yaw = s.yaw;
  p.vx = s.vx_world;
  p.vy = s.vy_world;
  p.wz = s.body.wz;
  p.ax = std::numeric_limits<double>::quiet_NaN();
  p.ay = std::numeric_limits<double>::quiet_NaN();
  p.cov_size = 0;
  return p;
}

inline ucon::mecanum::MecanumPlantParams plantParams(const ucon::mecanum::MecanumParams& geometry) {
  ucon::mecanum::MecanumPlantParams p;
  p.geometry = geometry;
  p.motor_time_constant = 0.05;  // a typical geared DC motor with its speed loop
  return p;
}

/// One controller + plant loop in message time: every 10 ms the plant pose goes to the
/// controller, it ticks, its wheel command goes to the plant, the plant steps 10 ms.
struct ClosedLoop {
  ucon::base_controller::BaseController ctrl;
  ucon::mecanum::MecanumPlant plant;
  int64_t t = 0;  // [us]
  bool send_pose = true;
  std::vector<ucon::base_controller::BaseControllerOutput> outputs;

  ClosedLoop(const ucon::base_controller::BaseControllerParams& p, int64_t t0)
      : ctrl(p), plant(plantParams(p.mecanum)), t(t0) {
    plant.reset(0, 0, 0);
  }

  ucon::base_controller::BaseControllerOutput step() {
    if (send_pose) ctrl.onPose(poseFrom(plant.state(), t));
    ucon::base_controller::BaseControllerOutput out = ctrl.tick(t);
    if (out.wheel_cmd) {
      const auto& c = *out.wheel_cmd;
      plant.setCommand({c.w_fl, c.w_fr, c.w_rl, c.w_rr}, c.enable);
    }
    plant.step(0.01);
    t += 10000;
    return out;
  }
};

}  // namespace test_support
