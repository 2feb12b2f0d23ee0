#include "ucon/lio/lidar_only_odometry.hpp"

#include <cmath>

#include "ucon/lio/so3.hpp"

namespace ucon {
namespace lio {

namespace {
constexpr double kInitialThreshold = 2.0;  // KISS-ICP's initial_threshold [m]
constexpr double kMinMotion = 0.1;         // frames that moved less do not update the threshold [m]

// Motion of the constant body twist (w, v) over tau seconds (first order in v: the frames
// are 20 ms apart).
Eigen::Isometry3d twistMotion(const Eigen::Matrix<double, 6, 1>& xi, double tau) {
  Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
  D.linear() = expSO3(xi.head<3>() * tau);
  D.translation() = xi.tail<3>() * tau;
  return D;
}
}  // namespace

LidarOnlyOdometry::LidarOnlyOdometry(const LioParams& params) : p_(params), map_(params.map) {
  T_last_.linear() = rotationFromRpy(0.0, 0.0, params.initial_pose.z());
  T_last_.translation() = Eigen::Vector3d(params.initial_pose.x(), params.initial_pose.y(), 0.0);
}

LidarOnlyOdometry::Result LidarOnlyOdometry::addFrame(const PointFrame& f) {
  Result res;
  const int64_t t_end = f.endNs();
  res.t_ns = t_end;
  res.T = T_last_;
  if (started_ && t_end <= t_last_) return res;
  const double dt = started_ ? static_cast<double>(t_end - t_last_) * 1e-9 : 0.0;
  const Eigen::Isometry3d T_pred = T_last_ * twistMotion(velocity_, dt);

  // De-skew with the constant velocity to the frame end; range filter about the sensor.
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(f.points.size());
  const double rmin2 = p_.min_range * p_.min_range, rmax2 = p_.max_range * p_.max_range;
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    const Eigen::Vector3d p = f.points[i].cast<double>();
    const double r2 = (p - p_.imu_position).squaredNorm();
    if (!(r2 >= rmin2 && r2 <= rmax2)) continue;
    const double tau = static_cast<double>(f.t0_ns + (i < f.dt_ns.size() ? f.dt_ns[i] : 0) - t_end) * 1e-9;
    pts.push_back((twistMotion(velocity_, tau) * p).cast<float>());
  }
  pts = voxelDownsample(pts, p_.downsample_voxel);

  Eigen::Isometry3d T_new = T_pred;
  if (map_.empty()) {
    res.registered = true;
  } else if (static_cast<int>(pts.size()) >= p_.min_points) {
    const double sigma = dev_n_ > 0 ? std::sqrt(dev2_sum_ / dev_n_) : kInitialThreshold / 3.0;
    RegistrationParams rp;
    rp.max_iterations = 20;
    rp.knn = p_.knn;
    rp.max_correspondence = std::max(3.0 * sigma, 0.1);
    rp.plane_threshold = p_.plane_threshold;
    rp.robust_scale = std::max(sigma / 3.0, 0.01);
    const RegistrationResult r = registerPointToPlane(map_, pts, T_pred, rp);
    res.iterations = r.iterations;
    res.correspondences = r.correspondences;
    if (r.correspondences >= std::max(6, static_cast<int>(p_.min_matched_ratio * static_cast<double>(pts.size())))) {
      T_new = r.T;
      res.registered = true;
      const Eigen::Isometry3d dev = T_pred.inverse() * T_new;
      const double angle = Eigen::AngleAxisd(dev.linear()).angle();
      const double model_error = dev.translation().norm() + 2.0 * p_.max_range * std::sin(0.5 * angle);
      if ((T_last_.inverse() * T_new).translation().norm() > kMinMotion) {
        dev2_sum_ += model_error * model_error;
        ++dev_n_;
      }
    }
  }
  if (res.registered)
    for (const auto& u : pts) map_.insert((T_new * u.cast<double>()).cast<float>());
  if (started_ && dt > 0.0) {
    const Eigen::Isometry3d D = T_last_.inverse() * T_new;
    velocity_.head<3>() = logSO3(D.linear()) / dt;
    velocity_.tail<3>() = D.translation() / dt;
  }
  T_last_ = T_new;
  t_last_ = t_end;
  started_ = true;
  res.T = T_new;
  return res;
}

}  // namespace lio
}  // namespace ucon
