// ucon-bench-minco: time of one evaluation of the MINCO sequence an optimiser runs per cost
// evaluation (set inner waypoints and durations, energy, energy gradients with respect to the
// coefficients and durations, propagation of those gradients to the waypoints, durations and
// tail position) for ucon::minco::MinimumJerk2D and for a straightforward dense reference
// (tests/minco/dense_minimum_jerk.hpp: the 6N x 6N system solved with Eigen's LU), at
// N = 4, 8, 16, 32 pieces. Both run interleaved in one process on the same random problems
// (durations 0.4-2 s, waypoints about 1.5 m apart); each repetition times a batch of each,
// and the figures are medians over repetitions. Every output of MinimumJerk2D is checked
// against the dense reference (max |difference| / max |reference| per output, at most 1e-12).
//
// The load average (/proc/loadavg) before and after is printed and written to the JSON: on a
// shared machine the wall times are only comparable between runs under similar load.
//
//   ucon-bench-minco [--pieces 4,8,16,32] [--reps R] [--problems P] [--seed S] [--quick]
//                    [--json FILE]
//   ucon-bench-minco --count N --reps R    (MinimumJerk2D only, no timing, for callgrind:
//       valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*countOurs*' ...;
//       instructions per evaluation = Ir / (R x problems))
//
// --quick: correctness check and a few repetitions (for ctest); the exit status is non-zero
// only when the two implementations disagree, never because of a timing.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "dense_minimum_jerk.hpp"
#include "ucon/minco/minimum_jerk.hpp"

namespace {

using ucon::minco::MinimumJerk2D;
using ucon::minco::testing::DenseMinimumJerk2D;
using ucon::minco::testing::MincoSequenceResult;
using ucon::minco::testing::relativeDifference;

constexpr double kTolerance = 1e-12;

struct Problem {
  MinimumJerk2D::Boundary head, tail;
  Eigen::Matrix2Xd inner;
  Eigen::VectorXd T;
};

// A path that wanders forward: waypoints about 1.5 m apart, durations 0.4-2 s, moving ends.
Problem randomProblem(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), ut(0.4, 2.0);
  Problem p;
  Eigen::Vector2d at(u(rng), u(rng));
  p.head.col(0) = at;
  p.head.col(1) << u(rng), u(rng);
  p.head.col(2) << u(rng), u(rng);
  p.inner.resize(2, n - 1);
  for (int i = 0; i + 1 < n; ++i) {
    at += Eigen::Vector2d(1.5 + 0.5 * u(rng), 0.8 * u(rng));
    p.inner.col(i) = at;
  }
  at += Eigen::Vector2d(1.5 + 0.5 * u(rng), 0.8 * u(rng));
  p.tail.col(0) = at;
  p.tail.col(1) << u(rng), u(rng);
  p.tail.col(2) << u(rng), u(rng);
  p.T.resize(n);
  for (int i = 0; i < n; ++i) p.T(i) = ut(rng);
  return p;
}

// The optimiser's per-evaluation buffers for MinimumJerk2D, allocated once.
struct OursBuffers {
  Eigen::MatrixXd gC;
  Eigen::VectorXd gT, g_durations;
  Eigen::Matrix2Xd g_inner;
  Eigen::Vector2d g_tail;
  explicit OursBuffers(int n) : gC(6 * n, 2), gT(n), g_durations(n), g_inner(2, n - 1) {}
};

// One evaluation of the sequence; returns the energy (kept so the work cannot be elided).
// g_tail: also the gradient with respect to the tail position (the planner does not ask).
double runOurs(MinimumJerk2D& mj, const Problem& p, OursBuffers& b, Eigen::Vector2d* g_tail) {
  if (!mj.setParameters(p.inner, p.T)) return 0.0;
  const double e = mj.energy();
  b.gC.setZero();
  b.gT.setZero();
  mj.addEnergyGradient(b.gC, b.gT);
  mj.propagateGradient(b.gC, b.gT, b.g_inner, b.g_durations, g_tail);
  return e;
}

struct Row {
  int pieces = 0;
  double ours_ns = 0.0, dense_ns = 0.0;
  double max_rel_diff = 0.0;
  int reps = 0;
};

