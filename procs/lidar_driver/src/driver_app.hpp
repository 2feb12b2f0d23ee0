#pragma once
// The three ways ucon-lidar-driver runs (process side: sockets, files, LCM, wall clock):
// live, --check and --pcap. main.cpp parses the flags and calls one of them.
#include <string>

#include "ucon/lidar_driver/driver_params.hpp"

namespace ucon {
namespace lidar_driver {

/// Finds and configures the sensors, then streams until SIGINT/SIGTERM. Returns the exit code
/// (1 when start-up fails or control.timeout_s > 0 passed with a sensor unconfigured).
int runLive(const DriverParams& params, const std::string& lcm_url);

/// Finds and configures the sensors, asks each for serial and firmware, measures point and IMU
/// rates over `seconds`, prints a report. 0 when every sensor answered and streamed, else 1
/// with the reasons. Gives up finding after `find_timeout_s`.
int runCheck(const DriverParams& params, double seconds, double find_timeout_s);

/// Plays a capture (pcap/pcapng) through the same parser and frame assembly and publishes as
/// live, paced at `speed` x the capture's time (0: as fast as possible).
int runPcap(const DriverParams& params, const std::string& lcm_url, const std::string& path,
            double speed);

}  // namespace lidar_driver
}  // namespace ucon
