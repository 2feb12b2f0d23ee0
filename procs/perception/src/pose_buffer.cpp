#include "ucon/perception/pose_buffer.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace perception {

PoseBuffer::AddResult PoseBuffer::add(const robot_pose_t& pose) {
  if (!pose.valid || pose.utime <= 0) return AddResult::kInvalid;
  const Eigen::Vector3d p(pose.x, pose.y, pose.z);
  Eigen::Quaterniond q(pose.qw, pose.qx, pose.qy, pose.qz);
  if (!p.allFinite() || !q.coeffs().allFinite() || q.norm() < 1e-6) return AddResult::kNonFinite;
  if (!poses_.empty() && pose.utime <= poses_.back().utime) return AddResult::kOutOfOrder;
  q.normalize();
  Eigen::Vector3d v(pose.vx, pose.vy, pose.vz), w(pose.wx, pose.wy, pose.wz);
  if (!v.allFinite()) v.setZero();
  if (!w.allFinite()) w.setZero();
  poses_.push_back({pose.utime, p, q, v, w});
  while (poses_.size() > 2 && poses_.front().utime < pose.utime - window_us_) poses_.pop_front();
  return AddResult::kAdded;
}

std::optional<Eigen::Isometry3d> PoseBuffer::at(int64_t utime, double max_gap_s) const {
  if (poses_.empty()) return std::nullopt;
  const int64_t max_gap_us = static_cast<int64_t>(max_gap_s * 1e6);
  auto make = [](const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = p;
    return T;
  };
  if (utime <= poses_.front().utime) {
    if (poses_.front().utime - utime > max_gap_us) return std::nullopt;
    return make(poses_.front().p, poses_.front().q);
  }
  if (utime >= poses_.back().utime) {
    const Stamped& n = poses_.back();
    if (utime - n.utime > max_gap_us) return std::nullopt;
    // Constant velocity over the gap (at most max_gap_s): the body turns about its own axes.
    const double dt = static_cast<double>(utime - n.utime) * 1e-6;
    const double angle = n.w.norm() * dt;
    const Eigen::Quaterniond dq =
        angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, n.w.normalized())) : Eigen::Quaterniond::Identity();
    return make(n.p + dt * n.v, (n.q * dq).normalized());
  }
  auto it = std::lower_bound(poses_.begin(), poses_.end(), utime,
                             [](const Stamped& s, int64_t t) { return s.utime < t; });
  const Stamped& b = *it;
  const Stamped& a = *(it - 1);
  if (b.utime - a.utime > 2 * max_gap_us) return std::nullopt;  // a hole in the pose stream
  const double s = static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime);
  return make(a.p + s * (b.p - a.p), a.q.slerp(s, b.q));
}

}  // namespace perception
}  // namespace ucon
