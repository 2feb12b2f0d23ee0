// Ray casting, disk contact and surface distance: hand-computed cases, and the grid
// traversal against an independent brute-force reference (sphere tracing over the exact
// distance function of every obstacle).
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/world/bench_generator.hpp"
#include "ucon/world/rng.hpp"
#include "ucon/world/world.hpp"

using namespace ucon::world;

namespace {

Scenario emptyWorld() {
  Scenario s;
  s.name = "geom";
  s.bounds = Bounds{-20, 20, -20, 20};
  return s;
}

StaticObstacle cylinder(double x, double y, double r, double h) {
  StaticObstacle o;
  o.kind = ShapeKind::kCylinder;
  o.center = Vec2(x, y);
  o.radius = r;
  o.height = h;
  return o;
}

StaticObstacle box(double x, double y, double sx, double sy, double yaw, double h) {
  StaticObstacle o;
  o.kind = ShapeKind::kBox;
  o.center = Vec2(x, y);
  o.half_size = Vec2(sx / 2, sy / 2);
  o.yaw = yaw;
  o.height = h;
  return o;
}

// Brute-force reference: march along the ray by the exact distance to the nearest surface
// (cap larger than the world: every obstacle is examined). Returns the range of the first
// point closer than eps, or inf.
double sphereTrace(const World& w, const Vec3& o, const Vec3& d, double max_range) {
  double t = 0;
  for (int k = 0; k < 100000 && t < max_range; ++k) {
    // A capped distance is a lower bound of the true one, so the march never overshoots.
    const double dist = w.surfaceDistance(o + t * d, 3.0);
    if (dist < 1e-7) return t;
    t += dist;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

TEST(RayCast, GivenAHorizontalRayThenItHitsTheCylinderSideAtTheClosedFormRange) {
  Scenario s = emptyWorld();
  s.statics.push_back(cylinder(5, 0, 1, 2));
  World w(s);
  const auto h = w.castRay(Vec3(0, 0, 1), Vec3(1, 0, 0), 40);
  ASSERT_EQ(h.kind, HitKind::kStatic);
  EXPECT_NEAR(h.range, 4.0, 1e-12);
  EXPECT_NEAR(h.normal.x(), -1.0, 1e-12);
  // Off-centre by 0.6: chord entry at 5 - sqrt(1 - 0.36) = 4.2.
  const auto h2 = w.castRay(Vec3(0, 0.6, 1), Vec3(1, 0, 0), 40);
  EXPECT_NEAR(h2.range, 4.2, 1e-12);
  // Above it: nothing (no ground in a horizontal ray).
  EXPECT_EQ(w.castRay(Vec3(0, 0, 2.5), Vec3(1, 0, 0), 40).kind, HitKind::kNone);
  // Out of range.
  EXPECT_EQ(w.castRay(Vec3(0, 0, 1), Vec3(1, 0, 0), 3.9).kind, HitKind::kNone);
}

TEST(RayCast, GivenADownwardRayThenItHitsTheGroundOrTheTopFace) {
  Scenario s = emptyWorld();
  s.statics.push_back(box(3, 0, 2, 2, 0.0, 1.0));
  World w(s);
  // 45 deg down. From (-5, 0, 2) the ground is reached at x = -3, before the box (x in [2, 4]).
  // From (1.5, 0, 2) the ray passes over the box's side (z = 1.5 at x = 2) and meets the top
  // face z = 1 at x = 2.5.
  const Vec3 d = Vec3(1, 0, -1).normalized();
  const auto g = w.castRay(Vec3(-5, 0, 2), d, 40);  // ground at x = -3
  ASSERT_EQ(g.kind, HitKind::kGround);
  EXPECT_NEAR(g.range, 2.0 * std::sqrt(2.0), 1e-12);
  const auto top = w.castRay(Vec3(1.5, 0, 2.0), d, 40);  // z = 1 at x = 2.5: on the top face
  ASSERT_EQ(top.kind, HitKind::kStatic);
  EXPECT_NEAR(top.range, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(top.normal.z(), 1.0, 1e-12);
}

TEST(RayCast, GivenARotatedBoxThenTheHitIsOnItsSurface) {
  Scenario s = emptyWorld();
  s.statics.push_back(box(4, 1, 2, 1, 0.7, 1.5));
  World w(s);
  const Vec3 o(0, 1, 0.5);
  const auto h = w.castRay(o, Vec3(1, 0, 0), 40);
  ASSERT_EQ(h.kind, HitKind::kStatic);
  const Vec3 p = o + h.range * Vec3(1, 0, 0);
  EXPECT_NEAR(w.staticFootprintDistance(0, Vec2(p.x(), p.y())), 0.0, 1e-9);
  EXPECT_NEAR(w.surfaceDistance(p, 5.0), 0.0, 1e-9);
}

TEST(RayCast, GivenAMovingObstacleThenTheRayHitsItWhereItIsAtTheSetTime) {
  Scenario s = emptyWorld();
  MovingObstacle m;
  m.id = 4;
  m.radius = 0.5;
  m.height = 1.7;
  m.motion.kind = MotionKind::kConstantVelocity;
  m.motion.position = Vec2(6, -3);
  m.motion.velocity = Vec2(0, 1);
  s.movers.push_back(m);
  World w(s);
  EXPECT_EQ(w.castRay(Vec3(0, 0, 1), Vec3(1, 0, 0), 40).kind, HitKind::kNone);
  w.setTime(3.0);  // now at (6, 0)
  const auto h = w.castRay(Vec3(0, 0, 1), Vec3(1, 0, 0), 40);
  ASSERT_EQ(h.kind, HitKind::kMoving);
  EXPECT_EQ(h.index, 0);
  EXPECT_NEAR(h.range, 5.5, 1e-12);
}

TEST(RayCast, GivenTheBenchWorldThenGridTraversalAgreesWithBruteForceOnRandomRays) {
  World w(generateBench(140, 3));  // 160 static + 140 moving = 300 obstacles
  w.setTime(12.5);
  Rng rng(1234);
  int hits = 0, grounds = 0;
  for (int k = 0; k < 1500; ++k) {
    const Vec3 o(rng.uniform(-24, 24), rng.uniform(-24, 24), rng.uniform(0.1, 1.5));
    if (w.diskContact(Vec2(o.x(), o.y()), 0.05).collision()) continue;  // origin inside/on one
    const double az = rng.uniform(-M_PI, M_PI), el = rng.uniform(-0.9, 0.9);
    const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const auto h = w.castRay(o, d, 40.0);
    const double ref = sphereTrace(w, o, d, 40.0);
    if (std::isinf(ref)) {
      EXPECT_EQ(h.kind, HitKind::kNone) << k;
      continue;
    }
    ASSERT_NE(h.kind, HitKind::kNone) << k;
    EXPECT_NEAR(h.range, ref, 1e-5) << k;
    if (h.kind == HitKind::kGround) ++grounds;
    else ++hits;
  }
  EXPECT_GT(hits, 200);
  EXPECT_GT(grounds, 100);
}

TEST(Contact, GivenADiskThenClearanceIsTheSurfaceGapAndCollisionIsItsSign) {
  Scenario s = emptyWorld();
  s.statics.push_back(cylinder(0, 0, 1, 2));
  s.statics.push_back(box(10, 0, 2, 2, M_PI / 4, 2));
  MovingObstacle m;
  m.id = 1;
  m.radius = 0.5;
  m.motion.position = Vec2(0, 10);
  s.movers.push_back(m);
  World w(s);
  auto c = w.diskContact(Vec2(2, 0), 0.3);
  EXPECT_NEAR(c.clearance, 0.7, 1e-12);
  EXPECT_EQ(c.kind, HitKind::kStatic);
  EXPECT_FALSE(c.collision());
  // Rotated box: its corner points along -x at 10 - sqrt(2).
  c = w.diskContact(Vec2(7, 0), 0.3);
  EXPECT_NEAR(c.clearance, 3 - std::sqrt(2.0) - 0.3, 1e-12);
  c = w.diskContact(Vec2(0, 9.3), 0.3);
  EXPECT_EQ(c.kind, HitKind::kMoving);
  EXPECT_NEAR(c.clearance, -0.1, 1e-12);
  EXPECT_TRUE(c.collision());
  // The static obstacles alone: beside the mover, the nearest is the cylinder 8 m away.
  c = w.staticContact(Vec2(0, 9.3), 0.3);
  EXPECT_EQ(c.kind, HitKind::kStatic);
  EXPECT_EQ(c.index, 0);
  EXPECT_NEAR(c.clearance, 9.3 - 1.0 - 0.3, 1e-12);
  EXPECT_TRUE(std::isnan(w.staticContact(Vec2(std::nan(""), 0), 0.3).clearance));
  EXPECT_EQ(World(emptyWorld()).staticContact(Vec2(0, 0), 0.3).kind, HitKind::kNone);
}

TEST(SurfaceDistance, GivenPointsAroundAPrismThenDistancesAreExact) {
  Scenario s = emptyWorld();
  s.statics.push_back(cylinder(0, 0, 1, 2));
  World w(s);
  EXPECT_NEAR(w.surfaceDistance(Vec3(3, 0, 1.5), 10), 1.5, 1e-12);   // ground 1.5, side 2
  EXPECT_NEAR(w.surfaceDistance(Vec3(1.5, 0, 1.0), 10), 0.5, 1e-12);  // side
  EXPECT_NEAR(w.surfaceDistance(Vec3(0, 0, 2.25), 10), 0.25, 1e-12);  // top
  EXPECT_NEAR(w.surfaceDistance(Vec3(4, 0, 5), 10), std::hypot(3.0, 3.0), 1e-12);  // top edge
  EXPECT_NEAR(w.surfaceDistance(Vec3(4, 0, 6), 10), 5.0, 1e-12);
  EXPECT_NEAR(w.surfaceDistance(Vec3(0.9, 0, 1.0), 10), 0.1, 1e-12);  // inside: nearest side
  EXPECT_NEAR(w.surfaceDistance(Vec3(15, 0, 9), 2), 2.0, 1e-12);      // capped
}

TEST(Geometry, GivenNonFiniteQueriesThenResultsSayNothingAndNothingCrashes) {
  World w(generateBench(20, 1));
  const double nan = std::nan("");
  EXPECT_EQ(w.castRay(Vec3(nan, 0, 1), Vec3(1, 0, 0), 40).kind, HitKind::kNone);
  EXPECT_EQ(w.castRay(Vec3(0, 0, 1), Vec3(nan, 0, 0), 40).kind, HitKind::kNone);
  EXPECT_TRUE(std::isnan(w.surfaceDistance(Vec3(nan, 1, 1), 1.0)));
  const Contact c = w.diskContact(Vec2(1, nan), 0.3);
  EXPECT_TRUE(std::isnan(c.clearance));
  EXPECT_FALSE(c.collision());
  EXPECT_EQ(c.kind, HitKind::kNone);
  // Far outside the grid: still well defined.
  EXPECT_NEAR(w.surfaceDistance(Vec3(1e6, 1e6, 0.5), 2.0), 0.5, 1e-12);
}

TEST(Geometry, GivenAHugeWorldThenTheGridStaysBoundedAndQueriesStillWork) {
  Scenario s = emptyWorld();
  s.bounds = Bounds{-5e4, 5e4, -5e4, 5e4};  // 100 km square: 1e10 one-metre cells if unbounded
  s.statics.push_back(cylinder(100, 0, 1, 2));
  World w(s);
  const auto h = w.castRay(Vec3(0, 0, 1), Vec3(1, 0, 0), 500);
  ASSERT_EQ(h.kind, HitKind::kStatic);
  EXPECT_NEAR(h.range, 99.0, 1e-9);
}
