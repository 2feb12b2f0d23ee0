#include "ucon/perception/registration.hpp"

#include <cmath>
#include <limits>

namespace ucon {
namespace perception {

bool registerTranslation(const Points& from, const Points& to, const Eigen::Vector2d& guess,
                         const RegistrationParams& params, Eigen::Vector2d* d) {
  const int n_from = static_cast<int>(from.size()), n_to = static_cast<int>(to.size());
  if (n_from < params.min_points || n_to < params.min_points || params.iterations < 1 || !guess.allFinite())
    return false;
  const int iters = params.iterations;
  // Gates shrink geometrically from initial_gate to final_gate.
  const double ratio = iters > 1 ? std::pow(params.final_gate / params.initial_gate, 1.0 / (iters - 1)) : 1.0;
  Eigen::Vector2d t = guess;
  double gate = iters > 1 ? params.initial_gate : params.final_gate;
  int inliers = 0;
  for (int it = 0; it < iters; ++it, gate *= ratio) {
    const double gate2 = gate * gate;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    inliers = 0;
    for (const auto& pf : from) {
      const Eigen::Vector2d p = pf.head<2>().cast<double>() + t;
      double best = std::numeric_limits<double>::infinity();
      Eigen::Vector2d best_q = Eigen::Vector2d::Zero();
      for (const auto& qf : to) {
        const Eigen::Vector2d q = qf.head<2>().cast<double>();
        const double d2 = (q - p).squaredNorm();
        if (d2 < best) best = d2, best_q = q;
      }
      if (!(best <= gate2)) continue;
      sum += best_q - p;
      ++inliers;
    }
    if (inliers == 0) return false;
    t += sum / static_cast<double>(inliers);
    if (!t.allFinite()) return false;
  }
  if (static_cast<double>(inliers) < params.min_inliers * static_cast<double>(n_from)) return false;
  *d = t;
  return true;
}

}  // namespace perception
}  // namespace ucon
