#include "ucon/lio/lio_odometry.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ucon/lio/plane.hpp"
#include "ucon/lio/registration.hpp"
#include "ucon/lio/so3.hpp"

namespace ucon {
namespace lio {

namespace {
// Frames kept before the start: those that began this long before the standstill window too.
constexpr double kStillFrameMarginS = 0.2;

double sec(int64_t ns) { return static_cast<double>(ns) * 1e-9; }

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof(buf), f, a, b, c);
  return buf;
}

}  // namespace

const char* toString(Phase p) {
  switch (p) {
    case Phase::kInitialising: return "initialising";
    case Phase::kMovingAtStart: return "moving at start";
    case Phase::kRunning: return "running";
  }
  return "?";
}

const char* toString(FrameResult r) {
  switch (r) {
    case FrameResult::kUpdated: return "updated";
    case FrameResult::kMapStarted: return "map started";
    case FrameResult::kTooFewPoints: return "too few points";
    case FrameResult::kNotRegistered: return "not registered";
    case FrameResult::kNotInitialised: return "not initialised";
    case FrameResult::kOutOfOrder: return "out of order";
    case FrameResult::kLate: return "late";
    case FrameResult::kNoImu: return "no IMU";
  }
  return "?";
}

std::string LioParams::validate() const {
  if (!imu_position.allFinite()) return "imu.position: must be finite";
  if (!(std::fabs(imu_time_offset_s) <= 0.1)) return "imu.time_offset_s: must be within +-0.1 s";
  if (!(gravity >= 9.0 && gravity <= 10.5)) return "imu.gravity: must be in [9, 10.5]";
  if (!(noise.gyro_noise > 0 && noise.acc_noise > 0 && noise.gyro_bias_walk > 0 && noise.acc_bias_walk > 0))
    return "imu.gyro_noise: every noise density must be > 0";
  if (!(init_window_s > 0.0 && init_window_s <= 1.0)) return "init.window_s: must be in (0, 1]";
  if (!(init_max_gyro_std > 0 && init_max_acc_std > 0 && init_max_gravity_error > 0))
    return "init.max_gyro_std: standstill thresholds must be > 0";
  if (!initial_pose.allFinite()) return "init.pose: must be finite";
  if (!(initial_position_std > 0 && initial_yaw_std > 0 && initial_velocity_std > 0 && initial_acc_bias_std > 0 &&
        initial_gyro_bias_std > 0))
    return "init.position_std: initial stds must be > 0";
  if (!(min_range >= 0 && max_range > min_range)) return "points.max_range: must exceed min_range";
  if (!(downsample_voxel >= 0)) return "points.downsample_voxel: must be >= 0";
  if (min_points < 1) return "points.min_points: must be >= 1";
  if (max_points != 0 && max_points < min_points) return "points.max_points: must be 0 (all) or >= min_points";
  if (max_iterations < 1) return "update.max_iterations: must be >= 1";
  if (knn < 3 || knn > Neighbours::kMax) return "update.knn: must be in [3, 8]";
  if (!(max_correspondence > 0 && plane_threshold > 0 && point_std > 0 && robust_scale > 0 && outlier_distance > 0))
    return "update.max_correspondence: distances and stds must be > 0";
  if (!(map_trim_every_m > 0 && map_insert_max_residual > 0)) return "map.trim_every_m: distances must be > 0";
  if (!(research_translation > 0 && research_rotation > 0)) return "update.research_translation: must be > 0";
  if (!(min_matched_ratio >= 0 && min_matched_ratio <= 1)) return "update.min_matched_ratio: must be in [0, 1]";
  if (!(map.voxel_size > 0)) return "map.voxel_size: must be > 0";
  if (map.max_points_per_voxel < 1 || map.max_points_per_voxel > 64) return "map.max_points_per_voxel: must be in [1, 64]";
  if (!(map.radius > max_range)) return "map.radius: must exceed points.max_range";
  if (!(ground_height_std > 0 && ground_tilt_std > 0)) return "ground_prior.height_std: stds must be > 0";
  if (!(imu_gap_s > 0 && max_imu_gap_s > imu_gap_s)) return "imu.max_gap_s: must exceed imu.gap_s";
  if (!(imu_only_timeout_s > 0)) return "output.imu_only_timeout_s: must be > 0";
  if (max_pending_frames < 1) return "output.max_pending_frames: must be >= 1";
  return "";
}

