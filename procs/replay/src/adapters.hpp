#pragma once
// Factories of the per-node adapters (internal to ucon_replay).
#include <memory>
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

}  // namespace replay
}  // namespace ucon
