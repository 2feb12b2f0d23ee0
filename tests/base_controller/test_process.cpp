// The ucon-base-controller process end to end over LCM (udpm, this test's own port).
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <termios.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "ucon/base_controller/serial_frame.hpp"
#include "ucon/base_status_t.hpp"
#include "ucon/channels.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/trajectory_t.hpp"
#include "ucon/wheel_cmd_t.hpp"
#include "../support/test_support.hpp"

namespace {
constexpr const char* kUrl = "udpm://239.255.76.67:7741?ttl=0";

int64_t wallUs() {
  timeval tv;
  gettimeofday(&tv, nullptr);
  return static_cast<int64_t>(tv.tv_sec) * 1000000 + tv.tv_usec;
}

pid_t launch(const std::vector<std::string>& args) { return ucon::test::spawn(args); }

int waitExit(pid_t pid, int timeout_ms) {
  for (int i = 0; i < timeout_ms / 10; ++i) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -2;
}

struct Sink {
  std::vector<ucon::wheel_cmd_t> cmds;
  std::vector<ucon::base_status_t> statuses;
  void onCmd(const lcm::ReceiveBuffer*, const std::string&, const ucon::wheel_cmd_t* m) { cmds.push_back(*m); }
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const ucon::base_status_t* m) {
    statuses.push_back(*m);
  }
};

ucon::trajectory_t straightLine(int64_t start, int64_t seq) {
  // x = 0.5 t for 5 s, y = 0 (linear pieces: order1 = 2).
  ucon::trajectory_t m{};
  m.utime = start;
  m.seq = seq;
  m.plan_id = 1;
  m.status = ucon::trajectory_t::STATUS_OK;
  m.start_utime = start;
  m.dim = 2;
  m.order1 = 2;
  m.num_pieces = 1;
  m.durations = {5.0};
  m.num_coeffs = 4;
  m.coeffs = {0.0, 0.5, 0.0, 0.0};
  m.yaw = std::numeric_limits<double>::quiet_NaN();
  return m;
}

ucon::robot_pose_t pose(int64_t utime) {
  ucon::robot_pose_t p{};
  p.utime = utime;
  p.valid = true;
  p.qw = 1.0;
  p.ax = p.ay = std::numeric_limits<double>::quiet_NaN();
  return p;
}
}  // namespace

TEST(BaseControllerProcess, GivenPosesAndAPlanThenDrivesAndWhenPosesStopThenStopsAndExitsCleanly) {
  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good());
  Sink sink;
  lcm.subscribe(ucon::channels::kBaseWheelCmd, &Sink::onCmd, &sink);
  lcm.subscribe(ucon::channels::kBaseStatus, &Sink::onStatus, &sink);
  const pid_t pid = launch({std::string(UCON_BIN_DIR) + "/ucon-base-controller", "--config",
                            "deploy/config/base_controller.yaml", "--lcm-url", kUrl});
  ASSERT_GT(pid, 0);

  auto pump = [&](double seconds, bool poses) {
    const int64_t end = wallUs() + static_cast<int64_t>(seconds * 1e6);
    int64_t next_pose = 0, next_plan = 0;
    static int64_t seq = 0;
    static int64_t plan_start = 0;
    while (wallUs() < end) {
      const int64_t now = wallUs();
      if (plan_start == 0) plan_start = now;
      if (poses && now >= next_pose) {
        const ucon::robot_pose_t p = pose(now);
        lcm.publish(ucon::channels::kRobotPose, &p);
        next_pose = now + 10000;
      }
      if (now >= next_plan) {
        const ucon::trajectory_t t = straightLine(plan_start, seq++);
        ucon::trajectory_t m = t;
        m.utime = now;
        lcm.publish(ucon::channels::kPlannerTrajectory, &m);
        next_plan = now + 100000;
      }
      lcm.handleTimeout(2);
    }
  };

  pump(1.5, true);
  ASSERT_FALSE(sink.cmds.empty()) << "no BASE_WHEEL_CMD from the process";
  ASSERT_FALSE(sink.statuses.empty()) << "no BASE_STATUS from the process";
  EXPECT_EQ(sink.statuses.back().state, ucon::base_status_t::STATE_TRACKING) << sink.statuses.back().reason;
  EXPECT_TRUE(sink.cmds.back().enable);
  EXPECT_GT(sink.cmds.back().vx, 0.3);  // following x = 0.5 t (plus feedback: the pose stays put)
  const std::size_t n_cmds = sink.cmds.size();
  EXPECT_GT(n_cmds, 80u);  // ~100 Hz once the first message arrived

  pump(1.5, false);  // poses stop; plans keep coming
  ASSERT_FALSE(sink.statuses.empty());
  EXPECT_EQ(sink.statuses.back().state, ucon::base_status_t::STATE_STOPPED);
  EXPECT_NE(sink.statuses.back().reason.find("pose stale"), std::string::npos) << sink.statuses.back().reason;
  EXPECT_GT(sink.cmds.size(), n_cmds + 100);  // the loop kept running on its own timer
  EXPECT_EQ(sink.cmds.back().w_fl, 0.0);

  kill(pid, SIGTERM);
  EXPECT_EQ(waitExit(pid, 3000), 0);
  lcm.handleTimeout(200);
  EXPECT_FALSE(sink.cmds.back().enable);  // a last braking command on exit
}

