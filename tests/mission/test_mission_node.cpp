// MissionNode: goals sent in order and re-sent, run ends when reached or at the duration,
// tracked objects scored against ground truth (invisible objects ignored), summary; a loop
// goes back to the start after the last goal and ends at the duration.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/mission/mission_node.hpp"

using ucon::mission::MissionNode;
using ucon::mission::MissionParams;

namespace {
ucon::robot_pose_t pose(int64_t utime, double x, double y) {
  ucon::robot_pose_t p{};
  p.utime = utime;
  p.valid = true;
  p.x = x;
  p.y = y;
  p.vx = 1.0;
  return p;
}
ucon::sim_ground_truth_t gt(int64_t utime, double ox, double visible, int collisions = 0) {
  ucon::sim_ground_truth_t g{};
  g.utime = utime;
  g.num_collisions = collisions;
  g.min_clearance = 0.7;
  ucon::sim_object_t o{};
  o.id = 5;
  o.x = ox;
  o.visible = visible;
  g.objects = {o};
  g.num_objects = 1;
  return g;
}
ucon::tracked_objects_t objects(int64_t utime, int64_t id, double x) {
  ucon::tracked_objects_t m{};
  m.utime = utime;
  m.valid = true;
  ucon::tracked_object_t o{};
  o.id = id;
  o.state = ucon::tracked_object_t::STATE_CONFIRMED;
  o.x = x;
  m.objects = {o};
  m.num_objects = 1;
  return m;
}
}  // namespace

TEST(MissionNode, GivenTwoGoalsWhenTheRobotReachesThemThenGoalsAreSentInOrderAndTheRunEnds) {
  MissionParams p;
  p.settle_s = 0.5;
  MissionNode m(p, {{5.0, 0.0}, {5.0, 5.0}}, 0.0);
  auto g = m.onPose(pose(1000000, 0, 0));
  ASSERT_TRUE(g.has_value());
  EXPECT_EQ(g->goal_id, 1);
  EXPECT_DOUBLE_EQ(g->x, 5.0);
  EXPECT_FALSE(m.onPose(pose(1500000, 1, 0)).has_value()) << "no re-send before resend_period_s";
  g = m.onPose(pose(2100000, 2, 0));
  ASSERT_TRUE(g.has_value()) << "re-sent after a second";
  EXPECT_EQ(g->goal_id, 1);
  g = m.onPose(pose(2200000, 4.8, 0));
  ASSERT_TRUE(g.has_value());
  EXPECT_EQ(g->goal_id, 2) << "the next goal goes out as soon as the first is reached";
  EXPECT_FALSE(m.done());
  m.onPose(pose(3000000, 5.0, 4.9));
  EXPECT_FALSE(m.done()) << "settles before ending";
  m.onPose(pose(3600000, 5.0, 4.9));
  EXPECT_TRUE(m.done());
  EXPECT_EQ(m.endReason(), "all goals reached");
  const auto s = m.summary();
  EXPECT_EQ(s.goals_reached, 2);
  EXPECT_NEAR(s.time_to_goals_s, 2.0, 1e-9);
  EXPECT_TRUE(s.success());
}

TEST(MissionNode, GivenADurationThenTheRunEndsThereWithTheGoalUnreached) {
  MissionNode m(MissionParams{}, {{50.0, 0.0}}, 3.0);
  m.onPose(pose(1000000, 0, 0));
  m.onPose(pose(3000000, 1, 0));
  EXPECT_FALSE(m.done());
  m.onPose(pose(4000000, 2, 0));
  EXPECT_TRUE(m.done());
  EXPECT_EQ(m.endReason(), "duration reached");
  EXPECT_FALSE(m.summary().success());
}

