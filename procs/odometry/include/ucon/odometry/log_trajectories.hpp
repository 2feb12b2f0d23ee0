#pragma once
/// @file log_trajectories.hpp
/// Collects what ucon-odom-eval and the odometry benchmark compare: the ground-truth
/// trajectory (SIM_GROUND_TRUTH: planar, z = 0, level), the estimated base trajectory
/// (ROBOT_POSE, valid poses only) and the per-frame results (ODOMETRY_STATUS). Pure: the
/// caller decodes the messages.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ucon/lio/trajectory_metrics.hpp"
#include "ucon/odometry_status_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/sim_ground_truth_t.hpp"

namespace ucon {
namespace odometry {

/// ROBOT_POSE as a pose (quaternion normalised; the yaw field when the quaternion is zero).
Eigen::Isometry3d toIsometry(const robot_pose_t& m);
/// SIM_GROUND_TRUTH's robot as a planar pose (z = 0, level).
Eigen::Isometry3d toIsometry(const sim_ground_truth_t& g);

class LogTrajectories {
 public:
  void onGroundTruth(const sim_ground_truth_t& g);
  void onPose(const robot_pose_t& m);
  void onStatus(const odometry_status_t& s);

  /// Ground truth and valid estimates, each sorted by utime (out-of-order ones dropped).
  const std::vector<lio::TimedPose>& truth() const { return truth_; }
  const std::vector<lio::TimedPose>& estimate() const { return estimate_; }
  int64_t poses() const { return poses_; }
  int64_t posesInvalid() const { return poses_invalid_; }
  int64_t statuses() const { return statuses_; }
  /// ODOMETRY_STATUS count per RESULT_* value (index = result, 0..8).
  const std::array<int64_t, 9>& results() const { return results_; }
  /// Median of the residual rms and of the matched points over updated frames (NaN if none).
  double medianResidualRms() const;
  double medianPointsMatched() const;

 private:
  std::vector<lio::TimedPose> truth_, estimate_;
  int64_t poses_ = 0, poses_invalid_ = 0, statuses_ = 0;
  std::array<int64_t, 9> results_{};
  std::vector<double> residual_rms_, matched_;
};

/// Name of an ODOMETRY_STATUS result value ("updated", "too few points", ...).
const char* resultName(int result);

}  // namespace odometry
}  // namespace ucon
