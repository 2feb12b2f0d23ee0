// ucon-bench-nav --planner-model / --check-growth: the shipped planner.yaml with the obstacle
// model and the shared covariance growth replaced, everything else as shipped.
#include "planner_variant.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "ucon/config.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/runtime/config_file.hpp"

namespace nav = ucon::bench::nav;
using ucon::planner::PlannerParams;

namespace {

std::string shipped() {
  std::string err;
  auto t = ucon::runtime::readTextFile(std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml", &err);
  EXPECT_TRUE(t) << err;
  return t ? *t : std::string();
}

PlannerParams load(const std::string& text) {
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<PlannerParams>(text, "variant", &errors);
  EXPECT_TRUE(p) << (errors.empty() ? "" : errors[0].toString());
  return p ? *p : PlannerParams{};
}

}  // namespace

TEST(BenchNavPlannerVariant, GivenAModelAndAGrowthThenOnlyThoseKeysChange) {
  const std::string yaml = shipped();
  const PlannerParams before = load(yaml);
  std::string out, err;
  ASSERT_TRUE(nav::plannerVariant(yaml, "fapp", 0.0, &out, &err)) << err;
  const PlannerParams after = load(out);
  EXPECT_EQ(after.optimizer.obstacle_model, ucon::trajopt::ObstacleModel::kFapp);
  EXPECT_EQ(after.optimizer.check_uncertainty_k, 0.0);
  EXPECT_EQ(after.fallback.uncertainty_k, 0.0);
  ASSERT_NE(before.optimizer.check_uncertainty_k, 0.0);  // else the test shows nothing
  // The rest as shipped.
  EXPECT_EQ(after.optimizer.lambda_d, before.optimizer.lambda_d);
  EXPECT_EQ(after.optimizer.sector.k, before.optimizer.sector.k);
  EXPECT_EQ(after.optimizer.check_uncertainty_cap, before.optimizer.check_uncertainty_cap);
  EXPECT_EQ(after.prediction.accel_psd_xy, before.prediction.accel_psd_xy);
  EXPECT_EQ(after.fallback.detours, before.fallback.detours);
  EXPECT_EQ(after.map.resolution, before.map.resolution);
  EXPECT_EQ(after.rate_hz, before.rate_hz);
}

TEST(BenchNavPlannerVariant, GivenNoGrowthThenTheShippedGrowthStays) {
  const std::string yaml = shipped();
  std::string out, err;
  ASSERT_TRUE(nav::plannerVariant(yaml, "no_uncertainty", -1.0, &out, &err)) << err;
  const PlannerParams before = load(yaml), after = load(out);
  EXPECT_EQ(after.optimizer.obstacle_model, ucon::trajopt::ObstacleModel::kNoUncertainty);
  EXPECT_EQ(after.optimizer.check_uncertainty_k, before.optimizer.check_uncertainty_k);
  EXPECT_EQ(after.fallback.uncertainty_k, before.fallback.uncertainty_k);
}

TEST(BenchNavPlannerVariant, GivenABadModelOrGrowthOrTextThenAnErrorNamesIt) {
  const std::string yaml = shipped();
  std::string out = "untouched", err;
  EXPECT_FALSE(nav::plannerVariant(yaml, "bubbles", -1.0, &out, &err));
  EXPECT_NE(err.find("obstacle_model"), std::string::npos) << err;
  EXPECT_FALSE(nav::plannerVariant(yaml, "sector", 9.0, &out, &err));
  EXPECT_NE(err.find("uncertainty_k"), std::string::npos) << err;
  EXPECT_FALSE(nav::plannerVariant("optimizer: [1, 2", "sector", -1.0, &out, &err));
  EXPECT_FALSE(nav::plannerVariant("rate_hz: 10.0\n", "sector", -1.0, &out, &err));
  EXPECT_NE(err.find("optimizer.obstacle_model"), std::string::npos) << err;
  EXPECT_EQ(out, "untouched");
}
