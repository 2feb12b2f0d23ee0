#pragma once
/// @file logger_params.hpp
/// Parameters of the logger process (deploy/config/logger.yaml).

#include <cstdint>
#include <regex>
#include <string>

#include "ucon/config.hpp"

namespace ucon {
namespace logger {

struct LoggerParams {
  std::string include = ".*";       ///< ECMAScript regex of channels to record
  std::string exclude = "";         ///< regex of channels to leave out; empty = none
  std::string run_name = "run";     ///< file name prefix: <run_name>_<YYYYmmdd_HHMMSS>_<index>.lcm
  double max_file_mb = 1024.0;      ///< rotate when a file reaches this size [MiB], [1, 1e6]
  double max_file_s = 600.0;        ///< rotate after this long [s], [1, 1e6]
  double flush_interval_s = 0.5;    ///< fflush period [s], [0.01, 60]
  double min_free_mb = 512.0;       ///< stop writing when the disk has less free space [MiB], [0, 1e7]
  double queue_limit_mb = 512.0;    ///< writer queue bound [MiB]; beyond it messages are dropped and counted, [16, 16384]
  double status_period_s = 1.0;     ///< LOGGER_STATUS period [s], [0.1, 60]

  void read(ConfigReader& r) {
    r.read("include", include);
    r.read("exclude", exclude);
    r.read("run_name", run_name);
    r.read("max_file_mb", max_file_mb, 1.0, 1e6);
    r.read("max_file_s", max_file_s, 1.0, 1e6);
    r.read("flush_interval_s", flush_interval_s, 0.01, 60.0);
    r.read("min_free_mb", min_free_mb, 0.0, 1e7);
    r.read("queue_limit_mb", queue_limit_mb, 16.0, 16384.0);
    r.read("status_period_s", status_period_s, 0.1, 60.0);
    for (const auto* key : {"include", "exclude"}) {
      try {
        std::regex re(std::string(key) == std::string("include") ? include : exclude);
      } catch (const std::regex_error& e) {
        r.fail(key, std::string("not a valid regular expression: ") + e.what());
      }
    }
    if (run_name.empty() || run_name.find('/') != std::string::npos) {
      r.fail("run_name", "must be a non-empty file name without '/'");
    }
  }
};

}  // namespace logger
}  // namespace ucon
