#include "ucon/lidar_driver/sensor_configurator.hpp"

#include <cstdio>

namespace ucon {
namespace lidar_driver {

using livox::ControlFrame;

const char* toString(SensorConfigurator::State s) {
  switch (s) {
    case SensorConfigurator::State::kDiscovering: return "discovering";
    case SensorConfigurator::State::kConfiguring: return "configuring";
    case SensorConfigurator::State::kDone: return "done";
    case SensorConfigurator::State::kFailed: return "failed";
  }
  return "unknown";
}

SensorConfigurator::SensorConfigurator(const DriverParams& params)
    : params_(params),
      state_(params.network.discovery ? State::kDiscovering : State::kConfiguring) {
  sensor_ip_ = livox::parseIpv4(params_.network.sensor_ip).value_or(std::array<uint8_t, 4>{});
  sensor_cmd_port_ = static_cast<uint16_t>(params_.network.sensor_command_port);
  pending_ = currentRequest();
}

ControlFrame SensorConfigurator::currentRequest() const {
  if (state_ == State::kDiscovering) return livox::makeDiscoveryRequest(seq_);
  const auto host = livox::parseIpv4(params_.network.host_ip).value_or(std::array<uint8_t, 4>{});
  std::vector<livox::KeyValue> kvs;
  kvs.push_back(livox::makeHostIpConfig(
      livox::Key::kPointDataHostIpConfig,
      livox::HostIpConfig{host, static_cast<uint16_t>(params_.network.host_point_port),
                          static_cast<uint16_t>(params_.network.sensor_point_port)}));
  kvs.push_back(livox::makeHostIpConfig(
      livox::Key::kImuDataHostIpConfig,
      livox::HostIpConfig{host, static_cast<uint16_t>(params_.network.host_imu_port),
                          static_cast<uint16_t>(params_.network.sensor_imu_port)}));
  kvs.push_back(livox::KeyValue{static_cast<uint16_t>(livox::Key::kImuDataEnable),
                                {static_cast<uint8_t>(params_.control.imu_enabled ? 1 : 0)}});
  kvs.push_back(livox::makeWorkMode(params_.control.work_mode == "sleep" ? livox::WorkMode::kSleep
                                                                         : livox::WorkMode::kNormal));
  return livox::makeSetKeyValueRequest(seq_, kvs);
}

void SensorConfigurator::fail(const std::string& what) {
  state_ = State::kFailed;
  failure_ = what;
}

std::vector<OutgoingDatagram> SensorConfigurator::poll(double t_s) {
  std::vector<OutgoingDatagram> out;
  if (start_s_ < 0) {
    start_s_ = t_s;
    next_send_s_ = t_s;
  }
  if (state_ == State::kDone || state_ == State::kFailed) return out;
  char buf[64];
  if (t_s - start_s_ >= params_.control.timeout_s) {
    std::snprintf(buf, sizeof(buf), "%.1f s (%d requests sent)", params_.control.timeout_s,
                  requests_sent_);
    const NetworkParams& n = params_.network;
    if (state_ == State::kDiscovering) {
      fail("no Mid-360 answered the discovery request sent to " + n.discovery_address + ":" +
           std::to_string(n.sensor_discovery_port) + " within " + buf +
           ". Check: the sensor is powered and its cable connected; the host interface has an "
           "address in the sensor's subnet (network.host_ip = " + n.host_ip +
           ", bound to port " + std::to_string(n.host_command_port) +
           "); no firewall drops UDP ports 56000-56501; or set network.discovery: false and "
           "network.sensor_ip. In simulation: is ucon-simulator running with the same ports?");
    } else {
      fail("no Mid-360 answered the configuration request (host IP/ports, work mode) sent to " +
           livox::formatIpv4(sensor_ip_) + ":" + std::to_string(sensor_cmd_port_) + " within " +
           buf + ". Check: network.sensor_ip is the sensor's address (factory default "
           "192.168.1.1XX, XX = last two digits of the serial number) or enable "
           "network.discovery; the host has an address in that subnet (network.host_ip = " +
           n.host_ip + ", command port " + std::to_string(n.host_command_port) +
           "); no firewall drops UDP ports 56000-56501. In simulation: is ucon-simulator "
           "running with the same ports?");
    }
    return out;
  }
  if (t_s >= next_send_s_) {
    OutgoingDatagram d;
    if (state_ == State::kDiscovering) {
      d.ip = livox::parseIpv4(params_.network.discovery_address).value_or(std::array<uint8_t, 4>{});
      d.port = static_cast<uint16_t>(params_.network.sensor_discovery_port);
    } else {
      d.ip = sensor_ip_;
      d.port = sensor_cmd_port_;
    }
    d.bytes = livox::encodeControlFrame(pending_);
    out.push_back(std::move(d));
    ++requests_sent_;
    next_send_s_ = t_s + params_.control.retry_interval_s;
  }
  return out;
}

void SensorConfigurator::onDatagram(const uint8_t* data, std::size_t size, double t_s) {
  ControlFrame f;
  if (livox::decodeControlFrame(data, size, f) != livox::ControlStatus::kOk ||
      !livox::isAckOf(f, pending_)) {
    ++ignored_;
    return;
  }
  if (state_ == State::kDiscovering) {
    const auto info = livox::parseDiscoveryAck(f);
    if (!info || info->ret_code != 0) {
      ++ignored_;
      return;
    }
    sensor_ip_ = info->lidar_ip;
    sensor_cmd_port_ = info->cmd_port;
    serial_ = info->serial;
    state_ = State::kConfiguring;
    ++seq_;
    pending_ = currentRequest();
    next_send_s_ = t_s;  // configure right away
    return;
  }
  if (state_ == State::kConfiguring) {
    const auto ack = livox::parseSetKeyValueAck(f);
    if (!ack) {
      ++ignored_;
      return;
    }
    if (ack->ret_code != 0) {
      char buf[96];
      std::snprintf(buf, sizeof(buf), "ret_code %u, key 0x%04X", ack->ret_code, ack->error_key);
      fail("the Mid-360 at " + livox::formatIpv4(sensor_ip_) + " rejected the configuration (" +
           buf + "). Check network.host_ip and the host ports in the config.");
      return;
    }
    state_ = State::kDone;
  }
}

}  // namespace lidar_driver
}  // namespace ucon
