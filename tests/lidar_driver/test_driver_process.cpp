// ucon-lidar-driver as a process: no sensor answering -> clear error and exit 1 within the
// timeout; a fake Mid-360 on loopback is configured and its packets come out as LIDAR_POINTS
// frames on LCM; SIGTERM -> clean exit 0. Ports: UDP 27000-27029, LCM 7720-7722.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "ucon/lidar_driver/udp_socket.hpp"
#include "ucon/livox/protocol.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/process_status_t.hpp"

extern char** environ;

namespace ld = ucon::lidar_driver;
namespace livox = ucon::livox;

namespace {

std::string configText(int base_port, double timeout_s) {
  std::ostringstream y;
  y << "network:\n"
    << "  host_ip: \"127.0.0.1\"\n  discovery: false\n"
    << "  discovery_address: \"127.0.0.1\"\n"
    << "  discovery_port: " << base_port + 0 << "\n"
    << "  sensor_command_port: " << base_port + 1 << "\n"
    << "  sensor_push_port: " << base_port + 7 << "\n"
    << "  sensor_point_port: " << base_port + 2 << "\n"
    << "  sensor_imu_port: " << base_port + 3 << "\n"
    << "  host_command_port: " << base_port + 4 << "\n"
    << "  host_push_port: " << base_port + 8 << "\n"
    << "  host_point_port: " << base_port + 5 << "\n"
    << "  host_imu_port: " << base_port + 6 << "\n"
    << "  socket_buffer_bytes: 2097152\n"
    << "control:\n  enabled: true\n  timeout_s: " << timeout_s << "\n  retry_interval_s: 0.2\n"
    << "  work_mode: sampling\n  point_data_type: 1\n  reset_install_attitude: true\n"
    << "  reconfigure_after_s: 30\n"
    << "frame:\n  rate_hz: 50\n  max_points: 200000\n  idle_flush_s: 0.2\n  apply_extrinsic: false\n"
    << "  merge_wait_s: 0.05\n"
    << "filter:\n  min_range_m: 0.1\n  max_range_m: 70\n  drop_sticking_level: 0\n"
    << "  drop_rain_fog_dust_level: 0\n  drop_other_noise_level: 0\n"
    << "sensors:\n  - ip: \"127.0.0.1\"\n    xyz: [0, 0, 0]\n    rpy_deg: [0, 0, 0]\n    imu: true\n"
    << "status_period_s: 0.2\n";
  return y.str();
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Starts the driver with stdout+stderr to `log`; returns its pid.
pid_t spawnDriver(const std::string& config, const std::string& url, const std::string& log) {
  const std::string bin = std::string(UCON_BIN_DIR) + "/ucon-lidar-driver";
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  std::vector<std::string> args = {bin, "--config", config, "--lcm-url", url};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, bin.c_str(), &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

// Waits up to `limit_s` for `pid`; returns its exit status (or -1 on timeout, after killing it).
int waitFor(pid_t pid, double limit_s, double* elapsed_s) {
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    int st = 0;
    if (waitpid(pid, &st, WNOHANG) == pid) {
      *elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > limit_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      *elapsed_s = limit_s;
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace

TEST(LidarDriverProcess, GivenNoSensorAnsweringThenItExitsNonZeroWithinTheTimeoutNamingWhatToCheck) {
  const std::string cfg = writeTemp("ld_nosensor.yaml", configText(27000, 1.0));
  const std::string log = ::testing::TempDir() + "ld_nosensor.log";
  const pid_t pid = spawnDriver(cfg, "udpm://239.255.76.67:7720?ttl=0", log);
  ASSERT_GT(pid, 0);
  double elapsed = 0;
  const int code = waitFor(pid, 10.0, &elapsed);
  const std::string out = readFile(log);
  EXPECT_EQ(code, 1) << out;
  EXPECT_LT(elapsed, 3.0) << "timeout_s is 1.0";
  EXPECT_NE(out.find("error"), std::string::npos) << out;
  EXPECT_NE(out.find("not every Mid-360 is configured"), std::string::npos) << out;
  EXPECT_NE(out.find("127.0.0.1:27001"), std::string::npos) << out;
  EXPECT_NE(out.find("ucon-simulator"), std::string::npos) << out;
}

TEST(LidarDriverProcess, GivenABadConfigThenItExitsWithCode2NamingTheKey) {
  std::string text = configText(27010, 1.0);
  text.replace(text.find("rate_hz: 50"), 11, "rate_hz: 33");
  const std::string cfg = writeTemp("ld_badcfg.yaml", text);
  const std::string log = ::testing::TempDir() + "ld_badcfg.log";
  const pid_t pid = spawnDriver(cfg, "udpm://239.255.76.67:7720?ttl=0", log);
  ASSERT_GT(pid, 0);
  double elapsed = 0;
  EXPECT_EQ(waitFor(pid, 10.0, &elapsed), 2);
  EXPECT_NE(readFile(log).find("frame.rate_hz"), std::string::npos) << readFile(log);
}

namespace {
struct Received {
  std::atomic<int> frames{0};
  std::atomic<int64_t> points{0};
  std::atomic<int> statuses{0};
  std::atomic<int64_t> last_lost{-1};
  std::atomic<int64_t> status_packets{0};
  int32_t first_frame_points = 0;
  void onCloud(const lcm::ReceiveBuffer*, const std::string&, const ucon::point_cloud_t* c) {
    if (frames == 0) first_frame_points = c->num_points;
    ++frames;
    points += c->num_points;
  }
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const ucon::process_status_t* s) {
    ++statuses;
    for (int i = 0; i < s->num_counters; ++i) {
      if (s->counter_names[i] == "packets") status_packets = s->counter_values[i];
      if (s->counter_names[i] == "lost_packets") last_lost = s->counter_values[i];
    }
  }
};
}  // namespace

TEST(LidarDriverProcess, GivenAFakeSensorThenItIsConfiguredAndItsPacketsBecomeFramesOnLcm) {
  const int base = 27020;
  const std::string url = "udpm://239.255.76.67:7721?ttl=0";
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good());
  Received rx;
  lcm.subscribe("LIDAR_POINTS", &Received::onCloud, &rx);
  lcm.subscribe("LIDAR_STATUS", &Received::onStatus, &rx);

  // Fake Mid-360: answers the configuration on its command port, then streams from its
  // point port to the host port it was told.
  std::string err, warn;
  auto cmd = ld::UdpSocket::open("127.0.0.1", base + 1, 0, &err, &warn);
  ASSERT_TRUE(cmd) << err;
  auto data = ld::UdpSocket::open("127.0.0.1", base + 2, 0, &err, &warn);
  ASSERT_TRUE(data) << err;
  std::atomic<int> host_point_port{0};
  std::atomic<bool> work_mode_set{false};
  std::atomic<bool> stop{false};
  std::thread sensor([&] {
    while (!stop) {
      const int n = cmd->receiveBatch();
      for (int i = 0; i < n; ++i) {
        livox::ControlFrame f;
        if (livox::decodeControlFrame(cmd->data(i), cmd->size(i), f) != livox::ControlStatus::kOk) continue;
        auto kvs = livox::parseSetKeyValueRequest(f);
        if (!kvs) continue;
        for (const auto& kv : *kvs) {
          if (kv.key == static_cast<uint16_t>(livox::Key::kPointDataHostIpConfig)) {
            host_point_port = livox::parseHostIpConfig(kv)->host_port;
          }
          if (kv.key == static_cast<uint16_t>(livox::Key::kWorkMode)) work_mode_set = true;
        }
        const auto ack = livox::encodeControlFrame(livox::makeSetKeyValueAck(f.seq, {}));
        cmd->sendTo(cmd->sourceIp(i), cmd->sourcePort(i), ack.data(), ack.size());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });

  const std::string cfg = writeTemp("ld_fake.yaml", configText(base, 5.0));
  const std::string log = ::testing::TempDir() + "ld_fake.log";
  const pid_t pid = spawnDriver(cfg, url, log);
  ASSERT_GT(pid, 0);
  for (int i = 0; i < 300 && !work_mode_set; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(host_point_port, base + 5) << readFile(log);
  ASSERT_TRUE(work_mode_set) << readFile(log);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // driver enters its data loop

  // 0.2 s of sensor time at 200 000 points/s from t = 50 s (a frame boundary): 10 frames of
  // 4000 points; packet 100 is dropped on purpose. Sent in bursts of 10 packets per ms.
  std::vector<livox::LidarPoint> pts(96, livox::LidarPoint{3.0f, 1.0f, 0.5f, 100, 0});
  std::vector<uint8_t> b;
  const int packets = 417;  // 417 * 96 = 40032 points: the last 32 open frame 11
  for (int k = 0; k < packets; ++k) {
    if (k == 100) continue;
    livox::PacketInfo info;
    info.timestamp_ns = 50'000'000'000ull + static_cast<uint64_t>(k) * 96 * 5000;
    info.time_interval = 4800;
    info.udp_cnt = static_cast<uint16_t>(k);
    info.time_type = livox::TimeType::kPtp;
    livox::encodePointPacket(info, livox::DataType::kCartesianHigh, pts, b);
    data->sendTo({127, 0, 0, 1}, static_cast<uint16_t>(host_point_port.load()), b.data(), b.size());
    if (k % 10 == 9) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  // Frames, the idle flush of the last partial frame, and a status message.
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(3) &&
         (rx.frames < 11 || rx.status_packets < packets - 1)) {
    lcm.handleTimeout(50);
  }
  kill(pid, SIGTERM);
  double elapsed = 0;
  const int code = waitFor(pid, 5.0, &elapsed);
  stop = true;
  sensor.join();
  const std::string out = readFile(log);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("configured"), std::string::npos) << out;
  EXPECT_EQ(rx.frames, 11) << out;
  EXPECT_EQ(rx.points, (packets - 1) * 96);
  EXPECT_EQ(rx.first_frame_points, 4000);
  EXPECT_GE(rx.statuses, 1);
  EXPECT_EQ(rx.status_packets, packets - 1);
  EXPECT_EQ(rx.last_lost, 1);
}
