#pragma once
/// @file simulator.hpp
/// The simulator node: the world, the Mecanum base and the Mid-360, stepped in simulation time.
/// No sockets and no clock: advanceTo() returns the datagrams and messages due up to a time;
/// the live main sends them, the in-process benchmarks consume them directly (optionally as
/// assembled point frames, without packets).
///
/// Timeline (integer nanoseconds since simulation start; utime = start_utime + t/1000):
///  - point k is measured at k * 1e9/point_rate; packet j holds points 96j .. 96j+95 and is
///    stamped with its first point's time; time_interval = 96 * spacing (ucon::livox
///    convention: point i at timestamp + i * time_interval / dot_num);
///  - a LiDAR frame is 1/frame_rate_hz long: frame_cnt increments and udp_cnt restarts at the
///    first packet of each frame; SIM_GROUND_TRUTH is sampled at each frame start;
///  - IMU at imu.rate_hz (stamped imu.time_offset_s late), ROBOT_POSE at pose_rate_hz (none
///    with pose_source "none").
/// Livox timestamps are (start_utime * 1000 + t) ns with time_type 0, so the driver's utime,
/// ROBOT_POSE and SIM_GROUND_TRUTH share one clock.

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <vector>

#include "ucon/livox/point_packet.hpp"
#include "ucon/mecanum/plant.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/simulator/control_responder.hpp"
#include "ucon/simulator/lidar_emulator.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/wheel_cmd_t.hpp"
#include "ucon/world/world.hpp"

namespace ucon {
namespace simulator {

/// One UDP datagram to send.
struct Datagram {
  std::vector<uint8_t> bytes;
  std::array<uint8_t, 4> ip{{127, 0, 0, 1}};
  uint16_t port = 0;
  uint8_t sensor = 0;  ///< which emulated Mid-360 sends it: 0 the first, i extra_lidars[i - 1]
};

/// What advanceTo() produced, in time order per kind.
struct SimOutputs {
  std::vector<Datagram> point_packets;
  std::vector<Datagram> imu_packets;
  std::vector<robot_pose_t> poses;
  std::vector<sim_ground_truth_t> ground_truth;
  std::vector<point_cloud_t> frames;  ///< only with SimOptions::make_frames
  void clear();
};

/// What to produce.
struct SimOptions {
  bool make_packets = true;  ///< Livox point and IMU datagrams
  bool make_frames = false;  ///< point_cloud_t per LiDAR frame (zero points dropped)
  /// Frames in the base frame (mount transform applied, frame_id "base", as the driver
  /// publishes with its extrinsic) instead of the raw sensor frame (frame_id "lidar").
  bool frames_in_base = false;
};

/// Totals since start.
struct SimCounters {
  int64_t packets = 0;          ///< point packets produced
  int64_t points = 0;           ///< points in them (zero points included)
  int64_t returns = 0;          ///< points with a return
  int64_t imu_packets = 0;
  int64_t encode_errors = 0;
  int64_t poses = 0;
  int64_t ground_truth = 0;
  int64_t frames = 0;
  int64_t wheel_cmds = 0;
  int64_t bad_wheel_cmds = 0;   ///< non-finite commands (dropped, motors brake)
  int64_t cmd_timeouts = 0;     ///< watchdog stops
  int64_t collision_episodes = 0;
};

class Simulator {
 public:
  /// `params` should satisfy params.validate() and the scenario world::validate(); the
  /// simulator stays well defined otherwise but its output is then meaningless.
  Simulator(const SimulatorParams& params, world::Scenario scenario, SimOptions options = {});

  /// Current simulation time [us] (start_utime at construction).
  int64_t utime() const { return params_.start_utime + now_ns_ / 1000; }
  /// Seconds since the simulation started.
  double simTime() const { return static_cast<double>(now_ns_) * 1e-9; }

  /// Advances to `utime` [us], appending everything due in (current, utime] to `out`.
  /// Earlier times do nothing.
  void advanceTo(int64_t utime, SimOutputs& out);

  /// A BASE_WHEEL_CMD: applied at the current simulation time. Non-finite speeds are counted
  /// and brake the motors. Returns false if rejected.
  bool onWheelCmd(const wheel_cmd_t& cmd);

