#pragma once
/// @file lio_odometry.hpp
/// Tightly coupled LiDAR-inertial odometry: an iterated error-state Kalman filter on
/// SO(3) x R^12 (FAST-LIO2, Xu et al., T-RO 2022) with Faster-LIO's incremental voxel map
/// (Bai et al., RA-L 2022). Pure: samples and frames in, poses and per-frame reports out; no
/// clock, no I/O, deterministic.
///
/// Frames. Points and IMU samples arrive in one frame, the "points frame" (the robot's base
/// frame when the driver applies its extrinsic): the driver has rotated the IMU axes into it,
/// and the IMU's origin sits at `imu_position` in it. The filter's body frame is the IMU
/// (base axes, IMU origin). The world frame is z up, gravity (0, 0, -gravity), with its
/// origin where the base stands at `initial_pose` (x, y, yaw; z = 0 on the floor).
///
/// Choices (and why):
///  - Gravity is a known constant of the world frame, not a state (FAST-LIO2 estimates it on
///    S2). Roll and pitch come from the mean specific force of a standstill window; the
///    horizontal accelerometer bias that this cannot separate from tilt enters the initial
///    covariance as the exact correlation at rest (d ba = -[f]x d theta). The LiDAR cannot
///    tell the tilt either (the map is built in the same tilted frame), so a 5 mg horizontal
///    bias leaves the frame ~0.3 deg off level until turning makes the bias observable. With
///    the ground prior the base starts level instead and the whole standstill residual is bias.
///    A ground robot starts on a floor, so a standstill of at most 1 s is always available,
///    and 3 fewer states cost nothing.
///  - The update is the iterated EKF written as Gauss-Newton on the MAP cost: at iterate x_j,
///    dx = -(J^T P^-1 J + H^T W H)^-1 (J^T P^-1 (x_j [-] x_prior) + H^T W r), with J the
///    boxminus Jacobian (FAST-LIO2 eqs. 17-18); P+ = (J^T P^-1 J + H^T W H)^-1.
///  - Residuals are point-to-plane against planes of the 5 nearest map points (eq. 11), with
///    a Cauchy kernel (weights 1/(1 + r^2/c^2), iteratively reweighted) so that walking
///    people, which do not lie on the map's planes, pull little; points farther than
///    `outlier_distance` from their plane are dropped. A point that disagrees with a good
///    plane is not added to the map either (a mover in front of a mapped wall).
///  - Every point is moved to the frame end with the pose propagated to its own time
///    (backward propagation, Sec. III-C): the IMU states between the last update and the
///    frame end are kept and each point uses the one just before it.
///  - A ROBOT_POSE per IMU sample comes from a second propagation of the last update through
///    the newest samples; it is produced before the LiDAR update that sample unlocks, so its
///    latency is one propagation step; the update shows in the next sample's pose.
///
/// Bad input: IMU samples out of order or non-finite are dropped and counted; a gap over
/// `imu_gap_s` is bridged by holding the last reading, with the covariance inflated by
/// `gap_acc_std` / `gap_gyro_std` per second of gap; over `max_imu_gap_s` the filter
/// re-initialises at its last pose (map kept). Without LiDAR updates the pose is IMU-only
/// for `imu_only_timeout_s`, then invalid until a frame registers again. Frames out of
/// order, late, with too few points or that do not register are reported and skipped.

#include <Eigen/Core>

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "ucon/lio/nav_state.hpp"
#include "ucon/lio/voxel_map.hpp"

namespace ucon {
namespace lio {

/// Parameters of the odometry (deploy/config/odometry.yaml maps onto them).
struct LioParams {
  // Mounting and time.
  Eigen::Vector3d imu_position = Eigen::Vector3d(0.011, -0.023, 0.544);  ///< IMU origin in the points frame [m]
  double imu_time_offset_s = 0.0;   ///< added to IMU stamps to bring them onto the LiDAR clock [s], |.| <= 0.1
  double gravity = 9.80665;         ///< [m/s^2], [9, 10.5]
  ImuNoise noise;                   ///< IMU model noise (filter tuning)
  double gap_acc_std = 1.0;         ///< acceleration std assumed during an IMU gap [m/s^2], >= 0
  double gap_gyro_std = 0.3;        ///< rate std assumed during an IMU gap [rad/s], >= 0

