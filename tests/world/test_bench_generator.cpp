// The bench:<N_d>:<seed> generator: the paper's parameters and the project's defaults hold.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/world/bench_generator.hpp"
#include "ucon/world/world.hpp"

using namespace ucon::world;

TEST(BenchGenerator, GivenNdAndASeedThenTheWorldHasThePaperParameters) {
  for (int nd : {50, 80, 110}) {
    for (uint64_t seed : {1, 2, 3}) {
      const Scenario s = generateBench(nd, seed);
      SCOPED_TRACE(s.name);
      EXPECT_EQ(s.name, "bench:" + std::to_string(nd) + ":" + std::to_string(seed));
      EXPECT_FALSE(validate(s).has_value()) << *validate(s);
      EXPECT_DOUBLE_EQ(s.bounds.xmax - s.bounds.xmin, 50.0);
      EXPECT_DOUBLE_EQ(s.bounds.ymax - s.bounds.ymin, 50.0);
      EXPECT_EQ(s.statics.size(), 160u);
      ASSERT_EQ(s.movers.size(), static_cast<std::size_t>(nd));
      EXPECT_DOUBLE_EQ(s.robot.radius, 0.3);
      EXPECT_DOUBLE_EQ(s.robot.max_speed, 1.5);
      EXPECT_DOUBLE_EQ(s.robot.max_accel, 2.0);
      ASSERT_EQ(s.robot.goals.size(), 1u);
      EXPECT_GE((s.robot.goals[0] - s.robot.start).norm(), 40.0);
      int kinds[3] = {0, 0, 0};
      World w(s);
      for (std::size_t i = 0; i < s.movers.size(); ++i) {
        const auto& m = s.movers[i];
        EXPECT_GE(m.radius, 0.2);
        EXPECT_LE(m.radius, 0.5);
        ++kinds[static_cast<int>(m.motion.kind)];
        // Speed over time stays within the cap (CA capped at 1.5; sinusoid bounded).
        double vmax = 0, vsum = 0;
        int n = 0;
        for (double t = 0; t <= 120; t += 0.5, ++n) {
          const double v = w.moverState(i, t).velocity.norm();
          vmax = std::max(vmax, v);
          vsum += v;
        }
        EXPECT_LE(vmax, 1.5 + 1e-9);
        if (m.motion.kind == MotionKind::kConstantVelocity) {
          EXPECT_GE(m.motion.velocity.norm(), 0.3);
        }
        EXPECT_GE(vsum / n, 0.05);  // everything moves
      }
      EXPECT_EQ(kinds[0], (nd + 2) / 3);
      EXPECT_EQ(kinds[1], (nd + 1) / 3);
      EXPECT_EQ(kinds[2], nd / 3);
      // Start and goal kept clear at t = 0.
      w.setTime(0.0);
      EXPECT_GE(w.diskContact(s.robot.start, s.robot.radius).clearance, 2.0);
      EXPECT_GE(w.diskContact(s.robot.goals[0], s.robot.radius).clearance, 2.0);
      // Static spacing.
      for (std::size_t a = 0; a < s.statics.size(); ++a)
        for (std::size_t b = a + 1; b < s.statics.size(); ++b)
          ASSERT_GE(w.staticFootprintDistance(a, s.statics[b].center), 0.5);
    }
  }
}

TEST(BenchGenerator, GivenTheSameSeedThenTheSameWorldAndADifferentSeedADifferentOne) {
  const Scenario a = generateBench(80, 7), b = generateBench(80, 7), c = generateBench(80, 8);
  ASSERT_EQ(a.statics.size(), b.statics.size());
  for (std::size_t i = 0; i < a.statics.size(); ++i) {
    EXPECT_EQ(a.statics[i].center, b.statics[i].center);
    EXPECT_EQ(a.statics[i].height, b.statics[i].height);
  }
  for (std::size_t i = 0; i < a.movers.size(); ++i) {
    EXPECT_EQ(a.movers[i].motion.position, b.movers[i].motion.position);
    EXPECT_EQ(a.movers[i].motion.velocity, b.movers[i].motion.velocity);
  }
  EXPECT_NE(a.statics[0].center, c.statics[0].center);
  EXPECT_EQ(a.robot.start.x(), -22.0);
  EXPECT_EQ(a.robot.goals[0].x(), 22.0);
}

TEST(BenchGenerator, GivenSeed7ThenTheWorldIsBitIdenticalToTheReferenceLayout) {
  // Reference values produced on x86-64 (GCC, glibc). Generation uses no libm function, so any
  // IEEE-754 machine must reproduce them exactly; a difference means the generator changed.
  const Scenario s = generateBench(80, 7);
  double sum = 0;
  for (const auto& o : s.statics)
    sum += o.center.x() * 3 + o.center.y() + o.height + o.half_size.x() + o.radius + o.yaw;
  for (const auto& m : s.movers)
    sum += m.motion.position.x() + m.motion.velocity.y() + m.radius + m.motion.acceleration.x() +
           m.motion.amplitude.y() + m.motion.omega.x() + m.motion.offset.y();
  EXPECT_EQ(sum, 0x1.e00d792d16c0fp+8);
  EXPECT_EQ(s.robot.start.y(), 0x1.7d24d90d1e01cp+2);
  EXPECT_EQ(s.statics[0].center.x(), 0x1.7b4a8a91a68f8p+1);
  EXPECT_EQ(s.movers[3].motion.velocity.x(), 0x1.c1e8f0a4d46cp-1);
}
