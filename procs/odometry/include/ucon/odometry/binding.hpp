#pragma once
/// @file binding.hpp
/// ucon-odometry's wiring, used by its main and by its replay adapter (see
/// ucon/runtime/binding.hpp): LIDAR_IMU -> onImu (the pose at that sample first), then
/// processFrames (ODOMETRY_STATUS of the frames the sample lets run); LIDAR_POINTS -> onPoints
/// (ODOMETRY_STATUS of a frame dropped at once). No tick: the handlers do everything.
/// ODOMETRY_HEALTH from the node's own report every health_period_s.

#include <string>

#include "ucon/channels.hpp"
#include "ucon/odometry/odometry_node.hpp"
#include "ucon/runtime/binding.hpp"

namespace ucon {
namespace odometry {

/// The odometry as its harnesses run it: the node, the channel its poses go to
/// (`pose_channel`) and the last estimator phase logged.
struct BoundOdometry {
  explicit BoundOdometry(const OdometryParams& params) : node(params), pose_channel(params.pose_channel) {}
  OdometryNode node;
  std::string pose_channel;
  lio::Phase logged_phase = lio::Phase::kInitialising;
};

inline const runtime::Output<odometry_status_t> kStatusOutput{channels::kOdometryStatus};

/// Publishes the pose, then the frame statuses; logs each change of the estimator's phase.
inline void publish(BoundOdometry& n, const OdometryOutput& o, runtime::Outbox& out) {
  if (o.pose) out.publish(runtime::Output<robot_pose_t>{n.pose_channel.c_str()}, *o.pose);
  for (const auto& s : o.statuses) out.publish(kStatusOutput, s);
  const lio::Phase phase = n.node.estimator().phase();
  if (phase != n.logged_phase) {
    n.logged_phase = phase;
    const std::string& why = n.node.estimator().phaseReason();
    out.log("info", std::string("state: ") + lio::toString(phase) + (why.empty() ? "" : " (" + why + ")"));
  }
}

inline runtime::NodeBinding<BoundOdometry> binding(const OdometryParams& params) {
  using N = BoundOdometry;
  using runtime::Outbox;
  runtime::NodeBinding<N> b;
  b.name = "odometry";
  b.inputs = {
      runtime::input<imu_t, N>(channels::kLidarImu,
                               [](N& n, const imu_t& m, Outbox& out) {
                                 publish(n, n.node.onImu(m), out);
                                 publish(n, n.node.processFrames(), out);
                               }),
      runtime::input<point_cloud_t, N>(channels::kLidarPoints, [](N& n, const point_cloud_t& m, Outbox& out) {
        publish(n, n.node.onPoints(m), out);
      }),
  };
  b.outputs = {params.pose_channel, kStatusOutput.channel};
  b.tick_rule = runtime::TickRule::none(20);
  b.clock = [](const N& n) { return n.node.now(); };
  b.status_channel = channels::kOdometryHealth;
  b.status_period_s = params.health_period_s;
  b.status = [](N& n) -> StatusReport& { return n.node.status(); };
  return b;
}

}  // namespace odometry
}  // namespace ucon
