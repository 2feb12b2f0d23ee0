#pragma once
/// @file bench_util.hpp
/// Small helpers the benchmark programs share: comma lists and percentiles.

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace ucon {
namespace bench {

/// "50,80,110" -> {"50", "80", "110"}; empty items are skipped.
inline std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

/// Linear-interpolated percentile, q in [0, 1]; NaN for no samples.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace bench
}  // namespace ucon