  // Start-up.
  double init_window_s = 0.5;       ///< standstill needed to initialise [s], (0, 1]
  double init_max_gyro_std = 0.02;  ///< standstill test: per-axis gyro std below [rad/s]
  double init_max_acc_std = 0.1;    ///< per-axis accelerometer std below [m/s^2]
  double init_max_gravity_error = 0.5;  ///< | |mean acc| - gravity | below [m/s^2]
  Eigen::Vector3d initial_pose = Eigen::Vector3d::Zero();  ///< base x [m], y [m], yaw [rad] at start
  double initial_position_std = 0.001;  ///< [m]
  double initial_yaw_std = 0.001;       ///< [rad]
  double initial_velocity_std = 0.05;   ///< a standstill is not exactly still [m/s]
  double initial_acc_bias_std = 0.1;    ///< horizontal accelerometer bias prior (sets the tilt prior) [m/s^2]
  double initial_gyro_bias_std = 0.002; ///< after the standstill mean [rad/s]

  // Points.
  double min_range = 0.4;           ///< points nearer the IMU origin are dropped [m]
  double max_range = 40.0;          ///< [m]
  double downsample_voxel = 0.3;    ///< one point per cell of this size per frame [m], >= 0
  int min_points = 100;             ///< fewer points after downsampling: no update [1, 1e5]
  /// More points than this after downsampling (a large open scene): evenly spaced ones of them
  /// are kept, in scan order; 0 = all. Bounds the update's time per frame.
  int max_points = 1000;

  // Update.
  int max_iterations = 4;           ///< IEKF iterations, [1, 20]
  int knn = 5;                      ///< map points per plane, [3, 8]
  double max_correspondence = 1.0;  ///< farthest map point used for a plane [m]
  double plane_threshold = 0.1;     ///< a plane is rejected if a neighbour is farther [m]
  double point_std = 0.02;          ///< point-to-plane noise (1 sigma) [m], > 0
  double robust_scale = 0.1;        ///< Cauchy kernel scale c [m], > 0
  double outlier_distance = 0.5;    ///< residuals beyond are dropped [m], > 0
  double converged_rotation = 1e-4; ///< stop iterating below this step [rad]
  double converged_translation = 1e-3;  ///< ... and this one [m]
  /// Correspondences are searched at the first iteration and again only once the iterate has
  /// moved this far from where they were last searched (FAST-LIO2 searches at every iteration;
  /// below these steps the same neighbours come back).
  double research_translation = 0.02;   ///< [m], > 0
  double research_rotation = 0.002;     ///< [rad], > 0
  double min_matched_ratio = 0.2;   ///< fewer matched points than this share: the frame does not register
  double map_insert_max_residual = 0.1;  ///< a point this far from a good plane is not inserted [m]

  // Map.
  VoxelMapParams map;
  double map_trim_every_m = 2.0;    ///< removeFar() after the robot moved this far [m]
  /// VoxelMap::carve() with the undistorted scan after every this many updates; 0 = never.
  int map_carve_every = 5;

  // Ground-robot prior (optional): the base starts level (roll and pitch 0 at start, so the
  // standstill's horizontal specific force is accelerometer bias, not tilt) and its height and
  // tilt are pseudo-measurements at every update.
  bool ground_prior = true;
  double ground_height_std = 0.02;  ///< base z around 0 [m], > 0
  double ground_tilt_std = 0.02;    ///< base roll and pitch around 0 [rad], > 0

  // Validity and bad input.
  double imu_gap_s = 0.05;          ///< a longer interval is a gap (inflated, reported) [s]
  double max_imu_gap_s = 1.0;       ///< a longer gap re-initialises [s]
  double imu_only_timeout_s = 0.5;  ///< pose valid this long after the last LiDAR update [s]
  int max_pending_frames = 10;      ///< frames waiting for IMU data beyond this are dropped