TEST(MissionNode, GivenTrackedObjectsThenTheyAreScoredAgainstGroundTruthAndInvisibleOnesIgnored) {
  MissionNode m(MissionParams{}, {{50.0, 0.0}}, 0.0);
  m.onGroundTruth(gt(20000, 1.0, 1.0));
  m.onObjects(objects(20000, 7, 1.1));           // match
  m.onGroundTruth(gt(40000, 1.0, 1.0));
  m.onObjects(objects(40000, 8, 1.0));           // identity switch
  m.onGroundTruth(gt(60000, 1.0, 0.0));          // hidden: not scored
  m.onObjects(objects(60000, 8, 1.0));
  m.onObjects(objects(80000, 8, 1.0));           // arrives before its ground truth: waits
  m.onGroundTruth(gt(80000, 1.0, 1.0, 1));
  const auto s = m.summary();
  EXPECT_EQ(s.mot.num_objects, 3);
  EXPECT_EQ(s.mot.num_switches, 1);
  EXPECT_EQ(s.mot.num_misses, 0);
  EXPECT_NEAR(s.mot.mota, 1.0 - 1.0 / 3.0, 1e-12);
  EXPECT_EQ(s.collisions, 1);
  EXPECT_FALSE(s.success());
  const std::string json = MissionNode::toJson(s, "x");
  EXPECT_NE(json.find("\"idsw\": 1"), std::string::npos) << json;
  EXPECT_NE(json.find("\"collisions\": 1"), std::string::npos) << json;
}

TEST(MissionNode, GivenALoopWhenTheLastGoalIsReachedThenTheRobotGoesBackToTheStartAndAgain) {
  MissionParams p;
  MissionNode m(p, {{5.0, 0.0}, {5.0, 5.0}}, 100.0, /*loop=*/true);
  auto g = m.onPose(pose(1000000, 1, 2));  // first seen at (1, 2): each lap ends there
  ASSERT_TRUE(g.has_value());
  EXPECT_EQ(g->goal_id, 1);
  g = m.onPose(pose(2000000, 5, 0));
  ASSERT_TRUE(g.has_value());
  EXPECT_EQ(g->goal_id, 2);
  EXPECT_DOUBLE_EQ(g->y, 5.0);
  g = m.onPose(pose(3000000, 5, 5));
  ASSERT_TRUE(g.has_value()) << "after the last goal, back to the start";
  EXPECT_EQ(g->goal_id, 3);
  EXPECT_DOUBLE_EQ(g->x, 1.0);
  EXPECT_DOUBLE_EQ(g->y, 2.0);
  EXPECT_FALSE(m.done()) << "a loop does not end at its last goal";
  EXPECT_EQ(m.summary().laps, 0);
  EXPECT_FALSE(m.summary().success()) << "no lap completed yet";
  g = m.onPose(pose(4000000, 1, 2));
  ASSERT_TRUE(g.has_value()) << "the second lap starts with the first goal, as a new goal";
  EXPECT_EQ(g->goal_id, 4);
  EXPECT_DOUBLE_EQ(g->x, 5.0);
  EXPECT_DOUBLE_EQ(g->y, 0.0);
  auto s = m.summary();
  EXPECT_EQ(s.laps, 1);
  EXPECT_EQ(s.goals_reached, 3);
  EXPECT_EQ(s.goals_total, 4) << "driven so far and the one under way";
  EXPECT_NEAR(s.time_to_goals_s, 3.0, 1e-9) << "the first lap's goals";
  EXPECT_TRUE(s.success());
  m.onPose(pose(102000000, 3, 0));
  EXPECT_TRUE(m.done());
  EXPECT_EQ(m.endReason(), "duration reached");
  s = m.summary();
  EXPECT_TRUE(s.loop);
  EXPECT_TRUE(s.success()) << "a loop succeeds with a lap and no collision";
  EXPECT_NE(MissionNode::toJson(s, m.endReason()).find("\"laps\": 1"), std::string::npos);
  EXPECT_NE(MissionNode::format(s, m.endReason()).find("1 lap(s) (loop)"), std::string::npos);
  m.onGroundTruth(gt(102000000, 9.0, 1.0, /*collisions=*/1));
  EXPECT_FALSE(m.summary().success()) << "a collision fails a loop";
}
