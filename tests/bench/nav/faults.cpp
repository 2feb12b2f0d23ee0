#include "faults.hpp"

#include <cmath>
#include <cstdlib>
#include <regex>


namespace ucon::bench::nav {

namespace {

bool number(const std::string& key, const std::string& v, double lo, double hi, double* out, std::string* error) {
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || end == nullptr || *end != '\0' || !std::isfinite(x) || x < lo || x > hi) {
    *error = key + "=" + v + ": expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    return false;
  }
  *out = x;
  return true;
}

bool knownNode(const std::string& n) {
  return n == "perception" || n == "planner" || n == "base_controller" || n == "odometry";
}

}  // namespace

bool parseFaults(const std::string& spec, FaultSpec* out, std::string* error) {
  FaultSpec f;
  f.text = spec;
  if (spec.empty()) {
    *error = "empty fault list";
    return false;
  }
  std::size_t pos = 0;
  while (pos <= spec.size()) {
    const std::size_t comma = spec.find(',', pos);
    const std::string item = spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? spec.size() + 1 : comma + 1;
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      *error = "'" + item + "': expected key=value (drop, delay, jitter, channel, kill, restart)";
      return false;
    }
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    if (key == "drop") {
      if (!number(key, value, 0.0, 1.0, &f.drop, error)) return false;
    } else if (key == "delay") {
      if (!number(key, value, 0.0, 10000.0, &f.delay_ms, error)) return false;
    } else if (key == "jitter") {
      if (!number(key, value, 0.0, 10000.0, &f.jitter_ms, error)) return false;
    } else if (key == "channel") {
      try {
        std::regex re(value, std::regex::ECMAScript);
      } catch (const std::regex_error& e) {
        *error = "channel=" + value + ": not a regular expression (" + e.what() + ")";
        return false;
      }
      if (value.empty()) {
        *error = "channel=: empty pattern";
        return false;
      }
      f.channels = value;
    } else if (key == "kill") {
      const std::size_t at = value.find('@');
      FaultSpec::Kill k;
      k.node = value.substr(0, at);
      if (at == std::string::npos || !knownNode(k.node)) {
        *error = "kill=" + value + ": expected NODE@SECONDS, NODE one of perception, planner, base_controller, odometry";
        return false;
      }
      if (!number("kill", value.substr(at + 1), 0.0, 3600.0, &k.at_s, error)) return false;
      f.kills.push_back(k);
    } else if (key == "restart") {
      if (f.kills.empty() || f.kills.back().restart_s >= 0.0) {
        *error = "restart=" + value + ": must follow the kill=NODE@T it restarts";
        return false;
      }
      if (!number(key, value, 0.0, 3600.0, &f.kills.back().restart_s, error)) return false;
    } else {
      *error = "unknown fault '" + key + "' (drop, delay, jitter, channel, kill, restart)";
      return false;
    }
  }
  if (!f.any()) {
    *error = "'" + spec + "' injects no fault";
    return false;
  }
  *out = f;
  return true;
}

bool toBusFaults(const FaultSpec& spec, uint64_t seed, const std::function<int(const std::string&)>& node_index,
                 replay::BusFaults* out, std::string* error) {
  replay::BusFaults b;
  b.drop = spec.drop;
  b.delay_us = std::llround(spec.delay_ms * 1e3);
  b.jitter_us = std::llround(spec.jitter_ms * 1e3);
  b.channels = spec.channels;
  b.seed = seed;
  for (const auto& k : spec.kills) {
    const int i = node_index(k.node);
    if (i < 0) {
      *error = "kill=" + k.node + ": that node is not in this run";
      return false;
    }
    replay::BusFaults::Kill bk;
    bk.node = std::size_t(i);
    bk.at_us = std::llround(k.at_s * 1e6);
    bk.restart_after_us = k.restart_s < 0.0 ? -1 : std::llround(k.restart_s * 1e6);
    b.kills.push_back(bk);
  }
  b.restart = out->restart;  // set by the caller beforehand
  *out = b;
  return true;
}

}  // namespace ucon::bench::nav
