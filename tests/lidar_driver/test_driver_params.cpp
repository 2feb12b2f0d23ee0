// The driver's YAML: the shipped file loads; bad values are rejected naming their key.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "ucon/lidar_driver/driver_params.hpp"

using ucon::lidar_driver::DriverParams;

namespace {
std::string shippedConfig() {
  std::ifstream f("deploy/config/lidar_driver.yaml");  // tests run from the source root
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}
std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}
std::string errorsOf(const std::string& yaml) {
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<DriverParams>(yaml, "lidar_driver.yaml", &errors);
  EXPECT_FALSE(p.has_value());
  std::string all;
  for (const auto& e : errors) all += e.toString() + "\n";
  return all;
}
}  // namespace

TEST(DriverParams, GivenTheShippedConfigThenEveryKeyLoadsAndEqualsTheDefaults) {
  const std::string text = shippedConfig();
  ASSERT_FALSE(text.empty()) << "deploy/config/lidar_driver.yaml not found";
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<DriverParams>(text, "lidar_driver.yaml", &errors);
  ASSERT_TRUE(p.has_value()) << (errors.empty() ? "" : errors[0].toString());
  const DriverParams d;  // one source of truth: the shipped file equals the in-class defaults
  EXPECT_EQ(p->network.host_ip, d.network.host_ip);
  EXPECT_EQ(p->network.discovery, d.network.discovery);
  EXPECT_EQ(p->network.discovery_address, d.network.discovery_address);
  EXPECT_EQ(p->network.discovery_port, 56000);
  EXPECT_EQ(p->network.host_point_port, d.network.host_point_port);
  EXPECT_EQ(p->network.host_imu_port, d.network.host_imu_port);
  EXPECT_EQ(p->network.host_push_port, d.network.host_push_port);
  EXPECT_EQ(p->network.sensor_command_port, d.network.sensor_command_port);
  EXPECT_EQ(p->network.socket_buffer_bytes, d.network.socket_buffer_bytes);
  EXPECT_EQ(p->control.timeout_s, d.control.timeout_s);
  EXPECT_EQ(p->control.retry_interval_s, d.control.retry_interval_s);
  EXPECT_EQ(p->control.work_mode, d.control.work_mode);
  EXPECT_EQ(p->control.point_data_type, d.control.point_data_type);
  EXPECT_EQ(p->control.reset_install_attitude, d.control.reset_install_attitude);
  EXPECT_EQ(p->control.reconfigure_after_s, d.control.reconfigure_after_s);
  EXPECT_EQ(p->frame.rate_hz, d.frame.rate_hz);
  EXPECT_EQ(p->frame.max_points, d.frame.max_points);
  EXPECT_EQ(p->frame.idle_flush_s, d.frame.idle_flush_s);
  EXPECT_EQ(p->frame.merge_wait_s, d.frame.merge_wait_s);
  EXPECT_EQ(p->frame.apply_extrinsic, d.frame.apply_extrinsic);
  EXPECT_EQ(p->filter.min_range_m, d.filter.min_range_m);
  EXPECT_EQ(p->filter.max_range_m, d.filter.max_range_m);
  EXPECT_EQ(p->filter.drop_rain_fog_dust_level, d.filter.drop_rain_fog_dust_level);
  EXPECT_EQ(p->status_period_s, d.status_period_s);
  ASSERT_EQ(p->sensors.size(), 1u);
  EXPECT_EQ(p->sensors[0].ip, "127.0.0.1");
  EXPECT_DOUBLE_EQ(p->sensors[0].rpy_deg[0], 180.0);  // the simulator's upside-down mount
  EXPECT_DOUBLE_EQ(p->sensors[0].xyz[2], 0.5);
  EXPECT_TRUE(p->sensors[0].imu);
  EXPECT_TRUE(p->control.enabled);
}

TEST(DriverParams, GivenBadValuesThenTheErrorNamesTheKey) {
  const std::string good = shippedConfig();
  EXPECT_NE(errorsOf(replace(good, "rate_hz: 50", "rate_hz: 30")).find("frame.rate_hz"), std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "host_ip: \"127.0.0.1\"", "host_ip: \"127.0.0\"")).find("network.host_ip"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "host_imu_port: 56401", "host_imu_port: 56301")).find("network.host_point_port"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "max_range_m: 70.0", "max_range_m: 0.05")).find("filter.max_range_m"),
            std::string::npos);
  // 0x03 ("sleep") is not a Mid-360 work mode: only sampling and idle are accepted.
  EXPECT_NE(errorsOf(replace(good, "work_mode: sampling", "work_mode: sleep")).find("control.work_mode"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "drop_other_noise_level: 0", "drop_other_noise_level: 4")).find(
                "filter.drop_other_noise_level"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "  timeout_s: 0.0", "")).find("control.timeout_s"), std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "- ip: \"127.0.0.1\"", "- ip: \"0.0.0.0\"")).find("sensors[0].ip"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "    imu: true", "    imu: true\n    name: x")).find("sensors[0].name"),
            std::string::npos);
  // Two sensors: both with the IMU, or the same address, are refused.
  const std::string second = "  - ip: \"127.0.0.2\"\n    xyz: [0, 0, 0]\n    rpy_deg: [0, 0, 0]\n    imu: true\n";
  EXPECT_NE(errorsOf(replace(good, "status_period_s:", second + "status_period_s:")).find("imu: true on more"),
            std::string::npos);
  const std::string same = "  - ip: \"127.0.0.1\"\n    xyz: [0, 0, 0]\n    rpy_deg: [0, 0, 0]\n    imu: false\n";
  EXPECT_NE(errorsOf(replace(good, "status_period_s:", same + "status_period_s:")).find("listed twice"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "\nsensors:", "\nsensors: []\nx:")).find("list 1 to 8"), std::string::npos);
}

TEST(DriverParams, GivenAnAutoSensorThenItNeedsDiscoveryAndStandsAlone) {
  const std::string good = shippedConfig();
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<DriverParams>(replace(good, "- ip: \"127.0.0.1\"", "- ip: auto"), "", &errors);
  ASSERT_TRUE(p.has_value());
  EXPECT_TRUE(p->sensors[0].isAuto());
  EXPECT_NE(errorsOf(replace(replace(good, "- ip: \"127.0.0.1\"", "- ip: auto"), "discovery: true", "discovery: false"))
                .find("needs network.discovery"),
            std::string::npos);
}
