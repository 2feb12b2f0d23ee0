#include "ucon/odometry/log_trajectories.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ucon/lio/so3.hpp"

namespace ucon {
namespace odometry {

namespace {
double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}
}  // namespace

Eigen::Isometry3d toIsometry(const robot_pose_t& m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond q(m.qw, m.qx, m.qy, m.qz);
  if (q.norm() > 1e-9 && std::isfinite(q.norm()))
    T.linear() = q.normalized().toRotationMatrix();
  else
    T.linear() = lio::rotationFromRpy(0.0, 0.0, m.yaw);
  T.translation() = Eigen::Vector3d(m.x, m.y, m.z);
  return T;
}

Eigen::Isometry3d toIsometry(const sim_ground_truth_t& g) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = lio::rotationFromRpy(0.0, 0.0, g.robot_yaw);
  T.translation() = Eigen::Vector3d(g.robot_x, g.robot_y, 0.0);
  return T;
}

void LogTrajectories::onGroundTruth(const sim_ground_truth_t& g) {
  if (g.utime <= 0 || !std::isfinite(g.robot_x) || !std::isfinite(g.robot_y) || !std::isfinite(g.robot_yaw)) return;
  if (!truth_.empty() && g.utime <= truth_.back().utime) return;
  truth_.push_back({g.utime, toIsometry(g)});
}

void LogTrajectories::onPose(const robot_pose_t& m) {
  ++poses_;
  if (!m.valid || m.utime <= 0) {
    ++poses_invalid_;
    return;
  }
  const Eigen::Isometry3d T = toIsometry(m);
  if (!T.matrix().allFinite()) return;
  if (!estimate_.empty() && m.utime <= estimate_.back().utime) return;
  estimate_.push_back({m.utime, T});
}

void LogTrajectories::onStatus(const odometry_status_t& s) {
  ++statuses_;
  if (s.result >= 0 && s.result < static_cast<int>(results_.size())) ++results_[static_cast<std::size_t>(s.result)];
  if (s.result == odometry_status_t::RESULT_UPDATED) {
    if (std::isfinite(s.residual_rms)) residual_rms_.push_back(s.residual_rms);
    matched_.push_back(s.points_matched);
  }
}

double LogTrajectories::medianResidualRms() const { return median(residual_rms_); }
double LogTrajectories::medianPointsMatched() const { return median(matched_); }

const char* resultName(int r) {
  switch (r) {
    case odometry_status_t::RESULT_UPDATED: return "updated";
    case odometry_status_t::RESULT_MAP_STARTED: return "map started";
    case odometry_status_t::RESULT_TOO_FEW_POINTS: return "too few points";
    case odometry_status_t::RESULT_NOT_REGISTERED: return "not registered";
    case odometry_status_t::RESULT_NOT_INITIALISED: return "not initialised";
    case odometry_status_t::RESULT_OUT_OF_ORDER: return "out of order";
    case odometry_status_t::RESULT_LATE: return "late";
    case odometry_status_t::RESULT_NO_IMU: return "no IMU";
    case odometry_status_t::RESULT_BAD_FRAME: return "bad frame";
  }
  return "?";
}

}  // namespace odometry
}  // namespace ucon
