// ucon-simulator as a process: Livox packets arrive over loopback UDP and parse, the control
// port answers discovery, ROBOT_POSE arrives over LCM, --duration ends it cleanly; bad
// configuration or scenario give a clear error and a non-zero exit.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <thread>

#include "ucon/livox/protocol.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/runtime/config_file.hpp"
#include "../support/test_support.hpp"

namespace {

// Ports of this test (tests/simulator uses 27100-27199 for UDP, 7700-7719 for LCM). Tests bind UDP
// ports below Linux's ephemeral range (32768-60999): a port in it can be held at any moment by
// another process's automatically bound socket (an LCM sender), and the bind then fails.
constexpr int kPointPort = 27110, kImuPort = 27111, kDiscoveryPort = 27112, kCommandPort = 27113;
constexpr int kHostCommandPort = 27114;
const char* kLcmUrl = "udpm://239.255.76.67:7702?ttl=0";

// Bound to 127.0.0.1, or (any_address) to 0.0.0.0: a Mid-360 answers discovery by broadcast,
// which Linux delivers only to a socket bound to the any-address.
int udpSocket(int port, bool any_address = false) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  const int buf = 8 * 1024 * 1024;
  setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &buf, sizeof(buf));
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(any_address ? INADDR_ANY : INADDR_LOOPBACK);
  if (bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    close(fd);
    return -1;
  }
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) | O_NONBLOCK);
  return fd;
}

std::string writeConfig() {
  std::string err;
  std::string text = *ucon::runtime::readTextFile("deploy/config/simulator.yaml", &err);
  auto set = [&](const std::string& key, const std::string& value) {
    const auto pos = text.find(key + ":");
    ASSERT_NE(pos, std::string::npos) << key;
    const auto end = text.find('#', pos) != std::string::npos && text.find('#', pos) < text.find('\n', pos)
                         ? text.find('#', pos)
                         : text.find('\n', pos);
    text.replace(pos, end - pos, key + ": " + value + " ");
  };
  set("host_point_port", std::to_string(kPointPort));
  set("host_imu_port", std::to_string(kImuPort));
  set("discovery_port", std::to_string(kDiscoveryPort));
  set("command_port", std::to_string(kCommandPort));
  set("point_src_port", "0");
  set("imu_src_port", "0");
  const std::string path = "/tmp/ucon_test_simulator_process_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

using ucon::test::spawn;

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

struct PoseCounter {
  int n = 0;
  int64_t last_utime = 0;
  void on(const lcm::ReceiveBuffer*, const std::string&, const ucon::robot_pose_t* m) {
    ++n;
    last_utime = m->utime;
  }
};

}  // namespace

