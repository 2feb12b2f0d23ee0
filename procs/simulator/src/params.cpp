#include "ucon/simulator/params.hpp"

#include <cmath>

#include "ucon/config.hpp"

namespace ucon {
namespace simulator {

void LidarParams::read(ConfigReader& r) {
  r.read("point_rate", point_rate, 20000.0, 1e6);
  r.read("data_type", data_type, 1, 3);
  r.read("min_range", min_range, 0.0, 10.0);
  r.read("max_range", max_range, 0.01, 500.0);
  r.read("range_noise_sigma", range_noise_sigma, 0.0, 1.0);
  r.read("elevation_min_deg", elevation_min_deg, -90.0, 90.0);
  r.read("elevation_max_deg", elevation_max_deg, -90.0, 90.0);
  r.read("mount_xyz", mount_xyz, 3, -10.0, 10.0);
  r.read("mount_rpy_deg", mount_rpy_deg, 3, -360.0, 360.0);
  r.read("ground_reflectivity", ground_reflectivity, 0.0, 255.0);
  r.read("seed", seed, int64_t{0}, INT64_MAX);
  if (!(max_range > min_range)) r.fail("max_range", "must be greater than min_range");
  if (!(elevation_max_deg > elevation_min_deg))
    r.fail("elevation_max_deg", "must be greater than elevation_min_deg");
  // time_interval is in 0.1 us: the point spacing must be a whole number of 100 ns.
  const double spacing = 1e9 / point_rate / 100.0;
  if (std::fabs(spacing - std::round(spacing)) > 1e-9)
    r.fail("point_rate", "1e9 / point_rate must be a multiple of 100 ns (e.g. 200000, 250000, 100000)");
}

void ImuParams::read(ConfigReader& r) {
  r.read("rate_hz", rate_hz, 1.0, 2000.0);
  r.read("gyro_noise_sigma", gyro_noise_sigma, 0.0, 1.0);
  r.read("acc_noise_sigma", acc_noise_sigma, 0.0, 10.0);
  r.read("gyro_bias_walk", gyro_bias_walk, 0.0, 1.0);
  r.read("acc_bias_walk", acc_bias_walk, 0.0, 10.0);
  r.read("gyro_bias", gyro_bias, 3, -1.0, 1.0);
  r.read("acc_bias", acc_bias, 3, -10.0, 10.0);
  r.read("position", position, 3, -1.0, 1.0);
  r.read("time_offset_s", time_offset_s, -0.1, 0.1);
  const double period = 1e9 / rate_hz;
  if (std::fabs(period - std::round(period)) > 1e-6)
    r.fail("rate_hz", "1e9 / rate_hz must be a whole number of nanoseconds");
}

void VibrationParams::read(ConfigReader& r) {
  r.read("amplitude_deg", amplitude_deg, 0.0, 5.0);
  r.read("frequency_hz", frequency_hz, 1e-3, 50.0);
}

void NetParams::read(ConfigReader& r) {
  r.read("host_ip", host_ip);
  r.read("host_point_port", host_point_port, 1, 65535);
  r.read("host_imu_port", host_imu_port, 1, 65535);
  r.read("sensor_ip", sensor_ip);
  r.read("discovery_port", discovery_port, 1, 65535);
  r.read("command_port", command_port, 1, 65535);
  r.read("point_src_port", point_src_port, 0, 65535);
  r.read("imu_src_port", imu_src_port, 0, 65535);
  r.read("serial", serial);
  if (serial.size() > 16) r.fail("serial", "at most 16 characters");
}

void ExtraLidarParams::read(ConfigReader& r) {
  r.read("sensor_ip", sensor_ip);
  r.read("serial", serial);
  r.read("mount_xyz", mount_xyz, 3, -10.0, 10.0);
  r.read("mount_rpy_deg", mount_rpy_deg, 3, -360.0, 360.0);
  r.read("seed", seed, int64_t{0}, INT64_MAX);
  if (serial.size() > 16) r.fail("serial", "at most 16 characters");
}

void SimulatorParams::read(ConfigReader& r) {
  r.read("start_utime", start_utime, int64_t{1}, int64_t{4000000000000000000});
  r.read("frame_rate_hz", frame_rate_hz, 1.0, 100.0);
  r.read("pose_rate_hz", pose_rate_hz, 1.0, 1000.0);
  r.read("cmd_timeout_s", cmd_timeout_s, 1e-3, 10.0);
  r.read("status_period_s", status_period_s, 1e-3, 60.0);
  r.read("pose_source", pose_source, {"ground_truth", "none"});
  auto l = r.section("lidar");
  lidar.read(l);
  auto i = r.section("imu");
  imu.read(i);
  auto v = r.section("vibration");
  vibration.read(v);
  auto n = r.section("net");
  net.read(n);
  extra_lidars.clear();
  for (auto& e : r.sections("extra_lidars")) {
    extra_lidars.emplace_back();
    extra_lidars.back().read(e);
  }
  if (extra_lidars.size() > 7) r.fail("extra_lidars", "at most 7 (8 sensors in all)");
  auto b = r.section("base");
  base.geometry.read(b);
  base.read(b);
  const std::string bad = base.validate();
  if (!bad.empty()) r.fail("base", bad);
  const double fp = 1e9 / frame_rate_hz, pp = 1e9 / pose_rate_hz;
  if (std::fabs(fp - std::round(fp)) > 1e-6)
    r.fail("frame_rate_hz", "1e9 / frame_rate_hz must be a whole number of nanoseconds");
  if (std::fabs(pp - std::round(pp)) > 1e-6)
    r.fail("pose_rate_hz", "1e9 / pose_rate_hz must be a whole number of nanoseconds");
}

std::string SimulatorParams::validate() const {
  if (!(lidar.max_range > lidar.min_range)) return "lidar.max_range: must exceed min_range";
  if (!(lidar.elevation_max_deg > lidar.elevation_min_deg)) return "lidar.elevation_max_deg: must exceed min";
  if (lidar.data_type < 1 || lidar.data_type > 3) return "lidar.data_type: must be 1, 2 or 3";
  if (lidar.mount_xyz.size() != 3 || lidar.mount_rpy_deg.size() != 3) return "lidar.mount: need 3 values each";
  if (!(start_utime > 0)) return "start_utime: must be > 0";
  if (!(lidar.point_rate >= 20000.0 && lidar.point_rate <= 1e6)) return "lidar.point_rate: must be in [2e4, 1e6]";
  const double spacing = 1e9 / lidar.point_rate / 100.0;
  if (std::fabs(spacing - std::round(spacing)) > 1e-9) return "lidar.point_rate: 1e9 / rate must be a multiple of 100 ns";
  if (!(imu.rate_hz >= 1.0 && imu.rate_hz <= 2000.0)) return "imu.rate_hz: must be in [1, 2000]";
  if (!(frame_rate_hz >= 1.0 && frame_rate_hz <= 100.0)) return "frame_rate_hz: must be in [1, 100]";
  if (!(pose_rate_hz >= 1.0 && pose_rate_hz <= 1000.0)) return "pose_rate_hz: must be in [1, 1000]";
  if (pose_source != "ground_truth" && pose_source != "none") return "pose_source: must be ground_truth or none";
  if (imu.gyro_bias.size() != 3 || imu.acc_bias.size() != 3 || imu.position.size() != 3)
    return "imu.gyro_bias, acc_bias, position: need 3 values each";
  if (!(std::fabs(imu.time_offset_s) <= 0.1)) return "imu.time_offset_s: must be within +-0.1 s";
  if (!(vibration.amplitude_deg >= 0.0 && vibration.amplitude_deg <= 5.0)) return "vibration.amplitude_deg: must be in [0, 5]";
  if (!(vibration.frequency_hz > 0.0)) return "vibration.frequency_hz: must be > 0";
  const std::string b = base.validate();
  if (!b.empty()) return "base." + b;
  for (std::size_t i = 0; i < extra_lidars.size(); ++i) {
    const std::string k = "extra_lidars[" + std::to_string(i) + "].";
    if (extra_lidars[i].mount_xyz.size() != 3 || extra_lidars[i].mount_rpy_deg.size() != 3)
      return k + "mount: need 3 values each";
    if (extra_lidars[i].sensor_ip == net.sensor_ip) return k + "sensor_ip: the same as net.sensor_ip";
  }
  return "";
}

}  // namespace simulator
}  // namespace ucon
