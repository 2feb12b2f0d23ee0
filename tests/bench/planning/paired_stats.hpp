#pragma once
/// @file paired_stats.hpp
/// Statistics of the planning benchmark's paired comparisons (issue 31): McNemar's test on
/// the discordant pairs of two methods solving the same problems, and Wilson intervals.

#include <cstdint>

namespace ucon::bench {

/// McNemar's test of two methods on the same n problems: `b` problems only the first method
/// solved, `c` only the second (the concordant pairs carry no information).
struct McNemar {
  int64_t b = 0, c = 0;
  double exact_p = 1.0;     ///< two-sided exact binomial p: min(1, 2 P[X <= min(b, c)]), X ~ Bin(b + c, 1/2)
  double chi2 = 0.0;        ///< (|b - c| - 1)^2 / (b + c), continuity-corrected (0 when b + c = 0)
  double chi2_p = 1.0;      ///< its p-value, chi-square with one degree of freedom
};
McNemar mcnemar(int64_t b, int64_t c);

/// Difference of two paired proportions (b - c) / n with its 95 % Wald interval
/// (b - c)/n -/+ 1.96 sqrt(b + c - (b - c)^2 / n) / n. n = 0 gives NaN.
struct PairedDifference {
  double diff = 0.0, lo = 0.0, hi = 0.0;
};
PairedDifference pairedDifference(int64_t b, int64_t c, int64_t n);

/// Wilson score 95 % interval of a proportion k / n (n = 0: NaN, NaN).
struct Interval {
  double lo = 0.0, hi = 0.0;
};
Interval wilson(int64_t k, int64_t n);

}  // namespace ucon::bench
