// Scenario files: the shipped ones parse and their rooms are closed; every kind of mistake
// names its key.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <cmath>

#include "ucon/world/scenario_yaml.hpp"
#include "ucon/world/world.hpp"

using namespace ucon::world;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

const char* kMinimal = R"(
name: t
duration: 10
bounds: {xmin: -5, xmax: 5, ymin: -5, ymax: 5}
robot: {start: [0, 0], yaw: 0, radius: 0.3, max_speed: 1.5, max_accel: 2, goals: [[4, 0]]}
static:
  - {type: cylinder, center: [2, 2], radius: 0.3, height: 2}
  - {type: box, center: [-2, 2], size: [1, 0.5], yaw: 0.3, height: 1}
  - {type: wall, from: [-5, -4], to: [5, -4], thickness: 0.2, height: 2}
moving:
  - {id: 1, radius: 0.3, height: 1.7, motion: {type: constant_velocity, position: [0, 3], velocity: [1, 0]}}
  - {id: 2, radius: 0.3, height: 1.7, motion: {type: constant_acceleration, position: [0, -3], velocity: [1, 0], acceleration: [0.1, 0], speed_cap: 1.5}}
  - {id: 3, radius: 0.3, height: 1.7, motion: {type: sinusoidal, position: [3, 0], amplitude: [0.5, 0.5], omega: [1, 1], offset: [0, 0.2]}}
  - id: 4
    radius: 0.25
    height: 1.75
    motion: {type: pedestrian, waypoints: [[-3, -3], [3, 3]], mode: loop, speed: [0.5, 1.8], speed_change_interval: [2, 6], pause_probability: 0.2, pause: [0.5, 1], jitter: 0.1}
)";

// Parses kMinimal with `from` replaced by `to`; returns the error (key, message).
ScenarioError errorFor(const std::string& from, const std::string& to) {
  std::string text = kMinimal;
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  text.replace(pos, from.size(), to);
  ScenarioError err;
  EXPECT_FALSE(parseScenarioYaml(text, "test.yaml", &err)) << to;
  return err;
}

}  // namespace

TEST(ScenarioYaml, GivenAFileWithEveryShapeAndMotionThenItParses) {
  ScenarioError err;
  auto s = parseScenarioYaml(kMinimal, "test.yaml", &err);
  ASSERT_TRUE(s) << err.toString();
  EXPECT_EQ(s->name, "t");
  EXPECT_EQ(s->seed, 1u);
  ASSERT_EQ(s->statics.size(), 3u);
  EXPECT_EQ(s->statics[2].kind, ShapeKind::kBox);
  EXPECT_NEAR(s->statics[2].half_size.x(), 5.0, 1e-12);  // wall: 10 m long
  EXPECT_NEAR(s->statics[1].half_size.y(), 0.25, 1e-12);
  ASSERT_EQ(s->movers.size(), 4u);
  EXPECT_EQ(s->movers[1].motion.kind, MotionKind::kConstantAcceleration);
  EXPECT_EQ(s->movers[3].motion.kind, MotionKind::kPedestrian);
  EXPECT_EQ(s->movers[3].motion.mode, PathMode::kLoop);
  EXPECT_DOUBLE_EQ(s->movers[3].motion.speed_max, 1.8);
}

TEST(ScenarioYaml, GivenTheShippedScenariosThenTheyParse) {
  for (const char* f : {"deploy/scenarios/pedestrians.yaml", "deploy/scenarios/crossing.yaml",
                        "deploy/scenarios/corridor.yaml", "deploy/scenarios/hall.yaml"}) {
    const std::string text = readFile(f);
    ASSERT_FALSE(text.empty()) << f;
    ScenarioError err;
    auto s = parseScenarioYaml(text, f, &err);
    EXPECT_TRUE(s) << err.toString();
  }
}

// A room whose walls only touch end to end leaves a slot at each corner: a LiDAR sees the floor
// beyond it, and the odometry's map kept growing with those far returns. Every horizontal ray
// from where the robot stands (start and goals, at sensor and at chest height) must hit a
// wall or an obstacle; 0.005 deg apart, a 0.1 m slot is found from 500 m.
TEST(ScenarioYaml, GivenTheShippedRoomsThenNoHorizontalRayLeavesThem) {
  for (const char* f : {"deploy/scenarios/pedestrians.yaml", "deploy/scenarios/crossing.yaml",
                        "deploy/scenarios/corridor.yaml", "deploy/scenarios/hall.yaml"}) {
    ScenarioError err;
    auto s = parseScenarioYaml(readFile(f), f, &err);
    ASSERT_TRUE(s) << err.toString();
    std::vector<Vec2> origins{s->robot.start};
    origins.insert(origins.end(), s->robot.goals.begin(), s->robot.goals.end());
    World world(*s);
    int escaped = 0;
    for (const Vec2& o : origins)
      for (double z : {0.5, 1.2})
        for (int k = 0; k < 72000; ++k) {
          const double a = 2.0 * M_PI * k / 72000.0;
          const RayHit h = world.castRay(Vec3(o.x(), o.y(), z), Vec3(std::cos(a), std::sin(a), 0.0), 500.0);
          if (h.kind == HitKind::kNone) ++escaped;
        }
    EXPECT_EQ(escaped, 0) << f << ": rays that left the room";
  }
}

