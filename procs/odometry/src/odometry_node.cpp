#include "ucon/odometry/odometry_node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "ucon/lio/so3.hpp"

namespace ucon {
namespace odometry {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int8_t stateOf(lio::Phase p) {
  switch (p) {
    case lio::Phase::kInitialising: return odometry_status_t::STATE_INITIALISING;
    case lio::Phase::kMovingAtStart: return odometry_status_t::STATE_MOVING_AT_START;
    case lio::Phase::kRunning: return odometry_status_t::STATE_RUNNING;
  }
  return odometry_status_t::STATE_INITIALISING;
}

int8_t resultOf(lio::FrameResult r) {
  switch (r) {
    case lio::FrameResult::kUpdated: return odometry_status_t::RESULT_UPDATED;
    case lio::FrameResult::kMapStarted: return odometry_status_t::RESULT_MAP_STARTED;
    case lio::FrameResult::kTooFewPoints: return odometry_status_t::RESULT_TOO_FEW_POINTS;
    case lio::FrameResult::kNotRegistered: return odometry_status_t::RESULT_NOT_REGISTERED;
    case lio::FrameResult::kNotInitialised: return odometry_status_t::RESULT_NOT_INITIALISED;
    case lio::FrameResult::kOutOfOrder: return odometry_status_t::RESULT_OUT_OF_ORDER;
    case lio::FrameResult::kLate: return odometry_status_t::RESULT_LATE;
    case lio::FrameResult::kNoImu: return odometry_status_t::RESULT_NO_IMU;
  }
  return odometry_status_t::RESULT_BAD_FRAME;
}

// World angular velocity from Euler-angle rates for R = Rz(yaw) Ry(pitch) Rx(roll):
// w = E(rpy) d(rpy)/dt.
Eigen::Matrix3d eulerRateMatrix(const Eigen::Vector3d& rpy) {
  const double cp = std::cos(rpy.y()), sp = std::sin(rpy.y());
  const double cy = std::cos(rpy.z()), sy = std::sin(rpy.z());
  Eigen::Matrix3d E;
  E << cy * cp, -sy, 0.0, sy * cp, cy, 0.0, -sp, 0.0, 1.0;
  return E;
}

}  // namespace

Eigen::Matrix<double, 6, 1> basePoseVector(const lio::NavState& x, const Eigen::Vector3d& t) {
  Eigen::Matrix<double, 6, 1> v;
  v.head<3>() = x.p - x.R * t;
  v.tail<3>() = lio::rpyFromRotation(x.R);
  return v;
}

Eigen::Matrix<double, 6, lio::kStateDim> basePoseJacobian(const lio::NavState& x, const Eigen::Vector3d& t) {
  Eigen::Matrix<double, 6, lio::kStateDim> M = Eigen::Matrix<double, 6, lio::kStateDim>::Zero();
  // p_b = p - R Exp(dth) t  ->  dp_b = dp + R [t]x dth
  M.block<3, 3>(0, lio::kPos) = Eigen::Matrix3d::Identity();
  M.block<3, 3>(0, lio::kRot) = x.R * lio::hat(t);
  // World-frame rotation error R dth = E(rpy) d(rpy).
  M.block<3, 3>(3, lio::kRot) = eulerRateMatrix(lio::rpyFromRotation(x.R)).inverse() * x.R;
  return M;
}

robot_pose_t toRobotPose(const lio::PoseEstimate& e, const Eigen::Vector3d& t) {
  robot_pose_t m{};
  m.utime = e.t_ns / 1000;
  m.valid = e.valid;
  const lio::NavState& x = e.x;
  const Eigen::Vector3d pb = x.p - x.R * t;
  m.x = pb.x();
  m.y = pb.y();
  m.z = pb.z();
  Eigen::Quaterniond q(x.R);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;
  m.qw = q.w();
  m.qx = q.x();
  m.qy = q.y();
  m.qz = q.z();
  m.yaw = std::atan2(x.R(1, 0), x.R(0, 0));
  // Base velocity: v_b = v_imu + w x (p_b - p_imu) = v - R (w x t).
  const Eigen::Vector3d vb = x.v - x.R * e.omega.cross(t);
  m.vx = vb.x();
  m.vy = vb.y();
  m.vz = vb.z();
  m.wx = e.omega.x();
  m.wy = e.omega.y();
  m.wz = e.omega.z();
  // Base acceleration without the (unmeasured) angular-acceleration term.
  const Eigen::Vector3d ww = x.R * e.omega;
  const Eigen::Vector3d ab = e.acc_world + ww.cross(ww.cross(-(x.R * t)));
  m.ax = ab.x();
  m.ay = ab.y();
  const Eigen::Matrix<double, 6, lio::kStateDim> M = basePoseJacobian(x, t);
  const Eigen::Matrix<double, 6, 6> C = M * e.P * M.transpose();
  m.cov_size = 36;
  m.cov.resize(36);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) m.cov[static_cast<std::size_t>(r * 6 + c)] = 0.5 * (C(r, c) + C(c, r));
  return m;
}

