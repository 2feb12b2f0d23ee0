#pragma once
/// @file driver_params.hpp
/// Parameters of the lidar driver; deploy/config/lidar_driver.yaml maps one-to-one onto them.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ucon/config.hpp"

namespace ucon {
namespace lidar_driver {

/// Host address and UDP ports. Host ports are what the driver binds; sensor ports are where it
/// sends commands and where the sensor's data comes from. Defaults are the Mid-360's.
struct NetworkParams {
  std::string host_ip = "127.0.0.1";  ///< host interface the sensors send to (IPv4)
  bool discovery = true;              ///< broadcast discovery first (every retry_interval_s until
                                      ///< every sensor answered); false: command the IPs directly
  std::string discovery_address = "255.255.255.255";  ///< where discovery requests go (IPv4)
  int discovery_port = 56000;         ///< [1, 65535] the sensors' discovery port; the host sends
                                      ///< from and listens (on 0.0.0.0) on the same port
  int sensor_command_port = 56100;    ///< [1, 65535] (a discovery answer overrides it)
  int sensor_push_port = 56200;       ///< [1, 65535] source port of the sensor's status pushes
  int sensor_point_port = 56300;      ///< [1, 65535] source port of point packets
  int sensor_imu_port = 56400;        ///< [1, 65535] source port of IMU packets
  int host_command_port = 56101;      ///< [1, 65535]
  int host_push_port = 56201;         ///< [1, 65535] where the sensor pushes its status
  int host_point_port = 56301;        ///< [1, 65535]
  int host_imu_port = 56401;          ///< [1, 65535]
  int socket_buffer_bytes = 8 << 20;  ///< [bytes] [65536, 1 GiB] SO_RCVBUF asked for
  void read(ConfigReader& r);
};

/// The control path: find and configure every sensor before (and while) reading data.
struct ControlParams {
  bool enabled = true;             ///< false: only listen (sensors configured elsewhere, a replay)
  double timeout_s = 0.0;          ///< [s] [0, 3600] 0: retry without end (the status says what
                                   ///< the driver waits for); > 0: give up (exit 1) after this
  double retry_interval_s = 1.0;   ///< [s] [0.01, 10] resend an unanswered request
  std::string work_mode = "sampling";  ///< sampling | idle (the Mid-360's settable modes)
  int point_data_type = 1;         ///< [1, 3] record type asked for: 1 Cartesian mm (the
                                   ///< Mid-360's full resolution), 2 Cartesian cm, 3 spherical
  bool reset_install_attitude = true;  ///< set the sensor's own attitude (key 0x0012) to zero at
                                       ///< start: the extrinsic below is applied here, once
  double reconfigure_after_s = 3.0;  ///< [s] [0.5, 60] a configured sensor silent this long is
                                     ///< found and configured again (it rebooted)
  void read(ConfigReader& r);
};

/// Frame assembly.
struct FrameParams {
  int rate_hz = 50;            ///< [Hz] 10, 20 or 50: frames cut on sensor-time boundaries
  int max_points = 200000;     ///< [points] [1000, 2000000] points beyond this are dropped
  double idle_flush_s = 0.2;   ///< [s] [0.01, 10] publish pending frames when no packet came
                               ///< for this long (wall clock, process side only)
  bool apply_extrinsic = true;  ///< false: publish in the sensor frame ("lidar"; one sensor only)
  double merge_wait_s = 0.05;  ///< [s] [0, 1] several sensors: a frame waits for a sensor that
                               ///< lags the others by up to this (sensor time), then goes without
  void read(ConfigReader& r);
};

/// Point filters (applied in the sensor frame, before the extrinsic).
struct FilterParams {
  double min_range_m = 0.1;   ///< [m] [0, 1000] closer points (and 0,0,0 "no return") dropped
  double max_range_m = 70.0;  ///< [m] [0.1, 1000] farther points dropped
  /// Mid-360 tag confidences (2 bits each, 0 = a normal point, 1-3 = flagged): drop a point
  /// whose field is >= the level; 0 keeps all. Level 1 drops every flagged point.
  int drop_sticking_level = 0;       ///< [0, 3] tag bits 0-1: between two nearby objects
  int drop_rain_fog_dust_level = 0;  ///< [0, 3] tag bits 2-3: rain, fog, dust
  int drop_other_noise_level = 0;    ///< [0, 3] tag bits 4-5: other noise
  void read(ConfigReader& r);
};

/// One Mid-360 on the robot.
struct SensorParams {
  std::string ip = "127.0.0.1";   ///< the sensor's IPv4 (factory 192.168.1.1XX, XX the serial's
                                  ///< last two digits); "auto": the first Mid-360 that answers
                                  ///< discovery (or, without control, that sends data)
  /// [m] sensor origin in the body frame, each in [-10, 10]; the shipped mount: 0.5 m above
  /// the base origin
  std::vector<double> xyz = {0.0, 0.0, 0.5};
  /// [deg] roll, pitch, yaw (R = Rz Ry Rx), each in [-360, 360], p_base = R p_sensor + xyz;
  /// the shipped mount: upside down
  std::vector<double> rpy_deg = {180.0, 0.0, 0.0};
  bool imu = true;                ///< publish this sensor's IMU on LIDAR_IMU (at most one sensor);
                                  ///< the others are told not to send IMU packets
  void read(ConfigReader& r);
  bool isAuto() const { return ip == "auto"; }
};

/// Everything the driver reads from its YAML file.
struct DriverParams {
  NetworkParams network;
  ControlParams control;
  FrameParams frame;
  FilterParams filter;
  std::vector<SensorParams> sensors{SensorParams{}};  ///< 1 to 8 sensors
  double status_period_s = 1.0;  ///< [s] [0.1, 60] LIDAR_STATUS period (wall clock)
  void read(ConfigReader& r);
};

/// The sensor id carried in point_cloud_t: the IPv4 address as an integer (0 = unknown).
int64_t sensorIdOf(const std::array<uint8_t, 4>& ip);

}  // namespace lidar_driver
}  // namespace ucon
