// Motion laws against closed forms, mirror bounce, pedestrian timelines, determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "ucon/world/bench_generator.hpp"
#include "ucon/world/rng.hpp"
#include "ucon/world/world.hpp"

using namespace ucon::world;

namespace {

Scenario bigBox() {
  Scenario s;
  s.name = "test";
  s.bounds = Bounds{-1000, 1000, -1000, 1000};
  s.duration_s = 100;
  return s;
}

MovingObstacle mover(int64_t id, MotionParams p, double r = 0.5) {
  MovingObstacle m;
  m.id = id;
  m.radius = r;
  m.motion = p;
  return m;
}

}  // namespace

TEST(Rng, GivenAFixedSeedThenTheFirstValuesAreTheReferenceXoshiroOutputs) {
  // xoshiro256** seeded through SplitMix64(0): state words are SplitMix64's first outputs.
  uint64_t sm = 0;
  EXPECT_EQ(splitmix64(sm), 0xE220A8397B1DCDAFULL);
  Rng a(42), b(42), c(43);
  for (int i = 0; i < 100; ++i) {
    const uint64_t x = a.next();
    EXPECT_EQ(x, b.next());
    EXPECT_NE(x, c.next());
  }
  Rng u(7);
  double lo = 1, hi = 0, sum = 0;
  for (int i = 0; i < 100000; ++i) {
    const double v = u.uniform01();
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    sum += v;
  }
  EXPECT_GE(lo, 0.0);
  EXPECT_LT(hi, 1.0);
  EXPECT_NEAR(sum / 100000, 0.5, 0.01);
  Rng g(9);
  double m1 = 0, m2 = 0;
  for (int i = 0; i < 100000; ++i) {
    const double v = g.normal();
    m1 += v;
    m2 += v * v;
  }
  EXPECT_NEAR(m1 / 100000, 0.0, 0.02);
  EXPECT_NEAR(m2 / 100000, 1.0, 0.02);
}

TEST(Motion, GivenConstantVelocityThenPositionIsLinearInTime) {
  Scenario s = bigBox();
  MotionParams p;
  p.kind = MotionKind::kConstantVelocity;
  p.position = Vec2(1, 2);
  p.velocity = Vec2(0.5, -0.25);
  s.movers.push_back(mover(1, p));
  World w(s);
  const auto st = w.moverState(0, 8.0);
  EXPECT_NEAR(st.position.x(), 5.0, 1e-12);
  EXPECT_NEAR(st.position.y(), 0.0, 1e-12);
  EXPECT_NEAR(st.velocity.x(), 0.5, 1e-12);
  EXPECT_EQ(st.id, 1);
}

TEST(Motion, GivenConstantAccelerationThenSpeedGrowsUntilTheCapThenStaysConstant) {
  Scenario s = bigBox();
  MotionParams p;
  p.kind = MotionKind::kConstantAcceleration;
  p.position = Vec2(0, 0);
  p.velocity = Vec2(0.5, 0);
  p.acceleration = Vec2(0.25, 0);
  p.speed_cap = 1.5;
  s.movers.push_back(mover(1, p));
  World w(s);
  // Before the cap (t_cap = (1.5 - 0.5) / 0.25 = 4 s): x = 0.5 t + 0.125 t^2.
  auto a = w.moverState(0, 2.0);
  EXPECT_NEAR(a.position.x(), 1.0 + 0.5, 1e-12);
  EXPECT_NEAR(a.velocity.x(), 1.0, 1e-12);
  // After: x(4) = 2 + 2 = 4, then 1.5 m/s.
  auto b = w.moverState(0, 10.0);
  EXPECT_NEAR(b.velocity.x(), 1.5, 1e-12);
  EXPECT_NEAR(b.position.x(), 4.0 + 1.5 * 6.0, 1e-9);
}

TEST(Motion, GivenAccelerationAgainstTheVelocityThenTheObstacleTurnsBackAndIsCapped) {
  Scenario s = bigBox();
  MotionParams p;
  p.kind = MotionKind::kConstantAcceleration;
  p.velocity = Vec2(1.0, 0);
  p.acceleration = Vec2(-0.5, 0);
  p.speed_cap = 1.5;
  s.movers.push_back(mover(1, p));
  World w(s);
  EXPECT_NEAR(w.moverState(0, 2.0).velocity.x(), 0.0, 1e-12);
  EXPECT_NEAR(w.moverState(0, 2.0).position.x(), 1.0, 1e-12);  // apex: v0^2 / (2a)
  EXPECT_NEAR(w.moverState(0, 20.0).velocity.x(), -1.5, 1e-12);  // cap at t = 5
}