lio::ImuSample toImuSample(const imu_t& m) {
  lio::ImuSample s;
  s.t_ns = m.utime * 1000;
  s.gyro = Eigen::Vector3d(m.gyro_x, m.gyro_y, m.gyro_z);
  s.acc = Eigen::Vector3d(m.acc_x, m.acc_y, m.acc_z);
  return s;
}

lio::PointFrame toPointFrame(const point_cloud_t& c, int32_t* dropped) {
  const std::size_t n = static_cast<std::size_t>(std::max(0, c.num_points));
  // Points in time order (the driver sends them so; a stable sort keeps equal times in order).
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  if (!std::is_sorted(c.t_offset_ns.begin(), c.t_offset_ns.end()))
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return c.t_offset_ns[static_cast<std::size_t>(a)] < c.t_offset_ns[static_cast<std::size_t>(b)];
    });
  lio::PointFrame f;
  f.t0_ns = c.utime * 1000;
  f.seq = c.seq;
  f.points.reserve(n);
  f.dt_ns.reserve(n);
  int32_t bad = 0;
  for (int i : order) {
    const std::size_t k = static_cast<std::size_t>(i);
    const float x = c.x[k], y = c.y[k], z = c.z[k];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || c.t_offset_ns[k] < 0) {
      ++bad;
      continue;
    }
    f.points.emplace_back(x, y, z);
    f.dt_ns.push_back(c.t_offset_ns[k]);
  }
  if (dropped) *dropped = bad;
  return f;
}

OdometryNode::OdometryNode(const OdometryParams& params, Stopwatch stopwatch)
    : params_(params),
      stopwatch_(stopwatch ? std::move(stopwatch) : Stopwatch(steadySeconds)),
      lio_(params.lio),
      status_("odometry") {}

OdometryOutput OdometryNode::onImu(const imu_t& m) {
  OdometryOutput out;
  const bool finite = std::isfinite(m.gyro_x) && std::isfinite(m.gyro_y) && std::isfinite(m.gyro_z) &&
                      std::isfinite(m.acc_x) && std::isfinite(m.acc_y) && std::isfinite(m.acc_z);
  if (m.utime <= 0 || !finite) {
    ++imu_bad_;
    return out;
  }
  if (m.frame_id != params_.points_frame) {
    ++imu_wrong_frame_;
    return out;
  }
  now_ = std::max(now_, m.utime);
  const double t0 = stopwatch_();
  const auto e = lio_.addImu(toImuSample(m));
  if (e) {
    robot_pose_t p = toRobotPose(*e, params_.lio.imu_position);
    p.seq = pose_seq_++;
    ++poses_out_;
    if (!p.valid) ++poses_invalid_;
    out.pose = std::move(p);
    last_pose_ms_ = (stopwatch_() - t0) * 1e3;
    status_.time("pose", last_pose_ms_);
  }
  return out;
}

OdometryOutput OdometryNode::processFrames() {
  OdometryOutput out;
  reports_.clear();
  const double t0 = stopwatch_();
  lio_.runDueFrames(&reports_);
  if (!reports_.empty()) {
    last_frame_ms_ = (stopwatch_() - t0) * 1e3 / static_cast<double>(reports_.size());
    status_.time("frame", last_frame_ms_);
  }
  emitReports(out);
  return out;
}

