#include "ucon/lidar_driver/driver_params.hpp"

#include "ucon/livox/control.hpp"

namespace ucon {
namespace lidar_driver {

namespace {
void readIp(ConfigReader& r, const std::string& key, std::string& out, bool allow_auto = false) {
  r.read(key, out);
  if (!r.has(key) || (allow_auto && out == "auto")) return;
  const auto ip = livox::parseIpv4(out);
  if (!ip) {
    r.fail(key, "'" + out + "' is not an IPv4 address a.b.c.d" + (allow_auto ? " (or auto)" : ""));
  } else if (allow_auto && *ip == std::array<uint8_t, 4>{0, 0, 0, 0}) {
    r.fail(key, "0.0.0.0 is not a sensor address; use auto to take the first sensor found");
  }
}
}  // namespace

int64_t sensorIdOf(const std::array<uint8_t, 4>& ip) {
  return (int64_t{ip[0]} << 24) | (int64_t{ip[1]} << 16) | (int64_t{ip[2]} << 8) | int64_t{ip[3]};
}

void NetworkParams::read(ConfigReader& r) {
  readIp(r, "host_ip", host_ip);
  r.read("discovery", discovery);
  readIp(r, "discovery_address", discovery_address);
  r.read("discovery_port", discovery_port, 1, 65535);
  r.read("sensor_command_port", sensor_command_port, 1, 65535);
  r.read("sensor_push_port", sensor_push_port, 1, 65535);
  r.read("sensor_point_port", sensor_point_port, 1, 65535);
  r.read("sensor_imu_port", sensor_imu_port, 1, 65535);
  r.read("host_command_port", host_command_port, 1, 65535);
  r.read("host_push_port", host_push_port, 1, 65535);
  r.read("host_point_port", host_point_port, 1, 65535);
  r.read("host_imu_port", host_imu_port, 1, 65535);
  r.read("socket_buffer_bytes", socket_buffer_bytes, 65536, 1 << 30);
  const int ports[] = {host_command_port, host_push_port, host_point_port, host_imu_port,
                       discovery_port};
  for (int i = 0; i < 5; ++i) {
    for (int j = i + 1; j < 5; ++j) {
      if (ports[i] == ports[j]) {
        r.fail("host_point_port",
               "discovery_port and the host command, push, point and IMU ports must all differ");
        return;
      }
    }
  }
}

void ControlParams::read(ConfigReader& r) {
  r.read("enabled", enabled);
  r.read("timeout_s", timeout_s, 0.0, 3600.0);
  r.read("retry_interval_s", retry_interval_s, 0.01, 10.0);
  r.read("work_mode", work_mode, {"sampling", "idle"});
  r.read("point_data_type", point_data_type, 1, 3);
  r.read("reset_install_attitude", reset_install_attitude);
  r.read("reconfigure_after_s", reconfigure_after_s, 0.5, 60.0);
}

void FrameParams::read(ConfigReader& r) {
  r.read("rate_hz", rate_hz, 10, 50);
  if (rate_hz != 10 && rate_hz != 20 && rate_hz != 50) {
    r.fail("rate_hz", "must be 10, 20 or 50 (got " + std::to_string(rate_hz) + ")");
  }
  r.read("max_points", max_points, 1000, 2000000);
  r.read("idle_flush_s", idle_flush_s, 0.01, 10.0);
  r.read("apply_extrinsic", apply_extrinsic);
  r.read("merge_wait_s", merge_wait_s, 0.0, 1.0);
}

void FilterParams::read(ConfigReader& r) {
  r.read("min_range_m", min_range_m, 0.0, 1000.0);
  r.read("max_range_m", max_range_m, 0.1, 1000.0);
  r.read("drop_sticking_level", drop_sticking_level, 0, 3);
  r.read("drop_rain_fog_dust_level", drop_rain_fog_dust_level, 0, 3);
  r.read("drop_other_noise_level", drop_other_noise_level, 0, 3);
  if (min_range_m >= max_range_m) r.fail("max_range_m", "must be greater than min_range_m");
}

void SensorParams::read(ConfigReader& r) {
  readIp(r, "ip", ip, true);
  r.read("xyz", xyz, 3, -10.0, 10.0);
  r.read("rpy_deg", rpy_deg, 3, -360.0, 360.0);
  r.read("imu", imu);
}

void DriverParams::read(ConfigReader& r) {
  auto n = r.section("network");
  network.read(n);
  auto c = r.section("control");
  control.read(c);
  auto f = r.section("frame");
  frame.read(f);
  auto fl = r.section("filter");
  filter.read(fl);
  auto list = r.sections("sensors");
  if (r.has("sensors")) {
    sensors.clear();
    for (auto& s : list) {
      sensors.emplace_back();
      sensors.back().read(s);
    }
  }
  r.read("status_period_s", status_period_s, 0.1, 60.0);
  if (sensors.empty() || sensors.size() > 8) {
    r.fail("sensors", "list 1 to 8 sensors (got " + std::to_string(sensors.size()) + ")");
    return;
  }
  int imus = 0, autos = 0;
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    imus += sensors[i].imu ? 1 : 0;
    autos += sensors[i].isAuto() ? 1 : 0;
    for (std::size_t j = 0; j < i; ++j) {
      if (!sensors[i].isAuto() && sensors[i].ip == sensors[j].ip) {
        r.fail("sensors[" + std::to_string(i) + "].ip", "listed twice: " + sensors[i].ip);
      }
    }
  }
  if (imus > 1) r.fail("sensors", "imu: true on more than one sensor (LIDAR_IMU carries one IMU)");
  if (autos > 0 && sensors.size() > 1) {
    r.fail("sensors", "ip: auto works with one sensor only; give each sensor its address");
  }
  if (autos > 0 && control.enabled && !network.discovery) {
    r.fail("sensors[0].ip", "auto needs network.discovery: true (or control.enabled: false)");
  }
  if (!frame.apply_extrinsic && sensors.size() > 1) {
    f.fail("apply_extrinsic", "false (sensor frame) works with one sensor only");
  }
}

}  // namespace lidar_driver
}  // namespace ucon
