#include <gtest/gtest.h>

#include <cmath>

#include "ucon/config.hpp"
#include "ucon/mecanum/kinematics.hpp"

using namespace ucon::mecanum;

namespace {
MecanumParams params() {
  MecanumParams p;
  p.wheel_radius = 0.05;
  p.half_wheelbase = 0.2;
  p.half_track = 0.15;
  p.max_wheel_speed = 20.0;
  return p;
}
}  // namespace

TEST(MecanumKinematics, GivenPureForwardVelocityThenAllWheelsTurnForwardAtVOverR) {
  MecanumKinematics k(params());
  const WheelSpeeds w = k.inverse({1.0, 0.0, 0.0});
  EXPECT_DOUBLE_EQ(w.fl, 20.0);
  EXPECT_DOUBLE_EQ(w.fr, 20.0);
  EXPECT_DOUBLE_EQ(w.rl, 20.0);
  EXPECT_DOUBLE_EQ(w.rr, 20.0);
  const BodyTwist t = k.forward(w);
  EXPECT_DOUBLE_EQ(t.vx, 1.0);
  EXPECT_DOUBLE_EQ(t.vy, 0.0);
  EXPECT_DOUBLE_EQ(t.wz, 0.0);
}

TEST(MecanumKinematics, GivenPureLeftVelocityThenDiagonalWheelsTurnOpposite) {
  MecanumKinematics k(params());
  const WheelSpeeds w = k.inverse({0.0, 0.5, 0.0});
  EXPECT_DOUBLE_EQ(w.fl, -10.0);
  EXPECT_DOUBLE_EQ(w.fr, 10.0);
  EXPECT_DOUBLE_EQ(w.rl, 10.0);
  EXPECT_DOUBLE_EQ(w.rr, -10.0);
  const BodyTwist t = k.forward(w);
  EXPECT_DOUBLE_EQ(t.vx, 0.0);
  EXPECT_DOUBLE_EQ(t.vy, 0.5);
  EXPECT_DOUBLE_EQ(t.wz, 0.0);
}

TEST(MecanumKinematics, GivenPureRotationThenLeftWheelsBackRightWheelsForward) {
  MecanumKinematics k(params());
  // (lx + ly) = 0.35 m, r = 0.05 m: w = 0.35 * 2 / 0.05 = 14 rad/s.
  const WheelSpeeds w = k.inverse({0.0, 0.0, 2.0});
  EXPECT_DOUBLE_EQ(w.fl, -14.0);
  EXPECT_DOUBLE_EQ(w.fr, 14.0);
  EXPECT_DOUBLE_EQ(w.rl, -14.0);
  EXPECT_DOUBLE_EQ(w.rr, 14.0);
  const BodyTwist t = k.forward(w);
  EXPECT_DOUBLE_EQ(t.vx, 0.0);
  EXPECT_DOUBLE_EQ(t.vy, 0.0);
  EXPECT_DOUBLE_EQ(t.wz, 2.0);
}

TEST(MecanumKinematics, GivenAnyTwistWhenRoundTrippedThenRecovered) {
  MecanumKinematics k(params());
  for (double vx : {-1.3, 0.0, 0.7}) {
    for (double vy : {-0.4, 0.25}) {
      for (double wz : {-1.1, 0.0, 2.5}) {
        const BodyTwist t = k.forward(k.inverse({vx, vy, wz}));
        EXPECT_NEAR(t.vx, vx, 1e-12);
        EXPECT_NEAR(t.vy, vy, 1e-12);
        EXPECT_NEAR(t.wz, wz, 1e-12);
      }
    }
  }
}

TEST(MecanumKinematics, GivenInconsistentWheelsThenForwardIsTheLeastSquaresFit) {
  MecanumKinematics k(params());
  // One wheel alone: the least-squares twist reproduces the wheel pattern's projection, and
  // the residual w - J t is orthogonal to every column of J (normal equations).
  const WheelSpeeds w{4.0, 0.0, 0.0, 0.0};
  const WheelSpeeds back = k.inverse(k.forward(w));
  const double res[4] = {w.fl - back.fl, w.fr - back.fr, w.rl - back.rl, w.rr - back.rr};
  EXPECT_NEAR(res[0] + res[1] + res[2] + res[3], 0.0, 1e-12);        // vx column
  EXPECT_NEAR(-res[0] + res[1] + res[2] - res[3], 0.0, 1e-12);       // vy column
  EXPECT_NEAR(-res[0] + res[1] - res[2] + res[3], 0.0, 1e-12);       // wz column
  EXPECT_NEAR(std::fabs(res[0]), 1.0, 1e-12);  // the slip pattern (1, 1, -1, -1)
}

