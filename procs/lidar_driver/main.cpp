// ucon-lidar-driver: Livox Mid-360 over UDP -> LIDAR_POINTS, LIDAR_IMU, LIDAR_STATUS.
//
// The node (LidarDriverNode) holds the logic; this file moves bytes. The loop differs from the
// LCM-driven one of other processes because the input is UDP: poll() waits on the two data
// sockets (and the LCM socket, to keep it drained), recvmmsg drains each in batches.
#include <CLI/CLI.hpp>
#include <poll.h>

#include <cstdio>
#include <memory>

#include "ucon/channels.hpp"
#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/lidar_driver/lidar_driver_node.hpp"
#include "ucon/lidar_driver/sensor_configurator.hpp"
#include "ucon/lidar_driver/udp_socket.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

namespace {

constexpr const char* kName = "lidar_driver";
using ucon::runtime::logLine;
namespace ld = ucon::lidar_driver;

std::unique_ptr<ld::UdpSocket> openSocket(const std::string& ip, int port, int rcvbuf,
                                          const char* what) {
  std::string err, warn;
  auto s = ld::UdpSocket::open(ip, static_cast<uint16_t>(port), rcvbuf, &err, &warn);
  if (!s) {
    logLine(kName, "error", std::string("cannot open the ") + what + " socket: " + err);
    return nullptr;
  }
  if (!warn.empty()) logLine(kName, "warning", warn);
  return s;
}

// Runs the control path until the sensor is configured. Returns false (after logging why) if
// it failed; true when configured or when exit was requested.
bool configureSensor(ld::SensorConfigurator& cfg, ld::UdpSocket& cmd) {
  while (!ucon::runtime::exitRequested()) {
    const double t = ld::monotonicSeconds();
    for (const auto& d : cfg.poll(t)) {
      if (!cmd.sendTo(d.ip, d.port, d.bytes.data(), d.bytes.size())) {
        logLine(kName, "warning",
                "sending a control frame to " + ucon::livox::formatIpv4(d.ip) + ":" +
                    std::to_string(d.port) + " failed (no route?); retrying");
      }
    }
    if (cfg.state() == ld::SensorConfigurator::State::kFailed) {
      logLine(kName, "error", cfg.failure());
      return false;
    }
    if (cfg.state() == ld::SensorConfigurator::State::kDone) return true;
    pollfd pfd{cmd.fd(), POLLIN, 0};
    ::poll(&pfd, 1, 10);
    const int n = cmd.receiveBatch();
    for (int i = 0; i < n; ++i) cfg.onDatagram(cmd.data(i), cmd.size(i), ld::monotonicSeconds());
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Livox Mid-360 driver: UDP point/IMU packets -> LIDAR_POINTS, LIDAR_IMU."};
  std::string config_path, url;
  app.add_option("--config", config_path, "YAML config (deploy/config/lidar_driver.yaml)")->required();
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  CLI11_PARSE(app, argc, argv);

  const auto params = ucon::runtime::loadConfigFile<ld::DriverParams>(kName, config_path);
  if (!params) return 2;
  const ld::NetworkParams& net = params->network;

  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open(kName, url, &err);
  if (!rt) {
    logLine(kName, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();

  auto points = openSocket(net.host_ip, net.host_point_port, net.socket_buffer_bytes, "point-data");
  auto imu = openSocket(net.host_ip, net.host_imu_port, net.socket_buffer_bytes, "IMU");
  if (!points || !imu) return 1;

  std::array<uint8_t, 4> sensor_ip = *ucon::livox::parseIpv4(net.sensor_ip);
  if (params->control.enabled) {
    auto cmd = openSocket(net.host_ip, net.host_command_port, 0, "command");
    if (!cmd) return 1;
    ld::SensorConfigurator cfg(*params);
    if (!configureSensor(cfg, *cmd)) return 1;
    if (ucon::runtime::exitRequested()) return 0;
    sensor_ip = cfg.sensorIp();
    logLine(kName, "info",
            "Mid-360 " + (cfg.serial().empty() ? std::string() : cfg.serial() + " ") + "at " +
                ucon::livox::formatIpv4(sensor_ip) + " configured after " +
                std::to_string(cfg.requestsSent()) + " request(s); points to " + net.host_ip + ":" +
                std::to_string(net.host_point_port) + ", IMU to :" + std::to_string(net.host_imu_port));
  } else {
    logLine(kName, "info", "control disabled: listening on " + net.host_ip + ":" +
                               std::to_string(net.host_point_port) + " and :" +
                               std::to_string(net.host_imu_port));
  }

  const int64_t sensor_id = (int64_t{sensor_ip[0]} << 24) | (int64_t{sensor_ip[1]} << 16) |
                            (int64_t{sensor_ip[2]} << 8) | int64_t{sensor_ip[3]};
  ld::LidarDriverNode node(*params, sensor_id);
  ucon::StatusReport status(kName);
  rt->setStatus(ucon::channels::kLidarStatus, params->status_period_s,
                [&status]() -> ucon::StatusReport& { return status; }, [&node] { return node.now(); });

  // Only the sensor's datagrams are used (another lidar or program may send to our ports);
  // sensor_ip 0.0.0.0 with control disabled accepts any source (e.g. a pcap replay).
  const bool filter_source = sensor_ip != std::array<uint8_t, 4>{0, 0, 0, 0};
  ld::DriverOutputs out;
  const auto publishOutputs = [&] {
    for (const auto& c : out.clouds) rt->publish(ucon::channels::kLidarPoints, c);
    if (out.imu) rt->publish(ucon::channels::kLidarImu, *out.imu);
  };
  const auto drain = [&](ld::UdpSocket& s, double now_s, double& last_rx_s) {
    for (;;) {
      const int n = s.receiveBatch();
      if (n < 0) {
        status.count("socket_errors");
        return;
      }
      if (n == 0) return;
      last_rx_s = now_s;
      for (int i = 0; i < n; ++i) {
        if (s.truncated(i)) {
          node.onOversizeDatagram();
          continue;
        }
        if (filter_source && s.sourceIp(i) != sensor_ip) {
          status.count("foreign_packets");  // another sensor or program on our port
          continue;
        }
        node.onDatagram(s.data(i), s.size(i), out);
        publishOutputs();
      }
      if (n < ld::UdpSocket::kBatch) return;
    }
  };

  const int lcm_fd = rt->lcm().getFileno();
  const double start_s = ld::monotonicSeconds();
  double last_point_rx_s = start_s, last_imu_rx_s = start_s;
  double next_status_s = start_s + params->status_period_s;
  int64_t last_bad = 0;
  bool flushed = true;
  while (!ucon::runtime::exitRequested()) {
    pollfd fds[3] = {{points->fd(), POLLIN, 0}, {imu->fd(), POLLIN, 0}, {lcm_fd, POLLIN, 0}};
    const int pr = ::poll(fds, lcm_fd >= 0 ? 3 : 2, 10);
    const double now_s = ld::monotonicSeconds();
    if (pr > 0) {
      if (fds[0].revents & POLLIN) {
        drain(*points, now_s, last_point_rx_s);
        flushed = false;
      }
      if (fds[1].revents & POLLIN) drain(*imu, now_s, last_imu_rx_s);
      if (lcm_fd >= 0 && (fds[2].revents & POLLIN)) rt->handleOnce(0);
    }
    // No packet for a while: publish the frame being assembled rather than hold it.
    if (!flushed && now_s - last_point_rx_s > params->frame.idle_flush_s) {
      if (auto c = node.flush()) rt->publish(ucon::channels::kLidarPoints, *c);
      flushed = true;
    }
    if (now_s >= next_status_s) {
      node.report(status);
      const auto& c = node.counters();
      const double silent_s = now_s - last_point_rx_s;
      const int64_t bad = c.crc_errors + c.malformed;
      if (silent_s > 1.0) {
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%.1f s", silent_s);
        status.setHealth(ucon::process_status_t::HEALTH_ERROR,
                         std::string("no point packets for ") + buf + " on " + net.host_ip + ":" +
                             std::to_string(net.host_point_port) +
                             " (sensor off, wrong host IP/port, or a firewall)");
      } else if (params->control.imu_enabled && now_s - last_imu_rx_s > 1.0) {
        status.setHealth(ucon::process_status_t::HEALTH_WARN,
                         "no IMU packets on " + net.host_ip + ":" + std::to_string(net.host_imu_port));
      } else if (bad > last_bad) {
        status.setHealth(ucon::process_status_t::HEALTH_WARN,
                         std::to_string(bad - last_bad) + " invalid packets in the last period");
      } else if (node.timeSync() == ucon::point_cloud_t::TIME_NONE) {
        status.setHealth(ucon::process_status_t::HEALTH_WARN,
                         "sensor time not synchronised (time_type 0): stamps are since power-on");
      } else {
        status.setHealth(ucon::process_status_t::HEALTH_OK, "");
      }
      last_bad = bad;
      rt->publishStatus();
      next_status_s = now_s + params->status_period_s;
    }
  }
  if (auto c = node.flush()) rt->publish(ucon::channels::kLidarPoints, *c);
  node.report(status);
  rt->publishStatus();
  return 0;
}