LioOdometry::LioOdometry(const LioParams& params) : LioOdometry(params, Options{}) {}

LioOdometry::LioOdometry(const LioParams& params, const Options& options)
    : p_(params),
      opt_(options),
      gravity_(0.0, 0.0, -params.gravity),
      map_(params.map),
      start_pose_(params.initial_pose) {
  reason_ = "waiting for IMU samples";
}

bool LioOdometry::valid(int64_t t_ns) const {
  return phase_ == Phase::kRunning && sec(t_ns - last_update_ns_) <= p_.imu_only_timeout_s;
}

void LioOdometry::step(NavState& x, Matrix15* P, int64_t t, int64_t t_next, const Sample& a, const Sample& b) const {
  if (t_next <= t) return;
  const double dt = sec(t_next - t);
  const Eigen::Vector3d gyro = 0.5 * (a.s.gyro + b.s.gyro);
  const Eigen::Vector3d acc = 0.5 * (a.s.acc + b.s.acc);
  if (P) {
    propagateCovariance(*P, x, gyro, acc, dt, p_.noise);
    if (b.gap_before_s > 0.0 && b.s.t_ns > a.s.t_ns) {
      // Nothing measured the motion in a gap: inflate by what it could have done.
      const double frac = static_cast<double>(t_next - t) / static_cast<double>(b.s.t_ns - a.s.t_ns);
      const double T = b.gap_before_s;
      const double sv = p_.gap_acc_std * T, sp = 0.5 * p_.gap_acc_std * T * T, sr = p_.gap_gyro_std * T;
      for (int i = 0; i < 3; ++i) {
        (*P)(kVel + i, kVel + i) += frac * sv * sv;
        (*P)(kPos + i, kPos + i) += frac * sp * sp;
        (*P)(kRot + i, kRot + i) += frac * sr * sr;
      }
    }
  }
  x = propagate(x, gyro, acc, dt, gravity_);
}

std::optional<PoseEstimate> LioOdometry::addImu(const ImuSample& sample) {
  ++n_.imu_in;
  ImuSample s = sample;
  s.t_ns += static_cast<int64_t>(std::llround(p_.imu_time_offset_s * 1e9));
  if (!s.gyro.allFinite() || !s.acc.allFinite()) {
    ++n_.imu_non_finite;
    return std::nullopt;
  }
  if (have_imu_ && s.t_ns <= last_imu_ns_) {
    ++n_.imu_out_of_order;
    return std::nullopt;
  }
  Sample smp{s, 0.0};
  const double interval = have_imu_ ? sec(s.t_ns - last_imu_ns_) : 0.0;
  if (have_imu_ && interval > p_.imu_gap_s) {
    ++n_.imu_gaps;
    smp.gap_before_s = interval;
  }
  have_imu_ = true;
  last_imu_ns_ = s.t_ns;
  last_sample_ = smp;

  if (phase_ == Phase::kRunning && interval > p_.max_imu_gap_s) {
    reinitialise(fmt("IMU gap of %.2f s: re-initialising at the last pose", interval));
  }
  if (phase_ != Phase::kRunning) {
    tryInitialise(smp);
    if (phase_ != Phase::kRunning) return std::nullopt;
  } else {
    imu_.push_back(smp);
    step(xo_, &Po_, t_o_, s.t_ns, prev_o_, smp);
    t_o_ = s.t_ns;
    prev_o_ = smp;
  }

  PoseEstimate out;
  out.t_ns = s.t_ns;
  out.x = xo_;
  out.P = Po_;
  out.omega = s.gyro - xo_.bg;
  out.acc_world = xo_.R * (s.acc - xo_.ba) + gravity_;
  out.valid = valid(s.t_ns);
  out.imu_only_s = sec(s.t_ns - last_update_ns_);
  return out;
}

