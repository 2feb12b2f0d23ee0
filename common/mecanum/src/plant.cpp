#include "ucon/mecanum/plant.hpp"

#include <algorithm>
#include <cmath>

#include "ucon/config.hpp"

namespace ucon {
namespace mecanum {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxSubstep = 0.01;  // [s]

double finiteOr0(double v) { return std::isfinite(v) ? v : 0.0; }
}  // namespace

double wrapAngle(double a) {
  if (!std::isfinite(a)) return 0.0;
  a = std::fmod(a, 2.0 * kPi);
  if (a <= -kPi) a += 2.0 * kPi;
  if (a > kPi) a -= 2.0 * kPi;
  return a;
}

void MecanumPlantParams::read(ConfigReader& r) {
  r.read("motor_time_constant", motor_time_constant, 0.0, 10.0);
  r.read("max_wheel_accel", max_wheel_accel, 0.0, 1e5);
}

std::string MecanumPlantParams::validate() const {
  std::string g = geometry.validate();
  if (!g.empty()) return g;
  if (!(motor_time_constant >= 0.0) || !std::isfinite(motor_time_constant)) {
    return "motor_time_constant: must be >= 0";
  }
  if (!(max_wheel_accel >= 0.0) || !std::isfinite(max_wheel_accel)) {
    return "max_wheel_accel: must be >= 0";
  }
  return {};
}

MecanumPlant::MecanumPlant(const MecanumPlantParams& params)
    : params_(params), kin_(params.geometry) {}

void MecanumPlant::reset(double x, double y, double yaw) {
  state_ = PlantState{};
  state_.x = finiteOr0(x);
  state_.y = finiteOr0(y);
  state_.yaw = wrapAngle(yaw);
  cmd_ = WheelSpeeds{};
}

void MecanumPlant::setState(const PlantState& s) {
  state_.x = finiteOr0(s.x);
  state_.y = finiteOr0(s.y);
  state_.yaw = wrapAngle(s.yaw);
  state_.wheels = WheelSpeeds{finiteOr0(s.wheels.fl), finiteOr0(s.wheels.fr),
                              finiteOr0(s.wheels.rl), finiteOr0(s.wheels.rr)};
  updateVelocities();
}

bool MecanumPlant::setCommand(const WheelSpeeds& cmd, bool enable) {
  if (!cmd.allFinite()) {
    cmd_ = WheelSpeeds{};
    return false;
  }
  if (!enable) {
    cmd_ = WheelSpeeds{};
    return true;
  }
  const double m = params_.geometry.max_wheel_speed;
  auto clamp = [m](double v) { return std::clamp(v, -m, m); };
  cmd_ = WheelSpeeds{clamp(cmd.fl), clamp(cmd.fr), clamp(cmd.rl), clamp(cmd.rr)};
  return true;
}

bool MecanumPlant::step(double dt) {
  if (!std::isfinite(dt) || !(dt > 0.0)) return false;
  const int n = static_cast<int>(std::ceil(dt / kMaxSubstep - 1e-9));
  const double h = dt / static_cast<double>(std::max(n, 1));
  for (int i = 0; i < std::max(n, 1); ++i) stepOnce(h);
  return true;
}

void MecanumPlant::stepOnce(double dt) {
  // Wheels: exact discretisation of tau * dw/dt = cmd - w. The pose integration below uses
  // the exact mean wheel speed over the step, w_mean = c + (w0 - c) * tau/dt * (1 - e^{-dt/tau})
  // (= c for ideal motors). When the acceleration limit cuts the change, the mean is taken
  // as the trapezoid of the start and end speeds instead.
  const double tau = params_.motor_time_constant;
  const double alpha = tau > 0.0 ? 1.0 - std::exp(-dt / tau) : 1.0;
  const double mean_gain = tau > 0.0 ? tau / dt * alpha : 0.0;  // weight of (w0 - c) in the mean
  const double max_dw = params_.max_wheel_accel > 0.0 ? params_.max_wheel_accel * dt : 0.0;
  auto advance = [&](double& w, double c) {
    double dw = alpha * (c - w);
    double mean = c + (w - c) * mean_gain;
    if (max_dw > 0.0 && std::fabs(dw) > max_dw) {
      dw = std::clamp(dw, -max_dw, max_dw);
      mean = w + 0.5 * dw;
    }
    w += dw;
    return mean;
  };
  WheelSpeeds& w = state_.wheels;
  WheelSpeeds mean_w;
  mean_w.fl = advance(w.fl, cmd_.fl);
  mean_w.fr = advance(w.fr, cmd_.fr);
  mean_w.rl = advance(w.rl, cmd_.rl);
  mean_w.rr = advance(w.rr, cmd_.rr);
  const BodyTwist mean = kin_.forward(mean_w);

  // Pose: exact SE(2) motion under the mean body twist of the step.
  const double vx = mean.vx;
  const double vy = mean.vy;
  const double wz = mean.wz;
  const double dth = wz * dt;
  double a, b;  // displacement in the start body frame = [a -b; b a] * [vx vy] * dt
  if (std::fabs(dth) < 1e-6) {
    a = 1.0 - dth * dth / 6.0;
    b = 0.5 * dth;
  } else {
    a = std::sin(dth) / dth;
    b = (1.0 - std::cos(dth)) / dth;
  }
  const double dx_b = (a * vx - b * vy) * dt;
  const double dy_b = (b * vx + a * vy) * dt;
  const double c = std::cos(state_.yaw), s = std::sin(state_.yaw);
  state_.x += c * dx_b - s * dy_b;
  state_.y += s * dx_b + c * dy_b;
  state_.yaw = wrapAngle(state_.yaw + dth);
  updateVelocities();
}

void MecanumPlant::updateVelocities() {
  state_.body = kin_.forward(state_.wheels);
  const double c = std::cos(state_.yaw), s = std::sin(state_.yaw);
  state_.vx_world = c * state_.body.vx - s * state_.body.vy;
  state_.vy_world = s * state_.body.vx + c * state_.body.vy;
}

}  // namespace mecanum
}  // namespace ucon
