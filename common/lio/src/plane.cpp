#include "ucon/lio/plane.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "ucon/lio/so3.hpp"

namespace ucon {
namespace lio {

SymmetricEigen3 smallestEigen(const Eigen::Matrix3d& S_in) {
  SymmetricEigen3 out;
  const double tr = S_in.trace();
  if (!(tr > 0.0) || !std::isfinite(tr)) return out;
  // Scaled to trace 1: the characteristic polynomial q(l) = l^3 - l^2 + c1 l - c0 has its three
  // real roots in [0, 1].
  const Eigen::Matrix3d S = S_in / tr;
  const double c1 = S(0, 0) * S(1, 1) - S(0, 1) * S(0, 1) + S(0, 0) * S(2, 2) - S(0, 2) * S(0, 2) +
                    S(1, 1) * S(2, 2) - S(1, 2) * S(1, 2);
  const double c0 = S.determinant();
  // Newton from 0, left of the smallest root, where q is increasing and concave (its inflection
  // is at the mean eigenvalue 1/3): the iterates rise monotonically to the smallest root.
  double l = 0.0;
  for (int i = 0; i < 60; ++i) {
    const double q = ((l - 1.0) * l + c1) * l - c0;
    const double dq = (3.0 * l - 2.0) * l + c1;
    if (!(dq > 0.0)) break;
    const double step = q / dq;
    l -= step;
    if (std::fabs(step) <= 1e-16) break;
  }
  // The other two: l1 + l2 = 1 - l0, l1 l2 = c1 - l0 (l1 + l2).
  const double sum = 1.0 - l;
  const double prod = std::max(0.0, c1 - l * sum);
  const double l2 = 0.5 * (sum + std::sqrt(std::max(0.0, sum * sum - 4.0 * prod)));
  const double l1 = l2 > 0.0 ? prod / l2 : 0.0;
  // Eigenvector: the kernel of S - l0 I, the longest cross product of two of its rows.
  Eigen::Matrix3d A = S;
  A.diagonal().array() -= l;
  const Eigen::Vector3d c01 = A.row(0).transpose().cross(A.row(1).transpose());
  const Eigen::Vector3d c02 = A.row(0).transpose().cross(A.row(2).transpose());
  const Eigen::Vector3d c12 = A.row(1).transpose().cross(A.row(2).transpose());
  const double n01 = c01.squaredNorm(), n02 = c02.squaredNorm(), n12 = c12.squaredNorm();
  const Eigen::Vector3d& best = n01 >= n02 ? (n01 >= n12 ? c01 : c12) : (n02 >= n12 ? c02 : c12);
  const double nb = std::max(n01, std::max(n02, n12));
  if (!(nb > 1e-300) || !std::isfinite(nb)) return out;
  out.values = Eigen::Vector3d(l, l1, l2) * tr;
  out.vector = best / std::sqrt(nb);
  out.ok = true;
  return out;
}

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
  const SymmetricEigen3 es = smallestEigen(S);
  if (!es.ok) return std::nullopt;
  const Eigen::Vector3d& ev = es.values;  // ascending
  // Collinear points (two small eigenvalues) fix no plane.
  if (!(ev(1) > 1e-3 * ev(2)) || !std::isfinite(ev(0))) return std::nullopt;
  Plane pl;
  pl.normal = es.vector;
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
