#pragma once
/// @file outputs.hpp
/// Perception's messages: an object estimate (state, full covariance, box) as a
/// tracked_object_t, PERCEPTION_OBJECTS and PERCEPTION_STATIC with their validity. The one
/// conversion for the node and for every harness that publishes objects of its own (the
/// benchmarks' ground-truth and filtered-centroid stand-ins for perception).

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ucon/kalman/constant_velocity_kalman.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_object_t.hpp"
#include "ucon/tracked_objects_t.hpp"

namespace ucon {
namespace perception {

/// What is published of one object.
struct ObjectEstimate {
  int64_t id = 0;
  int8_t state = tracked_object_t::STATE_CONFIRMED;
  int8_t last_association = tracked_object_t::ASSOC_OBJECT;
  kalman::State6 x = kalman::State6::Zero();  ///< [x y z vx vy vz], world [m, m/s]
  kalman::Cov6 P = kalman::Cov6::Zero();      ///< covariance of x [m^2, m^2/s, m^2/s^2]
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< box extent x, y, z [m]
  int32_t num_points = 0;         ///< points of the latest measurement
  int32_t age_frames = 0;
  int32_t frames_since_seen = 0;
};

/// The message of one object: the full row-major 6x6 covariance (cov_size 36), box sides
/// floored at 0.01 m, yaw 0 (boxes are axis-aligned).
tracked_object_t toMessage(const ObjectEstimate& e);

/// A valid PERCEPTION_OBJECTS in the world frame; `frame_seq` is the LiDAR frame's seq (-1
/// for none).
tracked_objects_t objectsMessage(int64_t utime, int64_t seq, int64_t frame_seq, std::vector<tracked_object_t> objects);

/// An invalid, empty PERCEPTION_OBJECTS (inputs missing, stale or bad).
tracked_objects_t invalidObjects(int64_t utime, int64_t seq, int64_t frame_seq);

/// A valid PERCEPTION_STATIC: the points not marked in `dynamic` (per point), seen from
/// `origin` (the sensor, world [m]) out to `max_range` [m].
static_points_t staticMessage(int64_t utime, int64_t seq, const Eigen::Vector3d& origin, double max_range,
                              const std::vector<Eigen::Vector3f>& points, const std::vector<char>& dynamic);

/// An invalid, empty PERCEPTION_STATIC.
static_points_t invalidStatic(int64_t utime, int64_t seq, double max_range);

/// The covariance of a received object; false when the message carries none (cov_size != 36
/// or a short array).
bool covarianceOf(const tracked_object_t& o, kalman::Cov6* P);

}  // namespace perception
}  // namespace ucon
