#include "driver_app.hpp"

#include <poll.h>

#include <chrono>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/lidar_driver/captured_udp.hpp"
#include "ucon/lidar_driver/lidar_driver_node.hpp"
#include "ucon/lidar_driver/pcap_reader.hpp"
#include "ucon/lidar_driver/sensor_configurator.hpp"
#include "ucon/lidar_driver/udp_socket.hpp"
#include "ucon/runtime/node_runtime.hpp"

namespace ucon {
namespace lidar_driver {

namespace {

constexpr const char* kName = "lidar_driver";
using runtime::logLine;
using Ip = std::array<uint8_t, 4>;

std::unique_ptr<UdpSocket> openSocket(const std::string& ip, int port, int rcvbuf, const char* what,
                                      bool shared = false) {
  std::string err, warn;
  auto s = UdpSocket::open(ip, static_cast<uint16_t>(port), rcvbuf, &err, &warn, shared);
  if (!s) {
    logLine(kName, "error", std::string("cannot open the ") + what + " socket: " + err);
    return nullptr;
  }
  if (!warn.empty()) logLine(kName, "warning", warn);
  return s;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof(b), f, v);
  return b;
}

// Which listed sensor a datagram comes from, by its source address. An "auto" sensor takes the
// first address that discovery (or, without control, data) brings.
class Router {
 public:
  explicit Router(const DriverParams& p) : ips_(p.sensors.size()), known_(p.sensors.size(), false) {
    for (std::size_t i = 0; i < p.sensors.size(); ++i) {
      if (!p.sensors[i].isAuto()) {
        ips_[i] = *livox::parseIpv4(p.sensors[i].ip);
        known_[i] = true;
      }
    }
  }
  int find(const Ip& ip) const {
    for (std::size_t i = 0; i < ips_.size(); ++i) {
      if (known_[i] && ips_[i] == ip) return static_cast<int>(i);
    }
    return -1;
  }
  /// The sensor of `ip`; with `claim`, an unassigned auto sensor takes it. -1: foreign.
  int route(const Ip& ip, bool claim, LidarDriverNode& node) {
    const int i = find(ip);
    if (i >= 0 || !claim) return i;
    for (std::size_t k = 0; k < ips_.size(); ++k) {
      if (!known_[k]) {
        assign(k, ip, node);
        logLine(kName, "info", "sensor " + std::to_string(k) + " (auto) is " + livox::formatIpv4(ip));
        return static_cast<int>(k);
      }
    }
    return -1;
  }
  void assign(std::size_t i, const Ip& ip, LidarDriverNode& node) {
    ips_[i] = ip;
    known_[i] = true;
    node.setSensorAddress(i, ip);
  }
  bool known(std::size_t i) const { return known_[i]; }
  const Ip& ip(std::size_t i) const { return ips_[i]; }

 private:
  std::vector<Ip> ips_;
  std::vector<bool> known_;
};

// Everything the live modes (run and --check) share: sockets, the control path, the node.
class LiveDriver {
 public:
  LiveDriver(const DriverParams& params, bool query_info)
      : p_(params), node_(params), router_(params), last_rx_s_(params.sensors.size(), 0.0),
        done_at_s_(params.sensors.size(), -1.0) {
    if (p_.control.enabled) cfg_ = std::make_unique<SensorConfigurator>(p_, query_info);
  }

  bool open() {
    const NetworkParams& n = p_.network;
    points_ = openSocket(n.host_ip, n.host_point_port, n.socket_buffer_bytes, "point-data");
    imu_ = openSocket(n.host_ip, n.host_imu_port, n.socket_buffer_bytes, "IMU");
    if (!points_ || !imu_) return false;
    if (!cfg_) return true;
    cmd_ = openSocket(n.host_ip, n.host_command_port, 0, "command");
    push_ = openSocket(n.host_ip, n.host_push_port, 0, "status push");
    if (!cmd_ || !push_) return false;
    if (n.discovery) {
      // Requests go out from host_ip:56000 (a socket bound to the interface's address, so the
      // broadcast leaves through it); answers come back by broadcast, which Linux delivers only
      // to a socket bound to the any-address: 0.0.0.0:56000.
      disc_send_ = openSocket(n.host_ip, n.discovery_port, 0, "discovery (send)", true);
      disc_recv_ = openSocket("0.0.0.0", n.discovery_port, 0, "discovery (broadcast answers)", true);
      if (!disc_send_ || !disc_recv_) return false;
    }
    return true;
  }