  /// Empty when consistent, else "key: why" with the key as odometry.yaml names it.
  std::string validate() const;
};

/// One IMU sample in the points frame (SI units).
struct ImuSample {
  int64_t t_ns = 0;
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();  ///< [rad/s]
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();   ///< specific force [m/s^2]
};

/// One LiDAR frame: points in the points frame [m] with their times, ascending.
struct PointFrame {
  int64_t t0_ns = 0;                   ///< time of the first point
  int64_t seq = 0;                     ///< source sequence number (reported back)
  std::vector<Eigen::Vector3f> points;
  std::vector<int64_t> dt_ns;          ///< point time - t0_ns, >= 0, non-decreasing
  int64_t endNs() const { return t0_ns + (dt_ns.empty() ? 0 : dt_ns.back()); }
};

enum class Phase : uint8_t {
  kInitialising = 0,   ///< collecting a standstill window
  kMovingAtStart = 1,  ///< the window was not still: waiting for standstill
  kRunning = 2,
};
const char* toString(Phase p);

enum class FrameResult : uint8_t {
  kUpdated = 0,        ///< registered, state updated, map grown
  kMapStarted = 1,     ///< first frame, no standstill frame kept: map started, no update
  kTooFewPoints = 2,   ///< fewer than min_points after filtering: IMU only
  kNotRegistered = 3,  ///< too few matched points or a failed solve: IMU only
  kNotInitialised = 4, ///< arrived before the filter was initialised: dropped
  kOutOfOrder = 5,     ///< not after the previous frame: dropped
  kLate = 6,           ///< ends before the filter's time: dropped
  kNoImu = 7,          ///< waited too long for IMU samples: dropped
};
const char* toString(FrameResult r);

/// What happened to one frame.
struct FrameReport {
  int64_t t_end_ns = 0;         ///< frame end (the update's time); 0 when dropped unprocessed
  int64_t t0_ns = 0;
  int64_t seq = 0;
  FrameResult result = FrameResult::kUpdated;
  int points_in = 0;            ///< points given
  int points_in_range = 0;      ///< after the range filter
  int points_used = 0;          ///< after downsampling
  int points_matched = 0;       ///< with a plane at the last iteration
  int iterations = 0;
  int searches = 0;             ///< nearest-neighbour passes
  double residual_rms = 0.0;    ///< of matched points at the last iteration [m]
  double residual_median = 0.0; ///< median |r| [m]
  Eigen::Vector3d info_translation = Eigen::Vector3d::Zero();  ///< eigenvalues (ascending) of the position information [1/m^2]
  Eigen::Vector3d weak_direction = Eigen::Vector3d::Zero();    ///< eigenvector of the smallest one (world)
  Eigen::Vector3d info_rotation = Eigen::Vector3d::Zero();     ///< eigenvalues of the rotation information [1/rad^2]
  double correction_translation = 0.0;  ///< |posterior - prior| position [m]
  double correction_rotation = 0.0;     ///< [rad]
  double max_imu_gap_s = 0.0;   ///< longest IMU interval inside the frame's propagation [s]
  std::size_t map_voxels = 0, map_points = 0;
  // The odometry after this frame.
  Phase phase = Phase::kInitialising;
  bool valid = false;           ///< a pose at t_end would be valid
  double imu_only_s = 0.0;      ///< since the last LiDAR update, at t_end [s]
  NavState state;               ///< filter state at t_end (meaningful when running)
  Matrix15 covariance = Matrix15::Zero();
};

/// The pose the odometry gives at one IMU sample.
struct PoseEstimate {
  int64_t t_ns = 0;
  NavState x;                   ///< IMU state
  Matrix15 P = Matrix15::Zero();
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();     ///< bias-corrected body rate [rad/s]
  Eigen::Vector3d acc_world = Eigen::Vector3d::Zero(); ///< IMU acceleration, world [m/s^2]
  bool valid = false;
  double imu_only_s = 0.0;      ///< since the last LiDAR update [s]
};

/// Totals since start.
struct LioCounters {
  int64_t imu_in = 0, imu_out_of_order = 0, imu_non_finite = 0, imu_gaps = 0, reinitialisations = 0;
  int64_t frames_in = 0, frames_updated = 0, frames_skipped = 0, frames_dropped = 0;
  int64_t standstill_frames = 0;  ///< frames of the start-up standstill the first map was built from
  int64_t map_voxels_carved = 0;  ///< voxels dropped because the scans saw through them
};

/// Ground-robot prior, base height: r = z of the base origin p - R t_imu [m], with its
/// Jacobian over (dtheta, dp).
double groundHeightResidual(const NavState& x, const Eigen::Vector3d& imu_position, Eigen::Matrix<double, 1, 6>* J);
/// Ground-robot prior, tilt: r = the world x and y of the body z axis (~ pitch, -roll) [-],
/// with its Jacobian over (dtheta, dp).
Eigen::Vector2d groundTiltResidual(const NavState& x, Eigen::Matrix<double, 2, 6>* J);

class LioOdometry {
 public:
  struct Options {
    bool lidar_updates = true;  ///< false: IMU dead reckoning only (the baseline)
  };
  explicit LioOdometry(const LioParams& params);
  LioOdometry(const LioParams& params, const Options& options);

