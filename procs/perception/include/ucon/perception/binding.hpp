#pragma once
/// @file binding.hpp
/// ucon-perception's wiring, used by its main and by its replay adapter (see
/// ucon/runtime/binding.hpp): ROBOT_POSE -> onPose, LIDAR_POINTS -> onPoints, then tick(now)
/// after every input (live, also after 20 ms without one); PERCEPTION_OBJECTS before
/// PERCEPTION_STATIC; PERCEPTION_STATUS from the node's own report.

#include "ucon/channels.hpp"
#include "ucon/perception/perception_node.hpp"
#include "ucon/runtime/binding.hpp"

namespace ucon {
namespace perception {

inline const runtime::Output<tracked_objects_t> kObjectsOutput{channels::kPerceptionObjects};
inline const runtime::Output<static_points_t> kStaticOutput{channels::kPerceptionStatic};

inline void publish(const PerceptionOutput& o, runtime::Outbox& out) {
  if (o.objects) out.publish(kObjectsOutput, *o.objects);
  if (o.static_points) out.publish(kStaticOutput, *o.static_points);
}

inline runtime::NodeBinding<PerceptionNode> binding() {
  using N = PerceptionNode;
  runtime::NodeBinding<N> b;
  b.name = "perception";
  b.inputs = {
      runtime::input<robot_pose_t, N>(channels::kRobotPose,
                                      [](N& n, const robot_pose_t& m, runtime::Outbox&) { n.onPose(m); }),
      runtime::input<point_cloud_t, N>(channels::kLidarPoints, [](N& n, const point_cloud_t& m, runtime::Outbox& out) {
        publish(n.onPoints(m), out);
      }),
  };
  b.outputs = {kObjectsOutput.channel, kStaticOutput.channel};
  b.tick_rule = runtime::TickRule::afterInput(20);
  b.tick = [](N& n, int64_t now, runtime::Outbox& out) { publish(n.tick(now), out); };
  b.clock = [](const N& n) { return n.now(); };
  b.status_channel = channels::kPerceptionStatus;
  b.status = [](N& n) -> StatusReport& { return n.status(); };
  return b;
}

}  // namespace perception
}  // namespace ucon
