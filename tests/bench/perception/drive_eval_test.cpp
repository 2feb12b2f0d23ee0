// Tests of the --drive perception benchmark's parts (drive_eval.hpp): the per-point pose, the
// visibility test, visibility-aware scoring, the per-method replay and determinism.
#include "drive_eval.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/simulator/scenario_loader.hpp"

namespace {

using ucon::bench::PoseTrack;

constexpr double kPi = 3.14159265358979323846;

ucon::robot_pose_t pose(int64_t utime, double x, double y, double yaw, double vx = 0, double vy = 0, double wz = 0) {
  ucon::robot_pose_t p{};
  p.utime = utime;
  p.valid = true;
  p.x = x, p.y = y, p.yaw = yaw;
  p.qw = std::cos(yaw / 2), p.qz = std::sin(yaw / 2);
  p.vx = vx, p.vy = vy, p.wz = wz;
  p.cov_size = 0;
  return p;
}

ucon::sim_object_t mover(int64_t id, double x, double y, double vx = 0, double vy = 0) {
  ucon::sim_object_t o{};
  o.id = id;
  o.x = x, o.y = y, o.vx = vx, o.vy = vy;
  o.radius = 0.25;
  o.height = 1.75;
  o.visible = NAN;
  return o;
}

ucon::sim_ground_truth_t groundTruth(int64_t utime, std::vector<ucon::sim_object_t> objects, double rx = 0,
                                     double ry = 0) {
  ucon::sim_ground_truth_t g{};
  g.utime = utime;
  g.scenario = "test";
  g.robot_x = rx, g.robot_y = ry;
  g.robot_radius = 0.3;
  g.objects = std::move(objects);
  g.num_objects = static_cast<int32_t>(g.objects.size());
  return g;
}

struct P {
  float x, y, z;
  int32_t t_ns = 0;
};

/// A 6 m wall 6 m behind a parked robot at the origin: structure in every frame, so the node
/// has a scene to segment.
std::vector<P> wallBehind() {
  std::vector<P> wall;
  for (int i = 0; i < 60; ++i)
    for (int k = 0; k < 5; ++k) wall.push_back({-6.0f, -3.0f + 0.1f * i, 0.3f + 0.3f * k});
  return wall;
}

ucon::point_cloud_t cloud(int64_t utime, int64_t seq, const std::vector<P>& pts) {
  ucon::point_cloud_t c{};
  c.utime = utime;
  c.seq = seq;
  c.frame_id = "base";
  c.duration_us = 20000;
  for (const auto& p : pts) {
    c.x.push_back(p.x), c.y.push_back(p.y), c.z.push_back(p.z);
    c.t_offset_ns.push_back(p.t_ns);
    c.reflectivity.push_back(100);
    c.tag.push_back(0);
  }
  c.num_points = static_cast<int32_t>(pts.size());
  c.num_sensors = 0;
  c.num_point_sensors = 0;
  return c;
}

template <class M>
ucon::bench::RecordedEvent event(const std::string& channel, const M& m) {
  ucon::bench::RecordedEvent e;
  e.channel = channel;
  e.data.resize(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(e.data.data(), 0, static_cast<int>(e.data.size()));
  return e;
}

std::string source(const std::string& rel) { return std::string(UCON_SOURCE_DIR) + "/" + rel; }

template <class T>
T config(const std::string& name) {
  auto p = ucon::runtime::loadConfigFile<T>("test", source("deploy/config/" + name));
  EXPECT_TRUE(p.has_value()) << name;
  return p ? *p : T{};
}

ucon::bench::DriveConfig driveConfig(double duration_s) {
  ucon::bench::DriveConfig c;
  c.sim = config<ucon::simulator::SimulatorParams>("simulator.yaml");
  c.driver = config<ucon::lidar_driver::DriverParams>("lidar_driver.yaml");
  c.perception = config<ucon::perception::PerceptionParams>("perception.yaml");
  c.planner_yaml = *ucon::runtime::readTextFile(source("deploy/config/planner.yaml"), nullptr);
  c.base_controller_yaml = *ucon::runtime::readTextFile(source("deploy/config/base_controller.yaml"), nullptr);
  c.duration_s = duration_s;
  return c;
}

ucon::bench::Recording recordPedestrians(double duration_s, int64_t seed) {
  std::string err;
  auto sc = ucon::simulator::loadScenario("pedestrians", source("deploy/scenarios"), seed,
                                          ucon::runtime::readTextFile, &err);
  EXPECT_TRUE(sc.has_value()) << err;
  auto rec = ucon::bench::recordDrive(driveConfig(duration_s), *sc, "pedestrians", seed, &err);
  EXPECT_TRUE(rec.has_value()) << err;
  return rec ? *rec : ucon::bench::Recording{};
}

TEST(DrivePoseTrack, GivenTwoPosesAcrossPiWhenInterpolatedThenYawTakesTheShortArc) {
  PoseTrack t;
  ASSERT_TRUE(t.add(pose(1'000'000, 0.0, 0.0, kPi - 0.1)));
  ASSERT_TRUE(t.add(pose(1'100'000, 1.0, 2.0, -kPi + 0.1)));
  const auto q = t.at(1'050'000);
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(q->x, 0.5, 1e-12);
  EXPECT_NEAR(q->y, 1.0, 1e-12);
  EXPECT_NEAR(std::abs(q->yaw), kPi, 1e-9);  // through pi, not through 0
  EXPECT_FALSE(t.add(pose(1'100'000, 9.0, 9.0, 0.0)));  // not newer
}

TEST(DrivePoseTrack, GivenAPointAfterTheLastPoseWhenAskedThenExtrapolatesWithTheVelocity) {
  PoseTrack t;
  ASSERT_TRUE(t.add(pose(2'000'000, 1.0, 1.0, 0.0, 2.0, -1.0, 0.5)));
  const auto q = t.at(2'100'000);
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(q->x, 1.2, 1e-12);
  EXPECT_NEAR(q->y, 0.9, 1e-12);
  EXPECT_NEAR(q->yaw, 0.05, 1e-12);
  EXPECT_FALSE(PoseTrack().at(0).has_value());
}

TEST(DriveVisibility, GivenATurnedRobotWhenPointsHitAMoverThenOnlyThoseOnItsBodyCount) {
  // Robot at (1, 2) facing +y: body x is world +y. Mover 7 at world (1, 5) = body (3, 0).
  PoseTrack t;
  ASSERT_TRUE(t.add(pose(1'000'000, 1.0, 2.0, kPi / 2)));
  const auto gt = groundTruth(1'000'000, {mover(7, 1.0, 5.0), mover(8, 10.0, 10.0)});
  const auto c = cloud(1'000'000, 1,
                       {{2.8f, 0.0f, 1.0f},     // on 7's near face
                        {2.9f, 0.1f, 0.5f},     // on 7
                        {2.8f, -0.1f, 1.85f},   // just within height + margin
                        {3.0f, 0.0f, 2.1f},     // above 7's head
                        {3.0f, 0.0f, 0.05f},    // ground
                        {0.0f, 3.0f, 1.0f}});   // world (-2, 2): nothing
  const auto hits = ucon::bench::returnsOnMovers(c, t, gt);
  ASSERT_EQ(hits.count(7), 1u);
  EXPECT_EQ(hits.at(7), 3);
  EXPECT_EQ(hits.count(8), 0u);
}

TEST(DriveVisibility, GivenADrivingRobotWhenAPointIsLateInTheFrameThenItIsPlacedAtItsOwnTime) {
  // The robot drives +x at 2 m/s; a point 3.2 m ahead, 50 ms into the frame, lies at world 3.3:
  // 0.35 m from a mover's axis at 3.65 (radius 0.25 + margin 0.15 = 0.4: on it). Placed with
  // the pose of the frame's start it would lie at 3.2, 0.45 m off: not on it.
  PoseTrack t;
  ASSERT_TRUE(t.add(pose(1'000'000, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0)));
  const auto gt = groundTruth(1'000'000, {mover(1, 3.65, 0.0)});
  auto c = cloud(1'000'000, 1, {{3.2f, 0.0f, 1.0f, 50'000'000}});
  EXPECT_EQ(ucon::bench::returnsOnMovers(c, t, gt).count(1), 1u);  // 3.3 vs 3.65: 0.35 <= 0.4
  c.t_offset_ns[0] = 0;
  EXPECT_EQ(ucon::bench::returnsOnMovers(c, t, gt).count(1), 0u);  // 3.2 vs 3.65: 0.45 > 0.4
}

TEST(DriveScoring, GivenAMoverTheSensorNeverSeesWhenScoredThenItIsAMissOnlyWithoutVisibility) {
  // Ten frames of a parked robot: a wall of returns at x = -6, a mover at (5, 0) with no return
  // on it (hidden). Perception cannot see it: the plain score counts a miss per frame, the
  // visibility-aware one does not score it at all.
  ucon::bench::Recording rec;
  const std::vector<P> wall = wallBehind();
  for (int f = 0; f < 10; ++f) {
    const int64_t t = 1'000'000 + f * 20'000;
    rec.events.push_back(event(ucon::channels::kRobotPose, pose(t, 0, 0, 0)));
    rec.events.push_back(event(ucon::channels::kSimGroundTruth, groundTruth(t, {mover(3, 5.0, 0.0)})));
    rec.events.push_back(event(ucon::channels::kLidarPoints, cloud(t, f, wall)));
  }
  const auto shipped = config<ucon::perception::PerceptionParams>("perception.yaml");
  ucon::bench::ScoreOptions opt;
  const auto s = ucon::bench::scoreRecording(rec, {"ucon"}, {shipped}, opt);
  ASSERT_EQ(s.size(), 1u);
  // One PERCEPTION_OBJECTS per frame, and the node's invalid one after the first pose (no
  // frame yet), which comes before any ground truth and is not scored.
  EXPECT_GE(s[0].frames, 10);
  EXPECT_LE(s[0].frames, 11);
  EXPECT_EQ(s[0].all.num_objects, 10);
  EXPECT_EQ(s[0].all.num_misses, 10);
  EXPECT_EQ(s[0].visible.num_objects, 0);
  EXPECT_EQ(s[0].visible.num_misses, 0);
  EXPECT_EQ(s[0].visible.num_ignored, 10);
  EXPECT_EQ(s[0].sensor.objects, 10);  // never seen: no tracker could have held it
  EXPECT_EQ(s[0].sensor.visible, 0);
  EXPECT_EQ(s[0].sensor.seen, 0);
  EXPECT_EQ(s[0].sensor.held, 0);

  // The same mover with returns on its body: now it is scored in both.
  ucon::bench::Recording seen;
  for (int f = 0; f < 10; ++f) {
    const int64_t t = 1'000'000 + f * 20'000;
    auto pts = wall;
    for (int k = 0; k < 6; ++k) pts.push_back({4.78f, -0.1f + 0.04f * k, 0.4f + 0.2f * k});
    seen.events.push_back(event(ucon::channels::kRobotPose, pose(t, 0, 0, 0)));
    seen.events.push_back(event(ucon::channels::kSimGroundTruth, groundTruth(t, {mover(3, 5.0, 0.0)})));
    seen.events.push_back(event(ucon::channels::kLidarPoints, cloud(t, f, pts)));
  }
  const auto v = ucon::bench::scoreRecording(seen, {"ucon"}, {shipped}, opt);
  EXPECT_EQ(v[0].all.num_objects, 10);
  EXPECT_EQ(v[0].visible.num_objects, 10);
  EXPECT_EQ(v[0].visible.num_ignored, 0);
  // Its cluster is object-sized but the node has no motion reference in its first 0.2 s: each
  // miss is the motion test's, in the nearest range band.
  EXPECT_EQ(v[0].visible.num_misses, 10);
  EXPECT_EQ(v[0].miss_causes[ucon::bench::kMissMotionOther][0], 10);
  EXPECT_EQ(v[0].sensor.visible, 10);
  // 6 returns a frame, counted over the frames the node merges for one output.
  const int merged = shipped.preprocess.accumulate_frames;
  int64_t well = 0;
  for (int f = 0; f < 10; ++f) well += 6 * std::min(f + 1, merged) >= ucon::bench::kWellSeenPoints;
  EXPECT_EQ(v[0].sensor.well_seen, well);
}

// --trace with --drive: each visible miss is a line led by the label and the method, with the
// mover, its range and the cause the summary counts; nothing is written without a trace file.
TEST(DriveScoring, GivenATraceFileWhenScoredThenEachVisibleMissIsALineWithItsCause) {
  ucon::bench::Recording rec;
  for (int f = 0; f < 10; ++f) {
    const int64_t t = 1'000'000 + f * 20'000;
    std::vector<P> pts;
    for (int k = 0; k < 6; ++k) pts.push_back({4.78f, -0.1f + 0.04f * k, 0.4f + 0.2f * k});
    rec.events.push_back(event(ucon::channels::kRobotPose, pose(t, 0, 0, 0)));
    rec.events.push_back(event(ucon::channels::kSimGroundTruth, groundTruth(t, {mover(3, 5.0, 0.0)})));
    rec.events.push_back(event(ucon::channels::kLidarPoints, cloud(t, f, pts)));
  }
  const auto shipped = config<ucon::perception::PerceptionParams>("perception.yaml");
  ucon::bench::ScoreOptions opt;
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::tmpfile(), &std::fclose);
  ASSERT_TRUE(file);
  opt.trace = file.get();
  opt.trace_label = "scene:7";
  const auto s = ucon::bench::scoreRecording(rec, {"ucon"}, {shipped}, opt);
  ASSERT_EQ(s[0].visible.num_misses, 10);
  std::rewind(file.get());
  std::vector<std::string> lines;
  char buf[512];
  while (std::fgets(buf, sizeof(buf), file.get())) lines.emplace_back(buf);
  ASSERT_EQ(lines.size(), 10u);
  for (const auto& l : lines) {
    EXPECT_EQ(l.rfind("scene:7 ucon fn ", 0), 0u) << l;
    EXPECT_NE(l.find(" gt 3 at 5.00 0.00 range 5.00 motion_other"), std::string::npos) << l;
  }
}

TEST(DriveScoring, GivenAMoverSeenAndThenHiddenThenTheSensorSharesCountWhatATrackerCouldHold) {
  // 100 frames of a parked robot: a mover at (5, 0) with 12 returns on it in frames 0-4, none
  // afterwards. Every later object-frame was seen before; those within the method's coast time
  // after frame 4 could still be held; well seen only in frames 0-4.
  const auto shipped = config<ucon::perception::PerceptionParams>("perception.yaml");
  ucon::bench::Recording rec;
  const std::vector<P> wall = wallBehind();
  const int64_t t0 = 1'000'000, dt = 20'000;
  for (int f = 0; f < 100; ++f) {
    const int64_t t = t0 + f * dt;
    auto pts = wall;
    if (f < 5)
      for (int k = 0; k < 12; ++k) pts.push_back({4.78f, -0.15f + 0.025f * k, 0.3f + 0.1f * k});
    rec.events.push_back(event(ucon::channels::kRobotPose, pose(t, 0, 0, 0)));
    rec.events.push_back(event(ucon::channels::kSimGroundTruth, groundTruth(t, {mover(3, 5.0, 0.0)})));
    rec.events.push_back(event(ucon::channels::kLidarPoints, cloud(t, f, pts)));
  }
  const auto s = ucon::bench::scoreRecording(rec, {"ucon"}, {shipped}, ucon::bench::ScoreOptions{});
  ASSERT_EQ(s.size(), 1u);
  const auto& sh = s[0].sensor;
  EXPECT_EQ(sh.objects, s[0].all.num_objects);
  EXPECT_EQ(sh.objects, 100);
  // An output merges the node's last `merged` frames: frame 4's returns are still in frame
  // 4 + merged - 1's output.
  const int merged = shipped.preprocess.accumulate_frames;
  ASSERT_GE(merged, 1);
  EXPECT_EQ(sh.visible, s[0].visible.num_objects);
  EXPECT_EQ(sh.visible, 5 + merged - 1);
  EXPECT_EQ(sh.well_seen, 5 + merged - 1);
  EXPECT_EQ(sh.seen, 100);
  const int64_t coast_frames = static_cast<int64_t>(std::floor(1e6 * shipped.tracks.max_coast / dt + 1e-9));
  ASSERT_LT(5 + merged - 1 + coast_frames, 100);  // the hidden stretch outlasts the coast time
  EXPECT_EQ(sh.held, 5 + merged - 1 + coast_frames);
  EXPECT_EQ(sh.predictable, 100);  // it never moved: held in place, it is where it was
}

TEST(DriveScoring, GivenAHiddenMoverThatTurnsBackThenPredictableEndsWhereNeitherItsLastVelocityNorRestPutsIt) {
  // A mover at x = 5 walks +y at 1 m/s, seen in frames 0-4, hidden after; from frame 10 on it
  // walks back at 1.1 m/s. Its last view (the output of frame 4 + merged - 1 = 5) puts it at
  // y = 0.1 moving +1 m/s. Walked on, that view is 1 m off by frame 33; at rest, the mover is
  // within 1 m of it up to frame 58 (0.022 (f - 9) - 0.08 <= 1), not after. A second mover
  // at y = -2 walks -y at 1 m/s throughout, seen in the same frames: walked on, its last view
  // holds it to the end, though it leaves that place by 1 m by frame 56.
  const auto shipped = config<ucon::perception::PerceptionParams>("perception.yaml");
  const int merged = shipped.preprocess.accumulate_frames;
  ASSERT_EQ(merged, 2);  // the frame counts below are worked out for the shipped value
  ucon::bench::Recording rec;
  const std::vector<P> wall = wallBehind();
  const int64_t t0 = 1'000'000, dt = 20'000;
  for (int f = 0; f < 100; ++f) {
    const int64_t t = t0 + f * dt;
    const double y = f <= 9 ? 0.02 * f : 0.18 - 0.022 * (f - 9);
    const double vy = f < 9 ? 1.0 : -1.1;
    auto pts = wall;
    const double y4 = -2.0 - 0.02 * f;
    if (f < 5)
      for (int k = 0; k < 12; ++k) {
        pts.push_back({4.78f, static_cast<float>(y - 0.15 + 0.025 * k), static_cast<float>(0.3 + 0.1 * k)});
        pts.push_back({4.78f, static_cast<float>(y4 - 0.15 + 0.025 * k), static_cast<float>(0.3 + 0.1 * k)});
      }
    rec.events.push_back(event(ucon::channels::kRobotPose, pose(t, 0, 0, 0)));
    rec.events.push_back(event(ucon::channels::kSimGroundTruth,
                               groundTruth(t, {mover(3, 5.0, y, 0.0, vy), mover(4, 5.0, y4, 0.0, -1.0)})));
    rec.events.push_back(event(ucon::channels::kLidarPoints, cloud(t, f, pts)));
  }
  const auto s = ucon::bench::scoreRecording(rec, {"ucon"}, {shipped}, ucon::bench::ScoreOptions{});
  ASSERT_EQ(s.size(), 1u);
  const auto& sh = s[0].sensor;
  EXPECT_EQ(sh.objects, 200);
  EXPECT_EQ(sh.visible, 2 * (5 + merged - 1));
  EXPECT_EQ(sh.seen, 200);
  EXPECT_EQ(sh.predictable, 59 + 100);
}

TEST(DriveMissCauses, GivenEachSituationOfAMissedMoverThenItsCauseIsTheFirstThatApplies) {
  using namespace ucon::bench;
  using ucon::perception::Detection;
  const Eigen::Vector2d at(5.0, 0.0);
  auto det = [](double x, double y, double side, bool size_ok, bool moving) {
    Detection d;
    d.box.center = Eigen::Vector2d(x, y);
    d.box.size = Eigen::Vector2d(side, side);
    d.size_ok = size_ok;
    d.moving = moving;
    return d;
  };
  auto objects = [](std::vector<std::pair<double, int8_t>> xs) {
    ucon::tracked_objects_t m;
    for (const auto& [x, state] : xs) {
      ucon::tracked_object_t o{};
      o.x = x;
      o.state = state;
      m.objects.push_back(o);
    }
    m.num_objects = static_cast<int32_t>(m.objects.size());
    return m;
  };
  const auto none = objects({});
  using TO = ucon::tracked_object_t;
  // A confirmed track 0.8 m off (within the 1 m threshold) that another mover's match took.
  EXPECT_EQ(classifyMiss(at, {det(5.0, 0.0, 0.5, true, true)}, objects({{5.8, TO::STATE_CONFIRMED}}), 1.0),
            kMissTrackTaken);
  // The nearest cluster's box edge is 0.45 m away: no cluster of its own.
  EXPECT_EQ(classifyMiss(at, {det(5.7, 0.0, 0.5, true, true)}, none, 1.0), kMissNoCluster);
  // Its points are part of a wall-sized cluster.
  EXPECT_EQ(classifyMiss(at, {det(5.5, 0.0, 3.0, false, false)}, none, 1.0), kMissNotObject);
  // Object-sized, not moving: by what the motion test found for most of its points.
  Detection hidden = det(5.0, 0.0, 0.5, true, false);
  hidden.evidence.undecided = 6;
  hidden.evidence.near_reference = 2;
  hidden.evidence.surface = 2;
  EXPECT_EQ(classifyMiss(at, {hidden}, none, 1.0), kMissHidden);
  Detection trail = hidden;
  trail.evidence.undecided = 1;
  trail.evidence.near_reference = 7;
  EXPECT_EQ(classifyMiss(at, {trail}, none, 1.0), kMissOnReference);
  Detection seen = hidden;
  seen.evidence.undecided = 2;
  seen.evidence.surface = 6;
  EXPECT_EQ(classifyMiss(at, {seen}, none, 1.0), kMissMotionOther);
  // Supported by a live track's prediction counts as dynamic.
  Detection supported = seen;
  supported.supported = true;
  EXPECT_EQ(classifyMiss(at, {supported}, none, 1.0), kMissNoTrack);
  // Dynamic, with a tentative track beside it, or none.
  EXPECT_EQ(classifyMiss(at, {det(5.0, 0.0, 0.5, true, true)}, objects({{5.3, TO::STATE_TENTATIVE}}), 1.0),
            kMissTentative);
  EXPECT_EQ(classifyMiss(at, {det(5.0, 0.0, 0.5, true, true)}, objects({{6.5, TO::STATE_CONFIRMED}}), 1.0),
            kMissNoTrack);
  // Range bands and names.
  EXPECT_EQ(missRangeBand(5.9), 0);
  EXPECT_EQ(missRangeBand(6.0), 1);
  EXPECT_EQ(missRangeBand(11.9), 2);
  EXPECT_EQ(missRangeBand(14.0), 3);
  EXPECT_STREQ(missCauseName(kMissHidden), "motion_hidden");
}

TEST(DriveMethods, GivenAMethodNameWhenParamsAreMadeThenOnlyItsSwitchDiffers) {
  const auto shipped = config<ucon::perception::PerceptionParams>("perception.yaml");
  const auto u = ucon::bench::methodParams("ucon", shipped);
  const auto f = ucon::bench::methodParams("fapp", shipped);
  const auto n = ucon::bench::methodParams("ucon-noreassoc", shipped);
  ASSERT_TRUE(u && f && n);
  EXPECT_EQ(u->association, "ucon");
  EXPECT_TRUE(u->reassociation.enabled);
  EXPECT_EQ(f->association, "fapp");
  EXPECT_EQ(n->association, "ucon");
  EXPECT_FALSE(n->reassociation.enabled);
  EXPECT_FALSE(ucon::bench::methodParams("oracle", shipped).has_value());
}

TEST(DriveReplay, GivenARecordedDriveWhenScoredThenEachMethodSeesWhatUconReplayFeedsIt) {
  const auto rec = recordPedestrians(3.0, 2);
  ASSERT_FALSE(rec.events.empty());
  const auto shipped = config<ucon::perception::PerceptionParams>("perception.yaml");
  const auto s = ucon::bench::scoreRecording(rec, {"ucon", "fapp"}, {shipped, *ucon::bench::methodParams("fapp", shipped)},
                                             ucon::bench::ScoreOptions{});
  ASSERT_EQ(s.size(), 2u);
  // ucon-replay's adapter, made from the shipped YAML, fed every recorded event in order:
  // the same PERCEPTION_OBJECTS bytes as the scorer's UCON run.
  std::string err;
  auto node = ucon::replay::makeAdapter(
      "perception", *ucon::runtime::readTextFile(source("deploy/config/perception.yaml"), nullptr), "perception.yaml",
      &err);
  ASSERT_TRUE(node) << err;
  uint64_t h = 1469598103934665603ull;
  int64_t frames = 0;
  std::vector<ucon::replay::OutputMessage> outs;
  for (const auto& e : rec.events) {
    outs.clear();
    node->feed(e.channel, e.data.data(), e.data.size(), &outs);
    for (const auto& o : outs) {
      if (o.channel != ucon::channels::kPerceptionObjects) continue;
      ++frames;
      for (uint8_t b : o.data) h = (h ^ b) * 1099511628211ull;
    }
  }
  EXPECT_GT(frames, 100);
  EXPECT_EQ(s[0].frames, frames);
  EXPECT_EQ(s[0].output_digest, h);
  EXPECT_NE(s[1].output_digest, h);  // the baseline is another method
  EXPECT_GT(rec.stats.path_m, 0.5);  // the route drove the robot
}

TEST(DriveOdometry, GivenTheOdometrysConfigWhenADriveIsRecordedThenEveryNodeRunsOnTheOdometrysPose) {
  std::string err;
  auto sc = ucon::simulator::loadScenario("pedestrians", source("deploy/scenarios"), 1, ucon::runtime::readTextFile,
                                          &err);
  ASSERT_TRUE(sc.has_value()) << err;
  auto c = driveConfig(5.0);
  c.odometry_yaml = *ucon::runtime::readTextFile(source("deploy/config/odometry.yaml"), nullptr);
  const auto odo = ucon::bench::recordDrive(c, *sc, "pedestrians", 1, &err);
  ASSERT_TRUE(odo.has_value()) << err;
  const auto gt = recordPedestrians(5.0, 1);
  // The robot drove on the odometry (it localises from standstill first), whose pose is close
  // to the simulator's but not equal to it; on ground truth the two agree.
  EXPECT_GT(odo->stats.path_m, 1.0);
  EXPECT_GT(odo->stats.pose_error_max, 1e-4);
  EXPECT_LT(odo->stats.pose_error_max, 0.1);
  EXPECT_LT(gt.stats.pose_error_max, 1e-3);
  EXPECT_NE(odo->stats.digest, gt.stats.digest);
  int64_t poses = 0;
  for (const auto& e : odo->events) poses += e.channel == ucon::channels::kRobotPose;
  EXPECT_GT(poses, 100);
  // A configuration the odometry cannot start from is an error, not a drive on another pose.
  c.odometry_yaml = "not: [an odometry config";
  EXPECT_FALSE(ucon::bench::recordDrive(c, *sc, "pedestrians", 1, &err).has_value());
  EXPECT_FALSE(err.empty());
}

TEST(DriveDeterminism, GivenTheSameSeedWhenRecordedAndScoredTwiceThenEveryFigureIsTheSame) {
  const auto shipped = config<ucon::perception::PerceptionParams>("perception.yaml");
  const std::vector<std::string> methods{"ucon", "fapp", "ucon-noreassoc"};
  std::vector<ucon::perception::PerceptionParams> params;
  for (const auto& m : methods) params.push_back(*ucon::bench::methodParams(m, shipped));
  const auto a = recordPedestrians(5.0, 1);
  const auto b = recordPedestrians(5.0, 1);
  EXPECT_EQ(a.stats.digest, b.stats.digest);
  EXPECT_EQ(a.events.size(), b.events.size());
  EXPECT_EQ(a.stats.path_m, b.stats.path_m);
  EXPECT_GT(a.stats.path_m, 2.0);
  const auto sa = ucon::bench::scoreRecording(a, methods, params, ucon::bench::ScoreOptions{});
  const auto sb = ucon::bench::scoreRecording(b, methods, params, ucon::bench::ScoreOptions{});
  ASSERT_EQ(sa.size(), 3u);
  ASSERT_EQ(sb.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE(methods[k]);
    EXPECT_EQ(sa[k].output_digest, sb[k].output_digest);
    for (auto [x, y] : {std::pair{sa[k].all, sb[k].all}, std::pair{sa[k].visible, sb[k].visible}}) {
      EXPECT_EQ(x.num_objects, y.num_objects);
      EXPECT_EQ(x.num_matches, y.num_matches);
      EXPECT_EQ(x.num_switches, y.num_switches);
      EXPECT_EQ(x.num_false_positives, y.num_false_positives);
      EXPECT_EQ(x.num_misses, y.num_misses);
      EXPECT_EQ(x.total_distance, y.total_distance);
    }
    EXPECT_EQ(sa[k].velocity_error_median, sb[k].velocity_error_median);
    EXPECT_EQ(sa[k].track_ids, sb[k].track_ids);
    EXPECT_GT(sa[k].all.num_objects, 0);
  }
}

}  // namespace
