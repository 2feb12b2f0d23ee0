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

TEST(DriverParams, GivenTheShippedConfigThenEveryKeyLoads) {
  const std::string text = shippedConfig();
  ASSERT_FALSE(text.empty()) << "deploy/config/lidar_driver.yaml not found";
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<DriverParams>(text, "lidar_driver.yaml", &errors);
  ASSERT_TRUE(p.has_value()) << (errors.empty() ? "" : errors[0].toString());
  EXPECT_EQ(p->frame.rate_hz, 50);
  EXPECT_EQ(p->network.host_point_port, 56301);
  EXPECT_EQ(p->network.host_imu_port, 56401);
  EXPECT_EQ(p->network.sensor_command_port, 56100);
  EXPECT_DOUBLE_EQ(p->extrinsic.rpy_deg[0], 180.0);
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
  EXPECT_NE(errorsOf(replace(good, "work_mode: normal", "work_mode: turbo")).find("control.work_mode"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "tag_drop_mask: 0", "tag_drop_mask: 0\n  tag_mask: 1")).find("filter.tag_mask"),
            std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "  timeout_s: 5.0", "")).find("control.timeout_s"), std::string::npos);
  EXPECT_NE(errorsOf(replace(good, "sensor_ip: \"127.0.0.1\"", "sensor_ip: \"0.0.0.0\"")).find("network.sensor_ip"),
            std::string::npos);
}
