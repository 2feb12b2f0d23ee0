// The shipped simulator config loads; bad keys are named; scenario specs resolve.
#include <gtest/gtest.h>

#include "ucon/config.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/simulator/scenario_loader.hpp"

using namespace ucon;
using namespace ucon::simulator;

TEST(SimulatorParams, GivenTheShippedConfigThenItLoadsWithThePaperMount) {
  std::string err;
  const auto text = runtime::readTextFile("deploy/config/simulator.yaml", &err);
  ASSERT_TRUE(text) << err;
  std::vector<ConfigError> errors;
  const auto p = loadParams<SimulatorParams>(*text, "simulator.yaml", &errors);
  ASSERT_TRUE(p) << (errors.empty() ? "" : errors[0].toString());
  EXPECT_EQ(p->validate(), "");
  EXPECT_DOUBLE_EQ(p->lidar.point_rate, 200000);
  EXPECT_DOUBLE_EQ(p->lidar.mount_rpy_deg[0], 180.0);
  EXPECT_EQ(p->net.host_point_port, 56301);
  EXPECT_EQ(p->net.host_imu_port, 56401);
  EXPECT_DOUBLE_EQ(p->imu.rate_hz, 200);
}

TEST(SimulatorParams, GivenBadValuesThenTheErrorNamesTheKey) {
  std::string err;
  const std::string text = *runtime::readTextFile("deploy/config/simulator.yaml", &err);
  struct Case {
    std::string from, to, key;
  };
  for (const Case& c : std::vector<Case>{{"point_rate: 200000", "point_rate: 300000", "lidar.point_rate"},
                                         {"data_type: 1", "data_type: 7", "lidar.data_type"},
                                         {"max_range: 40.0", "max_range: 0.05", "lidar.max_range"},
                                         {"host_imu_port: 56401", "host_imu_port: 70000", "net.host_imu_port"},
                                         {"rate_hz: 200", "rate_hz: 300", "imu.rate_hz"},
                                         {"wheel_radius: 0.05", "wheel_radius: 0.05\n  wheel_radus: 1", "base.wheel_radus"},
                                         {"pose_rate_hz: 100", "pose_rate_hz: abc", "pose_rate_hz"}}) {
    std::string t = text;
    const auto pos = t.find(c.from);
    ASSERT_NE(pos, std::string::npos) << c.from;
    t.replace(pos, c.from.size(), c.to);
    std::vector<ConfigError> errors;
    EXPECT_FALSE(loadParams<SimulatorParams>(t, "simulator.yaml", &errors)) << c.to;
    bool named = false;
    for (const auto& e : errors) named = named || e.key == c.key;
    EXPECT_TRUE(named) << c.to << " -> " << (errors.empty() ? "no error" : errors[0].toString());
  }
}

TEST(ScenarioLoader, GivenSpecsThenBuiltinsBenchAndErrorsResolve) {
  std::string err;
  auto ped = loadScenario("pedestrians", "deploy/scenarios", -1, runtime::readTextFile, &err);
  ASSERT_TRUE(ped) << err;
  EXPECT_EQ(ped->name, "pedestrians");
  auto seeded = loadScenario("crossing", "deploy/scenarios", 9, runtime::readTextFile, &err);
  ASSERT_TRUE(seeded) << err;
  EXPECT_EQ(seeded->seed, 9u);
  auto bench = loadScenario("bench:50:4", "deploy/scenarios", -1, runtime::readTextFile, &err);
  ASSERT_TRUE(bench);
  EXPECT_EQ(bench->movers.size(), 50u);
  EXPECT_EQ(bench->seed, 4u);
  EXPECT_FALSE(loadScenario("no/such/file.yaml", "deploy/scenarios", -1, runtime::readTextFile, &err));
  EXPECT_NE(err.find("no/such/file.yaml"), std::string::npos) << err;
  EXPECT_FALSE(loadScenario("bench:x:1", "deploy/scenarios", -1, runtime::readTextFile, &err));
  EXPECT_NE(err.find("bench:"), std::string::npos) << err;
}
