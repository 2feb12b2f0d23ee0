// The ucon-planner process: a bad config or URL fails at start-up with a clear message; over
// LCM (udpm on a test port) it turns pose + obstacles + static points + a goal into a
// trajectory and publishes PLANNER_STATUS, and exits cleanly on SIGTERM.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include "ucon/channels.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/process_status_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/trajectory_t.hpp"

namespace {

const std::string kBin = std::string(UCON_BIN_DIR) + "/ucon-planner";
const std::string kConfig = std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml";

std::string runCapture(const std::string& args, int* status) {
  FILE* p = popen((kBin + " " + args + " 2>&1").c_str(), "r");
  std::string out;
  char buf[256];
  while (p && fgets(buf, sizeof(buf), p)) out += buf;
  *status = p ? pclose(p) : -1;
  return out;
}

}  // namespace

TEST(PlannerProcess, GivenAConfigWithATypoThenItExitsNonZeroNamingTheKey) {
  const std::string bad = "/tmp/ucon_planner_bad_config.yaml";
  {
    std::ifstream in(kConfig);
    std::ofstream out(bad);
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("rate_hz:", 0) == 0) line = "rate_hzz: 10.0";
      out << line << "\n";
    }
  }
  int status = 0;
  const std::string out = runCapture("--config " + bad + " --lcm-url memq://", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("rate_hzz"), std::string::npos) << out;
  EXPECT_NE(out.find("rate_hz"), std::string::npos) << out;
  std::remove(bad.c_str());
}

TEST(PlannerProcess, GivenABadUrlThenItExitsNonZeroAndSaysWhy) {
  int status = 0;
  const std::string out = runCapture("--config " + kConfig + " --lcm-url 'bogus://nowhere'", &status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("bogus://nowhere"), std::string::npos) << out;
}

TEST(PlannerProcess, GivenInputsOverLcmThenItPublishesATrajectoryAndStatusAndStopsOnSigterm) {
  const std::string url = "udpm://239.255.76.67:7761?ttl=0";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl(kBin.c_str(), kBin.c_str(), "--config", kConfig.c_str(), "--lcm-url", url.c_str(), (char*)nullptr);
    _exit(127);
  }
  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open("test", url, &err);
  ASSERT_TRUE(rt) << err;
  ucon::trajectory_t traj{};
  bool got_traj = false, got_status = false;
  rt->subscribe<ucon::trajectory_t>(ucon::channels::kPlannerTrajectory,
                                    [&](const ucon::trajectory_t& t, const std::string&) {
                                      if (t.status == ucon::trajectory_t::STATUS_OK) {
                                        traj = t;
                                        got_traj = true;
                                      }
                                    });
  rt->subscribe<ucon::process_status_t>(ucon::channels::kPlannerStatus,
                                        [&](const ucon::process_status_t& s, const std::string&) {
                                          if (s.name == "planner") got_status = true;
                                        });
  const auto wall0 = std::chrono::steady_clock::now();
  int64_t utime = 1'000'000;
  for (int k = 0; k < 400 && !(got_traj && got_status); ++k, utime += 20000) {
    ucon::robot_pose_t pose{};
    pose.utime = utime;
    pose.valid = true;
    pose.qw = 1.0;
    pose.ax = NAN;
    pose.ay = NAN;
    rt->publish(ucon::channels::kRobotPose, pose);
    ucon::tracked_objects_t objs{};
    objs.utime = utime;
    objs.valid = true;
    objs.frame_id = "world";
    rt->publish(ucon::channels::kPerceptionObjects, objs);
    if (k % 5 == 0) {  // a wall of static points at x = 3
      ucon::static_points_t sp{};
      sp.utime = utime;
      sp.valid = true;
      sp.origin_z = 0.3;
      sp.max_range = 10.0f;
      for (float y = -1.0f; y <= 1.0f; y += 0.05f) {
        sp.x.push_back(3.05f);
        sp.y.push_back(y);
        sp.z.push_back(0.3f);
      }
      sp.num_points = int32_t(sp.x.size());
      rt->publish(ucon::channels::kPerceptionStatic, sp);
    }
    if (k % 25 == 10) {
      ucon::nav_goal_t g{};
      g.utime = utime;
      g.goal_id = 42;
      g.x = 6.0;
      g.y = 0.0;
      g.yaw = NAN;
      g.tolerance = 0.3;
      rt->publish(ucon::channels::kNavGoal, g);
    }
    while (rt->handleOnce(0) > 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    // Keep waiting for the once-per-second status message.
    if (std::chrono::steady_clock::now() - wall0 > std::chrono::seconds(8)) break;
  }
  EXPECT_TRUE(got_traj);
  EXPECT_TRUE(got_status);
  if (got_traj) {
    EXPECT_EQ(traj.goal_id, 42);
    EXPECT_EQ(traj.dim, 2);
    EXPECT_EQ(traj.order1, 6);
    EXPECT_GT(traj.num_pieces, 0);
    EXPECT_GT(traj.start_utime, 1'000'000);  // from message time, not the wall clock
    EXPECT_LT(traj.start_utime, utime + 1'000'000);
  }
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}
