#pragma once
/// @file params.hpp
/// Parameters of the simulator node (deploy/config/simulator.yaml maps onto them one-to-one).

#include <cstdint>
#include <string>
#include <vector>

#include "ucon/mecanum/plant.hpp"

namespace ucon {
class ConfigReader;

namespace simulator {

/// The emulated Livox Mid-360.
struct LidarParams {
  double point_rate = 200000.0;       ///< points per second [1/s], [2e4, 1e6]; 1e9/rate a multiple of 100 ns
  int data_type = 1;                  ///< point record type sent: 1 (mm), 2 (cm) or 3 (spherical)
  double min_range = 0.1;             ///< nearer returns are dropped (sent as zero points) [m], [0, 10]
  double max_range = 40.0;            ///< [m], (min_range, 500]
  double range_noise_sigma = 0.02;    ///< Gaussian range noise [m], [0, 1]
  double elevation_min_deg = -7.0;    ///< lower edge of the field of view, sensor frame [deg]
  double elevation_max_deg = 52.0;    ///< upper edge [deg], > min
  std::vector<double> mount_xyz{0.0, 0.0, 0.5};      ///< sensor origin in the base frame [m]
  std::vector<double> mount_rpy_deg{180.0, 0.0, 0.0};  ///< sensor->base roll, pitch, yaw [deg]; 180 = upside down
  double ground_reflectivity = 20.0;  ///< reflectivity of the floor, [0, 255]
  int64_t seed = 1;                   ///< noise seed, >= 0

  void read(ConfigReader& r);
};

/// The IMU inside the Mid-360 (sensor frame): white noise, a bias that starts at a constant
/// and random-walks, its offset from the LiDAR origin, an optional clock offset.
struct ImuParams {
  double rate_hz = 200.0;             ///< [Hz], [1, 2000]; 1e9/rate must be whole ns
  /// White noise per sample [rad/s], [0, 1]: the ICM-40609-D datasheet's 4.5 mdps/sqrt(Hz) at 200 Hz.
  double gyro_noise_sigma = 0.0011;
  /// White noise per sample [m/s^2], [0, 10]: 100 ug/sqrt(Hz) at 200 Hz.
  double acc_noise_sigma = 0.014;
  /// Gyro bias random walk [rad/s/sqrt(s)], [0, 1]: no datasheet figure; FAST-LIO's Mid-360
  /// configuration (b_gyr_cov 1e-4 per step, squared step, 200 Hz) gives 7.1e-4.
  double gyro_bias_walk = 7.1e-4;
  double acc_bias_walk = 7.1e-4;      ///< accelerometer bias random walk [m/s^2/sqrt(s)], [0, 10]; as above
  std::vector<double> gyro_bias{0.002, -0.003, 0.0015};  ///< bias at start, sensor frame [rad/s], |.| <= 1
  std::vector<double> acc_bias{0.04, -0.03, 0.05};       ///< bias at start, sensor frame [m/s^2], |.| <= 10
  std::vector<double> position{0.011, 0.023, -0.044};    ///< IMU origin in the sensor frame [m] (the Mid-360's)
  double time_offset_s = 0.0;         ///< IMU stamps minus true sample time [s], [-0.1, 0.1]

  void read(ConfigReader& r);
};

/// Small roll and pitch of the whole robot (floor roughness, motor vibration): two sinusoids,
/// roll = A sin(2 pi f t), pitch = A sin(2 pi 1.37 f t + 1). The LiDAR and the IMU see it;
/// ground truth (planar) does not.
struct VibrationParams {
  double amplitude_deg = 0.0;         ///< A [deg], [0, 5]; 0 = off
  double frequency_hz = 8.0;          ///< f [Hz], (0, 50]

  void read(ConfigReader& r);
};

/// UDP endpoints (all on this host in simulation).
struct NetParams {
  std::string host_ip = "127.0.0.1";  ///< where point and IMU packets go until a driver says otherwise
  int host_point_port = 56301;        ///< [1, 65535]
  int host_imu_port = 56401;
  std::string sensor_ip = "127.0.0.1";  ///< the address the emulated sensor binds and reports
  int discovery_port = 56000;         ///< sensor side: discovery requests arrive here
  int command_port = 56100;           ///< sensor side: set/query commands arrive here
  int point_src_port = 56300;         ///< sensor side: source port of point packets (0 = any)
  int imu_src_port = 56400;           ///< sensor side: source port of IMU packets (0 = any)
  std::string serial = "SIM360000000001";  ///< reported in discovery acks (<= 16 chars)

  void read(ConfigReader& r);
};

/// A further emulated Mid-360 on the same robot: the optics of `lidar` (rate, ranges, noise,
/// field of view), its own address, serial and mounting. It sends points only (its IMU is not
/// emulated; the driver publishes one sensor's IMU and turns the others' off).
struct ExtraLidarParams {
  std::string sensor_ip = "127.0.0.2";     ///< its address (bound for its control and data)
  std::string serial = "SIM360000000002";  ///< <= 16 characters
  std::vector<double> mount_xyz{0.0, 0.0, 0.5};       ///< [m] origin in the base frame
  std::vector<double> mount_rpy_deg{0.0, 0.0, 0.0};   ///< [deg] sensor->base roll, pitch, yaw
  int64_t seed = 2;                        ///< noise seed, >= 0

  void read(ConfigReader& r);
};

/// Everything the simulator node needs.
struct SimulatorParams {
  int64_t start_utime = 1000000;      ///< simulation epoch [us] (> 0): utime of simulation time 0
  double frame_rate_hz = 50.0;        ///< LiDAR frame rate (frame_cnt, SIM_GROUND_TRUTH) [Hz], [1, 100]
  double pose_rate_hz = 100.0;        ///< ROBOT_POSE rate [Hz], [1, 1000]
  double cmd_timeout_s = 0.5;         ///< wheels brake when no BASE_WHEEL_CMD for this long [s], (0, 10]
  double status_period_s = 1.0;       ///< SIM_STATUS period [s] (wall time), (0, 60]
  /// ROBOT_POSE source: "ground_truth" (the simulator publishes the exact pose) or "none"
  /// (it publishes none; the odometry does). SIM_GROUND_TRUTH is published either way.
  std::string pose_source = "ground_truth";
  LidarParams lidar;
  ImuParams imu;
  VibrationParams vibration;
  NetParams net;
  std::vector<ExtraLidarParams> extra_lidars;  ///< more Mid-360s (0 to 7); empty: one sensor
  /// Section `base`: geometry keys + motor_time_constant, max_wheel_accel; the ucon::mecanum
  /// defaults, except the motor limit of the shipped base.
  mecanum::MecanumPlantParams base = [] {
    mecanum::MecanumPlantParams b;
    b.geometry.max_wheel_speed = 50.0;  // [rad/s] 2.5 m/s at the rim
    return b;
  }();

  void read(ConfigReader& r);
  /// Empty if consistent, else the bad key and why.
  std::string validate() const;
};

}  // namespace simulator
}  // namespace ucon