TEST(ScenarioYaml, GivenMistakesThenTheErrorNamesTheKey) {
  struct Case {
    std::string from, to, key, words;
  };
  const std::vector<Case> cases = {
      {"duration: 10", "duraton: 10", "duration", "missing"},
      {"name: t", "name: t\nextra: 1", "extra", "unknown key"},
      {"radius: 0.3, height: 2}", "radius: -0.3, height: 2}", "static[0].radius", "must be in (0"},
      {"type: box", "type: sphere", "static[1].type", "unknown static type"},
      {"center: [2, 2]", "center: [2]", "static[0].center", "[x, y]"},
      {"center: [2, 2]", "center: [2, nan]", "static[0].center[1]", "finite"},
      {"type: constant_velocity", "type: teleport", "moving[0].motion.type", "unknown motion"},
      {"velocity: [1, 0], acceleration", "velocity: [3, 0], acceleration", "moving[1].motion.velocity", "speed_cap"},
      {"omega: [1, 1]", "omega: [0, 1]", "moving[2].motion.omega", "> 0"},
      {"mode: loop", "mode: zigzag", "moving[3].motion.mode", "unknown mode"},
      {"speed: [0.5, 1.8]", "speed: [1.8, 0.5]", "moving[3].motion.speed", "min <= max"},
      {"waypoints: [[-3, -3], [3, 3]]", "waypoints: [[-3, -3], [30, 3]]", "moving[3].motion.waypoints[1]", "outside"},
      {"waypoints: [[-3, -3], [3, 3]]", "waypoints: [[-3, -3]]", "moving[3].motion.waypoints", "at least 2"},
      {"{id: 2,", "{id: 1,", "moving[1].id", "duplicate"},
      {"radius: 0.3, height: 1.7, motion: {type: sinusoidal", "radius: 0.3, height: 1.7, colour: red, motion: {type: sinusoidal", "moving[2].colour", "unknown key"},
      {"xmax: 5", "xmax: -6", "bounds", "xmin < xmax"},
      {"max_speed: 1.5", "max_speed: fast", "robot.max_speed", "expected a number"},
  };
  for (const auto& c : cases) {
    const ScenarioError e = errorFor(c.from, c.to);
    EXPECT_EQ(e.key, c.key) << c.to << " -> " << e.toString();
    EXPECT_NE(e.toString().find(c.words), std::string::npos) << e.toString();
    EXPECT_NE(e.toString().find("test.yaml"), std::string::npos) << e.toString();
  }
  ScenarioError syntax;
  EXPECT_FALSE(parseScenarioYaml("name: [unclosed", "bad.yaml", &syntax));
  EXPECT_NE(syntax.toString().find("YAML"), std::string::npos);
  EXPECT_FALSE(parseScenarioYaml("- just\n- a list\n", "bad.yaml", &syntax));
  EXPECT_NE(syntax.toString().find("mapping"), std::string::npos);
}

TEST(ScenarioSpec, GivenSpecStringsThenKindsAndBenchParametersAreParsed) {
  std::string err;
  auto a = parseScenarioSpec("pedestrians", &err);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->kind, ScenarioSpec::Kind::kBuiltin);
  auto b = parseScenarioSpec("bench:80:3", &err);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->kind, ScenarioSpec::Kind::kBench);
  EXPECT_EQ(b->num_moving, 80);
  EXPECT_EQ(b->seed, 3u);
  auto c = parseScenarioSpec("my/world.yaml", &err);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->kind, ScenarioSpec::Kind::kFile);
  for (const char* bad : {"bench:", "bench:80", "bench:x:1", "bench:80:-1", "bench:5000:1", ""}) {
    err.clear();
    EXPECT_FALSE(parseScenarioSpec(bad, &err)) << bad;
    EXPECT_FALSE(err.empty()) << bad;
  }
}
