#pragma once
/// @file status_report.hpp
/// Collects a node's counters, per-stage timings and gauges and turns them into the
/// ucon::process_status_t that every process publishes on its <NAME>_STATUS channel.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ucon/process_status_t.hpp"

namespace ucon {

/// Counters (totals), timings (median and max per period) and gauges of one process.
/// Names are kept in insertion order so messages are deterministic.
class StatusReport {
 public:
  explicit StatusReport(std::string process_name) : name_(std::move(process_name)) {}

  /// Adds `n` to counter `name` (created at 0).
  void count(const std::string& name, int64_t n = 1);
  /// Sets counter `name` to an absolute total.
  void setCounter(const std::string& name, int64_t total);
  /// Current total of counter `name` (0 if never counted).
  int64_t counter(const std::string& name) const;
  /// Records one duration of stage `name` [ms].
  void time(const std::string& name, double ms);
  /// Sets gauge `name` to `value`.
  void set(const std::string& name, double value);
  /// Health reported with the next message.
  void setHealth(int8_t health, const std::string& message);

  /// Builds the message (timings over the samples since the last call) and clears the
  /// timing samples. `utime` is the node's message time, `wall_utime` the wall clock.
  process_status_t build(int64_t utime, int64_t wall_utime);

  const std::string& name() const { return name_; }

 private:
  template <class T>
  struct Ordered {
    std::vector<std::string> names;
    std::map<std::string, T> values;
    T& at(const std::string& k) {
      auto it = values.find(k);
      if (it == values.end()) {
        names.push_back(k);
        return values[k];
      }
      return it->second;
    }
  };
  std::string name_;
  Ordered<int64_t> counters_;
  Ordered<std::vector<double>> timings_;
  Ordered<double> gauges_;
  int8_t health_ = process_status_t::HEALTH_OK;
  std::string message_;
  int64_t seq_ = 0;
};

/// Median of `v` (reorders it); NaN for an empty vector.
double medianInPlace(std::vector<double>& v);

}  // namespace ucon
