#include "planner_variant.hpp"

#include <yaml-cpp/yaml.h>

#include <vector>

#include "ucon/planner/planner_params.hpp"
#include "ucon/config.hpp"

namespace ucon::bench::nav {

namespace {

// Sets the existing scalar `section.key`; false when it is not there (a renamed key must not
// be added silently, which the planner would then reject as unknown or ignore).
bool setScalar(YAML::Node root, const char* section, const char* key, const std::string& value, std::string* error) {
  YAML::Node s = root[section];
  if (!s.IsMap() || !s[key].IsScalar()) {
    *error = std::string("planner.yaml has no scalar '") + section + "." + key + "'";
    return false;
  }
  s[key] = value;
  return true;
}

}  // namespace

bool plannerVariant(const std::string& yaml, const std::string& model, double check_growth, std::string* out,
                    std::string* error) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    *error = std::string("planner.yaml: ") + e.what();
    return false;
  }
  if (!root.IsMap()) {
    *error = "planner.yaml is not a mapping";
    return false;
  }
  if (!model.empty() && !setScalar(root, "optimizer", "obstacle_model", model, error)) return false;
  if (check_growth >= 0.0) {
    YAML::Emitter num;
    num << check_growth;
    if (!setScalar(root, "optimizer", "check_uncertainty_k", num.c_str(), error) ||
        !setScalar(root, "fallback", "uncertainty_k", num.c_str(), error))
      return false;
  }
  YAML::Emitter em;
  em << root;
  std::string text = em.c_str();
  std::vector<ConfigError> errors;
  if (!loadParams<planner::PlannerParams>(text, "planner.yaml (--planner-model, --check-growth)", &errors)) {
    *error = "planner.yaml (--planner-model, --check-growth):";
    for (const auto& e : errors) *error += " " + e.toString();
    return false;
  }
  *out = std::move(text);
  return true;
}

}  // namespace ucon::bench::nav
