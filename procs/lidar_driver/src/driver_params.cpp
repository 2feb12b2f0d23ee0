#include "ucon/lidar_driver/driver_params.hpp"

#include "ucon/livox/control.hpp"

namespace ucon {
namespace lidar_driver {

namespace {
void readIp(ConfigReader& r, const std::string& key, std::string& out) {
  r.read(key, out);
  if (r.has(key) && !livox::parseIpv4(out)) r.fail(key, "'" + out + "' is not an IPv4 address a.b.c.d");
}
}  // namespace

void NetworkParams::read(ConfigReader& r) {
  readIp(r, "host_ip", host_ip);
  readIp(r, "sensor_ip", sensor_ip);
  r.read("discovery", discovery);
  readIp(r, "discovery_address", discovery_address);
  r.read("sensor_discovery_port", sensor_discovery_port, 1, 65535);
  r.read("sensor_command_port", sensor_command_port, 1, 65535);
  r.read("sensor_point_port", sensor_point_port, 1, 65535);
  r.read("sensor_imu_port", sensor_imu_port, 1, 65535);
  r.read("host_command_port", host_command_port, 1, 65535);
  r.read("host_point_port", host_point_port, 1, 65535);
  r.read("host_imu_port", host_imu_port, 1, 65535);
  r.read("socket_buffer_bytes", socket_buffer_bytes, 65536, 1 << 30);
  if (host_point_port == host_imu_port || host_point_port == host_command_port ||
      host_imu_port == host_command_port) {
    r.fail("host_point_port", "host_command_port, host_point_port and host_imu_port must differ");
  }
}

void ControlParams::read(ConfigReader& r) {
  r.read("enabled", enabled);
  r.read("timeout_s", timeout_s, 0.001, 120.0);
  r.read("retry_interval_s", retry_interval_s, 0.01, 10.0);
  r.read("work_mode", work_mode, {"normal", "sleep"});
  r.read("imu_enabled", imu_enabled);
}

void FrameParams::read(ConfigReader& r) {
  r.read("rate_hz", rate_hz, 10, 50);
  if (rate_hz != 10 && rate_hz != 20 && rate_hz != 50) {
    r.fail("rate_hz", "must be 10, 20 or 50 (got " + std::to_string(rate_hz) + ")");
  }
  r.read("max_points", max_points, 1000, 2000000);
  r.read("idle_flush_s", idle_flush_s, 0.01, 10.0);
}

void ExtrinsicParams::read(ConfigReader& r) {
  r.read("apply", apply);
  r.read("xyz", xyz, 3, -10.0, 10.0);
  r.read("rpy_deg", rpy_deg, 3, -360.0, 360.0);
}

void FilterParams::read(ConfigReader& r) {
  r.read("min_range_m", min_range_m, 0.0, 1000.0);
  r.read("max_range_m", max_range_m, 0.1, 1000.0);
  r.read("tag_drop_mask", tag_drop_mask, 0, 255);
  if (min_range_m >= max_range_m) r.fail("max_range_m", "must be greater than min_range_m");
}

void DriverParams::read(ConfigReader& r) {
  auto n = r.section("network");
  network.read(n);
  auto c = r.section("control");
  control.read(c);
  auto f = r.section("frame");
  frame.read(f);
  auto e = r.section("extrinsic");
  extrinsic.read(e);
  auto fl = r.section("filter");
  filter.read(fl);
  r.read("status_period_s", status_period_s, 0.1, 60.0);
  if (control.enabled && !network.discovery && network.sensor_ip == "0.0.0.0") {
    n.fail("sensor_ip", "0.0.0.0 (any source) needs control.enabled: false or network.discovery: true");
  }
}

}  // namespace lidar_driver
}  // namespace ucon
