#pragma once
/// @file trajectory_metrics.hpp
/// Odometry accuracy against ground truth, as the LiDAR odometry literature reports it:
///  - relative pose error over path segments of `segment_m` (KITTI's measure: for segment
///    starts every `segment_step_m` of travelled path, E = (G_i^-1 G_j)^-1 (S_i^-1 S_j) with j
///    the first pose `segment_m` further along; translation |t(E)| in % of the segment's
///    length, rotation angle(E) in degrees per 10 m);
///  - absolute trajectory error after aligning the first pose (rms and max position error);
///  - final drift: the position error at the last pose, in m and in % of the path length.
/// The estimate is sampled at the ground-truth times (linear / slerp interpolation between
/// its two neighbours, never across a gap longer than max_gap_us).

#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <vector>

namespace ucon {
namespace lio {

struct TimedPose {
  int64_t utime = 0;  ///< [us]
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
};

struct MetricsOptions {
  double segment_m = 10.0;       ///< RPE segment length [m], > 0
  double segment_step_m = 1.0;   ///< distance between segment starts [m], > 0
  int64_t max_gap_us = 100000;   ///< longest estimate interval interpolated across [us]
};

struct TrajectoryErrors {
  int truth_poses = 0;           ///< ground-truth poses given
  int matched = 0;               ///< of those, with an estimate
  double path_length_m = 0.0;    ///< along the matched ground truth
  int segments = 0;              ///< RPE segments (0 when the path is shorter than segment_m)
  double rpe_translation_pct = 0.0;         ///< mean over segments [%]; NaN without segments
  double rpe_translation_pct_median = 0.0;  ///< [%]
  double rpe_translation_pct_max = 0.0;     ///< [%]
  double rpe_rotation_deg_per_10m = 0.0;         ///< mean [deg / 10 m]
  double rpe_rotation_deg_per_10m_median = 0.0;  ///< [deg / 10 m]
  double ate_rmse_m = 0.0;       ///< after aligning the first pose [m]
  double ate_max_m = 0.0;        ///< [m]
  double final_drift_m = 0.0;    ///< position error at the last matched pose [m]
  double final_drift_pct = 0.0;  ///< of the path length [%]
  double final_yaw_error_deg = 0.0;  ///< heading error at the last pose [deg]
};

/// `trajectory` (sorted by utime) at `utime`, interpolated; nullopt outside it or across a
/// gap longer than max_gap_us.
std::optional<Eigen::Isometry3d> interpolatePose(const std::vector<TimedPose>& trajectory, int64_t utime,
                                                 int64_t max_gap_us);

/// Errors of `estimate` against `truth` (both sorted by utime).
TrajectoryErrors evaluateTrajectory(const std::vector<TimedPose>& truth, const std::vector<TimedPose>& estimate,
                                    const MetricsOptions& options = {});

}  // namespace lio
}  // namespace ucon