  // One turn of the loop: waits up to `timeout_ms` for any socket, then handles everything.
  // `out` receives what the node produced (the caller publishes it).
  void step(int timeout_ms, int lcm_fd, const std::function<void(DriverOutputs&)>& publish,
            const std::function<void()>& on_lcm) {
    UdpSocket* const socks[6] = {points_.get(), imu_.get(), cmd_.get(), push_.get(),
                                 disc_send_.get(), disc_recv_.get()};
    pollfd fds[7];
    for (int i = 0; i < 6; ++i) fds[i] = {socks[i] ? socks[i]->fd() : -1, POLLIN, 0};
    fds[6] = {lcm_fd, POLLIN, 0};
    ::poll(fds, 7, timeout_ms);
    const double now = monotonicSeconds();
    if (fds[0].revents & POLLIN) drainData(*points_, now, publish);
    if (fds[1].revents & POLLIN) drainData(*imu_, now, publish);
    if (lcm_fd >= 0 && (fds[6].revents & POLLIN) && on_lcm) on_lcm();
    if (cfg_) {
      serviceControl(now, (fds[4].revents | fds[5].revents) & POLLIN, fds[2].revents & POLLIN,
                     fds[3].revents & POLLIN);
    }
    // No packet for a while: publish the frames being assembled rather than hold them.
    if (!flushed_ && now - last_any_rx_s_ > p_.frame.idle_flush_s) {
      DriverOutputs out;
      out.clouds = node_.flushAll();
      publish(out);
      flushed_ = true;
    }
  }

  // Sensors configured but silent for control.reconfigure_after_s are found and configured again.
  void reconfigureSilent(double now) {
    if (!cfg_ || p_.control.work_mode != "sampling") return;
    for (std::size_t i = 0; i < cfg_->size(); ++i) {
      if (cfg_->sensor(i).phase != SensorControlState::Phase::kDone) continue;
      const double since = now - std::max(last_rx_s_[i], done_at_s_[i]);
      if (since > p_.control.reconfigure_after_s) {
        logLine(kName, "warning",
                "sensor " + std::to_string(i) + " (" + livox::formatIpv4(cfg_->sensor(i).ip) +
                    ") sent nothing for " + fmt("%.1f", since) + " s after it was configured: "
                    "finding and configuring it again (rebooted? cable?)");
        cfg_->restart(i, now);
        done_at_s_[i] = -1.0;
      }
    }
  }

  SensorConfigurator* cfg() { return cfg_.get(); }
  LidarDriverNode& node() { return node_; }
  Router& router() { return router_; }
  double lastRx(std::size_t i) const { return last_rx_s_[i]; }
  int64_t foreign() const { return foreign_; }
  int64_t socketErrors() const { return socket_errors_; }
  const DriverParams& params() const { return p_; }
  void markStart(double now) {
    std::fill(last_rx_s_.begin(), last_rx_s_.end(), now);
    last_any_rx_s_ = now;
  }

 private:
  void drainData(UdpSocket& s, double now, const std::function<void(DriverOutputs&)>& publish) {
    DriverOutputs out;
    for (;;) {
      const int n = s.receiveBatch();
      if (n < 0) {
        ++socket_errors_;
        return;
      }
      if (n == 0) return;
      last_any_rx_s_ = now;
      flushed_ = false;
      for (int i = 0; i < n; ++i) {
        if (s.truncated(i)) {
          node_.onOversizeDatagram();
          continue;
        }
        // Only listed sensors' datagrams are used (another lidar or program may send to our
        // ports); without control an "auto" sensor is the first that sends.
        const int idx = router_.route(s.sourceIp(i), !cfg_, node_);
        if (idx < 0) {
          ++foreign_;
          continue;
        }
        last_rx_s_[static_cast<std::size_t>(idx)] = now;
        const int64_t stamp = s.receiveTimeNs(i) > 0 ? s.receiveTimeNs(i) : realtimeNs();
        node_.onDatagram(static_cast<std::size_t>(idx), s.data(i), s.size(i), stamp, out);
        publish(out);
      }
      if (n < UdpSocket::kBatch) return;
    }
  }

