#pragma once
/// @file angular_grid.hpp
/// Directions from a sensor origin binned by azimuth and elevation: the free-space evidence of
/// the motion test, the occluder search of the measurement and the "seen through" check of
/// unseen tracks all ask "what is the nearest (or farthest) return in this direction?".

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "ucon/fast_atan2.hpp"

namespace ucon {
namespace perception {

/// Azimuth in [0, 2 pi] and elevation in [0, pi] of a direction (shifted to start at 0) [rad].
struct Angles {
  double az, el;
};

/// For binning only: fastAtan2 is within 2e-5 rad of std::atan2, the bins are a degree or more.
inline Angles anglesOf(const Eigen::Vector3f& d) {
  return {fastAtan2(static_cast<double>(d.y()), static_cast<double>(d.x())) + M_PI,
          fastAtan2(static_cast<double>(d.z()), static_cast<double>(d.head<2>().norm())) + M_PI / 2};
}

/// Square angular bins of `bin_deg` degrees over the sphere, numbered az * elevationBins() + el.
class AngularGrid {
 public:
  /// `bin_deg` > 0 [deg].
  explicit AngularGrid(double bin_deg)
      : bin_(bin_deg * M_PI / 180.0),
        n_az_(static_cast<int>(std::ceil(360.0 / bin_deg))),
        n_el_(static_cast<int>(std::ceil(180.0 / bin_deg))) {}

  /// Bin of a direction's angles (clamped into the grid).
  int bin(const Angles& a) const {
    const int i = std::clamp(static_cast<int>(a.az / bin_), 0, n_az_ - 1);
    const int j = std::clamp(static_cast<int>(a.el / bin_), 0, n_el_ - 1);
    return i * n_el_ + j;
  }
  /// Bin of a direction (need not be normalised).
  int bin(const Eigen::Vector3f& d) const { return bin(anglesOf(d)); }

  /// The up to 8 bins around `bin` (azimuth wraps around, elevation ends at the poles), written
  /// to `out`; returns how many.
  int neighbours(int bin, int out[8]) const {
    const int i = bin / n_el_, j = bin % n_el_;
    int n = 0;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const int jj = j + dj;
        if ((di == 0 && dj == 0) || jj < 0 || jj >= n_el_) continue;
        out[n++] = ((i + di + n_az_) % n_az_) * n_el_ + jj;
      }
    return n;
  }

  int azimuthBins() const { return n_az_; }
  int elevationBins() const { return n_el_; }
  int size() const { return n_az_ * n_el_; }
  double binRad() const { return bin_; }  ///< bin edge [rad]

 private:
  double bin_;
  int n_az_, n_el_;
};

}  // namespace perception
}  // namespace ucon
