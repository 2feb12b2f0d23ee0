// base_controller in lock step, wired by its binding (ucon/base_controller/binding.hpp): the
// control step ticks on the period grid in message time, every tick due before a message first.
#include <vector>

#include "adapters.hpp"
#include "ucon/base_controller/binding.hpp"
#include "ucon/config.hpp"
#include "ucon/replay/bound_adapter.hpp"

namespace ucon {
namespace replay {

std::unique_ptr<NodeAdapter> makeBaseControllerAdapter(const std::string& yaml, const std::string& source,
                                                       std::string* error) {
  auto p = adapterParams<base_controller::BaseControllerParams, true>(yaml, source, error);
  if (!p) return nullptr;
  return std::make_unique<BoundAdapter<base_controller::BoundBaseController>>(
      base_controller::binding(*p), std::make_unique<base_controller::BoundBaseController>(*p),
      [](const base_controller::BoundBaseController& n, const FeedCounts& c) {
        auto counters = n.node.counters();
        counters.emplace_back("decode_errors", c.decode_errors);
        return counters;
      });
}

}  // namespace replay
}  // namespace ucon
