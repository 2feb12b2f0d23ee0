#pragma once
// Factories of the per-node adapters (internal to ucon_replay).
#include <memory>
#include <optional>
#include <string>

#include <vector>

#include "ucon/config.hpp"
#include "ucon/replay/node_adapter.hpp"

namespace ucon {
namespace replay {

std::unique_ptr<NodeAdapter> makeBaseControllerAdapter(const std::string& yaml, const std::string& source,
                                                       std::string* error);
#ifdef UCON_REPLAY_HAVE_ODOMETRY
std::unique_ptr<NodeAdapter> makeOdometryAdapter(const std::string& yaml, const std::string& source,
                                                 std::string* error);
#endif
#ifdef UCON_REPLAY_HAVE_PERCEPTION
std::unique_ptr<NodeAdapter> makePerceptionAdapter(const std::string& yaml, const std::string& source,
                                                   std::string* error);
#endif
#ifdef UCON_REPLAY_HAVE_PLANNER
std::unique_ptr<NodeAdapter> makePlannerAdapter(const std::string& yaml, const std::string& source,
                                                std::string* error);
#endif

/// "source: key: message; key: message" for config errors.
std::string configErrorText(const std::string& source, const std::vector<ConfigError>& errors);

/// A node's parameters from its YAML text; with kValidate, also checked by P::validate().
/// Nothing and `error` set when a key is wrong or (with kValidate) a value is out of range.
template <class P, bool kValidate>
std::optional<P> adapterParams(const std::string& yaml, const std::string& source, std::string* error) {
  std::vector<ConfigError> errors;
  auto p = loadParams<P>(yaml, source, &errors);
  if (!p) {
    if (error) *error = configErrorText(source, errors);
    return std::nullopt;
  }
  if constexpr (kValidate) {
    if (const std::string bad = p->validate(); !bad.empty()) {
      if (error) *error = source + ": " + bad;
      return std::nullopt;
    }
  }
  return p;
}

}  // namespace replay
}  // namespace ucon