TEST(BaseControllerProcess, GivenBadConfigOrDeviceThenFailsAtStartupWithNonZeroCode) {
  const std::string bin = std::string(UCON_BIN_DIR) + "/ucon-base-controller";
  EXPECT_EQ(waitExit(launch({bin, "--config", "/nonexistent.yaml", "--lcm-url", kUrl}), 5000), 2);
  EXPECT_EQ(waitExit(launch({bin, "--config", "deploy/config/base_controller.yaml", "--lcm-url", kUrl,
                             "--backend", "serial", "--serial-device", "/nonexistent/tty"}),
                     5000),
            1);
}

TEST(BaseControllerProcess, GivenMessageClockThenTicksFallOnTheMessageTimeGridOnly) {
  constexpr const char* kUrl2 = "udpm://239.255.76.67:7742?ttl=0";
  lcm::LCM lcm(kUrl2);
  ASSERT_TRUE(lcm.good());
  Sink sink;
  lcm.subscribe(ucon::channels::kBaseWheelCmd, &Sink::onCmd, &sink);
  const pid_t pid = launch({std::string(UCON_BIN_DIR) + "/ucon-base-controller", "--config",
                            "deploy/config/base_controller.yaml", "--lcm-url", kUrl2, "--clock", "message"});
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // let it subscribe
  // Message time runs 10x faster than the wall clock here: 2 s of data in ~0.2 s... but
  // paced a little so no datagram is lost.
  const int64_t t0 = 1'000'000'000'000;  // on the 10 ms grid
  for (int i = 0; i <= 100; ++i) {
    const int64_t t = t0 + i * 10000 + 5000;  // poses half-way between ticks
    if (i % 10 == 0) {
      ucon::trajectory_t m = straightLine(t0, i);
      m.utime = t;
      lcm.publish(ucon::channels::kPlannerTrajectory, &m);
    }
    const ucon::robot_pose_t p = pose(t);
    lcm.publish(ucon::channels::kRobotPose, &p);
    lcm.handleTimeout(2);
  }
  for (int i = 0; i < 50; ++i) lcm.handleTimeout(10);
  kill(pid, SIGTERM);
  EXPECT_EQ(waitExit(pid, 3000), 0);
  lcm.handleTimeout(100);
  ASSERT_GE(sink.cmds.size(), 90u);
  int on_grid = 0;
  for (std::size_t i = 0; i + 1 < sink.cmds.size(); ++i) {  // the last one is the exit brake
    const auto& c = sink.cmds[i];
    EXPECT_EQ(c.utime % 10000, 0) << c.utime;
    EXPECT_LT(c.utime, t0 + 100 * 10000 + 5000);
    ++on_grid;
  }
  EXPECT_EQ(on_grid, 100);  // ticks at t0 + 10 ms .. t0 + 1000 ms
  EXPECT_EQ(sink.cmds[sink.cmds.size() - 2].utime, t0 + 100 * 10000);
  EXPECT_TRUE(sink.cmds[sink.cmds.size() - 2].enable);
  EXPECT_GT(sink.cmds[sink.cmds.size() - 2].vx, 0.3);
}