  // Sends what the control path asks for and hands it what arrived on the control sockets
  // (only those poll() marked readable: this runs for every batch of data too).
  void serviceControl(double now, bool discovery_in, bool command_in, bool push_in) {
    SensorConfigurator& cfg = *cfg_;
    for (const OutgoingDatagram& d : cfg.poll(now)) {
      UdpSocket* via = d.via == OutgoingDatagram::Via::kDiscovery ? disc_send_.get() : cmd_.get();
      if (via && !via->sendTo(d.ip, d.port, d.bytes.data(), d.bytes.size()) && now >= next_send_warn_s_) {
        logLine(kName, "warning",
                "sending a control frame to " + livox::formatIpv4(d.ip) + ":" + std::to_string(d.port) +
                    " failed (" + std::string(std::strerror(errno)) + "; no route to it from " +
                    p_.network.host_ip + "?); retrying");
        next_send_warn_s_ = now + 5.0;
      }
    }
    const auto drain = [&](UdpSocket* s, int kind) {
      if (!s) return;
      for (;;) {
        const int n = s->receiveBatch();
        if (n <= 0) return;
        for (int i = 0; i < n; ++i) {
          if (kind == 0) cfg.onDiscoveryDatagram(s->sourceIp(i), s->data(i), s->size(i), now);
          if (kind == 1) cfg.onCommandDatagram(s->sourceIp(i), s->data(i), s->size(i), now);
          if (kind == 2) cfg.onPushDatagram(s->sourceIp(i), s->data(i), s->size(i));
        }
        if (n < UdpSocket::kBatch) return;
      }
    };
    if (discovery_in) {
      drain(disc_recv_.get(), 0);
      drain(disc_send_.get(), 0);  // a sensor answering by unicast reaches the sending socket
    }
    if (command_in) drain(cmd_.get(), 1);
    if (push_in) drain(push_.get(), 2);
    // Steady state (every sensor configured and reported, nothing arrived): nothing to do.
    if (!discovery_in && !command_in && !push_in && reported_done_ && cfg.allDone()) return;
    reported_done_ = cfg.allDone();
    for (const std::string& w : cfg.takeWarnings()) logLine(kName, "warning", w);
    for (std::size_t i = 0; i < cfg.size(); ++i) {
      const SensorControlState& st = cfg.sensor(i);
      if (st.ip_known && !router_.known(i)) router_.assign(i, st.ip, node_);
      if (st.phase == SensorControlState::Phase::kDone && done_at_s_[i] < 0) {
        done_at_s_[i] = now;
        logLine(kName, "info",
                "sensor " + std::to_string(i) + ": Mid-360 " + (st.serial.empty() ? "" : st.serial + " ") +
                    "at " + livox::formatIpv4(st.ip) + " configured after " +
                    std::to_string(cfg.requestsSent()) + " request(s) (" +
                    (p_.control.work_mode == "sampling" ? "sampling" : "idle") + ", point data type " +
                    std::to_string(p_.control.point_data_type) + ", IMU " +
                    (p_.sensors[i].imu ? "on" : "off") + "); points to " + p_.network.host_ip + ":" +
                    std::to_string(p_.network.host_point_port));
      }
    }
  }