TEST(SimulatorProcess, GivenTwoSecondsAtRealTimeThenPacketsPosesAndControlAcksArrive) {
  const int pts = udpSocket(kPointPort), imu = udpSocket(kImuPort), host = udpSocket(kHostCommandPort, true);
  ASSERT_GE(pts, 0);
  ASSERT_GE(imu, 0);
  ASSERT_GE(host, 0);
  lcm::LCM lcm(kLcmUrl);
  ASSERT_TRUE(lcm.good());
  PoseCounter poses;
  lcm.subscribe("ROBOT_POSE", &PoseCounter::on, &poses);
  const std::string cfg = writeConfig();
  const std::string log = cfg + ".log";
  const pid_t pid = spawn({std::string(UCON_BIN_DIR) + "/ucon-simulator", "--config", cfg, "--scenario",
                           "pedestrians", "--duration", "2", "--lcm-url", kLcmUrl},
                          log);
  ASSERT_GT(pid, 0);

  std::vector<uint8_t> buf(65536);
  ucon::livox::ParsedPacket pk;
  int point_packets = 0, imu_packets = 0, bad = 0, acks = 0;
  uint64_t last_ts = 0;
  bool sent_discovery = false;
  const auto t0 = std::chrono::steady_clock::now();
  int status = -1;
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(10)) {
    ssize_t n;
    while ((n = recv(pts, buf.data(), buf.size(), 0)) > 0) {
      if (ucon::livox::parsePacket(buf.data(), static_cast<std::size_t>(n), pk) == ucon::livox::ParseStatus::kOk &&
          pk.header.data_type == 1 && pk.points.size() == 96 && pk.header.timestamp_ns > last_ts) {
        ++point_packets;
        last_ts = pk.header.timestamp_ns;
      } else {
        ++bad;
      }
    }
    while ((n = recv(imu, buf.data(), buf.size(), 0)) > 0) {
      if (ucon::livox::parsePacket(buf.data(), static_cast<std::size_t>(n), pk) == ucon::livox::ParseStatus::kOk &&
          pk.header.data_type == 0)
        ++imu_packets;
      else
        ++bad;
    }
    if (!sent_discovery && point_packets > 100) {
      const auto req = ucon::livox::encodeControlFrame(ucon::livox::makeDiscoveryRequest(42));
      sockaddr_in to{};
      to.sin_family = AF_INET;
      to.sin_port = htons(kDiscoveryPort);
      to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
      sendto(host, req.data(), req.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
      sent_discovery = true;
    }
    while ((n = recv(host, buf.data(), buf.size(), 0)) > 0) {
      ucon::livox::ControlFrame f;
      if (ucon::livox::decodeControlFrame(buf.data(), static_cast<std::size_t>(n), f) == ucon::livox::ControlStatus::kOk &&
          ucon::livox::parseDiscoveryAck(f) && f.seq == 42)
        ++acks;
    }
    lcm.handleTimeout(2);
    if (waitpid(pid, &status, WNOHANG) == pid) {
      // Drain what is still queued.
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      while ((n = recv(pts, buf.data(), buf.size(), 0)) > 0) ++point_packets;
      while ((n = recv(imu, buf.data(), buf.size(), 0)) > 0) ++imu_packets;
      while (lcm.handleTimeout(10) > 0) {
      }
      break;
    }
  }
  close(pts);
  close(imu);
  close(host);
  const std::string out = slurp(log);
  ASSERT_TRUE(WIFEXITED(status)) << out;
  EXPECT_EQ(WEXITSTATUS(status), 0) << out;
  // 2 s of simulation: 4167 point packets, 401 IMU packets, 201 poses.
  EXPECT_GE(point_packets, 4160) << out;
  EXPECT_LE(point_packets, 4167);
  EXPECT_GE(imu_packets, 400);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(acks, 1);
  EXPECT_GE(poses.n, 195);
  EXPECT_EQ(poses.last_utime, 1000000 + 2000000);
  EXPECT_NE(out.find("difficulty from ground truth: close passes"), std::string::npos) << out;
  std::remove(cfg.c_str());
  std::remove(log.c_str());
}

TEST(SimulatorProcess, GivenABadScenarioOrConfigThenItExitsNonZeroAndSaysWhy) {
  const std::string log = "/tmp/ucon_test_simulator_bad_" + std::to_string(getpid()) + ".log";
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"--scenario", "bench:abc:1"},
           {"--scenario", "/nonexistent/world.yaml"},
           {"--config", "/nonexistent/simulator.yaml"}}) {
    std::vector<std::string> a = {std::string(UCON_BIN_DIR) + "/ucon-simulator", "--lcm-url", kLcmUrl};
    a.insert(a.end(), args.begin(), args.end());
    const pid_t pid = spawn(a, log);
    int status = 0;
    waitpid(pid, &status, 0);
    const std::string out = slurp(log);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_NE(WEXITSTATUS(status), 0) << out;
    EXPECT_NE(out.find(args[1]), std::string::npos) << out;
    EXPECT_NE(out.find("error"), std::string::npos) << out;
  }
  std::remove(log.c_str());
}