TEST(Saturation, GivenWheelsOverTheLimitThenAllScaledByOneFactorKeepingDirection) {
  MecanumKinematics k(params());
  const BodyTwist want{1.2, -0.8, 1.5};
  const WheelSpeeds w = k.inverse(want);
  const Saturated s = saturate(w, 20.0);
  ASSERT_GT(w.maxAbs(), 20.0);
  EXPECT_NEAR(s.wheels.maxAbs(), 20.0, 1e-12);
  EXPECT_NEAR(s.scale, 20.0 / w.maxAbs(), 1e-15);
  const BodyTwist got = k.forward(s.wheels);
  // Same direction: every component scaled by the same factor.
  EXPECT_NEAR(got.vx, want.vx * s.scale, 1e-12);
  EXPECT_NEAR(got.vy, want.vy * s.scale, 1e-12);
  EXPECT_NEAR(got.wz, want.wz * s.scale, 1e-12);
  EXPECT_NEAR(std::atan2(got.vy, got.vx), std::atan2(want.vy, want.vx), 1e-12);
}

TEST(Saturation, GivenWheelsWithinTheLimitThenUnchangedWithScaleOne) {
  const WheelSpeeds w{1.0, -2.0, 3.0, -4.0};
  const Saturated s = saturate(w, 4.0);
  EXPECT_EQ(s.scale, 1.0);
  EXPECT_EQ(s.wheels.rr, -4.0);
  EXPECT_EQ(s.wheels.fr, -2.0);
}

TEST(Saturation, GivenNaNWheelThenAllZeroAndScaleZero) {
  const Saturated s = saturate(WheelSpeeds{1.0, std::nan(""), 0.0, 0.0}, 4.0);
  EXPECT_EQ(s.scale, 0.0);
  EXPECT_EQ(s.wheels.fl, 0.0);
  EXPECT_EQ(s.wheels.maxAbs(), 0.0);
}

TEST(MotorMapping, GivenOrderAndSignsThenToMotorPermutesAndFromMotorInverts) {
  MecanumParams p = params();
  p.motor_order = {1, 0, 3, 2};  // board channel 0 drives FR, ...
  p.motor_sign = {1, -1, 1, -1};
  MecanumKinematics k(p);
  const WheelSpeeds w{1.0, 2.0, 3.0, 4.0};
  const auto m = k.toMotor(w);
  EXPECT_EQ(m[0], 2.0);
  EXPECT_EQ(m[1], -1.0);
  EXPECT_EQ(m[2], 4.0);
  EXPECT_EQ(m[3], -3.0);
  const WheelSpeeds back = k.fromMotor(m);
  EXPECT_EQ(back.fl, 1.0);
  EXPECT_EQ(back.fr, 2.0);
  EXPECT_EQ(back.rl, 3.0);
  EXPECT_EQ(back.rr, 4.0);
}

TEST(MecanumParams, GivenYamlThenReadAndBadOrderNamed) {
  const std::string good =
      "wheel_radius: 0.076\nhalf_wheelbase: 0.25\nhalf_track: 0.22\nmax_wheel_speed: 25\n"
      "motor_order: [3, 2, 1, 0]\nmotor_sign: [1, -1, 1, -1]\n";
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<MecanumParams>(good, "test", &errors);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->wheel_radius, 0.076);
  EXPECT_EQ(p->motor_order[0], 3);
  EXPECT_EQ(p->motor_sign[1], -1);
  EXPECT_TRUE(p->validate().empty());

  const std::string bad =
      "wheel_radius: 0.076\nhalf_wheelbase: 0.25\nhalf_track: 0.22\nmax_wheel_speed: 25\n"
      "motor_order: [0, 0, 1, 2]\nmotor_sign: [1, 0.5, 1, -1]\n";
  errors.clear();
  EXPECT_FALSE(ucon::loadParams<MecanumParams>(bad, "test", &errors).has_value());
  std::string all;
  for (const auto& e : errors) all += e.toString() + "\n";
  EXPECT_NE(all.find("motor_order"), std::string::npos) << all;
  EXPECT_NE(all.find("motor_sign"), std::string::npos) << all;
}