void LioOdometry::tryInitialise(const Sample& smp) {
  if (smp.gap_before_s > 0.0) init_window_.clear();  // a gap breaks the standstill window
  init_window_.push_back(smp);
  const int64_t window_ns = static_cast<int64_t>(std::llround(p_.init_window_s * 1e9));
  while (init_window_.size() > 2 && init_window_[1].s.t_ns <= smp.s.t_ns - window_ns) init_window_.pop_front();
  const double span = sec(smp.s.t_ns - init_window_.front().s.t_ns);
  if (span < p_.init_window_s) {
    if (phase_ == Phase::kInitialising)
      reason_ = fmt("waiting for a standstill of %.1f s (%.2f s so far)", p_.init_window_s, span);
    return;
  }
  Eigen::Vector3d mg = Eigen::Vector3d::Zero(), ma = Eigen::Vector3d::Zero();
  for (const auto& w : init_window_) {
    mg += w.s.gyro;
    ma += w.s.acc;
  }
  const double n = static_cast<double>(init_window_.size());
  mg /= n;
  ma /= n;
  Eigen::Vector3d vg = Eigen::Vector3d::Zero(), va = Eigen::Vector3d::Zero();
  for (const auto& w : init_window_) {
    vg += (w.s.gyro - mg).cwiseAbs2();
    va += (w.s.acc - ma).cwiseAbs2();
  }
  const double gstd = std::sqrt(vg.maxCoeff() / n), astd = std::sqrt(va.maxCoeff() / n);
  const double gerr = std::fabs(ma.norm() - p_.gravity);
  if (gstd < p_.init_max_gyro_std && astd < p_.init_max_acc_std && gerr < p_.init_max_gravity_error) {
    const int64_t still_from = init_window_.front().s.t_ns;
    initialise(smp.s.t_ns, mg, ma);
    startMapFromStandstill(still_from, smp.s.t_ns);
    return;
  }
  phase_ = Phase::kMovingAtStart;
  reason_ = fmt("moving at start (gyro std %.3f rad/s, acc std %.3f m/s^2, |g| off by %.2f m/s^2): "
                "no pose until the robot stands still",
                gstd, astd, gerr);
}

void LioOdometry::initialise(int64_t t_ns, const Eigen::Vector3d& mg, const Eigen::Vector3d& ma) {
  const Eigen::Vector3d zb = ma.normalized();  // world up, seen in the IMU frame
  NavState x;
  double st;  // std of roll and pitch
  if (p_.ground_prior) {
    // A ground robot starts on a level floor: roll and pitch are 0, and what the standstill
    // shows beyond gravity is accelerometer bias (horizontal part included).
    x.R = rotationFromRpy(0.0, 0.0, start_pose_.z());
    x.ba = ma - x.R.transpose() * Eigen::Vector3d(0.0, 0.0, p_.gravity);
    st = p_.ground_tilt_std;
  } else {
    // Gravity's direction from the mean specific force; only the bias along it is observable.
    const double pitch = std::asin(std::max(-1.0, std::min(1.0, -zb.x())));
    const double roll = std::atan2(zb.y(), zb.z());
    x.R = rotationFromRpy(roll, pitch, start_pose_.z());
    x.ba = zb * (ma.norm() - p_.gravity);
    st = p_.initial_acc_bias_std / p_.gravity;  // tilt from an unknown horizontal bias
  }
  x.bg = mg;
  x.v.setZero();
  x.p = Eigen::Vector3d(start_pose_.x(), start_pose_.y(), 0.0) + x.R * p_.imu_position;

  Matrix15 P = Matrix15::Zero();
  Eigen::Matrix3d Pth = Eigen::Vector3d(st * st, st * st, p_.initial_yaw_std * p_.initial_yaw_std).asDiagonal();
  P.block<3, 3>(kRot, kRot) = Pth;
  P.block<3, 3>(kPos, kPos) = Eigen::Matrix3d::Identity() * p_.initial_position_std * p_.initial_position_std;
  P.block<3, 3>(kVel, kVel) = Eigen::Matrix3d::Identity() * p_.initial_velocity_std * p_.initial_velocity_std;
  P.block<3, 3>(kBg, kBg) = Eigen::Matrix3d::Identity() * p_.initial_gyro_bias_std * p_.initial_gyro_bias_std;
  // At rest f = R^T (0 0 g) + ba: a tilt error d theta comes with d ba = -[f]x d theta.
  const Eigen::Matrix3d Fx = hat(ma);
  const double sz = p_.initial_acc_bias_std;
  P.block<3, 3>(kBa, kBa) = Fx * Pth * Fx.transpose() + sz * sz * zb * zb.transpose();
  P.block<3, 3>(kBa, kRot) = -Fx * Pth;
  P.block<3, 3>(kRot, kBa) = P.block<3, 3>(kBa, kRot).transpose();

  x_ = x;
  P_ = P;
  t_x_ = t_ns;
  prev_ = init_window_.back();
  imu_.clear();
  frames_.clear();
  init_window_.clear();
  last_update_ns_ = t_ns;
  last_frame_end_ns_ = t_ns;
  last_trim_position_ = basePosition(x);
  phase_ = Phase::kRunning;
  reason_.clear();
  restartOutput();
}

