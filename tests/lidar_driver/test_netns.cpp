// The driver against emulated Mid-360s on a real (virtual) Ethernet link, as on the robot:
// two network namespaces joined by a veth pair, the host side 192.168.1.50/24, the sensor side
// 192.168.1.100 (and .101), the Mid-360's own ports. The sensor side answers discovery by
// broadcast (a socket bound to the host's unicast address would never see that answer); the
// driver finds the sensors, configures them and streams. deploy/ucon record-sensor captures the
// traffic meanwhile, and ucon-lidar-driver --pcap plays the capture back: the frames equal the
// live ones. Needs root (CI runs as root): skipped otherwise. Namespaces ucon-mid-<h|s><pid>,
// removed at the end; LCM udpm ports 7733-7736 (inside the namespaces).
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../support/test_support.hpp"
#include "ucon/lidar_driver/captured_udp.hpp"
#include "ucon/lidar_driver/pcap_reader.hpp"
#include "ucon/livox/control.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/process_status_t.hpp"
#include "ucon/runtime/config_file.hpp"

namespace ld = ucon::lidar_driver;
namespace livox = ucon::livox;

namespace {

std::string readFile(const std::string& path) {
  return ucon::runtime::readTextFile(path, nullptr).value_or("");
}

int sh(const std::string& cmd) { return std::system((cmd + " >/dev/null 2>&1").c_str()); }

// Programs found on PATH (ip, bash) as well as built ones.
pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> a = {"/usr/bin/env"};
  a.insert(a.end(), args.begin(), args.end());
  return ucon::test::spawn(a, log);
}

int stop(pid_t pid, int sig, double limit_s) {
  if (pid <= 0) return -1;
  kill(pid, sig);
  return ucon::test::waitExit(pid, limit_s);
}

// Replaces the text after `key:` on the first line that has it (keeps the comment).
void setKey(std::string& yaml, const std::string& key, const std::string& value) {
  const std::string k = key + ":";
  const auto pos = yaml.find(k);
  ASSERT_NE(pos, std::string::npos) << key;
  const auto start = pos + k.size();
  const auto end = yaml.find_first_of("#\n", start);
  yaml.replace(start, end - start, " " + value + " ");
}

struct Frames {
  std::map<int64_t, std::vector<uint8_t>> by_utime;  // encoded frame per utime
  std::vector<ucon::point_cloud_t> clouds;
  std::map<std::string, int64_t> status;
  void onCloud(const lcm::ReceiveBuffer* rb, const std::string&, const ucon::point_cloud_t* c) {
    const auto* d = static_cast<const uint8_t*>(rb->data);
    by_utime[c->utime] = std::vector<uint8_t>(d, d + rb->data_size);
    clouds.push_back(*c);
  }
  void onStatus(const lcm::ReceiveBuffer*, const std::string&, const ucon::process_status_t* s) {
    for (int i = 0; i < s->num_counters; ++i) status[s->counter_names[i]] = s->counter_values[i];
  }
};

// Two namespaces and a veth pair; the test process itself moves into the host side (so its
// LCM sees the driver's traffic), and back at the end.
class NetnsLink : public ::testing::Test {
 protected:
  void SetUp() override {
    if (geteuid() != 0) GTEST_SKIP() << "needs root to create network namespaces (CI runs as root)";
    if (sh("command -v ip") != 0) GTEST_SKIP() << "needs iproute2's ip";
    const std::string id = std::to_string(getpid());
    host_ = "ucon-mid-h" + id;
    sensor_ = "ucon-mid-s" + id;
    veth_h_ = "umh" + std::to_string(getpid() % 1000000);
    veth_s_ = "ums" + std::to_string(getpid() % 1000000);
    tmp_ = ::testing::TempDir() + "netns_" + id + "/";
    ASSERT_EQ(sh("mkdir -p " + tmp_), 0);
    created_ = true;
    const std::vector<std::string> setup = {
        "ip netns add " + host_, "ip netns add " + sensor_,
        "ip link add " + veth_h_ + " type veth peer name " + veth_s_,
        "ip link set " + veth_h_ + " netns " + host_, "ip link set " + veth_s_ + " netns " + sensor_,
        "ip -n " + host_ + " addr add 192.168.1.50/24 dev " + veth_h_,
        "ip -n " + sensor_ + " addr add 192.168.1.100/24 dev " + veth_s_,
        "ip -n " + sensor_ + " addr add 192.168.1.101/24 dev " + veth_s_,
    };
    for (const auto& c : setup) ASSERT_EQ(sh(c), 0) << c;
    for (const auto& ns : {host_, sensor_}) {
      ASSERT_EQ(sh("ip -n " + ns + " link set lo up"), 0);
      ASSERT_EQ(sh("ip -n " + ns + " link set lo multicast on"), 0);
      ASSERT_EQ(sh("ip -n " + ns + " route add 224.0.0.0/4 dev lo"), 0);
    }
    ASSERT_EQ(sh("ip -n " + host_ + " link set " + veth_h_ + " up"), 0);
    ASSERT_EQ(sh("ip -n " + sensor_ + " link set " + veth_s_ + " up"), 0);
    home_ns_ = open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
    ASSERT_GE(home_ns_, 0);
  }

