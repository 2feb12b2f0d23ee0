#pragma once
/// @file driver_params.hpp
/// Parameters of the lidar driver; deploy/config/lidar_driver.yaml maps one-to-one onto them.

#include <string>
#include <vector>

#include "ucon/config.hpp"

namespace ucon {
namespace lidar_driver {

/// Addresses and UDP ports. Host ports are what the driver binds; sensor ports are where it
/// sends commands. Defaults are the Mid-360's (its ports and addresses: docs/reference.md).
struct NetworkParams {
  std::string host_ip = "127.0.0.1";    ///< host interface the sensor sends to (IPv4)
  std::string sensor_ip = "127.0.0.1";  ///< sensor address when discovery is off; only datagrams
                                        ///< from the sensor are used (0.0.0.0: any source)
  bool discovery = false;               ///< find the sensor by a discovery broadcast first
  std::string discovery_address = "255.255.255.255";  ///< where discovery requests go (IPv4)
  int sensor_discovery_port = 56000;    ///< [1, 65535]
  int sensor_command_port = 56100;      ///< [1, 65535] (a discovery ack overrides it)
  int sensor_point_port = 56300;        ///< [1, 65535] source port of point packets
  int sensor_imu_port = 56400;          ///< [1, 65535] source port of IMU packets
  int host_command_port = 56101;        ///< [1, 65535]
  int host_point_port = 56301;          ///< [1, 65535]
  int host_imu_port = 56401;            ///< [1, 65535]
  int socket_buffer_bytes = 8 << 20;    ///< [bytes] [65536, 1 GiB] SO_RCVBUF asked for
  void read(ConfigReader& r);
};

/// The control path: configure the sensor before reading data.
struct ControlParams {
  bool enabled = true;           ///< false: only listen (sensor configured elsewhere)
  double timeout_s = 5.0;        ///< [s] (0, 120] give up (non-zero exit) after this
  double retry_interval_s = 0.5; ///< [s] [0.01, 10] resend an unanswered request
  std::string work_mode = "normal";  ///< normal | sleep
  bool imu_enabled = true;       ///< ask the sensor to send IMU packets
  void read(ConfigReader& r);
};

/// Frame assembly.
struct FrameParams {
  int rate_hz = 50;            ///< [Hz] 10, 20 or 50: frames cut on sensor-time boundaries
  int max_points = 200000;     ///< [points] [1000, 2000000] points beyond this are dropped
  double idle_flush_s = 0.2;   ///< [s] [0.01, 10] publish a pending frame when no packet came
                               ///< for this long (wall clock, process side only)
  void read(ConfigReader& r);
};

/// Sensor pose in the robot body frame: p_base = R(rpy) * p_lidar + xyz.
struct ExtrinsicParams {
  bool apply = true;                       ///< false: publish in the sensor frame ("lidar")
  /// [m] translation, each in [-10, 10]; the shipped mount: 0.5 m above the base origin
  std::vector<double> xyz = {0.0, 0.0, 0.5};
  /// [deg] roll, pitch, yaw (R = Rz Ry Rx), each in [-360, 360]; the shipped mount: upside down
  std::vector<double> rpy_deg = {180.0, 0.0, 0.0};
  void read(ConfigReader& r);
};

/// Point filters (applied in the sensor frame, before the extrinsic).
struct FilterParams {
  double min_range_m = 0.1;   ///< [m] [0, 1000] closer points (and 0,0,0 "no return") dropped
  double max_range_m = 70.0;  ///< [m] [0.1, 1000] farther points dropped
  int tag_drop_mask = 0;      ///< [0, 255] drop a point when (tag & mask) != 0; 0 = keep all.
                              ///< Tag bits 0-1 spatial, 2-3 intensity, 4-5 return confidence.
  void read(ConfigReader& r);
};

/// Everything the driver reads from its YAML file.
struct DriverParams {
  NetworkParams network;
  ControlParams control;
  FrameParams frame;
  ExtrinsicParams extrinsic;
  FilterParams filter;
  double status_period_s = 1.0;  ///< [s] [0.1, 60] LIDAR_STATUS period (wall clock)
  void read(ConfigReader& r);
};

}  // namespace lidar_driver
}  // namespace ucon
