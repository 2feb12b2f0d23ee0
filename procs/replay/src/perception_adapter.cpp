// perception in lock step, wired by its binding (ucon/perception/binding.hpp).
#include <vector>

#include "adapters.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/perception/binding.hpp"
#include "ucon/replay/bound_adapter.hpp"

namespace ucon {
namespace replay {

std::unique_ptr<NodeAdapter> makePerceptionAdapter(const std::string& yaml, const std::string& source,
                                                   std::string* error) {
  auto p = adapterParams<perception::PerceptionParams, false>(yaml, source, error);
  if (!p) return nullptr;
  // The mean frame time [us] over the replay, for the summary (measurement only).
  auto frame_ms_total = std::make_shared<double>(0.0);
  auto a = std::make_unique<BoundAdapter<perception::PerceptionNode>>(
      perception::binding(), std::make_unique<perception::PerceptionNode>(*p),
      [frame_ms_total](const perception::PerceptionNode&, const FeedCounts& c)
          -> std::vector<std::pair<std::string, int64_t>> {
        const int64_t frames = c.inputs(channels::kLidarPoints);
        return {{"poses_in", c.inputs(channels::kRobotPose)},
                {"frames_in", frames},
                {"objects_out", c.outputs(channels::kPerceptionObjects)},
                {"static_out", c.outputs(channels::kPerceptionStatic)},
                {"decode_errors", c.decode_errors},
                {"frame_us_mean", frames ? static_cast<int64_t>(1e3 * *frame_ms_total / static_cast<double>(frames)) : 0}};
      });
  a->onHandled([frame_ms_total](const perception::PerceptionNode& n, const std::string& channel) {
    if (channel == channels::kLidarPoints) *frame_ms_total += n.lastFrameMs();
  });
  return a;
}

}  // namespace replay
}  // namespace ucon