  void TearDown() override {
    for (pid_t p : pids_) stop(p, SIGKILL, 2.0);
    if (home_ns_ >= 0) {
      setns(home_ns_, CLONE_NEWNET);
      close(home_ns_);
    }
    if (created_) {
      sh("ip netns del " + host_);
      sh("ip netns del " + sensor_);
    }
  }

  void enterHost() {
    const int fd = open(("/run/netns/" + host_).c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(setns(fd, CLONE_NEWNET), 0);
    close(fd);
  }

  // The shipped configs on this link: host 192.168.1.50, sensors 192.168.1.100 (and .101).
  std::string driverConfig(bool two) {
    std::string y = readFile("deploy/config/lidar_driver.yaml");
    setKey(y, "host_ip", "\"192.168.1.50\"");
    setKey(y, "  - ip", "\"192.168.1.100\"");
    setKey(y, "retry_interval_s", "0.3");
    if (two) {
      const auto at = y.find("status_period_s:");
      y.insert(at, "  - ip: \"192.168.1.101\"\n    xyz: [-0.3, 0.0, 0.4]\n    rpy_deg: [0.0, 0.0, 180.0]\n"
                   "    imu: false\n");
    }
    const std::string path = tmp_ + (two ? "drv2.yaml" : "drv1.yaml");
    std::ofstream(path) << y;
    return path;
  }
  std::string simConfig(bool two) {
    std::string y = readFile("deploy/config/simulator.yaml");
    setKey(y, "  host_ip", "192.168.1.50");
    setKey(y, "  sensor_ip", "192.168.1.100");
    if (two) {
      const auto at = y.find("extra_lidars: []");
      y.replace(at, 16, "extra_lidars:\n  - sensor_ip: 192.168.1.101\n    serial: SIM360REAR\n"
                        "    mount_xyz: [-0.3, 0.0, 0.4]\n    mount_rpy_deg: [0.0, 0.0, 180.0]\n    seed: 5");
    }
    const std::string path = tmp_ + (two ? "sim2.yaml" : "sim1.yaml");
    std::ofstream(path) << y;
    return path;
  }

  // Runs the simulator in the sensor namespace for `seconds` with the driver (and optionally a
  // capture) in the host namespace, the test listening there. Returns the driver's log.
  std::string runLive(bool two, double seconds, const std::string& url, Frames& rx, const std::string& pcap) {
    enterHost();
    const std::string bin = UCON_BIN_DIR;
    pid_t cap = -1;
    if (!pcap.empty()) {
      cap = spawn({"bash", "deploy/ucon", "record-sensor", "--interface", veth_h_, "--output", pcap},
                  tmp_ + "capture.log");
      pids_.push_back(cap);
      std::this_thread::sleep_for(std::chrono::milliseconds(800));  // tcpdump is listening
    }
    lcm::LCM lcm(url);
    EXPECT_TRUE(lcm.good());
    lcm.subscribe("LIDAR_POINTS", &Frames::onCloud, &rx);
    lcm.subscribe("LIDAR_STATUS", &Frames::onStatus, &rx);
    const std::string drv_log = tmp_ + (two ? "drv2.log" : "drv1.log");
    const pid_t drv = spawn({bin + "/ucon-lidar-driver", "--config", driverConfig(two), "--lcm-url", url}, drv_log);
    pids_.push_back(drv);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const pid_t sim = spawn({"ip", "netns", "exec", sensor_, bin + "/ucon-simulator", "--config", simConfig(two),
                             "--scenario", "crossing", "--duration", std::to_string(seconds), "--rate", "1.0",
                             "--lcm-url", "udpm://239.255.76.67:7736?ttl=0"},
                            tmp_ + (two ? "sim2.log" : "sim1.log"));
    pids_.push_back(sim);
    const auto t0 = std::chrono::steady_clock::now();
    int st = 0;
    bool sim_done = false;
    while (std::chrono::steady_clock::now() - t0 < std::chrono::duration<double>(seconds + 15.0)) {
      lcm.handleTimeout(20);
      if (waitpid(sim, &st, WNOHANG) == sim) {
        sim_done = true;
        break;
      }
    }
    EXPECT_TRUE(sim_done) << readFile(tmp_ + "sim1.log");
    if (sim_done) pids_.erase(std::find(pids_.begin(), pids_.end(), sim));
    for (auto t = std::chrono::steady_clock::now(); std::chrono::steady_clock::now() - t < std::chrono::milliseconds(700);) {
      lcm.handleTimeout(20);  // the idle flush of the last frame, a status message
    }
    EXPECT_EQ(stop(drv, SIGTERM, 5.0), 0) << readFile(drv_log);
    pids_.erase(std::find(pids_.begin(), pids_.end(), drv));
    for (int i = 0; i < 10; ++i) lcm.handleTimeout(20);
    if (cap > 0) {
      stop(cap, SIGINT, 5.0);
      pids_.erase(std::find(pids_.begin(), pids_.end(), cap));
    }
    return readFile(drv_log);
  }

  std::string host_, sensor_, veth_h_, veth_s_, tmp_;
  bool created_ = false;
  int home_ns_ = -1;
  std::vector<pid_t> pids_;
};

}  // namespace