TEST(BaseControllerProcess, GivenSerialBackendOnAPtyThenTheBoardReceivesValidFramesAndABrakeOnExit) {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(grantpt(master), 0);
  ASSERT_EQ(unlockpt(master), 0);
  const std::string slave = ptsname(master);
  termios t{};
  tcgetattr(master, &t);
  cfmakeraw(&t);
  tcsetattr(master, TCSANOW, &t);

  constexpr const char* kUrl3 = "udpm://239.255.76.67:7743?ttl=0";
  lcm::LCM lcm(kUrl3);
  ASSERT_TRUE(lcm.good());
  Sink sink;
  lcm.subscribe(ucon::channels::kBaseWheelCmd, &Sink::onCmd, &sink);
  const pid_t pid = launch({std::string(UCON_BIN_DIR) + "/ucon-base-controller", "--config",
                            "deploy/config/base_controller.yaml", "--lcm-url", kUrl3, "--backend", "serial",
                            "--serial-device", slave});
  ASSERT_GT(pid, 0);
  ucon::base_controller::WheelFrameParser parser;
  std::vector<ucon::base_controller::WheelFrame> frames;
  auto drain = [&] {
    pollfd pfd{master, POLLIN, 0};
    while (poll(&pfd, 1, 0) > 0 && (pfd.revents & POLLIN)) {
      uint8_t buf[512];
      const ssize_t n = read(master, buf, sizeof(buf));
      if (n <= 0) break;
      const auto f = parser.feed(buf, static_cast<std::size_t>(n));
      frames.insert(frames.end(), f.begin(), f.end());
    }
  };
  const int64_t end = wallUs() + 1'000'000;
  int64_t next_pose = 0, next_plan = 0, start = 0, seq = 0;
  while (wallUs() < end) {
    const int64_t now = wallUs();
    if (start == 0) start = now;
    if (now >= next_pose) {
      const ucon::robot_pose_t p = pose(now);
      lcm.publish(ucon::channels::kRobotPose, &p);
      next_pose = now + 10000;
    }
    if (now >= next_plan) {
      ucon::trajectory_t m = straightLine(start, seq++);
      m.utime = now;
      lcm.publish(ucon::channels::kPlannerTrajectory, &m);
      next_plan = now + 100000;
    }
    lcm.handleTimeout(2);
    drain();
  }
  kill(pid, SIGTERM);
  EXPECT_EQ(waitExit(pid, 3000), 0);
  drain();
  close(master);
  EXPECT_TRUE(sink.cmds.empty()) << "the serial backend must not drive a simulator over LCM";
  ASSERT_GT(frames.size(), 50u);
  EXPECT_EQ(parser.crcErrors(), 0);
  for (std::size_t i = 1; i < frames.size(); ++i) EXPECT_EQ(frames[i].seq, static_cast<uint16_t>(frames[i - 1].seq + 1));
  bool moving = false;
  for (const auto& f : frames) moving = moving || (f.enable && f.speeds()[0] > 5.0);  // 0.5 m/s / 0.05 m = 10 rad/s
  EXPECT_TRUE(moving);
  EXPECT_FALSE(frames.back().enable);  // brake on exit
  EXPECT_EQ(frames.back().raw[0], 0);
}
