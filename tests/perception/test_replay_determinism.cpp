// The node replayed twice over the same recorded LCM log (ROBOT_POSE + LIDAR_POINTS, written
// and read with lcm::LogFile) gives byte-identical PERCEPTION_OBJECTS and PERCEPTION_STATIC.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

#include "synthetic_scene.hpp"
#include "ucon/channels.hpp"
#include "ucon/perception/perception_node.hpp"
#include "../support/test_support.hpp"

namespace {

using ucon::test::writeLogEvent;

template <class Msg>
void append(std::vector<uint8_t>& out, const Msg& m) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  out.insert(out.end(), buf.begin(), buf.end());
}

// Replays the log through a fresh node, as the lock-step replay harness does.
std::vector<uint8_t> replay(const std::string& path, const char* association, int* frames) {
  ucon::perception::PerceptionParams p;
  p.association = association;
  ucon::perception::PerceptionNode node(p);
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good());
  std::vector<uint8_t> out;
  *frames = 0;
  while (const lcm::LogEvent* ev = log.readNextEvent()) {
    if (ev->channel == ucon::channels::kRobotPose) {
      ucon::robot_pose_t pose;
      if (pose.decode(ev->data, 0, ev->datalen) == ev->datalen) node.onPose(pose);
    } else if (ev->channel == ucon::channels::kLidarPoints) {
      ucon::point_cloud_t cloud;
      if (cloud.decode(ev->data, 0, ev->datalen) != ev->datalen) continue;
      const auto o = node.onPoints(cloud);
      if (o.objects) append(out, *o.objects), ++*frames;
      if (o.static_points) append(out, *o.static_points);
    }
  }
  return out;
}

}  // namespace

TEST(PerceptionReplay, GivenARecordedLogWhenReplayedTwiceThenOutputsAreByteIdentical) {
  const std::string path = "/tmp/ucon_test_perception_replay_" + std::to_string(::getpid()) + ".lcm";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    scene::Generator gen(11);
    const std::vector<scene::Person> people{{1.0, -2.0, 1.0, 0.0}, {6.0, 2.5, 0.0, -0.8}};
    const std::vector<scene::Wall> walls{{-3, 4, 6, 4}, {7, -3, 7, 3}};
    for (int k = 0; k < 90; ++k) {
      const int64_t t = scene::frameTime(k);
      writeLogEvent(log, ucon::channels::kRobotPose, scene::pose(t), t);
      writeLogEvent(log, ucon::channels::kLidarPoints, gen.frame(k, people, walls), t + 20000);
    }
  }
  for (const char* method : {"ucon", "fapp"}) {
    int f1 = 0, f2 = 0;
    const auto a = replay(path, method, &f1);
    const auto b = replay(path, method, &f2);
    EXPECT_EQ(f1, 90);
    EXPECT_EQ(f2, 90);
    EXPECT_GT(a.size(), 10000u);
    EXPECT_TRUE(a == b) << method;
  }
  std::remove(path.c_str());
}