TEST_F(NetnsLink, GivenASensorAnsweringDiscoveryByBroadcastThenTheDriverFindsItStreamsAndTheCaptureReplaysTheSame) {
  Frames live;
  const std::string pcap = tmp_ + "sensor.pcap";
  const std::string log = runLive(false, 4.0, "udpm://239.255.76.67:7733?ttl=0", live, pcap);
  ASSERT_NE(log.find("configured"), std::string::npos) << log;
  // 4 s at 50 Hz, 4000 points decoded per frame from one sensor.
  EXPECT_GE(live.clouds.size(), 150u) << log;
  ASSERT_FALSE(live.clouds.empty());
  EXPECT_EQ(live.status["crc_errors"], 0);
  EXPECT_EQ(live.status["malformed"], 0);
  EXPECT_GE(live.status["imu_packets"], 600);
  EXPECT_EQ(live.clouds[live.clouds.size() / 2].num_sensors, 1);
  EXPECT_EQ(live.clouds[live.clouds.size() / 2].sensor_id, (int64_t{192} << 24) | (int64_t{168} << 16) | (int64_t{1} << 8) | 100);

  // The capture shows the sensor's discovery answer going to the broadcast address.
  std::string err;
  auto reader = ld::PcapReader::open(pcap, &err);
  ASSERT_TRUE(reader) << err << "\n" << readFile(tmp_ + "capture.log");
  int broadcast_answers = 0, requests = 0, point_packets = 0;
  ld::PcapReader::Frame f;
  while (reader->next(f, &err) == 1) {
    const auto udp = ld::extractUdp(reader->linkType(), f.data, f.caplen, nullptr);
    if (!udp) continue;
    if (udp->dst_port == 56301) ++point_packets;
    if (udp->dst_port != 56000) continue;
    livox::ControlFrame cf;
    if (livox::decodeControlFrame(udp->payload, udp->size, cf) != livox::ControlStatus::kOk) continue;
    if (cf.cmd_type == 0 && udp->src_ip == std::array<uint8_t, 4>{192, 168, 1, 50}) ++requests;
    if (livox::parseDiscoveryAck(cf) && udp->src_ip == std::array<uint8_t, 4>{192, 168, 1, 100} &&
        udp->dst_ip == std::array<uint8_t, 4>{255, 255, 255, 255} && udp->src_port == 56000) {
      ++broadcast_answers;
    }
  }
  EXPECT_GE(requests, 1);
  EXPECT_GE(broadcast_answers, 1);
  EXPECT_GT(point_packets, 7000);

  // The capture through --pcap: the same parser and frame assembly give the same frames.
  Frames replay;
  {
    const std::string url = "udpm://239.255.76.67:7734?ttl=0";
    lcm::LCM lcm(url);
    ASSERT_TRUE(lcm.good());
    lcm.subscribe("LIDAR_POINTS", &Frames::onCloud, &replay);
    const std::string rlog = tmp_ + "replay.log";
    const pid_t rp = spawn({std::string(UCON_BIN_DIR) + "/ucon-lidar-driver", "--config", driverConfig(false), "--pcap",
                            pcap, "--speed", "1", "--lcm-url", url},
                           rlog);
    pids_.push_back(rp);
    int st = 0;
    bool done = false;
    for (auto t = std::chrono::steady_clock::now(); std::chrono::steady_clock::now() - t < std::chrono::seconds(30);) {
      lcm.handleTimeout(20);
      if (waitpid(rp, &st, WNOHANG) == rp) {
        done = true;
        break;
      }
    }
    ASSERT_TRUE(done);
    pids_.pop_back();
    for (int i = 0; i < 10; ++i) lcm.handleTimeout(20);
    EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << readFile(rlog);
  }
  std::size_t same = 0, differ = 0;
  std::string differing;
  for (const auto& [utime, bytes] : replay.by_utime) {
    const auto it = live.by_utime.find(utime);
    if (it == live.by_utime.end()) continue;
    if (it->second == bytes) {
      ++same;
    } else {
      ++differ;
      differing += " utime " + std::to_string(utime) + " (live " + std::to_string(it->second.size()) + " B, replay " +
                   std::to_string(bytes.size()) + " B; first live " + std::to_string(live.by_utime.begin()->first) +
                   ", last live " + std::to_string(live.by_utime.rbegin()->first) + ")";
    }
  }
  EXPECT_EQ(differ, 0u) << differing;
  EXPECT_GE(same, live.by_utime.size() * 95 / 100) << "replayed " << replay.by_utime.size() << ", live "
                                                    << live.by_utime.size();
  EXPECT_GE(static_cast<double>(replay.by_utime.size()), 0.95 * static_cast<double>(live.by_utime.size()));
}