void LioOdometry::startMapFromStandstill(int64_t from_ns, int64_t to_ns) {
  // One frame alone makes a sparse map whose floor planes are fitted from few, nearly collinear
  // points; registered against it, the frame tilts by a few hundredths of a degree and every
  // later part of the map inherits the tilt (the base's height then drifts by about 0.2 % of
  // the distance driven). The standstill's frames were all taken at the start pose.
  std::deque<PointFrame> frames;
  frames.swap(still_frames_);
  if (!map_.empty()) return;  // a re-initialisation keeps its map
  const double rmin2 = p_.min_range * p_.min_range, rmax2 = p_.max_range * p_.max_range;
  std::vector<Eigen::Vector3f> pts;
  for (const PointFrame& f : frames) {
    if (f.t0_ns < from_ns || f.endNs() > to_ns) continue;
    pts.clear();
    for (const auto& q : f.points) {
      const Eigen::Vector3d pI = q.cast<double>() - p_.imu_position;
      const double r2 = pI.squaredNorm();
      if (r2 >= rmin2 && r2 <= rmax2) pts.push_back(pI.cast<float>());
    }
    for (int i : voxelDownsampleIndices(pts, p_.downsample_voxel))
      map_.insert((x_.R * pts[static_cast<std::size_t>(i)].cast<double>() + x_.p).cast<float>());
    ++n_.standstill_frames;
  }
}

void LioOdometry::reinitialise(const std::string& why) {
  const Eigen::Vector3d pb = basePosition(xo_);
  start_pose_ = Eigen::Vector3d(pb.x(), pb.y(), std::atan2(xo_.R(1, 0), xo_.R(0, 0)));
  ++n_.reinitialisations;
  n_.frames_dropped += static_cast<int64_t>(frames_.size());
  frames_.clear();
  still_frames_.clear();
  imu_.clear();
  init_window_.clear();
  phase_ = Phase::kInitialising;
  reason_ = why;
}

void LioOdometry::restartOutput() {
  xo_ = x_;
  Po_ = P_;
  t_o_ = t_x_;
  prev_o_ = prev_;
  for (const Sample& b : imu_) {
    step(xo_, &Po_, t_o_, b.s.t_ns, prev_o_, b);
    t_o_ = b.s.t_ns;
    prev_o_ = b;
  }
}

