#include "paired_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ucon::bench {

McNemar mcnemar(int64_t b, int64_t c) {
  McNemar r;
  r.b = b;
  r.c = c;
  const int64_t n = b + c;
  if (n <= 0) return r;
  // P[X <= k] for X ~ Bin(n, 1/2), summed in log space (n may be thousands).
  const int64_t k = std::min(b, c);
  const double log_half_n = double(n) * std::log(0.5);
  double cdf = 0.0;
  for (int64_t i = 0; i <= k; ++i) {
    const double log_choose = std::lgamma(double(n) + 1.0) - std::lgamma(double(i) + 1.0) - std::lgamma(double(n - i) + 1.0);
    cdf += std::exp(log_choose + log_half_n);
  }
  r.exact_p = std::min(1.0, 2.0 * cdf);
  const double d = std::max(0.0, double(std::llabs(b - c)) - 1.0);
  r.chi2 = d * d / double(n);
  r.chi2_p = std::erfc(std::sqrt(0.5 * r.chi2));  // chi-square, 1 dof: P[Z^2 > x]
  return r;
}

PairedDifference pairedDifference(int64_t b, int64_t c, int64_t n) {
  PairedDifference r;
  if (n <= 0) {
    r.diff = r.lo = r.hi = NAN;
    return r;
  }
  const double nn = double(n);
  r.diff = double(b - c) / nn;
  const double var = std::max(0.0, double(b + c) - double(b - c) * double(b - c) / nn);
  const double half = 1.96 * std::sqrt(var) / nn;
  r.lo = r.diff - half;
  r.hi = r.diff + half;
  return r;
}

Interval wilson(int64_t k, int64_t n) {
  Interval r;
  if (n <= 0) {
    r.lo = r.hi = NAN;
    return r;
  }
  const double z = 1.96, nn = double(n), p = double(k) / nn;
  const double den = 1.0 + z * z / nn;
  const double centre = (p + z * z / (2.0 * nn)) / den;
  const double half = z * std::sqrt(p * (1.0 - p) / nn + z * z / (4.0 * nn * nn)) / den;
  r.lo = std::max(0.0, centre - half);
  r.hi = std::min(1.0, centre + half);
  return r;
}

}  // namespace ucon::bench
