#include "ucon/replay/node_adapter.hpp"

#include <algorithm>

#include "ucon/config.hpp"
#include "adapters.hpp"

namespace ucon {
namespace replay {

const char* toString(FeedResult r) {
  switch (r) {
    case FeedResult::kHandled: return "handled";
    case FeedResult::kIgnored: return "ignored";
    case FeedResult::kDecodeError: return "decode error";
  }
  return "?";
}

bool NodeAdapter::consumes(const std::string& channel) const {
  const auto in = inputChannels();
  return std::find(in.begin(), in.end(), channel) != in.end();
}

std::vector<std::string> availableNodes() {
  std::vector<std::string> out;
#ifdef UCON_REPLAY_HAVE_PERCEPTION
  out.push_back("perception");
#endif
#ifdef UCON_REPLAY_HAVE_PLANNER
  out.push_back("planner");
#endif
  out.push_back("base_controller");
#ifdef UCON_REPLAY_HAVE_ODOMETRY
  out.push_back("odometry");
#endif
  return out;
}

bool isKnownNode(const std::string& node) {
  return node == "perception" || node == "planner" || node == "base_controller" || node == "odometry";
}

std::string configErrorText(const std::string& source, const std::vector<ConfigError>& errors) {
  std::string s;
  for (const auto& e : errors) s += (s.empty() ? "" : "; ") + e.toString();
  if (errors.empty()) s = "config error";
  return source + ": " + s;
}

std::unique_ptr<NodeAdapter> makeAdapter(const std::string& node, const std::string& config_yaml,
                                         const std::string& source, std::string* error) {
  if (node == "base_controller") return makeBaseControllerAdapter(config_yaml, source, error);
#ifdef UCON_REPLAY_HAVE_ODOMETRY
  if (node == "odometry") return makeOdometryAdapter(config_yaml, source, error);
#endif
#ifdef UCON_REPLAY_HAVE_PERCEPTION
  if (node == "perception") return makePerceptionAdapter(config_yaml, source, error);
#endif
#ifdef UCON_REPLAY_HAVE_PLANNER
  if (node == "planner") return makePlannerAdapter(config_yaml, source, error);
#endif
  if (error) {
    std::string list;
    for (const auto& n : availableNodes()) list += (list.empty() ? "" : ", ") + n;
    *error = isKnownNode(node) ? "node '" + node + "' is not built in this version (available: " + list + ")"
                               : "unknown node '" + node + "' (available: " + list + ")";
  }
  return nullptr;
}

}  // namespace replay
}  // namespace ucon