void LioOdometry::addFrame(PointFrame frame, std::vector<FrameReport>* reports) {
  ++n_.frames_in;
  if (!opt_.lidar_updates) return;
  FrameReport rep;
  rep.t0_ns = frame.t0_ns;
  rep.seq = frame.seq;
  rep.points_in = static_cast<int>(frame.points.size());
  auto drop = [&](FrameResult r) {
    rep.result = r;
    describe(&rep, last_imu_ns_);
    ++n_.frames_dropped;
    if (reports) reports->push_back(rep);
  };
  if (phase_ != Phase::kRunning) {
    // Kept for the first map if the start-up finds the robot standing still over its time;
    // only frames within the last standstill window (and a margin for late IMU) can be.
    const int64_t keep_from =
        frame.endNs() - static_cast<int64_t>(std::llround((p_.init_window_s + kStillFrameMarginS) * 1e9));
    still_frames_.push_back(std::move(frame));
    while (!still_frames_.empty() && still_frames_.front().t0_ns < keep_from) still_frames_.pop_front();
    return drop(FrameResult::kNotInitialised);
  }
  const int64_t end = frame.endNs();
  if (end <= last_frame_end_ns_ && !frames_.empty()) return drop(FrameResult::kOutOfOrder);
  if (end <= t_x_) return drop(end <= last_frame_end_ns_ ? FrameResult::kOutOfOrder : FrameResult::kLate);
  last_frame_end_ns_ = end;
  frames_.push_back(std::move(frame));
  while (static_cast<int>(frames_.size()) > p_.max_pending_frames) {
    const PointFrame& old = frames_.front();
    FrameReport r;
    r.t0_ns = old.t0_ns;
    r.seq = old.seq;
    r.points_in = static_cast<int>(old.points.size());
    r.result = FrameResult::kNoImu;
    describe(&r, last_imu_ns_);
    ++n_.frames_dropped;
    if (reports) reports->push_back(r);
    frames_.pop_front();
  }
  runDueFrames(reports);
}

void LioOdometry::runDueFrames(std::vector<FrameReport>* reports) {
  while (phase_ == Phase::kRunning && !frames_.empty() && frames_.front().endNs() <= last_imu_ns_) {
    const PointFrame f = std::move(frames_.front());
    frames_.pop_front();
    FrameReport rep;
    processFrame(f, &rep);
    describe(&rep, rep.t_end_ns > 0 ? rep.t_end_ns : last_imu_ns_);
    if (reports) reports->push_back(rep);
  }
}

void LioOdometry::describe(FrameReport* rep, int64_t t_ns) const {
  rep->map_voxels = map_.numVoxels();
  rep->map_points = map_.numPoints();
  rep->phase = phase_;
  rep->valid = valid(t_ns);
  rep->imu_only_s = phase_ == Phase::kRunning ? sec(t_ns - last_update_ns_) : 0.0;
  rep->state = x_;
  rep->covariance = P_;
}

void LioOdometry::finishFrame(const NavState& x, const Matrix15& P, int64_t t_end_ns) {
  x_ = x;
  P_ = P;
  t_x_ = t_end_ns;
  restartOutput();
}

