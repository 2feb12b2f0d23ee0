#include "ucon/perception/preprocess.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace perception {

Preprocessor::Preprocessor(const PreprocessParams& params, const AngularGrid& fine, const AngularGrid& coarse)
    : params_(params), fine_(fine), coarse_(coarse) {}

Preprocessor::Result Preprocessor::process(const point_cloud_t& cloud, const Eigen::Isometry3d& pose,
                                           const PoseBuffer& poses, double max_gap_s, Frame* frame) {
  const PreprocessParams& p = params_;
  Frame& f = *frame;
  const bool in_world = cloud.frame_id == "world";  // once, not a string compare per point
  const Eigen::Isometry3d T = in_world ? Eigen::Isometry3d::Identity() : pose;
  f.utime = cloud.utime;
  f.pose = pose;
  f.robot_xy = pose.translation().head<2>();
  // Where the points were measured from: the cloud's first sensor as the driver gives it, or
  // (clouds without origins, e.g. older logs) the configured origin in the base frame.
  const auto& so = p.sensor_origin;
  f.sensor_origin_d = cloud.num_sensors > 0
                          ? T * Eigen::Vector3d(cloud.origin_x[0], cloud.origin_y[0], cloud.origin_z[0])
                          : pose * Eigen::Vector3d(so[0], so[1], so[2]);
  f.sensor_origin = f.sensor_origin_d.cast<float>();

  // The pose across the frame's span, every kPoseStepUs: knot k holds the pose at
  // utime + k * kPoseStepUs (knot 0 the frame's pose). A pose missing within the span (a hole
  // in the stream, or past max_gap_s after the newest) holds the knot before it.
  Result result;
  const std::size_t n_points = static_cast<std::size_t>(cloud.num_points);
  const bool timed = !in_world && cloud.t_offset_ns.size() == n_points && cloud.duration_us > 0;
  const int64_t span_us = timed ? std::min<int64_t>(cloud.duration_us, kMaxSpanUs) : 0;
  const std::size_t n_knots = timed ? static_cast<std::size_t>(span_us / kPoseStepUs) + 2 : 1;
  knot_rotation_.resize(n_knots);
  knot_translation_.resize(n_knots);
  knot_rotation_[0] = T.linear().cast<float>();
  knot_translation_[0] = T.translation().cast<float>();
  for (std::size_t k = 1; k < n_knots; ++k) {
    const int64_t t = cloud.utime + static_cast<int64_t>(k) * kPoseStepUs;
    const auto P = poses.at(t, max_gap_s);
    knot_rotation_[k] = P ? Eigen::Matrix3f(P->linear().cast<float>()) : knot_rotation_[k - 1];
    knot_translation_[k] = P ? Eigen::Vector3f(P->translation().cast<float>()) : knot_translation_[k - 1];
  }
  const Eigen::Vector3f robot_centre = pose.translation().cast<float>();  // world clouds: at utime
  result.pose_extrapolated = timed && cloud.utime + span_us > poses.newestUtime();
  const float min_r2 = static_cast<float>(p.min_range * p.min_range);
  const float max_r2 = static_cast<float>(p.max_range * p.max_range);
  Points kept;
  kept.reserve(static_cast<std::size_t>(cloud.num_points));
  f.returns.clear();
  // Several sensors: only the first one's returns are free-space evidence, since the free-space
  // test casts rays from that sensor's origin (another sensor's ray starts elsewhere).
  const bool several = cloud.num_sensors > 1 && cloud.num_point_sensors == cloud.num_points;
  for (int i = 0; i < cloud.num_points; ++i) {
    const Eigen::Vector3f b(cloud.x[i], cloud.y[i], cloud.z[i]);
    if (!b.allFinite()) {
      ++result.non_finite;
      continue;
    }
    std::size_t k = 0;
    if (timed) {
      const int64_t off_us = std::clamp<int64_t>(cloud.t_offset_ns[static_cast<std::size_t>(i)] / 1000, 0, span_us);
      k = static_cast<std::size_t>((off_us + kPoseStepUs / 2) / kPoseStepUs);
    }
    const Eigen::Vector3f w = in_world ? b : Eigen::Vector3f(knot_rotation_[k] * b + knot_translation_[k]);
    // Horizontal range from the robot's centre at the point's time.
    const Eigen::Vector3f& centre = in_world ? robot_centre : knot_translation_[k];
    const float r2 = (w.head<2>() - centre.head<2>()).squaredNorm();
    if (r2 < min_r2) continue;
    // Ground and far returns are not objects, but the space their rays crossed was free: the
    // motion test needs that (a mover's lower half is seen against the ground).
    if (!several || cloud.point_sensor[static_cast<std::size_t>(i)] == 0) f.returns.push_back(w);
    if (r2 > max_r2) continue;
    // Height above the floor under the robot, not world z: an odometry's frame drifts in z
    // (and tilts) by centimetres over tens of metres, and its floor with it.
    const float h = w.z() - (in_world ? robot_centre.z() : knot_translation_[k].z());
    if (h < p.min_height || h > p.max_height) continue;
    kept.push_back(w);
  }
  // Merge the previous frame(s): at 50 Hz a person 10 m away gets only a handful of returns
  // per frame. Motion blur over 20 ms is a few centimetres.
  recent_cropped_.push_back(std::move(kept));
  while (static_cast<int>(recent_cropped_.size()) > p.accumulate_frames) recent_cropped_.pop_front();
  Points merged;
  for (const auto& c : recent_cropped_) merged.insert(merged.end(), c.begin(), c.end());
  f.points = voxelDownsample(merged, p.voxel_size);
  f.nearest_coarse.assign(static_cast<std::size_t>(coarse_.size()), INFINITY);
  f.nearest_fine.assign(static_cast<std::size_t>(fine_.size()), INFINITY);
  for (const auto& q : f.points) {
    const Eigen::Vector3f ray = q - f.sensor_origin;
    const float r = ray.norm();
    const Angles a = anglesOf(ray);  // one pair of atan2 for both grids
    float& m = f.nearest_coarse[static_cast<std::size_t>(coarse_.bin(a))];
    m = std::min(m, r);
    float& n = f.nearest_fine[static_cast<std::size_t>(fine_.bin(a))];
    n = std::min(n, r);
  }
  for (const auto& q : f.returns) {
    const Eigen::Vector3f ray = q - f.sensor_origin;
    float& n = f.nearest_fine[static_cast<std::size_t>(fine_.bin(ray))];
    n = std::min(n, ray.norm());
  }
  f.moved.assign(f.points.size(), 0);
  return result;
}

}  // namespace perception
}  // namespace ucon
