// Extraction of a run from its LCM log: every channel, the covariance block, the trajectory
// layout, collisions; bad messages skipped and counted; damaged logs and logs without the
// channels reported clearly.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "synthetic_run.hpp"
#include "ucon/plot/run_data.hpp"
#include "ucon/trajectory/piecewise_polynomial.hpp"

namespace fs = std::filesystem;
using namespace ucon::plot;
namespace ch = ucon::channels;

namespace {
fs::path tmp(const std::string& name) {
  return fs::temp_directory_path() / ("ucon_plot_" + std::to_string(getpid()) + "_" + name);
}

template <typename Msg>
std::vector<uint8_t> encode(const Msg& m) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

ucon::robot_pose_t pose(int64_t t, double x, double y) {
  ucon::robot_pose_t m{};
  m.utime = t;
  m.valid = true;
  m.x = x;
  m.y = y;
  m.qw = 1;
  m.vx = 1.0;
  return m;
}
}  // namespace

TEST(RunData, GivenASyntheticLogThenEveryChannelIsExtracted) {
  const auto p = tmp("full.lcm");
  ucon_test::SyntheticRun gen;
  ASSERT_TRUE(gen.write(p.string()));
  RunData run;
  std::string err;
  ASSERT_EQ(loadRunLog(p.string(), {}, &run, &err), LoadStatus::kOk) << err;
  EXPECT_EQ(run.scenario, "synthetic");
  EXPECT_EQ(static_cast<int>(run.poses.size()), gen.poses);
  EXPECT_EQ(static_cast<int>(run.ground_truth.size()), gen.gts);
  EXPECT_EQ(static_cast<int>(run.objects.size()), gen.object_frames);
  EXPECT_EQ(static_cast<int>(run.trajectories.size()), gen.plans);
  EXPECT_EQ(run.static_messages, gen.statics);
  EXPECT_EQ(run.events, gen.poses + gen.gts + gen.object_frames + gen.plans + gen.statics);
  EXPECT_EQ(run.used.at(ch::kRobotPose), gen.poses);
  EXPECT_TRUE(run.skipped.empty());
  const auto [t0, t1] = run.timeRange();
  EXPECT_EQ(t0, gen.t0);
  EXPECT_EQ(t1, gen.t0 + 6'000'000);
  EXPECT_DOUBLE_EQ(run.robotRadius(), 0.3);

  // One collision episode, where the robot was at t = 4 s.
  ASSERT_EQ(run.collisions.size(), 1u);
  double x, y, vx, vy;
  gen.robotAt(4.0, &x, &y, &vx, &vy);
  EXPECT_EQ(run.collisions[0].utime, gen.t0 + 4'000'000);
  EXPECT_NEAR(run.collisions[0].x, x, 1e-9);
  EXPECT_NEAR(run.collisions[0].y, y, 1e-9);

  // Covariance: the x-y block is elements [0], [1], [6], [7] of the 6x6 row-major matrix.
  const auto& o = run.objects[0].objects[2];
  EXPECT_EQ(o.id, 13);
  ASSERT_TRUE(o.has_cov);
  EXPECT_NEAR(o.cov_xy(0, 0), 0.2 * 0.2, 1e-12);
  EXPECT_NEAR(o.cov_xy(1, 1), 0.2 * 0.2, 1e-12);
  EXPECT_NEAR(o.cov_xy(0, 1), 0.5 * 0.2 * 0.2, 1e-12);

  // Static: the wall cells (y = 5.02 -> iy = 50) and the pillar; the floor point is not there.
  const auto& cells = run.static_grid.cells;
  EXPECT_TRUE(cells.count({50, 50}));   // x = 5.0..5.1, y = 5.0..5.1
  EXPECT_GE(cells.at({50, 50}).hits, gen.statics);  // one or two wall points per message
  EXPECT_EQ(cells.at({50, 50}).first_utime, gen.t0);
  EXPECT_TRUE(cells.count({34, -20}));  // pillar edge at x = 3.4, y = -2.0
  EXPECT_FALSE(cells.count({10, 10}));  // floor point (z = 0) at (1, 1)
  fs::remove(p);
}

