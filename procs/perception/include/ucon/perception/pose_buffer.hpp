#pragma once
/// @file pose_buffer.hpp
/// Recent robot poses, interpolated at a LiDAR frame's time (or at each point's).

#include <cstdint>
#include <deque>
#include <optional>

#include <Eigen/Geometry>

#include "ucon/robot_pose_t.hpp"

namespace ucon {
namespace perception {

/// Keeps poses over a window of message time and interpolates between them.
class PoseBuffer {
 public:
  enum class AddResult { kAdded, kInvalid, kNonFinite, kOutOfOrder };

  /// `window_s` [s]: poses older than the newest minus this are forgotten.
  explicit PoseBuffer(double window_s = 2.0) : window_us_(static_cast<int64_t>(window_s * 1e6)) {}

  /// Adds a pose; rejects invalid (valid == false or utime <= 0), non-finite or
  /// not-newer poses.
  AddResult add(const robot_pose_t& pose);

  /// Body-to-world transform at `utime` [us]: linear interpolation of position and slerp of
  /// orientation between the two poses around it. After the newest pose, within `max_gap_s`
  /// [s] of it, the newest pose is carried forward with its own velocity (world linear, body
  /// angular; held where they are not finite): a LiDAR frame is published when its last point
  /// is measured, usually before the pose of that instant. Before the oldest pose, within
  /// `max_gap_s`, the oldest pose is held. Otherwise (or when empty) nullopt.
  std::optional<Eigen::Isometry3d> at(int64_t utime, double max_gap_s) const;

  bool empty() const { return poses_.empty(); }
  int64_t newestUtime() const { return poses_.empty() ? 0 : poses_.back().utime; }

 private:
  struct Stamped {
    int64_t utime;
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    Eigen::Vector3d v;  ///< world linear velocity [m/s] (zero when the message's is not finite)
    Eigen::Vector3d w;  ///< body angular velocity [rad/s] (likewise)
  };
  std::deque<Stamped> poses_;
  int64_t window_us_;
};

}  // namespace perception
}  // namespace ucon
