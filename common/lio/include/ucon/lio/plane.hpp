#pragma once
/// @file plane.hpp
/// Local planes and the point-to-plane residual (FAST-LIO2 Sec. III-D, eq. 11): a plane is
/// fitted to the k nearest map points of a scan point, and the residual is the signed
/// distance of the transformed scan point to it.

#include <Eigen/Core>

#include <optional>

#include "ucon/lio/voxel_map.hpp"

namespace ucon {
namespace lio {

/// n . x + d = 0 with |n| = 1.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double d = 0.0;
  double distance(const Eigen::Vector3d& x) const { return normal.dot(x) + d; }
};

/// Eigenvalues (ascending) of a symmetric positive semi-definite 3x3 matrix and the unit
/// eigenvector of the smallest; ok = false for a zero or non-finite matrix. Without the
/// trigonometry of the closed form (Newton on the characteristic polynomial from 0, then the
/// kernel by cross products): a plane fit per scan point and iteration calls it.
struct SymmetricEigen3 {
  Eigen::Vector3d values = Eigen::Vector3d::Zero();
  Eigen::Vector3d vector = Eigen::Vector3d::UnitZ();
  bool ok = false;
};
SymmetricEigen3 smallestEigen(const Eigen::Matrix3d& S);

/// Least-squares plane of `neighbours` (at least `min_points`, >= 3): the centroid and the
/// eigenvector of the smallest eigenvalue of their scatter. Rejected (nullopt) when any
/// point lies farther than `max_point_distance` [m] from it, or the points are nearly
/// collinear.
std::optional<Plane> fitPlane(const Neighbours& neighbours, int min_points, double max_point_distance);

/// Residual of body point `p_body` [m] under pose (R, t): r = n . (R p + t) + d [m], and its
/// Jacobian with respect to the right perturbation (dtheta, dt) of (R, t):
/// dr/ddtheta = -n^T R [p]x, dr/dt = n^T.
double pointToPlane(const Plane& plane, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                    const Eigen::Vector3d& p_body, Eigen::Matrix<double, 1, 6>* J);

}  // namespace lio
}  // namespace ucon
