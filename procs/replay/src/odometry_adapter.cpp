// odometry in lock step, wired by its binding (ucon/odometry/binding.hpp): LIDAR_IMU -> the pose
// at that sample (ROBOT_POSE, or the configured pose_channel), then ODOMETRY_STATUS of the frames
// it lets run; LIDAR_POINTS -> ODOMETRY_STATUS of a frame dropped at once. ODOMETRY_HEALTH carries
// wall-clock timings and is not replayed.
#include <vector>

#include "adapters.hpp"
#include "ucon/config.hpp"
#include "ucon/odometry/binding.hpp"
#include "ucon/replay/bound_adapter.hpp"

namespace ucon {
namespace replay {

std::unique_ptr<NodeAdapter> makeOdometryAdapter(const std::string& yaml, const std::string& source,
                                                 std::string* error) {
  auto p = adapterParams<odometry::OdometryParams, true>(yaml, source, error);
  if (!p) return nullptr;
  const std::string pose_channel = p->pose_channel;
  return std::make_unique<BoundAdapter<odometry::BoundOdometry>>(
      odometry::binding(*p), std::make_unique<odometry::BoundOdometry>(*p),
      [pose_channel](const odometry::BoundOdometry& n, const FeedCounts& c) {
        const auto& e = n.node.estimator().counters();
        return std::vector<std::pair<std::string, int64_t>>{
            {"imu_in", c.inputs(channels::kLidarImu)},
            {"frames_in", c.inputs(channels::kLidarPoints)},
            {"poses_out", c.outputs(pose_channel)},
            {"statuses_out", c.outputs(channels::kOdometryStatus)},
            {"frames_updated", e.frames_updated},
            {"frames_skipped", e.frames_skipped},
            {"frames_dropped", e.frames_dropped},
            {"imu_gaps", e.imu_gaps},
            {"decode_errors", c.decode_errors}};
      });
}

}  // namespace replay
}  // namespace ucon