TEST(RunData, GivenATwoPieceTrajectoryThenSamplesFollowTheDocumentedCoefficientLayout) {
  // Piece 0 (1 s): x = 1 + 2t, y = 3; piece 1 (2 s): x = 3, y = 3 + t^2.
  ucon::trajectory_t m{};
  m.utime = 5;
  m.plan_id = 7;
  m.start_utime = 5;
  m.dim = 2;
  m.order1 = 6;
  m.num_pieces = 2;
  m.durations = {1.0, 2.0};
  m.coeffs = {1, 2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 0, 3, 0, 0, 0, 0, 0, 3, 0, 1, 0, 0, 0};
  m.num_coeffs = 24;
  RunDataBuilder b(ExtractionParams{});  // 0.1 s steps
  const auto buf = encode(m);
  b.add(ch::kPlannerTrajectory, buf.data(), buf.size());
  const auto& run = b.data();
  ASSERT_EQ(run.trajectories.size(), 1u);
  const auto& pts = run.trajectories[0].points;
  ASSERT_EQ(pts.size(), 31u);  // 3 s at 0.1 s, both ends
  EXPECT_NEAR(pts[5].x(), 2.0, 1e-9);    // t = 0.5
  EXPECT_NEAR(pts[5].y(), 3.0, 1e-9);
  EXPECT_NEAR(pts[20].x(), 3.0, 1e-9);   // t = 2.0: 1 s into piece 1
  EXPECT_NEAR(pts[20].y(), 4.0, 1e-9);
  EXPECT_NEAR(pts[30].y(), 7.0, 1e-9);   // t = 3.0
  EXPECT_EQ(run.trajectories[0].plan_id, 7);
}

TEST(RunData, GivenBadMessagesThenTheyAreSkippedAndCountedByReason) {
  RunDataBuilder b;
  const auto good = encode(pose(10, 1, 2));
  b.add(ch::kRobotPose, good.data(), good.size());
  auto nan = pose(20, NAN, 2);
  auto bad = encode(nan);
  b.add(ch::kRobotPose, bad.data(), bad.size());
  auto inv = pose(30, 1, 2);
  inv.valid = false;
  bad = encode(inv);
  b.add(ch::kRobotPose, bad.data(), bad.size());
  const std::vector<uint8_t> junk(37, 0xAB);
  b.add(ch::kRobotPose, junk.data(), junk.size());
  b.add(ch::kRobotPose, good.data(), good.size() - 9);  // cut short
  b.add(ch::kSimGroundTruth, good.data(), good.size());  // a pose on the ground-truth channel
  b.add("SOMETHING_ELSE", junk.data(), junk.size());     // not drawn: ignored silently
  b.add(ch::kRobotPose, nullptr, 0);

  // A trajectory with a negative duration and an object with a NaN covariance.
  ucon::trajectory_t tr{};
  tr.utime = 1;
  tr.start_utime = 1;
  tr.dim = 2;
  tr.order1 = 6;
  tr.num_pieces = 1;
  tr.durations = {-1.0};
  tr.num_coeffs = 12;
  tr.coeffs.assign(12, 0.0);
  bad = encode(tr);
  b.add(ch::kPlannerTrajectory, bad.data(), bad.size());
  ucon::tracked_objects_t f{};
  f.utime = 5;
  f.valid = true;
  f.num_objects = 2;
  f.objects.resize(2);
  f.objects[0].id = 1;
  f.objects[0].cov_size = 36;
  f.objects[0].cov.assign(36, NAN);
  f.objects[1].id = 2;
  f.objects[1].x = INFINITY;
  bad = encode(f);
  b.add(ch::kPerceptionObjects, bad.data(), bad.size());

  const auto& run = b.data();
  ASSERT_EQ(run.poses.size(), 1u);
  EXPECT_EQ(run.skipped.at("ROBOT_POSE: non-finite"), 1);
  EXPECT_EQ(run.skipped.at("ROBOT_POSE: invalid"), 1);
  EXPECT_EQ(run.skipped.at("ROBOT_POSE: undecodable"), 3);
  EXPECT_EQ(run.skipped.at("SIM_GROUND_TRUTH: undecodable"), 1);
  EXPECT_EQ(run.skipped.at("PLANNER_TRAJECTORY: bad trajectory (" +
                           std::string(ucon::trajectory::toString(ucon::trajectory::TrajectoryStatus::kBadDuration)) +
                           ")"),
            1);
  EXPECT_EQ(run.skipped.at("PERCEPTION_OBJECTS: non-finite object"), 1);
  EXPECT_EQ(run.skipped.at("PERCEPTION_OBJECTS: bad covariance (drawn without)"), 1);
  ASSERT_EQ(run.objects.size(), 1u);
  ASSERT_EQ(run.objects[0].objects.size(), 1u);
  EXPECT_FALSE(run.objects[0].objects[0].has_cov);
  EXPECT_TRUE(run.trajectories.empty());
}

TEST(RunData, GivenAHugeArrayCountInACorruptMessageThenItIsUndecodableNotACrash) {
  ucon::static_points_t m{};
  m.utime = 1;
  m.valid = true;
  m.num_points = 1;
  m.x = {1};
  m.y = {1};
  m.z = {1};
  auto buf = encode(m);
  // num_points follows hash(8) utime(8) seq(8) valid(1) origin(24) max_range(4).
  const std::size_t off = 8 + 8 + 8 + 1 + 24 + 4;
  buf[off] = 0x7F;
  buf[off + 1] = 0xFF;
  RunDataBuilder b;
  b.add(ch::kPerceptionStatic, buf.data(), buf.size());
  EXPECT_EQ(b.data().skipped.at("PERCEPTION_STATIC: undecodable"), 1);
  EXPECT_EQ(b.data().static_messages, 0);
}