  ControlResponder& control() { return control_; }
  /// Emulated Mid-360s: 1 + params.extra_lidars.size(); control(0) is control().
  std::size_t sensorCount() const { return 1 + extras_.size(); }
  ControlResponder& control(std::size_t sensor) { return sensor == 0 ? control_ : extras_[sensor - 1].control; }
  const world::World& world() const { return world_; }
  const mecanum::PlantState& robot() const { return plant_.state(); }
  const SimCounters& counters() const { return counters_; }
  const ScanStats& scanStats() const { return scan_stats_; }
  const SimulatorParams& params() const { return params_; }
  /// Smallest robot-to-obstacle surface gap so far [m] (+inf before the first pose).
  double minClearance() const { return min_clearance_; }
  bool inCollision() const { return in_collision_; }
  /// World pose of the sensor now.
  Eigen::Isometry3d sensorPose() const;
  /// World pose of the base now: the plant's planar pose with the vibration's roll and pitch.
  Eigen::Isometry3d basePose() const;
  /// The IMU's current biases in the sensor frame: gyro [rad/s], accelerometer [m/s^2].
  const Eigen::Vector3d& gyroBias() const { return gyro_bias_; }
  const Eigen::Vector3d& accBias() const { return acc_bias_; }

 private:
  void stepPlantTo(int64_t t_ns);
  void emitPacket(int64_t t_ns, SimOutputs& out);
  void emitImu(int64_t t_ns, SimOutputs& out);
  void emitPose(int64_t t_ns, SimOutputs& out);
  void emitGroundTruth(int64_t t_ns, SimOutputs& out);
  void checkCollision(int64_t t_ns);
  void startFrame(int64_t frame_index, SimOutputs& out);
  // The extra sensors from params.extra_lidars, and the sensor origin of assembled frames
  // (extra_lidars.cpp).
  void initExtraLidars();
  // Point packets of the extra sensors at t_ns (extra_lidars.cpp).
  void emitExtraPackets(int64_t t_ns, SimOutputs& out);
  // One point packet of `st`'s configured type to its point host; false if it cannot be encoded.
  bool makePointDatagram(const SensorState& st, uint64_t stamp_ns, uint16_t udp_cnt, uint8_t sensor,
                         Datagram& d);

  struct ExtraLidar {
    LidarEmulator lidar;
    ControlResponder control;
    uint16_t udp_cnt = 0;
    int64_t frame = -1;
  };

  SimulatorParams params_;
  SimOptions options_;
  world::World world_;
  mecanum::MecanumPlant plant_;
  LidarEmulator lidar_;
  ControlResponder control_;
  std::vector<ExtraLidar> extras_;
  world::Rng imu_rng_;

  int64_t spacing_ns_, imu_period_ns_, pose_period_ns_, frame_period_ns_;
  int64_t now_ns_ = 0, plant_ns_ = 0;
  uint64_t next_point_k_ = 0;
  int64_t next_imu_ns_ = 0, next_pose_ns_ = 0, next_gt_ns_ = 0;
  int64_t last_cmd_ns_ = 0;
  bool cmd_active_ = false;

  int64_t cur_frame_ = -1;
  uint8_t frame_cnt_ = 0;
  uint16_t udp_cnt_ = 0;
  uint16_t imu_cnt_ = 0;
  point_cloud_t cloud_{};
  int64_t cloud_seq_ = 0;

  // Roll, pitch [rad] of the vibration at t_ns and their rates [rad/s].
  void vibration(int64_t t_ns, double* roll, double* pitch, double* droll, double* dpitch) const;

  Eigen::Vector3d gyro_bias_, acc_bias_, imu_position_;
  int64_t imu_time_offset_ns_ = 0;
  Eigen::Vector3d prev_sensor_vel_ = Eigen::Vector3d::Zero();
  bool have_prev_imu_ = false;
  double prev_pose_vx_ = 0.0, prev_pose_vy_ = 0.0;
  int64_t pose_seq_ = 0, gt_seq_ = 0;

  bool in_collision_ = false;
  double min_clearance_;
  std::vector<livox::LidarPoint> pts_;
  SimCounters counters_;
  ScanStats scan_stats_;
};

}  // namespace simulator
}  // namespace ucon
