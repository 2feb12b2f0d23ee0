// Difficulty counts: a hand-built case with known counts, and the shipped `pedestrians`
// scenario, which must be hard for every seed (issue 3).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "ucon/world/difficulty.hpp"
#include "ucon/world/scenario_yaml.hpp"

using namespace ucon::world;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

MovingObstacle cv(int64_t id, Vec2 p, Vec2 v) {
  MovingObstacle m;
  m.id = id;
  m.radius = 0.25;
  m.height = 1.7;
  m.motion.kind = MotionKind::kConstantVelocity;
  m.motion.position = p;
  m.motion.velocity = v;
  return m;
}

}  // namespace

TEST(Difficulty, GivenTwoWalkersCrossingInFrontOfAPillarThenEachEventIsCountedOnce) {
  Scenario s;
  s.name = "hand";
  s.bounds = Bounds{-50, 50, -50, 50};
  // A walks along y = 0.3 from x = 0 to 20 at 1 m/s; B walks along y = -0.3 the other way:
  // they pass at t = 10 with centres 0.6 m apart (one close pass). A passes a pillar at
  // (15, 1.0) r 0.2: gap = 0.7 - 0.2 - 0.25 = 0.25 (one static pass).
  s.movers.push_back(cv(1, Vec2(0, 0.3), Vec2(1, 0)));
  s.movers.push_back(cv(2, Vec2(20, -0.3), Vec2(-1, 0)));
  StaticObstacle pillar;
  pillar.center = Vec2(15, 1.0);
  pillar.radius = 0.2;
  pillar.height = 2.0;
  s.statics.push_back(pillar);
  World w(s);
  // Sensor far below the walkers' lines on the y axis: x = 10, y = -10. Around t = 10 the
  // walkers are aligned with it: B (nearer) hides A for about 2 * 0.25 / (2 * 1 m/s * ...).
  DifficultyParams P;
  const auto c = computeDifficulty(w, Vec3(10, -10, 0.5), 18.0, P);
  EXPECT_EQ(c.close_passes, 1);
  EXPECT_EQ(c.static_passes, 1);
  EXPECT_NEAR(c.min_mover_distance, 0.6, 0.03);
  // B (nearer) hides A's centre while |x_A - x_B * 20.3/19.7 ...| is small: both move at 1 m/s in
  // opposite directions, so the hidden interval is ~0.25 s long: shorter than 0.3 s, not counted.
  EXPECT_EQ(c.occlusions, 0);
  // Halve the relative speed: the same crossing now hides A for ~0.5 s.
  s.movers[0].motion.velocity = Vec2(0.5, 0);
  s.movers[1].motion.position = Vec2(15, -0.3);
  s.movers[1].motion.velocity = Vec2(-0.5, 0);
  World w2(s);
  const auto c2 = computeDifficulty(w2, Vec3(10, -10, 0.5), 30.0, P);
  EXPECT_EQ(c2.occlusions, 1);
  EXPECT_EQ(c2.occlusions_by_mover, 1);
}

TEST(Difficulty, GivenThePedestriansScenarioThenEverySeedIsHard) {
  ScenarioError err;
  auto s = parseScenarioYaml(readFile("deploy/scenarios/pedestrians.yaml"), "pedestrians.yaml", &err);
  ASSERT_TRUE(s) << err.toString();
  EXPECT_DOUBLE_EQ(s->duration_s, 243.0);
  ASSERT_EQ(s->movers.size(), 3u);
  for (uint64_t seed : {1, 2, 3, 4, 5, 6, 7, 8, 42, 1000}) {
    s->seed = seed;
    World w(*s);
    const auto c = computeDifficulty(w, Vec3(s->robot.start.x(), s->robot.start.y(), 0.55), 243.0);
    SCOPED_TRACE("seed " + std::to_string(seed) + ": " + c.toString());
    EXPECT_GE(c.close_passes, 10);
    EXPECT_GE(c.static_passes, 10);
    EXPECT_GE(c.occlusions, 10);
    EXPECT_GE(c.occlusions_by_mover, 1);
    EXPECT_GE(c.occlusions_by_static, 1);
    EXPECT_GT(c.min_mover_distance, 0.5);  // two bodies of 0.25 m never overlap
    // Nobody walks through a static obstacle or leaves the room.
    double min_gap = 1e9;
    for (double t = 0; t <= 243.0; t += 0.05) {
      for (std::size_t i = 0; i < w.numMovers(); ++i) {
        const auto st = w.moverState(i, t);
        for (std::size_t q = 0; q < s->statics.size(); ++q)
          min_gap = std::min(min_gap, w.staticFootprintDistance(q, st.position) - st.radius);
      }
    }
    EXPECT_GT(min_gap, 0.05);
    std::printf("pedestrians seed %llu: %s\n", static_cast<unsigned long long>(seed), c.toString().c_str());
  }
}