OdometryOutput OdometryNode::onPoints(const point_cloud_t& c) {
  OdometryOutput out;
  const std::size_t n = static_cast<std::size_t>(std::max(0, c.num_points));
  const bool sizes_ok = c.x.size() == n && c.y.size() == n && c.z.size() == n && c.t_offset_ns.size() == n;
  if (c.utime <= 0 || !sizes_ok || c.frame_id != params_.points_frame) {
    ++frames_bad_;
    odometry_status_t st{};
    st.utime = std::max<int64_t>(now_, 1);
    st.seq = status_seq_++;
    st.frame_utime = c.utime;
    st.frame_seq = c.seq;
    st.state = stateOf(lio_.phase());
    st.result = odometry_status_t::RESULT_BAD_FRAME;
    st.message = c.utime <= 0 ? "frame utime <= 0"
                 : !sizes_ok  ? "point arrays of different lengths"
                              : "frame_id '" + c.frame_id + "', expected '" + params_.points_frame + "'";
    st.points_in = static_cast<int32_t>(n);
    st.residual_rms = st.residual_median = kNaN;
    st.info_translation_min = st.info_translation_mid = st.info_translation_max = kNaN;
    st.weak_direction_x = st.weak_direction_y = st.weak_direction_z = kNaN;
    st.info_rotation_min = st.info_rotation_mid = st.info_rotation_max = kNaN;
    st.gyro_bias_x = st.gyro_bias_y = st.gyro_bias_z = st.acc_bias_x = st.acc_bias_y = st.acc_bias_z = kNaN;
    st.correction_translation = st.correction_rotation = kNaN;
    st.std_x = st.std_y = st.std_z = st.std_yaw = st.imu_only_s = kNaN;
    st.imu_gaps = lio_.counters().imu_gaps;
    out.statuses.push_back(std::move(st));
    return out;
  }
  now_ = std::max(now_, c.utime);
  int32_t dropped = 0;
  lio::PointFrame f = toPointFrame(c, &dropped);
  points_dropped_ += dropped;
  if (dropped > 0) {
    dropped_by_seq_[c.seq] = dropped;
    // Frames the estimator never reports back (cannot happen; bounded anyway).
    while (dropped_by_seq_.size() > 1000) dropped_by_seq_.erase(dropped_by_seq_.begin());
  }
  reports_.clear();
  const double t0 = stopwatch_();
  lio_.addFrame(std::move(f), &reports_);
  for (const auto& r : reports_) {
    if (r.t_end_ns > 0) {
      last_frame_ms_ = (stopwatch_() - t0) * 1e3;
      status_.time("frame", last_frame_ms_);
      break;
    }
  }
  emitReports(out);
  return out;
}

void OdometryNode::emitReports(OdometryOutput& out) {
  for (const auto& r : reports_) out.statuses.push_back(toStatus(r));
}

