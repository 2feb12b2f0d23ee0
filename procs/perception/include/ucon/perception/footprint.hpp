#pragma once
/// @file footprint.hpp
/// The x-y centre of an object seen from one side.
///
/// The sensor sees only the near half of a round object (a person, a post on wheels): the box
/// of its returns is centred about a quarter of the diameter in front of the body's centre,
/// and the offset turns with the viewing direction, so a track passing the robot gets a false
/// velocity. Seen from the sensor, a round body's depth equals its width; the visible depth is
/// about half of it. The centre is pushed away from the sensor by half the missing depth.

#include <vector>

#include <Eigen/Core>

#include "ucon/perception/point_index.hpp"

namespace ucon {
namespace perception {

/// Centre of the points `indices` of `points` in the frame of the viewing direction (from
/// `sensor_xy` to the points' box centre), moved away from the sensor by
/// min(max_shift, max(0, (width - depth) / 2)) where width and depth are the points' extents
/// across and along that direction [m]. max_shift <= 0 gives the plain x-y box centre.
Eigen::Vector2d viewCorrectedCenter(const Points& points, const std::vector<int>& indices,
                                    const Eigen::Vector2d& sensor_xy, double max_shift);

}  // namespace perception
}  // namespace ucon
