#include "ucon/lio/plane.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

#include "ucon/lio/so3.hpp"

namespace ucon {
namespace lio {

std::optional<Plane> fitPlane(const Neighbours& nb, int min_points, double max_point_distance) {
  const int n = nb.count;
  if (n < std::max(3, min_points)) return std::nullopt;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) c += nb.points[i].cast<double>();
  c /= n;
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = nb.points[i].cast<double>() - c;
    S.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(S);
  const Eigen::Vector3d ev = es.eigenvalues();  // ascending
  // Collinear points (two small eigenvalues) fix no plane.
  if (!(ev(1) > 1e-3 * ev(2)) || !std::isfinite(ev(0))) return std::nullopt;
  Plane pl;
  pl.normal = es.eigenvectors().col(0).normalized();
  pl.d = -pl.normal.dot(c);
  for (int i = 0; i < n; ++i)
    if (std::fabs(pl.distance(nb.points[i].cast<double>())) > max_point_distance) return std::nullopt;
  return pl;
}

double pointToPlane(const Plane& plane, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                    const Eigen::Vector3d& p_body, Eigen::Matrix<double, 1, 6>* J) {
  const Eigen::Vector3d q = R * p_body + t;
  if (J) {
    // d(R Exp(dth) p)/ddth = -R [p]x  ->  n^T (-R [p]x) = -(R^T n)^T [p]x = (p x R^T n)^T
    const Eigen::Vector3d Rtn = R.transpose() * plane.normal;
    J->leftCols<3>() = p_body.cross(Rtn).transpose();
    J->rightCols<3>() = plane.normal.transpose();
  }
  return plane.distance(q);
}

}  // namespace lio
}  // namespace ucon