TEST(Motion, GivenSinusoidalMotionThenVelocityMatchesTheLawAndPositionIsItsIntegral) {
  Scenario s = bigBox();
  MotionParams p;
  p.kind = MotionKind::kSinusoidal;
  p.position = Vec2(1, -1);
  p.amplitude = Vec2(0.8, 0.4);
  p.omega = Vec2(0.7, 1.3);
  p.phase = Vec2(0.2, -0.5);
  p.offset = Vec2(0.3, -0.1);
  s.movers.push_back(mover(1, p));
  World w(s);
  // Integrate the velocity law numerically (midpoint rule) and compare.
  Vec2 x = p.position;
  const double dt = 1e-3;
  for (int k = 0; k < 10000; ++k) {
    const double t = (k + 0.5) * dt;
    for (int i = 0; i < 2; ++i) x[i] += dt * (p.amplitude[i] * std::sin(p.omega[i] * t + p.phase[i]) + p.offset[i]);
  }
  const auto st = w.moverState(0, 10.0);
  EXPECT_NEAR(st.position.x(), x.x(), 1e-6);
  EXPECT_NEAR(st.position.y(), x.y(), 1e-6);
  EXPECT_NEAR(st.velocity.x(), 0.8 * std::sin(7.0 + 0.2) + 0.3, 1e-12);
}

TEST(Motion, GivenABorderThenTheObstacleBouncesLikeAMirror) {
  Scenario s = bigBox();
  s.bounds = Bounds{0, 10, 0, 10};
  MotionParams p;
  p.kind = MotionKind::kConstantVelocity;
  p.position = Vec2(5, 5);
  p.velocity = Vec2(1, 0);
  s.movers.push_back(mover(1, p, 0.5));
  World w(s);
  // Reaches x = 9.5 (10 - r) at t = 4.5, comes back: x(6) = 9.5 - 1.5 = 8.
  auto a = w.moverState(0, 6.0);
  EXPECT_NEAR(a.position.x(), 8.0, 1e-12);
  EXPECT_NEAR(a.velocity.x(), -1.0, 1e-12);
  // Full round trip (9 m each way): at t = 4.5 + 9 + 1 it has bounced off x = 0.5 too.
  auto b = w.moverState(0, 14.5);
  EXPECT_NEAR(b.position.x(), 1.5, 1e-9);
  EXPECT_NEAR(b.velocity.x(), 1.0, 1e-12);
  // Never leaves the bounds over a long run.
  for (double t = 0; t < 200; t += 0.37) {
    const auto st = w.moverState(0, t);
    EXPECT_GE(st.position.x(), 0.5 - 1e-9);
    EXPECT_LE(st.position.x(), 9.5 + 1e-9);
  }
  double sign;
  EXPECT_NEAR(foldIntoInterval(-3.0, 0.0, 10.0, &sign), 3.0, 1e-12);
  EXPECT_EQ(sign, -1.0);
  EXPECT_NEAR(foldIntoInterval(23.0, 0.0, 10.0, &sign), 3.0, 1e-12);
  EXPECT_EQ(sign, 1.0);
}