TEST(Scenarios, GivenCrossingThenFastMoversCrossTheRobotsStraightPath) {
  ScenarioError err;
  auto s = parseScenarioYaml(readFile("deploy/scenarios/crossing.yaml"), "crossing.yaml", &err);
  ASSERT_TRUE(s) << err.toString();
  World w(*s);
  const Vec2 a = s->robot.start, b = s->robot.goals.at(0);
  const Vec2 dir = (b - a).normalized();
  const Vec2 nrm(-dir.y(), dir.x());
  int crossers = 0;
  double top_speed = 0;
  for (std::size_t i = 0; i < w.numMovers(); ++i) {
    bool crossed = false;
    double prev_side = 0;
    for (double t = 0; t <= s->duration_s && !crossed; t += 0.05) {
      const auto st = w.moverState(i, t);
      top_speed = std::max(top_speed, st.velocity.norm());
      const double along = (st.position - a).dot(dir);
      const double side = (st.position - a).dot(nrm);
      if (t > 0 && along > 0 && along < (b - a).norm() && side * prev_side < 0) crossed = true;
      prev_side = side;
    }
    crossers += crossed;
  }
  EXPECT_GE(crossers, 4);
  EXPECT_GE(top_speed, 1.4);
  // The robot's start is free at t = 0.
  EXPECT_GT(w.diskContact(a, s->robot.radius).clearance, 0.5);
}

TEST(Visibility, GivenAnOccluderInFrontThenVisibilityDropsAndReturnsWhenItMovesAway) {
  Scenario s;
  s.name = "vis";
  s.bounds = Bounds{-50, 50, -50, 50};
  s.movers.push_back(cv(1, Vec2(6, 0), Vec2(0, 0)));    // target, 6 m ahead
  s.movers.push_back(cv(2, Vec2(3, -3), Vec2(0, 1)));   // walks through the line of sight
  StaticObstacle low;  // a low box that hides only the legs of a target at (6, 4)
  low.kind = ShapeKind::kBox;
  low.center = Vec2(3, 2);
  low.half_size = Vec2(0.3, 0.6);
  low.height = 0.6;
  s.statics.push_back(low);
  s.movers.push_back(cv(3, Vec2(6, 4), Vec2(0, 0)));
  World w(s);
  const Vec3 sensor(0, 0, 0.5);
  w.setTime(0.0);
  EXPECT_DOUBLE_EQ(moverVisibility(w, 0, sensor), 1.0);
  w.setTime(3.0);  // mover 2 at (3, 0): hides the middle of the target
  const double hidden = moverVisibility(w, 0, sensor);
  EXPECT_LT(hidden, 0.5);
  w.setTime(6.0);  // gone past
  EXPECT_DOUBLE_EQ(moverVisibility(w, 0, sensor), 1.0);
  // Mover 3 behind the low box: the lower rows are hidden, the upper ones seen.
  const double partly = moverVisibility(w, 2, sensor);
  EXPECT_GT(partly, 0.2);
  EXPECT_LT(partly, 0.9);
  EXPECT_DOUBLE_EQ(moverVisibility(w, 7, sensor), 0.0);  // no such mover
}