void LioOdometry::processFrame(const PointFrame& f, FrameReport* rep) {
  const int64_t t_end = f.endNs();
  rep->t0_ns = f.t0_ns;
  rep->seq = f.seq;
  rep->t_end_ns = t_end;
  rep->points_in = static_cast<int>(f.points.size());
  if (t_end <= t_x_) {
    rep->result = FrameResult::kLate;
    ++n_.frames_dropped;
    return;
  }

  // Forward propagation to the frame end, keeping the state at the start of each piece.
  segments_.clear();
  NavState x = x_;
  Matrix15 P = P_;
  int64_t t = t_x_;
  Sample a = prev_;
  std::size_t consumed = 0;
  double max_gap = 0.0;
  for (std::size_t i = 0; i < imu_.size() && t < t_end; ++i) {
    const Sample& b = imu_[i];
    const int64_t tn = std::min(b.s.t_ns, t_end);
    const Eigen::Vector3d gyro = 0.5 * (a.s.gyro + b.s.gyro);
    const Eigen::Vector3d acc = 0.5 * (a.s.acc + b.s.acc);
    segments_.push_back({t, x, gyro - x.bg, x.R * (acc - x.ba) + gravity_});
    step(x, &P, t, tn, a, b);
    max_gap = std::max(max_gap, b.gap_before_s);
    t = tn;
    if (tn == b.s.t_ns) {
      a = b;
      consumed = i + 1;
    }
  }
  for (std::size_t i = 0; i < consumed; ++i) imu_.pop_front();
  prev_ = a;
  rep->max_imu_gap_s = max_gap;
  if (segments_.empty()) segments_.push_back({t, x, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});

  // Backward propagation: each point into the IMU frame at the frame end, with the pose at
  // its own time (the piece that started last before it).
  undistorted_.clear();
  undistorted_.reserve(f.points.size());
  const Eigen::Matrix3d RendT = x.R.transpose();
  const double rmin2 = p_.min_range * p_.min_range, rmax2 = p_.max_range * p_.max_range;
  // Per piece, once: its pose seen from the frame end (M = R_end^T R_k, c, v, a in that frame);
  // per point only the small rotation Exp(w tau) p (expSO3Apply) and a sum.
  std::size_t k = 0;
  bool piece_ready = false;
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), v = c, a_half = c, w = c;
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    const Eigen::Vector3d pI = f.points[i].cast<double>() - p_.imu_position;
    const double r2 = pI.squaredNorm();
    if (!(r2 >= rmin2 && r2 <= rmax2)) continue;
    const int64_t tp = f.t0_ns + (i < f.dt_ns.size() ? f.dt_ns[i] : 0);
    while (k + 1 < segments_.size() && segments_[k + 1].t_ns <= tp) {
      ++k;
      piece_ready = false;
    }
    const Segment& sg = segments_[k];
    if (!piece_ready) {
      M = RendT * sg.x.R;
      c = RendT * (sg.x.p - x.p);
      v = RendT * sg.x.v;
      a_half = 0.5 * (RendT * sg.a_world);
      w = sg.w;
      piece_ready = true;
    }
    const double tau = sec(tp - sg.t_ns);
    const Eigen::Vector3d rp = expSO3Apply(w * tau, pI);
    undistorted_.push_back((M * rp + c + v * tau + a_half * (tau * tau)).cast<float>());
  }
  rep->points_in_range = static_cast<int>(undistorted_.size());
  const std::vector<int> keep = voxelDownsampleIndices(undistorted_, p_.downsample_voxel);
  used_.clear();
  const std::size_t cap = p_.max_points > 0 ? static_cast<std::size_t>(p_.max_points) : keep.size();
  if (keep.size() <= cap) {
    for (int i : keep) used_.push_back(undistorted_[static_cast<std::size_t>(i)]);
  } else {
    // Evenly spaced over the kept points (scan order sweeps the field of view).
    for (std::size_t j = 0; j < cap; ++j)
      used_.push_back(undistorted_[static_cast<std::size_t>(keep[j * keep.size() / cap])]);
  }
  rep->points_used = static_cast<int>(used_.size());

  if (map_.empty()) {
    if (static_cast<int>(used_.size()) >= p_.min_points) {
      for (const auto& u : used_) map_.insert((x.R * u.cast<double>() + x.p).cast<float>());
      rep->result = FrameResult::kMapStarted;
      last_update_ns_ = t_end;
    } else {
      rep->result = FrameResult::kTooFewPoints;
      ++n_.frames_skipped;
    }
    finishFrame(x, P, t_end);
    return;
  }
  if (static_cast<int>(used_.size()) < p_.min_points) {
    rep->result = FrameResult::kTooFewPoints;
    ++n_.frames_skipped;
    finishFrame(x, P, t_end);
    return;
  }
  update(used_, x, P, rep);
}

