#pragma once
/// @file odometry_node.hpp
/// The odometry node: LIDAR_IMU + LIDAR_POINTS -> ROBOT_POSE (one per IMU sample, base frame,
/// 6x6 covariance, valid flag) and ODOMETRY_STATUS (one per frame). The estimator is
/// ucon::lio::LioOdometry; this class converts messages, guards the inputs and keeps the
/// counters for ODOMETRY_HEALTH. No sockets and no clock in the logic (a stopwatch times
/// the work for the health message only), so a replay gives the same bytes.

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "ucon/imu_t.hpp"
#include "ucon/lio/lio_odometry.hpp"
#include "ucon/odometry/params.hpp"
#include "ucon/odometry_status_t.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/status_report.hpp"

namespace ucon {
namespace odometry {

/// What one input made the node publish, in this order.
struct OdometryOutput {
  std::optional<robot_pose_t> pose;
  std::vector<odometry_status_t> statuses;
};

/// Pose of the points frame ("base") and its covariance from an IMU state: position
/// p_b = p - R t, rotation R (the IMU axes are the points frame's), and the 6x6 covariance
/// over [x y z roll pitch yaw] (roll, pitch, yaw: R = Rz Ry Rx) as M P M^T with M the
/// Jacobian of (p_b, rpy) over the error state (world-frame rotation error R dtheta mapped to
/// Euler-angle rates).
Eigen::Matrix<double, 6, 1> basePoseVector(const lio::NavState& x, const Eigen::Vector3d& imu_position);
Eigen::Matrix<double, 6, lio::kStateDim> basePoseJacobian(const lio::NavState& x, const Eigen::Vector3d& imu_position);

/// Fills a ROBOT_POSE from a pose estimate (utime from its time, seq left 0).
robot_pose_t toRobotPose(const lio::PoseEstimate& e, const Eigen::Vector3d& imu_position);

/// LIDAR_IMU as an estimator sample (no checks: the node checks first).
lio::ImuSample toImuSample(const imu_t& m);
/// LIDAR_POINTS as an estimator frame: points in time order (stable), non-finite points and
/// negative offsets left out and counted in `dropped`. The message's arrays must have
/// num_points entries (the node checks first).
lio::PointFrame toPointFrame(const point_cloud_t& c, int32_t* dropped);

class OdometryNode {
 public:
  /// Seconds from an arbitrary origin; used only to time the work for the health message.
  using Stopwatch = std::function<double()>;

  /// `params` should satisfy validate(). `stopwatch` empty = std::chrono::steady_clock.
  explicit OdometryNode(const OdometryParams& params, Stopwatch stopwatch = {});

  /// LIDAR_IMU: the pose at this sample once initialised. Frames the sample lets run wait
  /// for processFrames(), which the caller runs after publishing the pose (so the pose does
  /// not wait for the LiDAR update). Wrong frame_id, utime <= 0 or non-finite values are
  /// counted and dropped.
  OdometryOutput onImu(const imu_t& imu);

  /// Runs the frames the IMU samples now cover: one status each.
  OdometryOutput processFrames();

  /// LIDAR_POINTS: queued until IMU samples cover it (a status once it runs), or a status at
  /// once when it is dropped. Non-finite points and negative offsets are dropped and counted.
  OdometryOutput onPoints(const point_cloud_t& cloud);

  /// Newest input time [us].
  int64_t now() const { return now_; }
  const lio::LioOdometry& estimator() const { return lio_; }
  /// Counters, timings and gauges for ODOMETRY_HEALTH, brought up to date.
  StatusReport& status();
  /// Processing time of the last frame that ran [ms] (wall clock; measurement only).
  double lastFrameMs() const { return last_frame_ms_; }
  /// Time to produce the last pose [ms] (wall clock; measurement only).
  double lastPoseMs() const { return last_pose_ms_; }

 private:
  odometry_status_t toStatus(const lio::FrameReport& r);
  void emitReports(OdometryOutput& out);

  OdometryParams params_;
  Stopwatch stopwatch_;
  lio::LioOdometry lio_;
  StatusReport status_;
  int64_t now_ = 0;
  int64_t pose_seq_ = 0, status_seq_ = 0;
  int64_t imu_bad_ = 0, imu_wrong_frame_ = 0, frames_bad_ = 0, points_dropped_ = 0, poses_out_ = 0,
          poses_invalid_ = 0;
  std::vector<lio::FrameReport> reports_;
  std::map<int64_t, int32_t> dropped_by_seq_;  // points the node dropped, per queued frame
  double last_frame_ms_ = 0.0, last_pose_ms_ = 0.0;
};

}  // namespace odometry
}  // namespace ucon
