#include <gtest/gtest.h>

#include <cmath>

#include "ucon/mecanum/plant.hpp"

using namespace ucon::mecanum;

namespace {
MecanumPlantParams plantParams(double tau) {
  MecanumPlantParams p;
  p.geometry.wheel_radius = 0.05;
  p.geometry.half_wheelbase = 0.2;
  p.geometry.half_track = 0.15;
  p.geometry.max_wheel_speed = 40.0;
  p.motor_time_constant = tau;
  return p;
}
constexpr double kPi = 3.14159265358979323846;
}  // namespace

TEST(MecanumPlant, GivenIdealMotorsAndForwardCommandThenMovesAlongHeading) {
  MecanumPlant plant(plantParams(0.0));
  plant.reset(1.0, 2.0, kPi / 2);
  plant.setCommand(plant.kinematics().inverse({0.5, 0.0, 0.0}));
  for (int i = 0; i < 100; ++i) plant.step(0.01);
  EXPECT_NEAR(plant.state().x, 1.0, 1e-9);
  EXPECT_NEAR(plant.state().y, 2.5, 1e-9);
  EXPECT_NEAR(plant.state().vy_world, 0.5, 1e-12);
  EXPECT_NEAR(plant.state().body.vx, 0.5, 1e-12);
}

TEST(MecanumPlant, GivenMotorLagThenSpeedFollowsFirstOrderResponse) {
  MecanumPlant plant(plantParams(0.1));
  plant.reset(0, 0, 0);
  plant.setCommand(WheelSpeeds{10, 10, 10, 10});
  plant.step(0.1);  // one time constant: 1 - e^-1 of the command
  EXPECT_NEAR(plant.state().wheels.fl, 10.0 * (1.0 - std::exp(-1.0)), 1e-9);
  // Position: integral of v(t) = v_c (1 - e^{-t/tau}) is v_c (t - tau (1 - e^{-t/tau})).
  const double vc = 10.0 * 0.05;
  EXPECT_NEAR(plant.state().x, vc * (0.1 - 0.1 * (1.0 - std::exp(-1.0))), 1e-12);
}

TEST(MecanumPlant, GivenConstantTwistWithRotationThenFollowsACircleExactly) {
  MecanumPlant plant(plantParams(0.0));
  plant.reset(0, 0, 0);
  const double v = 1.0, w = 0.5;  // circle of radius 2 m about (0, 2)
  plant.setCommand(plant.kinematics().inverse({v, 0.0, w}));
  for (int i = 0; i < 314; ++i) plant.step(0.01);
  const double t = 3.14, th = w * t;
  EXPECT_NEAR(plant.state().x, 2.0 * std::sin(th), 1e-9);
  EXPECT_NEAR(plant.state().y, 2.0 * (1.0 - std::cos(th)), 1e-9);
  EXPECT_NEAR(plant.state().yaw, th, 1e-12);
}

TEST(MecanumPlant, GivenCommandAboveTheMotorLimitThenEachWheelClamped) {
  MecanumPlant plant(plantParams(0.0));
  plant.reset(0, 0, 0);
  plant.setCommand(WheelSpeeds{100, -100, 5, 0});
  plant.step(0.01);
  EXPECT_EQ(plant.state().wheels.fl, 40.0);
  EXPECT_EQ(plant.state().wheels.fr, -40.0);
  EXPECT_EQ(plant.state().wheels.rl, 5.0);
}

TEST(MecanumPlant, GivenNaNCommandOrBadDtThenBrakesOrIgnoresWithoutNaN) {
  MecanumPlant plant(plantParams(0.0));
  plant.reset(0, 0, 0);
  plant.setCommand(WheelSpeeds{5, 5, 5, 5});
  plant.step(0.1);
  EXPECT_FALSE(plant.setCommand(WheelSpeeds{std::nan(""), 1, 1, 1}));
  EXPECT_FALSE(plant.step(std::nan("")));
  EXPECT_FALSE(plant.step(-0.1));
  plant.step(0.1);
  EXPECT_EQ(plant.state().wheels.fl, 0.0);
  EXPECT_TRUE(std::isfinite(plant.state().x));
  EXPECT_NEAR(plant.state().x, 0.025, 1e-12);  // ideal motors stop at once
}

TEST(MecanumPlant, GivenSameCommandsWhenSteppedInDifferentChunksThenSameResultClosely) {
  MecanumPlant a(plantParams(0.05)), b(plantParams(0.05));
  a.reset(0, 0, 0.3);
  b.reset(0, 0, 0.3);
  const WheelSpeeds cmd = a.kinematics().inverse({0.8, 0.3, 0.7});
  a.setCommand(cmd);
  b.setCommand(cmd);
  for (int i = 0; i < 200; ++i) a.step(0.005);
  for (int i = 0; i < 20; ++i) b.step(0.05);  // split into 10 ms sub-steps internally
  EXPECT_NEAR(a.state().x, b.state().x, 2e-3);
  EXPECT_NEAR(a.state().y, b.state().y, 2e-3);
  EXPECT_NEAR(a.state().yaw, b.state().yaw, 1e-3);
}

TEST(WrapAngle, GivenAnglesThenWrappedToMinusPiPi) {
  EXPECT_NEAR(wrapAngle(3 * kPi / 2), -kPi / 2, 1e-12);
  EXPECT_NEAR(wrapAngle(-kPi), kPi, 1e-12);
  EXPECT_NEAR(wrapAngle(7.0), 7.0 - 2 * kPi, 1e-12);
  EXPECT_EQ(wrapAngle(std::nan("")), 0.0);
}
