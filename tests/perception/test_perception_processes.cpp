// Integration: ucon-simulator (pedestrians, Mid-360 packets over UDP on this host),
// ucon-lidar-driver and ucon-perception as separate processes over LCM for 30 s of
// simulation time. PERCEPTION_OBJECTS must arrive at the LiDAR frame rate, valid, with the
// pedestrians tracked under a few stable identities.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "../support/test_support.hpp"

namespace {

// LCM and UDP ports of this test (the perception tests use 7780-7799).
constexpr const char* kUrl = "udpm://239.255.76.67:7780?ttl=0";

std::string readFile(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Replaces `key: <number>` (first occurrence after `section:` if given) with `key: value`.
void setKey(std::string& yaml, const std::string& key, const std::string& value) {
  const std::string k = " " + key + ":";
  const auto pos = yaml.find(k);
  ASSERT_NE(pos, std::string::npos) << key;
  const auto start = pos + k.size();
  auto end = yaml.find_first_of("#\n", start);
  yaml.replace(start, end - start, " " + value + " ");
}

using ucon::test::spawn;

struct Receiver {
  int messages = 0, valid = 0;
  int64_t first_utime = 0, last_utime = 0;
  std::map<int64_t, int> confirmed_frames_by_id;
  int frames_with_confirmed = 0;
  void on(const lcm::ReceiveBuffer*, const std::string&, const ucon::tracked_objects_t* m) {
    ++messages;
    if (!m->valid) return;
    ++valid;
    if (first_utime == 0) first_utime = m->utime;
    last_utime = m->utime;
    bool any = false;
    for (const auto& o : m->objects) {
      if (o.state != ucon::tracked_object_t::STATE_CONFIRMED) continue;
      ++confirmed_frames_by_id[o.id];
      any = true;
    }
    frames_with_confirmed += any ? 1 : 0;
  }
};

}  // namespace

TEST(PerceptionProcesses, GivenSimulatorDriverAndPerceptionOverLcmThenObjectsArriveAtFrameRateWithStableIds) {
  const std::string src = UCON_SOURCE_DIR, bin = UCON_BIN_DIR;
  const std::string tmp = "/tmp/ucon_test_perception_proc_" + std::to_string(::getpid());
  ASSERT_EQ(std::system(("mkdir -p " + tmp).c_str()), 0);
  // Private UDP ports so that parallel tests cannot collide with the default 563xx ones.
  std::string sim = readFile(src + "/deploy/config/simulator.yaml");
  setKey(sim, "host_point_port", "7786");
  setKey(sim, "host_imu_port", "7787");
  setKey(sim, "discovery_port", "7782");
  setKey(sim, "command_port", "7783");
  setKey(sim, "point_src_port", "7784");
  setKey(sim, "imu_src_port", "7785");
  std::string drv = readFile(src + "/deploy/config/lidar_driver.yaml");
  setKey(drv, "discovery_port", "7782");
  setKey(drv, "host_push_port", "7789");
  setKey(drv, "sensor_command_port", "7783");
  setKey(drv, "sensor_point_port", "7784");
  setKey(drv, "sensor_imu_port", "7785");
  setKey(drv, "host_point_port", "7786");
  setKey(drv, "host_imu_port", "7787");
  setKey(drv, "host_command_port", "7788");
  std::ofstream(tmp + "/simulator.yaml") << sim;
  std::ofstream(tmp + "/lidar_driver.yaml") << drv;

  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good());
  Receiver rx;
  lcm.subscribe(ucon::channels::kPerceptionObjects, &Receiver::on, &rx);

  const std::string url = std::string("--lcm-url=") + kUrl;
  const pid_t perc = spawn({bin + "/ucon-perception", "--config", src + "/deploy/config/perception.yaml", url},
                           tmp + "/perception.log");
  const pid_t drvp = spawn({bin + "/ucon-lidar-driver", "--config", tmp + "/lidar_driver.yaml", url}, tmp + "/driver.log");
  usleep(500000);
  const pid_t simp = spawn({bin + "/ucon-simulator", "--config", tmp + "/simulator.yaml", "--scenario", "pedestrians",
                            "--scenario-dir", src + "/deploy/scenarios", "--rate", "1.0", "--duration", "30", url},
                           tmp + "/simulator.log");
  const auto t_end = std::chrono::steady_clock::now() + std::chrono::seconds(45);
  int sim_status = 0;
  bool sim_done = false;
  while (std::chrono::steady_clock::now() < t_end) {
    lcm.handleTimeout(50);
    if (!sim_done && waitpid(simp, &sim_status, WNOHANG) == simp) sim_done = true;
    if (sim_done && rx.valid > 0) {
      // Drain what is still in flight, then stop.
      for (int i = 0; i < 20; ++i) lcm.handleTimeout(50);
      break;
    }
  }
  for (pid_t p : {simp, drvp, perc}) kill(p, SIGTERM);
  for (pid_t p : {simp, drvp, perc}) waitpid(p, nullptr, 0);

  const double span_s = static_cast<double>(rx.last_utime - rx.first_utime) * 1e-6;
  SCOPED_TRACE("logs in " + tmp);
  std::printf("PERCEPTION_OBJECTS: %d messages, %d valid over %.1f s of sensor time, %d with a confirmed "
              "object, %zu confirmed ids\n", rx.messages, rx.valid, span_s, rx.frames_with_confirmed,
              rx.confirmed_frames_by_id.size());
  EXPECT_TRUE(sim_done) << "simulator did not finish its 30 s";
  EXPECT_GT(span_s, 25.0);
  // 50 Hz frames; allow for start-up and a loaded machine.
  EXPECT_GT(rx.valid, static_cast<int>(0.85 * 50.0 * span_s)) << rx.valid << " valid in " << span_s << " s";
  // Pedestrians are tracked most of the time, by a few long-lived identities.
  EXPECT_GT(rx.frames_with_confirmed, rx.valid / 2);
  int long_lived = 0;
  for (const auto& [id, n] : rx.confirmed_frames_by_id) long_lived += n >= 250 ? 1 : 0;  // >= 5 s
  EXPECT_GE(long_lived, 2);
  EXPECT_LE(rx.confirmed_frames_by_id.size(), 20u);
}