TEST_F(NetnsLink, GivenTwoSensorsThenEachPeriodIsOneFrameInTheBodyFrameWithPointsOfBoth) {
  Frames live;
  const std::string log = runLive(true, 3.0, "udpm://239.255.76.67:7735?ttl=0", live, "");
  ASSERT_NE(log.find("sensor 1: Mid-360 SIM360REAR at 192.168.1.101 configured"), std::string::npos) << log;
  ASSERT_GE(live.clouds.size(), 100u) << log;
  EXPECT_EQ(live.status["imu_ignored"], 0) << "the rear sensor's IMU was turned off";
  int64_t both = 0;
  for (std::size_t i = 1; i + 1 < live.clouds.size(); ++i) {
    const auto& c = live.clouds[i];
    ASSERT_EQ(c.num_sensors, 2);
    ASSERT_EQ(c.num_point_sensors, c.num_points);
    EXPECT_FLOAT_EQ(c.origin_x[1], -0.3f);
    std::set<int> seen(c.point_sensor.begin(), c.point_sensor.end());
    both += seen.size() == 2 ? 1 : 0;
  }
  EXPECT_GE(both, static_cast<int64_t>(live.clouds.size()) - 5) << "frames merge both sensors' points";
  EXPECT_GE(live.status["packets_s1"], 5000);
  // A sensor's points that arrive after its frame was published (merge_wait_s of sensor time)
  // are counted and dropped: on a busy machine a few packets of the simulator lag that much.
  EXPECT_LE(live.status["points_late"], live.status["points"] / 100) << "of " << live.status["points"];
}