// The three load averages of /proc/loadavg ("" where it cannot be read).
std::string loadAverage() {
  std::ifstream f("/proc/loadavg");
  double a = 0.0, b = 0.0, c = 0.0;
  if (!(f >> a >> b >> c)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f %.2f %.2f", a, b, c);
  return buf;
}

double nowNs() {
  return static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                 std::chrono::steady_clock::now().time_since_epoch())
                                 .count());
}

// Largest relative difference of every output over all problems (and whether all solved).
double checkAgreement(const std::vector<Problem>& problems, int n, bool* ok) {
  MinimumJerk2D mj;
  DenseMinimumJerk2D dense;
  OursBuffers b(n);
  double worst = 0.0;
  for (const Problem& p : problems) {
    MincoSequenceResult ref;
    if (!mj.setConditions(p.head, p.tail, n) || !dense.evaluate(p.head, p.tail, p.inner, p.T, &ref)) {
      *ok = false;
      continue;
    }
    const double e = runOurs(mj, p, b, &b.g_tail);
    worst = std::max(worst, relativeDifference(mj.coeffs(), ref.coeffs));
    worst = std::max(worst, std::abs(e - ref.energy) / std::abs(ref.energy));
    if (n > 1) worst = std::max(worst, relativeDifference(b.g_inner, ref.g_inner));
    worst = std::max(worst, relativeDifference(b.g_durations, ref.g_durations));
    worst = std::max(worst, relativeDifference(b.g_tail, ref.g_tail));
  }
  return worst;
}

Row measure(int n, int problems, int reps, unsigned seed) {
  std::mt19937 rng(seed + 1000u * static_cast<unsigned>(n));
  std::vector<Problem> ps;
  for (int k = 0; k < problems; ++k) ps.push_back(randomProblem(n, rng));

  Row row;
  row.pieces = n;
  row.reps = reps;
  bool ok = true;
  row.max_rel_diff = checkAgreement(ps, n, &ok);
  if (!ok) row.max_rel_diff = INFINITY;

  // All problems share head and tail here, as in one optimisation: set the conditions once.
  MinimumJerk2D mj;
  mj.setConditions(ps[0].head, ps[0].tail, n);
  OursBuffers b(n);
  DenseMinimumJerk2D dense;
  MincoSequenceResult ref;
  // A batch is one pass over the problems for MinimumJerk2D (tens of us: long against the
  // clock's cost, short enough to be rarely preempted on a loaded machine) and one problem,
  // in turn, for the dense reference.
  std::vector<double> ours, dns;
  volatile double sink = 0.0;
  for (int r = 0; r < reps; ++r) {
    // The order alternates, so that neither side always runs on a cache the other warmed.
    for (int half = 0; half < 2; ++half) {
      if ((half + r) % 2 == 0) {
        const double t0 = nowNs();
        double acc = 0.0;
        for (const Problem& p : ps) acc += runOurs(mj, p, b, nullptr);
        const double t1 = nowNs();
        ours.push_back((t1 - t0) / static_cast<double>(ps.size()));
        sink = sink + acc;
      } else {
        const Problem& p = ps[static_cast<std::size_t>(r) % ps.size()];
        const double t0 = nowNs();
        dense.evaluate(p.head, p.tail, p.inner, p.T, &ref);
        const double t1 = nowNs();
        dns.push_back(t1 - t0);
        sink = sink + ref.energy;
      }
    }
  }
  row.ours_ns = ucon::bench::percentile(ours, 0.5);
  row.dense_ns = ucon::bench::percentile(dns, 0.5);
  return row;
}

