#pragma once
// A precomputed distance grid (0.1 m, bilinear, capped like the planner's ESDF) over discs.

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "ucon/trajopt/distance_field.hpp"

namespace trajopt_bench {

/// Discs are (x, y, radius).
class GridField : public ucon::trajopt::DistanceField2D {
 public:
  GridField(const std::vector<Eigen::Vector3d>& discs, double size, double res)
      : GridField(
            [&discs](double x, double y) {
              double best = 5.0;  // capped like an ESDF
              for (const auto& c : discs) best = std::min(best, std::hypot(x - c.x(), y - c.y()) - c.z());
              return best;
            },
            size, res) {}
  /// Samples `dist(x, y)` on the grid over [0, size]^2.
  GridField(const std::function<double(double, double)>& dist, double size, double res)
      : res_(res), n_(static_cast<int>(size / res) + 1), d_(static_cast<std::size_t>(n_) * n_) {
    for (int i = 0; i < n_; ++i)
      for (int j = 0; j < n_; ++j) d_[static_cast<std::size_t>(i) * n_ + j] = dist(i * res, j * res);
  }
  double distance(double x, double y, Eigen::Vector2d* grad) const override {
    const double fx = std::clamp(x / res_, 0.0, n_ - 1.001), fy = std::clamp(y / res_, 0.0, n_ - 1.001);
    const int i = static_cast<int>(fx), j = static_cast<int>(fy);
    const double u = fx - i, v = fy - j;
    const double a = at(i, j), b = at(i + 1, j), c = at(i, j + 1), d = at(i + 1, j + 1);
    if (grad) *grad = Eigen::Vector2d(((b - a) * (1 - v) + (d - c) * v) / res_, ((c - a) * (1 - u) + (d - b) * u) / res_);
    return a * (1 - u) * (1 - v) + b * u * (1 - v) + c * (1 - u) * v + d * u * v;
  }

 private:
  double at(int i, int j) const { return d_[static_cast<std::size_t>(i) * n_ + j]; }
  double res_;
  int n_;
  std::vector<double> d_;
};

}  // namespace trajopt_bench