TEST(Motion, GivenAPedestrianThenItWalksContinuouslyBetweenWaypointsAtAllowedSpeeds) {
  Scenario s = bigBox();
  s.seed = 5;
  MotionParams p;
  p.kind = MotionKind::kPedestrian;
  p.waypoints = {Vec2(0, 0), Vec2(10, 0), Vec2(10, 5)};
  p.mode = PathMode::kLoop;
  p.speed_min = 0.5;
  p.speed_max = 1.8;
  p.pause_probability = 0.5;
  s.movers.push_back(mover(1, p, 0.25));
  World w(s);
  const auto& tl = w.timeline(0);
  ASSERT_GT(tl.size(), 50u);
  bool paused = false;
  double vmin = 1e9, vmax = 0;
  for (std::size_t k = 0; k + 1 < tl.size(); ++k) {
    // Continuity: each piece ends where the next starts.
    const Vec2 end = tl[k].p0 + tl[k].v * (tl[k + 1].t0 - tl[k].t0);
    EXPECT_NEAR((end - tl[k + 1].p0).norm(), 0.0, 1e-9);
    const double sp = tl[k].v.norm();
    if (sp == 0.0) {
      paused = true;
    } else {
      vmin = std::min(vmin, sp);
      vmax = std::max(vmax, sp);
    }
  }
  EXPECT_TRUE(paused);
  EXPECT_GE(vmin, 0.5);
  EXPECT_LE(vmax, 1.8);
  EXPECT_LT(vmin, 0.8);  // speeds actually vary
  EXPECT_GT(vmax, 1.5);
  // Stays on the triangle's edges: within its bounding box.
  for (double t = 0; t < 500; t += 0.5) {
    const auto st = w.moverState(0, t);
    EXPECT_GE(st.position.x(), -1e-9);
    EXPECT_LE(st.position.x(), 10 + 1e-9);
    EXPECT_GE(st.position.y(), -1e-9);
    EXPECT_LE(st.position.y(), 5 + 1e-9);
  }
}

TEST(Determinism, GivenTheSameSeedThenTwoWorldsAreBitIdenticalAndAnotherSeedDiffers) {
  World a(generateBench(30, 11)), b(generateBench(30, 11)), c(generateBench(30, 12));
  ASSERT_EQ(a.scenario().statics.size(), b.scenario().statics.size());
  for (std::size_t i = 0; i < a.scenario().statics.size(); ++i) {
    EXPECT_EQ(a.scenario().statics[i].center, b.scenario().statics[i].center);
  }
  bool differs = false;
  for (double t : {0.0, 1.25, 17.0, 99.9}) {
    std::vector<ObstacleState> sa, sb, sc;
    a.moverStates(t, sa);
    b.moverStates(t, sb);
    c.moverStates(t, sc);
    for (std::size_t i = 0; i < sa.size(); ++i) {
      EXPECT_EQ(0, std::memcmp(sa[i].position.data(), sb[i].position.data(), sizeof(double) * 2));
      EXPECT_EQ(0, std::memcmp(sa[i].velocity.data(), sb[i].velocity.data(), sizeof(double) * 2));
      if (sa[i].position != sc[i].position) differs = true;
    }
  }
  EXPECT_TRUE(differs);
  // Pedestrian timelines depend on the scenario seed.
  Scenario s = bigBox();
  MotionParams p;
  p.kind = MotionKind::kPedestrian;
  p.waypoints = {Vec2(0, 0), Vec2(10, 0)};
  s.movers.push_back(mover(3, p));
  s.seed = 1;
  World p1(s), p1b(s);
  s.seed = 2;
  World p2(s);
  EXPECT_EQ(p1.moverState(0, 77.7).position, p1b.moverState(0, 77.7).position);
  EXPECT_NE(p1.moverState(0, 77.7).position, p2.moverState(0, 77.7).position);
}

TEST(Motion, GivenAnUnvalidatedDegeneratePedestrianThenTheWorldStillBuildsAndStaysFinite) {
  // validate() rejects all of these; the World must still neither hang nor misbehave.
  Scenario s = bigBox();
  MotionParams same;
  same.kind = MotionKind::kPedestrian;
  same.waypoints = {Vec2(1, 1), Vec2(1, 1)};  // zero-length legs
  same.pause_probability = 0.0;
  MotionParams frozen = same;
  frozen.waypoints = {Vec2(0, 0), Vec2(5, 0)};
  frozen.speed_min = frozen.speed_max = 0.0;  // cannot walk
  frozen.speed_change_min_s = frozen.speed_change_max_s = 0.0;
  MotionParams empty = same;
  empty.waypoints.clear();
  MotionParams bad = same;
  bad.waypoints = {Vec2(0, 0), Vec2(std::nan(""), 0)};
  s.movers = {mover(1, same), mover(2, frozen), mover(3, empty), mover(4, bad)};
  EXPECT_TRUE(validate(s).has_value());
  World w(s);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto st = w.moverState(i, 100.0);
    EXPECT_TRUE(st.position.allFinite()) << i;
  }
  EXPECT_EQ(w.moverState(0, 50.0).position, Vec2(1, 1));
  EXPECT_LE(w.moverState(1, 50.0).position.x(), 5.0);
}