  DriverParams p_;
  LidarDriverNode node_;
  Router router_;
  std::unique_ptr<SensorConfigurator> cfg_;
  std::unique_ptr<UdpSocket> points_, imu_, cmd_, push_, disc_send_, disc_recv_;
  std::vector<double> last_rx_s_, done_at_s_;
  double last_any_rx_s_ = 0.0;
  bool flushed_ = true;
  double next_send_warn_s_ = 0.0;
  bool reported_done_ = false;
  int64_t foreign_ = 0, socket_errors_ = 0;
};

const char* syncName(int8_t t) {
  switch (t) {
    case point_cloud_t::TIME_PTP: return "PTP (time_type 1)";
    case point_cloud_t::TIME_GPS: return "GPS (time_type 2)";
    default: return "none (time_type 0: nanoseconds since power-on)";
  }
}

// LIDAR_STATUS health from what the driver sees.
void setHealth(LiveDriver& d, StatusReport& status, double now, int64_t& last_bad) {
  const DriverParams& p = d.params();
  const LidarDriverNode& node = d.node();
  const auto& c = node.counters();
  const int64_t bad = c.crc_errors + c.malformed;
  status.setCounter("foreign_packets", d.foreign());
  status.setCounter("socket_errors", d.socketErrors());
  std::string error, warn;
  if (d.cfg() && !d.cfg()->allDone()) {
    error = "waiting for " + d.cfg()->waitingFor();
  }
  for (std::size_t i = 0; i < p.sensors.size() && error.empty(); ++i) {
    const double silent = now - d.lastRx(i);
    const std::string who = "sensor " + std::to_string(i) +
                            (d.router().known(i) ? " (" + livox::formatIpv4(d.router().ip(i)) + ")" : "");
    if (silent > 1.0 && p.control.work_mode == "sampling") {
      error = "no packets from " + who + " for " + fmt("%.1f", silent) + " s on " + p.network.host_ip +
              ":" + std::to_string(p.network.host_point_port) +
              " (sensor off, wrong host IP/port, or a firewall)";
    } else if (p.sensors[i].imu && node.stream(i).imu_packets == 0 && silent <= 1.0 &&
               node.stream(i).point_packets > 200) {
      warn = "no IMU packets from " + who + " on " + p.network.host_ip + ":" +
             std::to_string(p.network.host_imu_port);
    } else if (node.stream(i).have_time && node.stream(i).time_sync == point_cloud_t::TIME_NONE &&
               warn.empty()) {
      warn = who + ": sensor time not synchronised (time_type 0, since power-on); run PTP (docs/robot.md)";
    } else if (node.stream(i).correction_ns != 0 && warn.empty()) {
      warn = who + "'s clock differs from sensor 0's by " +
             fmt("%.1f", static_cast<double>(node.stream(i).correction_ns) * 1e-6) +
             " ms: aligned from receive times; synchronise them with PTP";
    }
  }
  if (!error.empty()) {
    status.setHealth(process_status_t::HEALTH_ERROR, error);
  } else if (bad > last_bad) {
    status.setHealth(process_status_t::HEALTH_WARN, std::to_string(bad - last_bad) + " invalid packets in the last period");
  } else if (!warn.empty()) {
    status.setHealth(process_status_t::HEALTH_WARN, warn);
  } else {
    status.setHealth(process_status_t::HEALTH_OK, "");
  }
  last_bad = bad;
}

}  // namespace

int runLive(const DriverParams& params, const std::string& lcm_url) {
  std::string err;
  auto rt = runtime::NodeRuntime::open(kName, lcm_url, &err);
  if (!rt) {
    logLine(kName, "error", err);
    return 1;
  }
  runtime::installSignalHandlers();
  LiveDriver d(params, false);
  if (!d.open()) return 1;
  StatusReport status(kName);
  rt->setStatus(channels::kLidarStatus, params.status_period_s, [&status]() -> StatusReport& { return status; },
                [&d] { return d.node().now(); });
  if (!params.control.enabled) {
    logLine(kName, "info", "control disabled: listening on " + params.network.host_ip + ":" +
                               std::to_string(params.network.host_point_port) + " and :" +
                               std::to_string(params.network.host_imu_port));
  }
  const auto publish = [&](DriverOutputs& out) {
    for (const auto& c : out.clouds) rt->publish(channels::kLidarPoints, c);
    if (out.imu) rt->publish(channels::kLidarImu, *out.imu);
  };
  const int lcm_fd = rt->lcm().getFileno();
  double now = monotonicSeconds();
  d.markStart(now);
  double next_status = now + params.status_period_s, next_wait_log = now + 2.0;
  int64_t last_bad = 0;
  while (!runtime::exitRequested()) {
    d.step(10, lcm_fd, publish, [&] { rt->handleOnce(0); });
    now = monotonicSeconds();
    if (SensorConfigurator* cfg = d.cfg()) {
      if (cfg->failed()) {
        logLine(kName, "error", cfg->failure());
        d.node().report(status);
        status.setHealth(process_status_t::HEALTH_ERROR, cfg->failure());
        rt->publishStatus();
        return 1;
      }
      if (!cfg->allDone() && now >= next_wait_log) {
        logLine(kName, "info", "waiting for " + cfg->waitingFor());
        next_wait_log = now + 5.0;
      }
      d.reconfigureSilent(now);
    }
    if (now >= next_status) {
      d.node().report(status);
      setHealth(d, status, now, last_bad);
      rt->publishStatus();
      next_status = now + params.status_period_s;
    }
  }
  DriverOutputs out;
  out.clouds = d.node().flushAll();
  publish(out);
  d.node().report(status);
  rt->publishStatus();
  return 0;
}

int runCheck(const DriverParams& params, double seconds, double find_timeout_s) {
  runtime::installSignalHandlers();
  DriverParams p = params;
  p.control.enabled = true;
  p.control.timeout_s = 0.0;  // this function's own limit below
  LiveDriver d(p, true);
  std::printf("ucon-lidar-driver --check: %zu sensor(s) listed, host %s, discovery %s\n",
              p.sensors.size(), p.network.host_ip.c_str(),
              p.network.discovery ? ("broadcast to " + p.network.discovery_address + ":" +
                                     std::to_string(p.network.discovery_port)).c_str()
                                  : "off");
  std::fflush(stdout);
  if (!d.open()) {
    std::printf("FAILED: cannot open the host sockets (see above). Is network.host_ip (%s) an "
                "address of this machine? Is another driver running?\n", p.network.host_ip.c_str());
    return 1;
  }
  const auto ignore = [](DriverOutputs&) {};
  const double t0 = monotonicSeconds();
  double next_wait_log = t0 + 2.0;
  while (!runtime::exitRequested() && !d.cfg()->allDone()) {
    d.step(10, -1, ignore, nullptr);
    const double now = monotonicSeconds();
    if (now - t0 > find_timeout_s) {
      std::printf("FAILED after %.1f s: waiting for %s\n", now - t0, d.cfg()->waitingFor().c_str());
      std::printf("Check: power and cable; `ip addr` shows %s on the interface to the sensor; the "
                  "sensors[].ip are right (factory 192.168.1.1XX); no firewall drops UDP %d-%d.\n",
                  p.network.host_ip.c_str(), p.network.discovery_port, p.network.host_imu_port + 100);
      return 1;
    }
    if (now >= next_wait_log) {
      std::printf("  waiting for %s\n", d.cfg()->waitingFor().c_str());
      std::fflush(stdout);
      next_wait_log = now + 2.0;
    }
  }
  if (runtime::exitRequested()) return 1;
  std::printf("found and configured every sensor in %.1f s; measuring for %.1f s...\n",
              monotonicSeconds() - t0, seconds);
  std::fflush(stdout);
  const LidarDriverNode& node = d.node();
  const std::size_t n = p.sensors.size();
  std::vector<int64_t> pk0(n), imu0(n);
  for (std::size_t i = 0; i < n; ++i) {
    pk0[i] = node.stream(i).point_packets;
    imu0[i] = node.stream(i).imu_packets;
  }
  const int64_t points0 = node.counters().points;
  const double m0 = monotonicSeconds();
  while (!runtime::exitRequested() && monotonicSeconds() - m0 < seconds) d.step(10, -1, ignore, nullptr);
  const double span = monotonicSeconds() - m0;
  std::vector<std::string> problems;
  for (std::size_t i = 0; i < n; ++i) {
    const SensorControlState& st = d.cfg()->sensor(i);
    const SensorStream& ss = node.stream(i);
    const double pk_rate = static_cast<double>(ss.point_packets - pk0[i]) / span;
    const double imu_rate = static_cast<double>(ss.imu_packets - imu0[i]) / span;
    std::printf("sensor %zu: Mid-360 at %s, serial %s, firmware %s, command port %u\n", i,
                livox::formatIpv4(st.ip).c_str(), st.serial.empty() ? "?" : st.serial.c_str(),
                st.firmware.empty() ? "unknown (no answer to the query)" : st.firmware.c_str(),
                st.command_port);
    std::printf("  time sync: %s", ss.have_time ? syncName(ss.time_sync) : "unknown (no packets)");
    if (st.time_sync_type >= 0) std::printf("; the sensor reports sync type %d", st.time_sync_type);
    if (ss.offset_valid) {
      std::printf("; host - sensor clock %.3f ms", static_cast<double>(ss.host_minus_sensor_ns) * 1e-6);
    }
    std::printf("\n  point packets %.1f /s, IMU packets %.1f /s (over %.1f s)\n", pk_rate, imu_rate, span);
    const std::string who = "sensor " + std::to_string(i) + " (" + livox::formatIpv4(st.ip) + ")";
    if (p.control.work_mode == "sampling" && pk_rate <= 0.0) {
      problems.push_back(who + " sends no point packets to " + p.network.host_ip + ":" +
                         std::to_string(p.network.host_point_port) + " (a firewall? another host_ip?)");
    }
    if (p.control.work_mode == "sampling" && p.sensors[i].imu && imu_rate <= 0.0) {
      problems.push_back(who + " sends no IMU packets to " + p.network.host_ip + ":" +
                         std::to_string(p.network.host_imu_port));
    }
  }
  const auto& c = node.counters();
  std::printf("all sensors: %.0f points/s; invalid packets %lld (crc dropped %lld), lost %lld, "
              "foreign %lld\n",
              static_cast<double>(c.points - points0) / span, static_cast<long long>(c.malformed + c.crc_errors),
              static_cast<long long>(c.crc_errors), static_cast<long long>(c.lost_packets),
              static_cast<long long>(d.foreign()));
  if (problems.empty()) {
    std::printf("OK\n");
    return 0;
  }
  std::printf("FAILED:\n");
  for (const auto& pr : problems) std::printf("  %s\n", pr.c_str());
  return 1;
}

int runPcap(const DriverParams& params, const std::string& lcm_url, const std::string& path,
            double speed) {
  std::string err;
  auto reader = PcapReader::open(path, &err);
  if (!reader) {
    logLine(kName, "error", err);
    return 2;
  }
  auto rt = runtime::NodeRuntime::open(kName, lcm_url, &err);
  if (!rt) {
    logLine(kName, "error", err);
    return 1;
  }
  runtime::installSignalHandlers();
  LidarDriverNode node(params);
  Router router(params);
  StatusReport status(kName);
  rt->setStatus(channels::kLidarStatus, params.status_period_s, [&status]() -> StatusReport& { return status; },
                [&node] { return node.now(); });
  const auto publish = [&](DriverOutputs& out) {
    for (const auto& c : out.clouds) rt->publish(channels::kLidarPoints, c);
    if (out.imu) rt->publish(channels::kLidarImu, *out.imu);
  };
  logLine(kName, "info", "playing " + path + " at " + (speed > 0 ? fmt("%g", speed) + "x" : std::string("full speed")));
  const auto wall0 = std::chrono::steady_clock::now();
  int64_t cap0 = -1, last_data_ns = -1, frames_seen = 0, datagrams = 0, skipped = 0, foreign = 0;
  double next_status = monotonicSeconds() + params.status_period_s;
  DriverOutputs out;
  PcapReader::Frame f;
  int rc;
  while (!runtime::exitRequested() && (rc = reader->next(f, &err)) == 1) {
    ++frames_seen;
    CaptureSkip why;
    const auto udp = extractUdp(reader->linkType(), f.data, f.caplen, &why);
    if (!udp) {
      ++skipped;
      continue;
    }
    if (udp->dst_port != params.network.host_point_port && udp->dst_port != params.network.host_imu_port) {
      continue;  // control traffic, other programs
    }
    const int idx = router.route(udp->src_ip, true, node);
    if (idx < 0) {
      ++foreign;
      continue;
    }
    if (cap0 < 0) cap0 = f.time_ns;
    if (speed > 0) {
      const auto due = wall0 + std::chrono::nanoseconds(static_cast<int64_t>(static_cast<double>(f.time_ns - cap0) / speed));
      std::this_thread::sleep_until(due);
    }
    // As live: a pause longer than idle_flush_s publishes the frames being assembled.
    if (last_data_ns >= 0 && static_cast<double>(f.time_ns - last_data_ns) * 1e-9 > params.frame.idle_flush_s) {
      out.clear();
      out.clouds = node.flushAll();
      publish(out);
    }
    last_data_ns = f.time_ns;
    ++datagrams;
    node.onDatagram(static_cast<std::size_t>(idx), udp->payload, udp->size, f.time_ns, out);
    publish(out);
    if (monotonicSeconds() >= next_status) {
      rt->handleOnce(0);
      node.report(status);
      status.setCounter("foreign_packets", foreign);
      status.setCounter("capture_frames_skipped", skipped);
      rt->publishStatus();
      next_status = monotonicSeconds() + params.status_period_s;
    }
  }
  out.clear();
  out.clouds = node.flushAll();
  publish(out);
  node.report(status);
  status.setCounter("foreign_packets", foreign);
  status.setCounter("capture_frames_skipped", skipped);
  rt->publishStatus();
  if (rc < 0) {
    logLine(kName, "error", "reading " + path + ": " + err);
    return 1;
  }
  logLine(kName, "info", "end of " + path + ": " + std::to_string(frames_seen) + " captured frames, " +
                             std::to_string(datagrams) + " sensor datagrams, " +
                             std::to_string(node.counters().frames) + " LIDAR_POINTS frames, " +
                             std::to_string(foreign) + " from unlisted addresses");
  return 0;
}

}  // namespace lidar_driver
}  // namespace ucon
