#include "ucon/lio/registration.hpp"

#include <cmath>

#include "ucon/lio/plane.hpp"
#include "ucon/lio/so3.hpp"

namespace ucon {
namespace lio {

namespace {

// splitmix64's finaliser (neighbouring cells land in unrelated slots).
uint64_t mixCell(uint64_t k) {
  k ^= k >> 30;
  k *= 0xbf58476d1ce4e5b9ULL;
  k ^= k >> 27;
  k *= 0x94d049bb133111ebULL;
  k ^= k >> 31;
  return k;
}

// floor() for finite coordinates well inside the int range, without the library call.
int64_t floorToInt(float x) {
  const int64_t i = static_cast<int64_t>(x);
  return static_cast<float>(i) > x ? i - 1 : i;
}

}  // namespace

std::vector<int> voxelDownsampleIndices(const std::vector<Eigen::Vector3f>& points, double voxel) {
  std::vector<int> out;
  out.reserve(points.size());
  if (!(voxel > 0.0)) {
    for (std::size_t i = 0; i < points.size(); ++i) out.push_back(static_cast<int>(i));
    return out;
  }
  const float inv = static_cast<float>(1.0 / voxel);
  // The cells seen so far: an open-addressing set (linear probing) of at most half load, made
  // once per call; cell keys are 63-bit, so ~0 marks an empty slot.
  constexpr uint64_t kEmpty = ~uint64_t{0};
  std::size_t size = 16;
  while (size < 2 * points.size()) size *= 2;
  const std::size_t mask = size - 1;
  std::vector<uint64_t> table(size, kEmpty);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    if (!p.allFinite()) continue;
    const uint64_t kx = static_cast<uint64_t>(floorToInt(p.x() * inv) & 0x1FFFFF);
    const uint64_t ky = static_cast<uint64_t>(floorToInt(p.y() * inv) & 0x1FFFFF);
    const uint64_t kz = static_cast<uint64_t>(floorToInt(p.z() * inv) & 0x1FFFFF);
    const uint64_t key = (kx << 42) | (ky << 21) | kz;
    std::size_t h = static_cast<std::size_t>(mixCell(key)) & mask;
    while (table[h] != kEmpty && table[h] != key) h = (h + 1) & mask;
    if (table[h] == kEmpty) {
      table[h] = key;
      out.push_back(static_cast<int>(i));
    }
  }
  return out;
}

std::vector<Eigen::Vector3f> voxelDownsample(const std::vector<Eigen::Vector3f>& points, double voxel) {
  std::vector<Eigen::Vector3f> out;
  for (int i : voxelDownsampleIndices(points, voxel)) out.push_back(points[static_cast<std::size_t>(i)]);
  return out;
}

RegistrationResult registerPointToPlane(const VoxelMap& map, const std::vector<Eigen::Vector3f>& points,
                                        const Eigen::Isometry3d& initial, const RegistrationParams& params) {
  RegistrationResult res;
  Eigen::Matrix3d R = initial.linear();
  Eigen::Vector3d t = initial.translation();
  const double c2 = params.robust_scale * params.robust_scale;
  Neighbours nb;
  for (int it = 0; it < params.max_iterations; ++it) {
    Matrix6 H = Matrix6::Zero();
    Vector6 b = Vector6::Zero();
    int n = 0;
    double sum_r2 = 0.0;
    for (const Eigen::Vector3f& pf : points) {
      const Eigen::Vector3d p = pf.cast<double>();
      const Eigen::Vector3d q = R * p + t;
      if (map.nearest(q.cast<float>(), params.knn, static_cast<float>(params.max_correspondence), &nb) < params.knn)
        continue;
      const auto plane = fitPlane(nb, params.knn, params.plane_threshold);
      if (!plane) continue;
      Eigen::Matrix<double, 1, 6> J;
      const double r = pointToPlane(*plane, R, t, p, &J);
      const double w = 1.0 / (1.0 + r * r / c2);
      H.noalias() += w * J.transpose() * J;
      b.noalias() += w * J.transpose() * r;
      sum_r2 += r * r;
      ++n;
    }
    res.iterations = it + 1;
    res.correspondences = n;
    res.rms = n > 0 ? std::sqrt(sum_r2 / n) : 0.0;
    res.information = H;
    if (n < 6) break;
    const Vector6 dx = H.ldlt().solve(-b);
    if (!dx.allFinite()) break;
    R = R * expSO3(dx.head<3>());
    t += dx.tail<3>();
    if (dx.head<3>().norm() < params.converged_rotation && dx.tail<3>().norm() < params.converged_translation) {
      res.converged = true;
      break;
    }
  }
  // Re-orthonormalise (many small products of rotations).
  const Eigen::Quaterniond qn(R);
  res.T = Eigen::Isometry3d::Identity();
  res.T.linear() = qn.normalized().toRotationMatrix();
  res.T.translation() = t;
  return res;
}

}  // namespace lio
}  // namespace ucon
