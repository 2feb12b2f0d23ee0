#pragma once
/// @file lidar_emulator.hpp
/// The Mid-360's optics: a non-repeating scan pattern over 360 deg x [elevation_min, max] and
/// ray casting into the World with range noise, range limits and reflectivity.
///
/// Pattern: point k looks along azimuth 2 pi {k a1} and sin(elevation) uniform over the band by
/// {k a2}, where {.} is the fractional part and (a1, a2) is the R2 low-discrepancy sequence
/// (a1 = 1/g, a2 = 1/g^2, g = 1.32471795724... the plastic number). Any run of consecutive
/// points covers the field of view evenly (a 20 ms frame of 4000 points has no holes) and the
/// pattern never repeats, like the real sensor's rosette. The fractions are computed in 64-bit
/// fixed point, so they are exact and identical everywhere.

#include <Eigen/Geometry>

#include <cstdint>

#include "ucon/livox/point_packet.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/world/rng.hpp"
#include "ucon/world/world.hpp"

namespace ucon {
namespace simulator {

/// Counters of one scan() call (accumulated).
struct ScanStats {
  int64_t rays = 0;
  int64_t returns = 0;         ///< rays that produced a point
  int64_t ground_returns = 0;
  int64_t obstacle_returns = 0;
};

class LidarEmulator {
 public:
  explicit LidarEmulator(const LidarParams& params);

  /// Unit direction of pattern point `k` in the sensor frame.
  Eigen::Vector3d direction(uint64_t k) const;

  /// Sensor -> base transform from the mounting parameters.
  const Eigen::Isometry3d& mount() const { return T_bs_; }

  /// Casts pattern points k0 .. k0+n-1 from the sensor at world pose `T_ws` into `world` (at
  /// its current time) and writes them in the sensor frame to `out[0..n)`. Rays without a
  /// return within [min_range, max_range] give a zero point (x = y = z = 0, reflectivity 0),
  /// as the real sensor sends them; receivers drop them with a minimum-range filter.
  void scan(const world::World& world, const Eigen::Isometry3d& T_ws, uint64_t k0, std::size_t n,
            livox::LidarPoint* out, ScanStats* stats);

  const LidarParams& params() const { return p_; }

 private:
  LidarParams p_;
  Eigen::Isometry3d T_bs_;
  double sin_el_min_, sin_el_span_;
  world::Rng rng_;
};

}  // namespace simulator
}  // namespace ucon