// MinimumJerk2D only, `reps` passes over the problems (callgrind counts this function).
__attribute__((noinline)) double countOurs(int n, int problems, int reps, unsigned seed) {
  std::mt19937 rng(seed + 1000u * static_cast<unsigned>(n));
  std::vector<Problem> ps;
  for (int k = 0; k < problems; ++k) ps.push_back(randomProblem(n, rng));
  MinimumJerk2D mj;
  mj.setConditions(ps[0].head, ps[0].tail, n);
  OursBuffers b(n);
  double acc = 0.0;
  for (int r = 0; r < reps; ++r)
    for (const Problem& p : ps) acc += runOurs(mj, p, b, nullptr);
  return acc;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ucon-bench-minco: MinimumJerk2D against a dense reference, ns per evaluation"};
  std::string pieces_list = "4,8,16,32", json_path;
  int reps = 1001, problems = 16;
  unsigned seed = 1;
  bool quick = false;
  app.add_option("--pieces", pieces_list, "comma list of piece counts N");
  app.add_option("--reps", reps, "timed repetitions (medians over these)")->check(CLI::PositiveNumber);
  app.add_option("--problems", problems, "random problems per N")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "seed of the random problems");
  app.add_flag("--quick", quick, "correctness check and 3 repetitions (for ctest)");
  app.add_option("--json", json_path, "write the results as JSON to this file");
  int count = 0;
  app.add_option("--count", count, "MinimumJerk2D only at this N, untimed (for callgrind)")
      ->check(CLI::Range(1, 1000));
  CLI11_PARSE(app, argc, argv);
  if (quick) reps = 3;
  if (count > 0) {
    // The problems are built inside countOurs; callgrind's count includes that set-up
    // (below 1 % at the default sizes, once per run, not per evaluation).
    const double acc = countOurs(count, problems, reps, seed);
    std::printf("MinimumJerk2D N=%d: %d evaluations (%g)\n", count, problems * reps, acc);
    return 0;
  }
  const std::string load_before = loadAverage();

  std::vector<Row> rows;
  for (const std::string& s : ucon::bench::split(pieces_list)) {
    const int n = std::atoi(s.c_str());
    if (n < 1 || n > 1000) {
      std::fprintf(stderr, "bench-minco: bad piece count '%s' (1..1000)\n", s.c_str());
      return 2;
    }
    rows.push_back(measure(n, problems, reps, seed));
  }

  const std::string load_after = loadAverage();
  std::printf("MINCO s=3, 2-D: set waypoints+durations, energy, energy gradients, propagation\n");
  std::printf("%d problems per N, %d interleaved repetitions, medians (ns per evaluation)\n",
              problems, reps);
  std::printf("load average before: %s, after: %s\n", load_before.c_str(), load_after.c_str());
  std::printf("%6s %14s %14s %12s %14s\n", "N", "MinimumJerk2D", "dense ref", "dense/ours", "max rel diff");
  bool agree = true;
  for (const Row& r : rows) {
    std::printf("%6d %14.0f %14.0f %12.1f %14.2e\n", r.pieces, r.ours_ns, r.dense_ns,
                r.dense_ns / r.ours_ns, r.max_rel_diff);
    agree = agree && r.max_rel_diff <= kTolerance;
  }
  std::printf("agreement with the dense reference (<= %.0e relative): %s\n", kTolerance,
              agree ? "yes" : "NO");

  if (!json_path.empty()) {
    std::ofstream js(json_path);
    js << "{\"benchmark\": \"minco\", \"sequence\": \"setParameters, energy, addEnergyGradient, "
          "propagateGradient\", \"problems\": "
       << problems << ", \"reps\": " << reps << ", \"seed\": " << seed
       << ", \"tolerance\": " << kTolerance << ", \"agree\": " << (agree ? "true" : "false")
       << ", \"loadavg_before\": \"" << load_before << "\", \"loadavg_after\": \"" << load_after
       << "\""
       << ", \"results\": [";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "%s{\"pieces\": %d, \"ours_ns_median\": %.1f, \"dense_ns_median\": %.1f, "
                    "\"ratio_dense_over_ours\": %.2f, \"max_rel_diff\": %.3e}",
                    i ? ", " : "", r.pieces, r.ours_ns, r.dense_ns, r.dense_ns / r.ours_ns,
                    std::isfinite(r.max_rel_diff) ? r.max_rel_diff : 1e300);
      js << buf;
    }
    js << "]}\n";
    if (!js) {
      std::fprintf(stderr, "bench-minco: cannot write '%s'\n", json_path.c_str());
      return 2;
    }
  }
  return agree ? 0 : 1;
}
