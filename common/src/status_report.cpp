#include "ucon/status_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ucon {

double medianInPlace(std::vector<double>& v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  double m = v[mid];
  if (v.size() % 2 == 0) {
    m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + mid));
  }
  return m;
}

void StatusReport::count(const std::string& name, int64_t n) { counters_.at(name) += n; }

void StatusReport::setCounter(const std::string& name, int64_t total) {
  counters_.at(name) = total;
}

int64_t StatusReport::counter(const std::string& name) const {
  auto it = counters_.values.find(name);
  return it == counters_.values.end() ? 0 : it->second;
}

void StatusReport::time(const std::string& name, double ms) { timings_.at(name).push_back(ms); }

void StatusReport::set(const std::string& name, double value) { gauges_.at(name) = value; }

void StatusReport::setHealth(int8_t health, const std::string& message) {
  health_ = health;
  message_ = message;
}

process_status_t StatusReport::build(int64_t utime, int64_t wall_utime) {
  process_status_t m;
  m.utime = utime;
  m.seq = seq_++;
  m.wall_utime = wall_utime;
  m.name = name_;
  m.health = health_;
  m.message = message_;
  for (const auto& n : counters_.names) {
    m.counter_names.push_back(n);
    m.counter_values.push_back(counters_.values[n]);
  }
  m.num_counters = static_cast<int32_t>(m.counter_names.size());
  for (const auto& n : timings_.names) {
    auto& samples = timings_.values[n];
    m.timing_names.push_back(n);
    m.timing_max_ms.push_back(samples.empty() ? std::numeric_limits<double>::quiet_NaN()
                                              : *std::max_element(samples.begin(), samples.end()));
    m.timing_median_ms.push_back(medianInPlace(samples));
    samples.clear();
  }
  m.num_timings = static_cast<int32_t>(m.timing_names.size());
  for (const auto& n : gauges_.names) {
    m.value_names.push_back(n);
    m.values.push_back(gauges_.values[n]);
  }
  m.num_values = static_cast<int32_t>(m.value_names.size());
  return m;
}

}  // namespace ucon
