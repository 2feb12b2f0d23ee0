// Lock-step replay of a recorded LCM log through the controller's binding: same outputs as
// the closed loop that recorded it, and the same outputs on every replay.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "figure_eight.hpp"
#include "ucon/base_controller/binding.hpp"
#include "ucon/channels.hpp"
#include "ucon/replay/bound_adapter.hpp"
#include "ucon/runtime/config_file.hpp"

using ucon::base_controller::BaseControllerOutput;
using ucon::base_controller::BaseControllerParams;
using ucon::base_controller::BoundBaseController;

namespace {
constexpr int64_t kT0 = 1'700'000'000'000'000;

template <class Msg>
std::vector<uint8_t> bytes(const Msg& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

void append(std::vector<uint8_t>* all, const BaseControllerOutput& o) {
  if (o.wheel_cmd) {
    const auto b = bytes(*o.wheel_cmd);
    all->insert(all->end(), b.begin(), b.end());
  }
  if (o.status) {
    const auto b = bytes(*o.status);
    all->insert(all->end(), b.begin(), b.end());
  }
}

struct TempFile {
  std::string path;
  TempFile() {
    char name[] = "/tmp/ucon_bc_replay_XXXXXX";
    const int fd = mkstemp(name);
    if (fd >= 0) close(fd);
    path = name;
  }
  ~TempFile() { std::remove(path.c_str()); }
};

std::vector<uint8_t> replay(const BaseControllerParams& p, const std::string& path, int* events,
                            int64_t* decode_errors) {
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good());
  ucon::replay::BoundAdapter<BoundBaseController> r(
      ucon::base_controller::binding(p), std::make_unique<BoundBaseController>(p),
      [](const BoundBaseController&, const ucon::replay::FeedCounts&) {
        return std::vector<std::pair<std::string, int64_t>>{};
      });
  std::vector<uint8_t> out;
  std::vector<ucon::replay::OutputMessage> msgs;
  *events = 0;
  *decode_errors = 0;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    ++*events;
    msgs.clear();
    const auto* data = static_cast<const uint8_t*>(e->data);
    if (r.feed(e->channel, data, static_cast<std::size_t>(e->datalen), &msgs) == ucon::replay::FeedResult::kDecodeError)
      ++*decode_errors;
    for (const auto& m : msgs) out.insert(out.end(), m.data.begin(), m.data.end());
  }
  return out;
}
}  // namespace

TEST(BaseControllerReplay, GivenARecordedLogThenReplayMatchesTheRecordingLoopAndItselfByteForByte) {
  auto p = ucon::runtime::loadConfigFile<BaseControllerParams>("test", "deploy/config/base_controller.yaml");
  ASSERT_TRUE(p.has_value());
  TempFile tmp;

  // Record: the closed loop's inputs go to a log; its outputs are kept for comparison.
  std::vector<uint8_t> live;
  {
    lcm::LogFile log(tmp.path, "w");
    ASSERT_TRUE(log.good());
    int64_t event = 0;
    auto write = [&](const char* channel, const std::vector<uint8_t>& b, int64_t utime) {
      lcm::LogEvent e{};
      e.eventnum = event++;
      e.timestamp = utime;
      e.channel = channel;
      e.datalen = static_cast<int32_t>(b.size());
      e.data = const_cast<uint8_t*>(b.data());
      ASSERT_EQ(log.writeEvent(&e), 0);
    };
    test_support::FigureEight fig;
    const ucon::trajectory_t plan = fig.message(kT0);
    test_support::ClosedLoop loop(*p, kT0);
    ucon::trajectory::PiecewisePolynomial ref;
    ucon::trajectory::PiecewisePolynomial::fromMessage(plan, &ref);
    loop.plant.reset(ref.position(kT0).x(), ref.position(kT0).y(), 0.0);
    loop.send_pose = false;  // the test hands poses over itself, to record them
    for (int i = 0; i < 300; ++i) {
      const int64_t t = loop.t;
      if (i % 10 == 0) {
        ucon::trajectory_t m = plan;
        m.utime = t;
        write(ucon::channels::kPlannerTrajectory, bytes(m), t);
        append(&live, loop.ctrl.onTrajectory(m));
      }
      if (i == 150) {  // an E-stop pulse and a garbage event in the middle
        ucon::estop_t e{};
        e.utime = t;
        e.engaged = true;
        e.source = "replay test";
        write(ucon::channels::kBaseEstop, bytes(e), t);
        append(&live, loop.ctrl.onEstop(e));
        write(ucon::channels::kRobotPose, {1, 2, 3}, t);
      }
      if (i == 200) {
        ucon::estop_t e{};
        e.utime = t;
        e.engaged = false;
        write(ucon::channels::kBaseEstop, bytes(e), t);
        append(&live, loop.ctrl.onEstop(e));
      }
      const ucon::robot_pose_t pose = test_support::poseFrom(loop.plant.state(), t);
      write(ucon::channels::kRobotPose, bytes(pose), t);
      append(&live, loop.ctrl.onPose(pose));
      if (i < 299) append(&live, loop.step());  // replay cannot tick after the last event
    }
  }

  int events = 0;
  int64_t decode_errors = 0;
  const std::vector<uint8_t> a = replay(*p, tmp.path, &events, &decode_errors);
  const std::vector<uint8_t> b = replay(*p, tmp.path, &events, &decode_errors);
  EXPECT_EQ(events, 300 + 30 + 3);
  EXPECT_EQ(decode_errors, 1);
  ASSERT_GT(a.size(), 10000u);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a, live);
}
