#pragma once
/// @file json_text.hpp
/// The two JSON spellings ucon-odom-eval and the odometry benchmark write by hand.

#include <cmath>
#include <cstdio>
#include <string>

namespace ucon {
namespace odometry {

/// A number with 6 significant digits; `null` for NaN or infinity.
inline std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6g", x);
  return buf;
}

/// A quoted string; quotes and backslashes escaped, control characters left out.
inline std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (static_cast<unsigned char>(c) < 0x20) continue;
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

}  // namespace odometry
}  // namespace ucon