TEST(RunData, GivenATruncatedLogThenTheErrorNamesTheByteOffsetAndTheEarlierEventsAreKept) {
  const auto p = tmp("trunc.lcm");
  ucon_test::SyntheticRun gen;
  gen.duration_s = 1.0;
  ASSERT_TRUE(gen.write(p.string()));
  const int64_t last = gen.offsets.back();
  fs::resize_file(p, static_cast<uintmax_t>(last + 30));  // header complete, data cut
  RunData run;
  std::string err;
  EXPECT_EQ(loadRunLog(p.string(), {}, &run, &err), LoadStatus::kCorrupt);
  EXPECT_NE(err.find("byte offset " + std::to_string(last)), std::string::npos) << err;
  EXPECT_EQ(run.events, static_cast<int64_t>(gen.offsets.size()) - 1);
  fs::remove(p);
}

TEST(RunData, GivenALogWithoutTheChannelsThenNoChannelsIsReportedWithTheirNames) {
  const auto p = tmp("other.lcm");
  {
    ucon::runtime::LogWriterFile w;
    std::string e;
    ASSERT_TRUE(w.open(p.string(), &e));
    const std::vector<uint8_t> d(10, 1);
    ASSERT_TRUE(w.write("LIDAR_IMU", d.data(), d.size(), 1));
    ASSERT_TRUE(w.write("NAV_GOAL", d.data(), d.size(), 2));
  }
  RunData run;
  std::string err;
  EXPECT_EQ(loadRunLog(p.string(), {}, &run, &err), LoadStatus::kNoChannels);
  EXPECT_NE(err.find("ROBOT_POSE"), std::string::npos) << err;
  EXPECT_NE(err.find("PLANNER_TRAJECTORY"), std::string::npos) << err;
  EXPECT_NE(err.find("2 events"), std::string::npos) << err;
  EXPECT_EQ(loadRunLog((p.string() + ".missing"), {}, &run, &err), LoadStatus::kOpenFailed);
  EXPECT_NE(err.find(".missing"), std::string::npos);
  fs::remove(p);
}

TEST(RunData, GivenOnlyGroundTruthThenTheRobotPathComesFromIt) {
  const auto p = tmp("gt.lcm");
  ucon_test::SyntheticRun gen;
  gen.duration_s = 1.0;
  gen.pose = gen.objects = gen.static_points = gen.trajectory = false;
  ASSERT_TRUE(gen.write(p.string()));
  RunData run;
  std::string err;
  ASSERT_EQ(loadRunLog(p.string(), {}, &run, &err), LoadStatus::kOk) << err;
  EXPECT_TRUE(run.poses.empty());
  const auto path = run.robotPath();
  ASSERT_EQ(static_cast<int>(path.size()), gen.gts);
  EXPECT_NEAR(path.back().x, ucon_test::SyntheticRun::kGoalX * 1.0, 1e-9);
  fs::remove(p);
}

TEST(RunData, GivenPerceptionOnAnotherClockThenItIsRebasedOntoThePoseClockWithANote) {
  const auto p = tmp("clock.lcm");
  ucon_test::SyntheticRun gen;
  gen.duration_s = 2.0;
  gen.other_clock = 1'795'396'898'314'732;  // a wall-clock stamp, as seen in an integration log
  ASSERT_TRUE(gen.write(p.string()));
  RunData run;
  std::string err;
  ASSERT_EQ(loadRunLog(p.string(), {}, &run, &err), LoadStatus::kOk) << err;
  const auto [t0, t1] = run.timeRange();
  EXPECT_EQ(t0, gen.t0);
  EXPECT_EQ(t1, gen.t0 + 2'000'000);
  EXPECT_EQ(run.objects.front().utime, gen.t0 + 20'000);  // first object frame: tick 1
  EXPECT_EQ(run.trajectories.front().utime, gen.t0 + 100'000);
  EXPECT_EQ(run.static_grid.cells.begin()->second.first_utime, gen.t0);
  ASSERT_EQ(run.notes.size(), 3u);  // objects, static points, trajectories
  EXPECT_NE(run.notes[0].find("PERCEPTION_OBJECTS is stamped on another clock than ROBOT_POSE"), std::string::npos)
      << run.notes[0];
  // Same clocks: nothing moved, no note.
  gen.other_clock = 0;
  ASSERT_TRUE(gen.write(p.string()));
  ASSERT_EQ(loadRunLog(p.string(), {}, &run, &err), LoadStatus::kOk) << err;
  EXPECT_TRUE(run.notes.empty());
  fs::remove(p);
}
