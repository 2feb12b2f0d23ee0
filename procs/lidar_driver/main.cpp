// ucon-lidar-driver: Livox Mid-360s over UDP -> LIDAR_POINTS, LIDAR_IMU, LIDAR_STATUS.
//
// The node (LidarDriverNode) holds the logic; driver_app.cpp moves bytes (live, --check, --pcap).
#include <CLI/CLI.hpp>

#include "src/driver_app.hpp"
#include "ucon/runtime/config_file.hpp"

int main(int argc, char** argv) {
  namespace ld = ucon::lidar_driver;
  CLI::App app{"Livox Mid-360 driver: finds and configures the sensors, then UDP point/IMU packets "
               "-> LIDAR_POINTS, LIDAR_IMU, LIDAR_STATUS."};
  std::string config_path, url, pcap;
  bool check = false;
  double check_s = 5.0, find_s = 15.0, speed = 1.0;
  app.add_option("--config", config_path, "YAML config (deploy/config/lidar_driver.yaml)")->required();
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_flag("--check", check,
               "find and configure the sensors, print serial, firmware, IP, time sync and point/IMU "
               "rates, exit non-zero with the reason when something is missing (no LCM)");
  app.add_option("--check-seconds", check_s, "--check: how long to measure the rates [s]")
      ->check(CLI::Range(0.5, 600.0));
  app.add_option("--find-timeout", find_s, "--check: give up finding the sensors after this [s]")
      ->check(CLI::Range(1.0, 3600.0));
  app.add_option("--pcap", pcap, "play a capture (deploy/ucon record-sensor) instead of the network");
  app.add_option("--speed", speed, "--pcap: playback speed, 1 = as captured, 0 = as fast as possible")
      ->check(CLI::Range(0.0, 1000.0));
  CLI11_PARSE(app, argc, argv);
  if (check && !pcap.empty()) {
    std::fprintf(stderr, "ucon-lidar-driver: --check and --pcap exclude each other\n");
    return 2;
  }

  const auto params = ucon::runtime::loadConfigFile<ld::DriverParams>("lidar_driver", config_path);
  if (!params) return 2;
  if (check) return ld::runCheck(*params, check_s, find_s);
  if (!pcap.empty()) return ld::runPcap(*params, url, pcap, speed);
  return ld::runLive(*params, url);
}
