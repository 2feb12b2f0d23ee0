// The front end: A* guide path around obstacles, to the window edge, and the clear statuses
// for goals in collision or unreachable; the initial MINCO guess from a guide path.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "ucon/planner/esdf_map.hpp"
#include "ucon/planner/guide_path.hpp"

using namespace ucon::planner;

namespace {

MapParams params() {
  MapParams p;
  p.resolution = 0.1;
  p.band_z_min = 0.1;
  p.band_z_max = 0.3;
  p.box_half_size = 8.0;
  p.recenter_distance = 1.0;
  p.max_distance = 2.0;
  return p;
}

FrontEndParams frontEnd() {
  FrontEndParams f;
  f.inflation = 0.35;
  f.window_radius = 6.0;
  return f;
}

double pathClearance(const EsdfMap& m, const GuidePath& g) {
  double worst = 1e9;
  for (std::size_t i = 1; i < g.points.size(); ++i) {
    const auto a = g.points[i - 1], b = g.points[i];
    const int n = int(std::ceil((b - a).norm() / 0.02)) + 1;
    for (int k = 0; k <= n; ++k) {
      const Eigen::Vector2d p = a + (b - a) * (double(k) / n);
      worst = std::min(worst, m.distance(p.x(), p.y(), nullptr));
    }
  }
  return worst;
}

}  // namespace

TEST(GuidePath, GivenAWallWithAGapWhenSearchingThenThePathGoesThroughTheGapWithClearance) {
  EsdfMap map(params());
  map.addBox(1.0, -6.0, 1.3, -0.6);  // wall at x = 1..1.3 with a gap at y in (-0.6, 2.0)
  map.addBox(1.0, 2.0, 1.3, 6.0);
  map.addBox(1.0, -0.6, 1.3, -0.5);
  map.update(Eigen::Vector2d(0, 0));
  const Eigen::Vector2d start(-2.0, -3.0), goal(3.0, -3.0);
  const GuidePath g = findGuidePath(map, start, goal, frontEnd());
  ASSERT_EQ(g.status, GuideStatus::kOk);
  EXPECT_TRUE(g.reaches_goal);
  EXPECT_EQ(g.points.front(), start);
  EXPECT_EQ(g.points.back(), goal);
  EXPECT_GE(pathClearance(map, g), 0.35 - 0.005);
  // The straight line is blocked, so the path must bend up into the gap.
  double max_y = -1e9;
  for (const auto& p : g.points) max_y = std::max(max_y, p.y());
  EXPECT_GT(max_y, -0.5 + 0.35 - 0.05);
  EXPECT_LT(g.points.size(), 8u);  // shortcut, not a cell staircase
}

TEST(GuidePath, GivenAFarGoalWhenSearchingThenThePathEndsAtTheWindowEdgeTowardTheGoal) {
  EsdfMap map(params());
  map.update(Eigen::Vector2d(0, 0));
  const GuidePath g = findGuidePath(map, Eigen::Vector2d(0, 0), Eigen::Vector2d(30, 0), frontEnd());
  ASSERT_EQ(g.status, GuideStatus::kOk);
  EXPECT_FALSE(g.reaches_goal);
  EXPECT_NEAR(g.points.back().norm(), 6.0, 0.15);
  EXPECT_NEAR(g.points.back().y(), 0.0, 0.15);
}

TEST(GuidePath, GivenAGoalInsideAnObstacleThenStatusSaysSoAndThePathEndsAtANearbySafePoint) {
  EsdfMap map(params());
  map.addCylinder(3.0, 0.0, 0.8);
  map.update(Eigen::Vector2d(0, 0));
  const GuidePath g = findGuidePath(map, Eigen::Vector2d(0, 0), Eigen::Vector2d(3.0, 0.0), frontEnd());
  EXPECT_EQ(g.status, GuideStatus::kGoalInCollision);
  EXPECT_FALSE(g.reaches_goal);
  const Eigen::Vector2d end = g.points.back();
  // Safe = at least the hard clearance (0.3 m); nearest = within a cell or two of that.
  EXPECT_GE(map.distance(end.x(), end.y(), nullptr), 0.3 - 1e-6);
  EXPECT_LT((end - Eigen::Vector2d(3.0, 0.0)).norm(), 0.8 + 0.3 + 0.2);
  EXPECT_GE(pathClearance(map, g), 0.3 - 0.005);
}