void LioOdometry::update(const std::vector<Eigen::Vector3f>& pts, const NavState& prior, const Matrix15& P_prior,
                         FrameReport* rep) {
  const int64_t t_end = rep->t_end_ns;
  const std::size_t n = pts.size();
  Eigen::LLT<Matrix15> llt(P_prior);
  if (llt.info() != Eigen::Success) {
    rep->result = FrameResult::kNotRegistered;
    ++n_.frames_skipped;
    finishFrame(prior, P_prior, t_end);
    return;
  }
  const Matrix15 Pinv = llt.solve(Matrix15::Identity());
  std::vector<Plane> planes(n);
  std::vector<uint8_t> has(n, 0);
  std::vector<double> abs_r;
  abs_r.reserve(n);
  const double c2 = p_.robust_scale * p_.robust_scale;
  const double inv_var = 1.0 / (p_.point_std * p_.point_std);
  const int min_matched = std::max(6, static_cast<int>(std::ceil(p_.min_matched_ratio * static_cast<double>(n))));
  NavState x = prior;
  Matrix15 A = Pinv;
  Eigen::Matrix<double, 6, 6> HtH = Eigen::Matrix<double, 6, 6>::Zero();
  Neighbours nb;
  bool ok = false;
  int matched = 0;
  double sum_r2 = 0.0;
  NavState searched_at = prior;
  for (int it = 0; it < p_.max_iterations; ++it) {
    // Correspondences at the current iterate: at the first iteration, then when the iterate
    // has moved enough to change them.
    const Vector15 moved = boxminus(x, searched_at);
    const bool search = it == 0 || moved.segment<3>(kPos).norm() > p_.research_translation ||
                        moved.segment<3>(kRot).norm() > p_.research_rotation;
    for (std::size_t i = 0; search && i < n; ++i) {
      has[i] = 0;
      const Eigen::Vector3f q = (x.R * pts[i].cast<double>() + x.p).cast<float>();
      if (map_.nearest(q, p_.knn, static_cast<float>(p_.max_correspondence), &nb) < p_.knn) continue;
      if (auto pl = fitPlane(nb, p_.knn, p_.plane_threshold)) {
        planes[i] = *pl;
        has[i] = 1;
      }
    }
    if (search) {
      ++rep->searches;
      searched_at = x;
    }
    HtH.setZero();
    Eigen::Matrix<double, 6, 1> Htr = Eigen::Matrix<double, 6, 1>::Zero();
    matched = 0;
    sum_r2 = 0.0;
    abs_r.clear();
    Eigen::Matrix<double, 1, 6> J;
    for (std::size_t i = 0; i < n; ++i) {
      if (!has[i]) continue;
      const double r = pointToPlane(planes[i], x.R, x.p, pts[i].cast<double>(), &J);
      if (!(std::fabs(r) <= p_.outlier_distance)) continue;
      const double w = inv_var / (1.0 + r * r / c2);
      HtH.noalias() += w * J.transpose() * J;
      Htr.noalias() += w * J.transpose() * r;
      sum_r2 += r * r;
      abs_r.push_back(std::fabs(r));
      ++matched;
    }
    if (matched < min_matched) break;
    if (p_.ground_prior) {
      // Base height 0 and base roll/pitch 0 as pseudo-measurements (ground robot).
      const Eigen::Vector3d& t = p_.imu_position;
      Eigen::Matrix<double, 1, 6> Jz;
      const double rz = groundHeightResidual(x, t, &Jz);
      const double wz = 1.0 / (p_.ground_height_std * p_.ground_height_std);
      HtH.noalias() += wz * Jz.transpose() * Jz;
      Htr.noalias() += wz * Jz.transpose() * rz;
      Eigen::Matrix<double, 2, 6> Jt;
      const Eigen::Vector2d rt = groundTiltResidual(x, &Jt);
      const double wt = 1.0 / (p_.ground_tilt_std * p_.ground_tilt_std);
      HtH.noalias() += wt * Jt.transpose() * Jt;
      Htr.noalias() += wt * Jt.transpose() * rt;
    }
    const Matrix15 Jb = boxminusJacobian(x, prior);
    const Vector15 e = boxminus(x, prior);
    const Matrix15 JtPinv = Jb.transpose() * Pinv;
    A = JtPinv * Jb;
    A.topLeftCorner<6, 6>() += HtH;
    Vector15 g = JtPinv * e;
    g.head<6>() += Htr;
    const Vector15 dx = A.ldlt().solve(-g);
    if (!dx.allFinite()) break;
    x = boxplus(x, dx);
    rep->iterations = it + 1;
    ok = true;
    if (dx.segment<3>(kRot).norm() < p_.converged_rotation && dx.segment<3>(kPos).norm() < p_.converged_translation)
      break;
  }
  rep->points_matched = matched;
  if (!ok) {
    rep->result = FrameResult::kNotRegistered;
    ++n_.frames_skipped;
    finishFrame(prior, P_prior, t_end);
    return;
  }
  Matrix15 Ppost = A.ldlt().solve(Matrix15::Identity());
  Ppost = 0.5 * (Ppost + Ppost.transpose()).eval();

  rep->residual_rms = matched > 0 ? std::sqrt(sum_r2 / matched) : 0.0;
  if (!abs_r.empty()) {
    auto mid = abs_r.begin() + static_cast<std::ptrdiff_t>(abs_r.size() / 2);
    std::nth_element(abs_r.begin(), mid, abs_r.end());
    rep->residual_median = *mid;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> et(HtH.block<3, 3>(3, 3));
  rep->info_translation = et.eigenvalues();
  rep->weak_direction = et.eigenvectors().col(0);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> er(HtH.block<3, 3>(0, 0), Eigen::EigenvaluesOnly);
  rep->info_rotation = er.eigenvalues();
  const Vector15 corr = boxminus(x, prior);
  rep->correction_translation = corr.segment<3>(kPos).norm();
  rep->correction_rotation = corr.segment<3>(kRot).norm();

  // Grow the map with the points that agree with it (or that it has no plane for yet).
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q = x.R * pts[i].cast<double>() + x.p;
    if (has[i] && std::fabs(planes[i].distance(q)) > p_.map_insert_max_residual) continue;
    map_.insert(q.cast<float>());
  }
  // What this scan sees through (a person who walked on) leaves the map.
  if (p_.map_carve_every > 0 && ++updates_since_carve_ >= p_.map_carve_every) {
    updates_since_carve_ = 0;
    n_.map_voxels_carved += static_cast<int64_t>(map_.carve(x.p, x.R, undistorted_));
  }
  const Eigen::Vector3d pb = basePosition(x);
  if ((pb - last_trim_position_).norm() > p_.map_trim_every_m) {
    map_.removeFar(pb);
    last_trim_position_ = pb;
  }
  rep->result = FrameResult::kUpdated;
  ++n_.frames_updated;
  last_update_ns_ = t_end;
  finishFrame(x, Ppost, t_end);
}

double groundHeightResidual(const NavState& x, const Eigen::Vector3d& imu_position, Eigen::Matrix<double, 1, 6>* J) {
  // Base origin p_b = p - R t: dp_b/ddtheta = R [t]x, dp_b/ddp = I; residual = e3 . p_b.
  if (J) {
    J->leftCols<3>() = (x.R * hat(imu_position)).row(2);
    J->rightCols<3>() = Eigen::RowVector3d(0.0, 0.0, 1.0);
  }
  return (x.p - x.R * imu_position).z();
}

Eigen::Vector2d groundTiltResidual(const NavState& x, Eigen::Matrix<double, 2, 6>* J) {
  // Body z in the world, its x and y: d(R Exp(dth) e3)/ddth = -R [e3]x.
  if (J) {
    J->setZero();
    J->leftCols<3>() = -(x.R * hat(Eigen::Vector3d::UnitZ())).topRows<2>();
  }
  return x.R.col(2).head<2>();
}

}  // namespace lio
}  // namespace ucon
