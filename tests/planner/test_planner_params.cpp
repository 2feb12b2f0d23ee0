// The planner's parameters: the paper's values, loading errors that name the key, the prediction
// model. That deploy/config/planner.yaml equals the in-class defaults field by field is
// ShippedConfig.GivenPlannerYaml* (tests/unit/test_shipped_config.cpp).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "ucon/config.hpp"
#include "ucon/planner/planner_params.hpp"

using namespace ucon;
using namespace ucon::planner;

namespace {

std::string readShipped() {
  std::ifstream f(std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

TEST(PlannerParams, GivenTheShippedConfigThenThePaperParametersAreThePapersValues) {
  // Sec. V-A: h = 0.02, k = 2, kappa = 0.05, alpha = 15, beta = 25, lambda_d = 5e3, rho = 10.
  const PlannerParams p;
  EXPECT_EQ(p.optimizer.sector.h, 0.02);
  EXPECT_EQ(p.optimizer.sector.k, 2.0);
  EXPECT_EQ(p.optimizer.sector.kappa, 0.05);
  EXPECT_EQ(p.optimizer.sector.alpha, 15.0);
  EXPECT_EQ(p.optimizer.sector.beta, 25.0);
  EXPECT_EQ(p.optimizer.lambda_d, 5e3);
  EXPECT_EQ(p.optimizer.rho, 10.0);
  EXPECT_EQ(p.optimizer.obstacle_model, trajopt::ObstacleModel::kSector);
}

TEST(PlannerParams, GivenTheShippedConfigWithAKeyMissingOrUnknownThenLoadingNamesIt) {
  std::string yaml = readShipped();
  std::vector<ConfigError> errors;
  std::string typo = yaml;
  typo.replace(typo.find("accel_psd_xy:"), 13, "accel_psd_yx:");
  EXPECT_FALSE(loadParams<PlannerParams>(typo, "planner.yaml", &errors).has_value());
  bool named = false;
  for (const auto& e : errors) named = named || e.toString().find("accel_psd") != std::string::npos;
  EXPECT_TRUE(named);
}

TEST(PlannerParams, GivenThePredictionModelThenOnlyItsProcessNoiseComesFromTheConfig) {
  PredictionParams p;
  p.accel_psd_xy = 0.7;
  p.accel_psd_z = 0.2;
  const kalman::KalmanParams k = p.model();
  EXPECT_EQ(k.accel_psd_xy, 0.7);
  EXPECT_EQ(k.accel_psd_z, 0.2);
  EXPECT_TRUE(k.validate().empty());
}