TEST(GuidePath, GivenAGoalEnclosedByARingThenStatusIsUnreachableAndThePathStaysOutside) {
  EsdfMap map(params());
  for (int k = 0; k < 72; ++k) {  // ring of radius 1.5 around (3, 0)
    const double a = k * 2 * M_PI / 72;
    map.addCylinder(3.0 + 1.5 * std::cos(a), 1.5 * std::sin(a), 0.15);
  }
  map.update(Eigen::Vector2d(0, 0));
  const GuidePath g = findGuidePath(map, Eigen::Vector2d(0, 0), Eigen::Vector2d(3.0, 0.0), frontEnd());
  EXPECT_EQ(g.status, GuideStatus::kGoalUnreachable);
  EXPECT_GT((g.points.back() - Eigen::Vector2d(3.0, 0.0)).norm(), 1.5);
  EXPECT_GE(pathClearance(map, g), 0.35 - 0.005);
}

TEST(GuidePath, GivenNoMapOrNaNThenClearStatuses) {
  EsdfMap map(params());
  EXPECT_EQ(findGuidePath(map, Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), frontEnd()).status,
            GuideStatus::kNoMap);
  map.update(Eigen::Vector2d(0, 0));
  EXPECT_EQ(findGuidePath(map, Eigen::Vector2d(0, 0), Eigen::Vector2d(NAN, 0), frontEnd()).status,
            GuideStatus::kBadInput);
  EXPECT_EQ(findGuidePath(map, Eigen::Vector2d(50, 0), Eigen::Vector2d(1, 0), frontEnd()).status,
            GuideStatus::kStartOutsideMap);
}

TEST(GuidePath, GivenAStartInsideTheInflationThenThePathLeavesIt) {
  EsdfMap map(params());
  map.addCylinder(0.0, 0.5, 0.3);
  map.update(Eigen::Vector2d(0, 0));
  // Start 0.1 m from the obstacle surface, goal below.
  const GuidePath g = findGuidePath(map, Eigen::Vector2d(0.0, 0.1), Eigen::Vector2d(0.0, -3.0), frontEnd());
  EXPECT_EQ(g.status, GuideStatus::kOk);
  EXPECT_TRUE(g.reaches_goal);
}

TEST(GuidePath, GivenAPolylineWhenMakingTheInitialGuessThenWaypointsLieOnItAndDurationsFitTheLimits) {
  FrontEndParams f = frontEnd();
  f.piece_length = 1.0;
  f.max_pieces = 8;
  const std::vector<Eigen::Vector2d> path{{0, 0}, {3, 0}, {3, 4}};
  const InitialGuess g = makeInitialGuess(path, 5.0, 0.0, 1.5, 2.0, f);
  EXPECT_NEAR(g.length, 5.0, 1e-9);
  EXPECT_NEAR(g.end.x(), 3.0, 1e-9);
  EXPECT_NEAR(g.end.y(), 2.0, 1e-9);
  ASSERT_EQ(g.durations.size(), 5u);
  ASSERT_EQ(g.waypoints.size(), 4u);
  EXPECT_NEAR(g.waypoints[2].x(), 3.0, 1e-9);  // arc length 3 = the corner
  EXPECT_NEAR(g.waypoints[2].y(), 0.0, 1e-9);
  const double total = std::accumulate(g.durations.begin(), g.durations.end(), 0.0);
  // Rest to rest over 5 m at 1.5 m/s and 2 m/s^2: 5/1.5 + 1.5/2 = 4.08 s.
  EXPECT_NEAR(total, 5.0 / 1.5 + 1.5 / 2.0, 0.1);
  EXPECT_GT(g.durations.front(), g.durations[2]);  // accelerating piece is slower
}

TEST(GuidePath, GivenAGapNarrowerThanTheInflationButWiderThanTheHardClearanceThenThePathUsesIt) {
  EsdfMap map(params());
  // Two walls leave a 0.8 m gap at y in (-0.4, 0.4): every point of it is closer than the
  // 0.45 m inflation to a wall, but the centre keeps the 0.3 m hard clearance.
  map.addBox(1.0, -9.0, 1.3, -0.4);  // to beyond the ESDF box: no way around
  map.addBox(1.0, 0.4, 1.3, 9.0);
  map.update(Eigen::Vector2d(0, 0));
  FrontEndParams f = frontEnd();
  f.inflation = 0.45;
  f.hard_clearance = 0.3;
  const GuidePath g = findGuidePath(map, Eigen::Vector2d(-2.0, 0.0), Eigen::Vector2d(3.0, 0.0), f);
  ASSERT_EQ(g.status, GuideStatus::kOk);
  EXPECT_TRUE(g.reaches_goal);
  EXPECT_GE(pathClearance(map, g), 0.3 - 0.005);
  // With a hard clearance above half the gap it is closed.
  f.hard_clearance = 0.45;
  const GuidePath closed = findGuidePath(map, Eigen::Vector2d(-2.0, 0.0), Eigen::Vector2d(3.0, 0.0), f);
  EXPECT_EQ(closed.status, GuideStatus::kGoalUnreachable);
}