odometry_status_t OdometryNode::toStatus(const lio::FrameReport& r) {
  int32_t dropped_points = 0;
  if (const auto it = dropped_by_seq_.find(r.seq); it != dropped_by_seq_.end()) {
    dropped_points = it->second;
    dropped_by_seq_.erase(it);
  }
  odometry_status_t st{};
  st.utime = r.t_end_ns > 0 ? r.t_end_ns / 1000 : std::max<int64_t>(now_, 1);
  st.seq = status_seq_++;
  st.frame_utime = r.t0_ns / 1000;
  st.frame_seq = r.seq;
  st.state = stateOf(r.phase);
  st.result = resultOf(r.result);
  st.valid = r.valid;
  st.message = r.phase == lio::Phase::kRunning ? std::string() : lio_.phaseReason();
  st.points_in = r.points_in + dropped_points;
  st.points_dropped = dropped_points;
  st.points_in_range = r.points_in_range;
  st.points_used = r.points_used;
  st.points_matched = r.points_matched;
  st.iterations = r.iterations;
  const bool updated = r.result == lio::FrameResult::kUpdated;
  st.residual_rms = updated ? r.residual_rms : kNaN;
  st.residual_median = updated ? r.residual_median : kNaN;
  st.info_translation_min = updated ? r.info_translation[0] : kNaN;
  st.info_translation_mid = updated ? r.info_translation[1] : kNaN;
  st.info_translation_max = updated ? r.info_translation[2] : kNaN;
  st.weak_direction_x = updated ? r.weak_direction[0] : kNaN;
  st.weak_direction_y = updated ? r.weak_direction[1] : kNaN;
  st.weak_direction_z = updated ? r.weak_direction[2] : kNaN;
  st.info_rotation_min = updated ? r.info_rotation[0] : kNaN;
  st.info_rotation_mid = updated ? r.info_rotation[1] : kNaN;
  st.info_rotation_max = updated ? r.info_rotation[2] : kNaN;
  st.correction_translation = updated ? r.correction_translation : kNaN;
  st.correction_rotation = updated ? r.correction_rotation : kNaN;
  const bool running = r.phase == lio::Phase::kRunning;
  if (running) {
    const Eigen::Matrix<double, 6, lio::kStateDim> M = basePoseJacobian(r.state, params_.lio.imu_position);
    const Eigen::Matrix<double, 6, 6> C = M * r.covariance * M.transpose();
    st.std_x = std::sqrt(std::max(0.0, C(0, 0)));
    st.std_y = std::sqrt(std::max(0.0, C(1, 1)));
    st.std_z = std::sqrt(std::max(0.0, C(2, 2)));
    st.std_yaw = std::sqrt(std::max(0.0, C(5, 5)));
    st.gyro_bias_x = r.state.bg.x();
    st.gyro_bias_y = r.state.bg.y();
    st.gyro_bias_z = r.state.bg.z();
    st.acc_bias_x = r.state.ba.x();
    st.acc_bias_y = r.state.ba.y();
    st.acc_bias_z = r.state.ba.z();
    st.imu_only_s = r.imu_only_s;
  } else {
    st.std_x = st.std_y = st.std_z = st.std_yaw = st.imu_only_s = kNaN;
    st.gyro_bias_x = st.gyro_bias_y = st.gyro_bias_z = st.acc_bias_x = st.acc_bias_y = st.acc_bias_z = kNaN;
  }
  st.max_imu_gap_s = r.max_imu_gap_s;
  st.imu_gaps = lio_.counters().imu_gaps;
  st.map_voxels = static_cast<int32_t>(r.map_voxels);
  st.map_points = static_cast<int32_t>(r.map_points);
  return st;
}

StatusReport& OdometryNode::status() {
  const lio::LioCounters& n = lio_.counters();
  status_.setCounter("imu_in", n.imu_in);
  status_.setCounter("imu_out_of_order", n.imu_out_of_order);
  status_.setCounter("imu_non_finite", n.imu_non_finite + imu_bad_);
  status_.setCounter("imu_wrong_frame", imu_wrong_frame_);
  status_.setCounter("imu_gaps", n.imu_gaps);
  status_.setCounter("reinitialisations", n.reinitialisations);
  status_.setCounter("frames_in", n.frames_in + frames_bad_);
  status_.setCounter("frames_updated", n.frames_updated);
  status_.setCounter("frames_skipped", n.frames_skipped);
  status_.setCounter("frames_dropped", n.frames_dropped + frames_bad_);
  status_.setCounter("standstill_frames", n.standstill_frames);
  status_.setCounter("map_voxels_carved", n.map_voxels_carved);
  status_.setCounter("points_dropped", points_dropped_);
  status_.setCounter("poses_out", poses_out_);
  status_.setCounter("poses_invalid", poses_invalid_);
  status_.set("map_voxels", static_cast<double>(lio_.map().numVoxels()));
  status_.set("map_points", static_cast<double>(lio_.map().numPoints()));
  const bool running = lio_.phase() == lio::Phase::kRunning;
  const double imu_only = running ? (lio_.lastImuNs() - lio_.stateTimeNs()) * 1e-9 : kNaN;
  status_.set("imu_only_s", imu_only);
  if (!running) {
    status_.setHealth(process_status_t::HEALTH_ERROR, lio_.phaseReason());
  } else if (imu_only > params_.lio.imu_only_timeout_s) {
    status_.setHealth(process_status_t::HEALTH_ERROR, "no LiDAR update for the IMU-only limit: pose invalid");
  } else if (imu_only > 0.1) {
    status_.setHealth(process_status_t::HEALTH_WARN, "IMU only (no LiDAR update)");
  } else {
    status_.setHealth(process_status_t::HEALTH_OK, "");
  }
  return status_;
}

}  // namespace odometry
}  // namespace ucon