  /// Adds one sample. Once initialised, returns the pose at its time; dropped samples (and
  /// samples before initialisation) return nullopt. Frames it lets run wait for
  /// runDueFrames(), so a caller can publish the pose before the LiDAR update.
  std::optional<PoseEstimate> addImu(const ImuSample& sample);

  /// Runs the queued frames that end at or before the newest sample; appends their reports.
  void runDueFrames(std::vector<FrameReport>* reports);

  /// Queues a frame until IMU samples cover its end, and runs it at once when they already
  /// do. Appends a report for every frame run or dropped (not initialised, out of order,
  /// late, or the oldest queued one when more than max_pending_frames wait).
  void addFrame(PointFrame frame, std::vector<FrameReport>* reports);

  Phase phase() const { return phase_; }
  /// Why the phase is what it is (for a status line), empty when running normally.
  const std::string& phaseReason() const { return reason_; }
  const LioCounters& counters() const { return n_; }
  const LioParams& params() const { return p_; }
  const VoxelMap& map() const { return map_; }
  /// Filter state at its last update (or initialisation).
  const NavState& state() const { return x_; }
  const Matrix15& covariance() const { return P_; }
  int64_t stateTimeNs() const { return t_x_; }
  int64_t lastImuNs() const { return last_imu_ns_; }

  /// Pose of the points frame ("base") for an IMU state: R and p - R imu_position.
  Eigen::Vector3d basePosition(const NavState& x) const { return x.p - x.R * p_.imu_position; }

 private:
  struct Sample {
    ImuSample s;
    double gap_before_s = 0.0;  ///< interval to the previous sample when it was a gap [s]
  };
  struct Segment {
    int64_t t_ns;
    NavState x;
    Eigen::Vector3d w, a_world;  // held over the segment
  };

  void tryInitialise(const Sample& s);
  void initialise(int64_t t_ns, const Eigen::Vector3d& mean_gyro, const Eigen::Vector3d& mean_acc);
  void reinitialise(const std::string& why);
  // Starts the map from the frames that lie within the standstill [from_ns, to_ns] that the
  // start-up verified: the pose of each is the start pose (nothing if the map is not empty).
  void startMapFromStandstill(int64_t from_ns, int64_t to_ns);
  // Propagates (x, P) from t to t_next with the mean of a and b; inflates for a gap.
  void step(NavState& x, Matrix15* P, int64_t t, int64_t t_next, const Sample& a, const Sample& b) const;
  void processFrame(const PointFrame& f, FrameReport* rep);
  void finishFrame(const NavState& x, const Matrix15& P, int64_t t_end_ns);
  void describe(FrameReport* rep, int64_t t_ns) const;
  void update(const std::vector<Eigen::Vector3f>& pts, const NavState& prior, const Matrix15& P_prior,
              FrameReport* rep);
  void restartOutput();
  bool valid(int64_t t_ns) const;

  LioParams p_;
  Options opt_;
  Eigen::Vector3d gravity_;
  Phase phase_ = Phase::kInitialising;
  std::string reason_;
  LioCounters n_;
  VoxelMap map_;

  std::deque<Sample> init_window_;
  Eigen::Vector3d start_pose_;  // base x, y, yaw used by the next initialisation
  int64_t last_imu_ns_ = 0;
  bool have_imu_ = false;
  Sample last_sample_;

  // Filter: state at t_x_, samples after it, and the last sample at or before it.
  NavState x_;
  Matrix15 P_ = Matrix15::Identity();
  int64_t t_x_ = 0;
  std::deque<Sample> imu_;
  Sample prev_;
  // Output propagation: the filter state carried to the newest sample.
  NavState xo_;
  Matrix15 Po_ = Matrix15::Identity();
  int64_t t_o_ = 0;
  Sample prev_o_;

  std::deque<PointFrame> frames_;
  std::deque<PointFrame> still_frames_;  // frames that came before the start (standstill candidates)
  int64_t last_frame_end_ns_ = 0;
  int64_t last_update_ns_ = 0;
  Eigen::Vector3d last_trim_position_ = Eigen::Vector3d::Zero();
  int updates_since_carve_ = 0;

  // Scratch (sized per frame, reused).
  std::vector<Segment> segments_;
  std::vector<Eigen::Vector3f> undistorted_;
  std::vector<Eigen::Vector3f> used_;
};

}  // namespace lio
}  // namespace ucon
