#pragma once
// Shared helpers of the trajopt tests: an analytic distance field and gradient checks.

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "ucon/trajopt/distance_field.hpp"

namespace trajopt_test {

/// Distance to the nearest of a set of discs (exact, smooth away from equidistant points).
class DiscField : public ucon::trajopt::DistanceField2D {
 public:
  struct Disc {
    Eigen::Vector2d c;
    double r;
  };
  explicit DiscField(std::vector<Disc> discs) : discs_(std::move(discs)) {}
  double distance(double x, double y, Eigen::Vector2d* grad) const override {
    double best = 1e9;
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (const auto& d : discs_) {
      const Eigen::Vector2d delta = Eigen::Vector2d(x, y) - d.c;
      const double n = delta.norm();
      if (n - d.r < best) {
        best = n - d.r;
        g = n > 0 ? Eigen::Vector2d(delta / n) : Eigen::Vector2d::Zero();
      }
    }
    if (grad) *grad = g;
    return best;
  }

 private:
  std::vector<Disc> discs_;
};

/// max_i |a_i - b_i| / max_i |b_i| (relative error of a gradient against a reference).
inline double relativeError(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-12, b.cwiseAbs().maxCoeff());
}

/// Central finite-difference gradient of f at x with step h.
inline Eigen::VectorXd finiteDifference(const std::function<double(const Eigen::VectorXd&)>& f,
                                        const Eigen::VectorXd& x, double h) {
  Eigen::VectorXd g(x.size());
  for (int i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    g(i) = (f(xp) - f(xm)) / (2 * h);
  }
  return g;
}

}  // namespace trajopt_test
