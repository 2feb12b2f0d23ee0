#include "ucon/mecanum/kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ucon/config.hpp"

namespace ucon {
namespace mecanum {

double WheelSpeeds::maxAbs() const {
  if (!allFinite()) return std::nan("");
  return std::max({std::fabs(fl), std::fabs(fr), std::fabs(rl), std::fabs(rr)});
}

bool WheelSpeeds::allFinite() const {
  return std::isfinite(fl) && std::isfinite(fr) && std::isfinite(rl) && std::isfinite(rr);
}

void MecanumParams::read(ConfigReader& r) {
  r.read("wheel_radius", wheel_radius, 1e-3, 1.0);
  r.read("half_wheelbase", half_wheelbase, 1e-3, 5.0);
  r.read("half_track", half_track, 1e-3, 5.0);
  r.read("max_wheel_speed", max_wheel_speed, 1e-3, 1000.0);
  std::vector<double> order(motor_order.begin(), motor_order.end());
  std::vector<double> sign(motor_sign.begin(), motor_sign.end());
  r.read("motor_order", order, 4, 0.0, 3.0);
  r.read("motor_sign", sign, 4, -1.0, 1.0);
  if (order.size() == 4) {
    std::array<bool, 4> seen{};
    bool ok = true;
    for (int i = 0; i < 4; ++i) {
      const double v = order[static_cast<std::size_t>(i)];
      const int k = static_cast<int>(v);
      if (v != static_cast<double>(k) || k < 0 || k > 3 || seen[static_cast<std::size_t>(k)]) {
        ok = false;
        break;
      }
      seen[static_cast<std::size_t>(k)] = true;
      motor_order[static_cast<std::size_t>(i)] = k;
    }
    if (!ok) r.fail("motor_order", "must be a permutation of 0, 1, 2, 3 (0 FL, 1 FR, 2 RL, 3 RR)");
  }
  if (sign.size() == 4) {
    for (std::size_t i = 0; i < 4; ++i) {
      if (sign[i] != 1.0 && sign[i] != -1.0) {
        r.fail("motor_sign", "each entry must be +1 or -1");
        break;
      }
      motor_sign[i] = static_cast<int>(sign[i]);
    }
  }
}

std::string MecanumParams::validate() const {
  if (!(wheel_radius > 0.0) || !std::isfinite(wheel_radius)) return "wheel_radius: must be > 0";
  if (!(half_wheelbase > 0.0) || !std::isfinite(half_wheelbase)) return "half_wheelbase: must be > 0";
  if (!(half_track > 0.0) || !std::isfinite(half_track)) return "half_track: must be > 0";
  if (!(max_wheel_speed > 0.0) || !std::isfinite(max_wheel_speed)) {
    return "max_wheel_speed: must be > 0";
  }
  std::array<bool, 4> seen{};
  for (int k : motor_order) {
    if (k < 0 || k > 3 || seen[static_cast<std::size_t>(k)]) {
      return "motor_order: must be a permutation of 0, 1, 2, 3";
    }
    seen[static_cast<std::size_t>(k)] = true;
  }
  for (int s : motor_sign) {
    if (s != 1 && s != -1) return "motor_sign: each entry must be +1 or -1";
  }
  return {};
}

WheelSpeeds MecanumKinematics::inverse(const BodyTwist& t) const {
  const double k = p_.half_wheelbase + p_.half_track;
  const double inv_r = 1.0 / p_.wheel_radius;
  WheelSpeeds w;
  w.fl = (t.vx - t.vy - k * t.wz) * inv_r;
  w.fr = (t.vx + t.vy + k * t.wz) * inv_r;
  w.rl = (t.vx + t.vy - k * t.wz) * inv_r;
  w.rr = (t.vx - t.vy + k * t.wz) * inv_r;
  return w;
}

BodyTwist MecanumKinematics::forward(const WheelSpeeds& w) const {
  // The 4x3 inverse-kinematics matrix J has orthogonal columns with squared norms 4/r^2,
  // 4/r^2 and 4 k^2/r^2, so the pseudo-inverse (J^T J)^-1 J^T is J^T scaled per row.
  const double k = p_.half_wheelbase + p_.half_track;
  const double r4 = p_.wheel_radius * 0.25;
  BodyTwist t;
  t.vx = r4 * (w.fl + w.fr + w.rl + w.rr);
  t.vy = r4 * (-w.fl + w.fr + w.rl - w.rr);
  t.wz = r4 / k * (-w.fl + w.fr - w.rl + w.rr);
  return t;
}

std::array<double, 4> MecanumKinematics::toMotor(const WheelSpeeds& wheels) const {
  const std::array<double, 4> c = wheels.toArray();
  std::array<double, 4> m{};
  for (std::size_t i = 0; i < 4; ++i) {
    m[i] = static_cast<double>(p_.motor_sign[i]) * c[static_cast<std::size_t>(p_.motor_order[i])];
  }
  return m;
}

WheelSpeeds MecanumKinematics::fromMotor(const std::array<double, 4>& motor) const {
  std::array<double, 4> c{};
  for (std::size_t i = 0; i < 4; ++i) {
    c[static_cast<std::size_t>(p_.motor_order[i])] = static_cast<double>(p_.motor_sign[i]) * motor[i];
  }
  return WheelSpeeds::fromArray(c);
}

Saturated saturate(const WheelSpeeds& wheels, double max_speed) {
  Saturated out;
  if (!wheels.allFinite() || !std::isfinite(max_speed) || !(max_speed > 0.0)) {
    out.wheels = WheelSpeeds{};
    out.scale = 0.0;
    return out;
  }
  const double m = wheels.maxAbs();
  if (m <= max_speed) {
    out.wheels = wheels;
    out.scale = 1.0;
    return out;
  }
  const double s = max_speed / m;
  out.wheels = WheelSpeeds{wheels.fl * s, wheels.fr * s, wheels.rl * s, wheels.rr * s};
  out.scale = s;
  return out;
}

}  // namespace mecanum
}  // namespace ucon
