#include "ucon/trajectory/piecewise_polynomial.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace trajectory {

const char* toString(TrajectoryStatus s) {
  switch (s) {
    case TrajectoryStatus::kOk: return "ok";
    case TrajectoryStatus::kNoPieces: return "no pieces";
    case TrajectoryStatus::kBadDimension: return "dimension not in [1, 3]";
    case TrajectoryStatus::kBadOrder: return "order1 out of range";
    case TrajectoryStatus::kSizeMismatch: return "array sizes inconsistent";
    case TrajectoryStatus::kNonFiniteCoefficient: return "non-finite coefficient";
    case TrajectoryStatus::kBadDuration: return "piece duration not finite or too short";
    case TrajectoryStatus::kTooLong: return "total duration too long";
    case TrajectoryStatus::kBadStartTime: return "start_utime not positive";
    case TrajectoryStatus::kOverflow: return "values overflow within a piece";
  }
  return "unknown";
}

namespace {
constexpr int64_t kMaxStartUtime = INT64_C(4000000000000000000);

TrajectoryStatus check(int64_t start_utime, int dim, int order1, const std::vector<double>& durations,
                       const std::vector<double>& coeffs) {
  if (start_utime <= 0 || start_utime > kMaxStartUtime) return TrajectoryStatus::kBadStartTime;
  if (dim < 1 || dim > 3) return TrajectoryStatus::kBadDimension;
  if (order1 < 1 || order1 > PiecewisePolynomial::kMaxOrder1) return TrajectoryStatus::kBadOrder;
  if (durations.empty()) return TrajectoryStatus::kNoPieces;
  const std::size_t expected = durations.size() * static_cast<std::size_t>(dim) *
                               static_cast<std::size_t>(order1);
  if (coeffs.size() != expected) return TrajectoryStatus::kSizeMismatch;
  double total = 0.0;
  for (double d : durations) {
    if (!std::isfinite(d) || !(d >= PiecewisePolynomial::kMinPieceDuration)) {
      return TrajectoryStatus::kBadDuration;
    }
    total += d;
  }
  if (!(total <= PiecewisePolynomial::kMaxTotalDuration)) return TrajectoryStatus::kTooLong;
  for (double c : coeffs) {
    if (!std::isfinite(c)) return TrajectoryStatus::kNonFiniteCoefficient;
  }
  // sum_j |c_j| j!/(j-m)! T^(j-m) bounds the m-th derivative (m = 0..3) and every Horner
  // intermediate on [0, T]: if the bounds are finite, sampling never overflows.
  const std::size_t dim_u = static_cast<std::size_t>(dim), n1 = static_cast<std::size_t>(order1);
  for (std::size_t k = 0; k < durations.size(); ++k) {
    const double T = durations[k];
    for (std::size_t d = 0; d < dim_u; ++d) {
      const double* c = &coeffs[(k * dim_u + d) * n1];
      for (std::size_t m = 0; m < 4; ++m) {
        double bound = 0.0;
        for (std::size_t jj = n1; jj-- > m;) {
          double falling = 1.0;  // j! / (j-m)!
          for (std::size_t q = 0; q < m; ++q) falling *= static_cast<double>(jj - q);
          bound = bound * T + falling * std::fabs(c[jj]);
        }
        if (!std::isfinite(bound)) return TrajectoryStatus::kOverflow;
      }
    }
  }
  return TrajectoryStatus::kOk;
}
}  // namespace

TrajectoryStatus PiecewisePolynomial::create(int64_t start_utime, int dim, int order1,
                                             std::vector<double> durations,
                                             std::vector<double> coeffs, PiecewisePolynomial* out) {
  const TrajectoryStatus s = check(start_utime, dim, order1, durations, coeffs);
  if (s != TrajectoryStatus::kOk || out == nullptr) return s;
  PiecewisePolynomial p;
  p.start_utime_ = start_utime;
  p.dim_ = dim;
  p.order1_ = order1;
  p.piece_start_.resize(durations.size());
  double acc = 0.0;
  for (std::size_t k = 0; k < durations.size(); ++k) {
    p.piece_start_[k] = acc;
    acc += durations[k];
  }
  p.total_ = acc;
  p.end_utime_ = start_utime + static_cast<int64_t>(std::llround(acc * 1e6));
  p.durations_ = std::move(durations);
  p.coeffs_ = std::move(coeffs);
  *out = std::move(p);
  return TrajectoryStatus::kOk;
}

TrajectoryStatus PiecewisePolynomial::validate(const ucon::trajectory_t& msg) {
  if (msg.num_pieces < 0 || static_cast<std::size_t>(msg.num_pieces) != msg.durations.size() ||
      msg.num_coeffs < 0 || static_cast<std::size_t>(msg.num_coeffs) != msg.coeffs.size()) {
    return TrajectoryStatus::kSizeMismatch;
  }
  return check(msg.start_utime, msg.dim, msg.order1, msg.durations, msg.coeffs);
}

TrajectoryStatus PiecewisePolynomial::fromMessage(const ucon::trajectory_t& msg,
                                                  PiecewisePolynomial* out) {
  const TrajectoryStatus s = validate(msg);
  if (s != TrajectoryStatus::kOk) return s;
  return create(msg.start_utime, msg.dim, msg.order1, msg.durations, msg.coeffs, out);
}

void PiecewisePolynomial::toMessage(ucon::trajectory_t* msg) const {
  if (msg == nullptr) return;
  msg->start_utime = start_utime_;
  msg->dim = static_cast<int8_t>(dim_);
  msg->order1 = static_cast<int8_t>(order1_);
  msg->num_pieces = static_cast<int32_t>(durations_.size());
  msg->durations = durations_;
  msg->num_coeffs = static_cast<int32_t>(coeffs_.size());
  msg->coeffs = coeffs_;
}

TrajectorySample PiecewisePolynomial::sample(int64_t utime) const {
  if (!valid()) return TrajectorySample{};
  if (utime <= start_utime_) return sampleRelative(0.0);
  if (utime >= end_utime_) return sampleRelative(total_);
  return sampleRelative(static_cast<double>(utime - start_utime_) * 1e-6);
}

TrajectorySample PiecewisePolynomial::sampleRelative(double t) const {
  TrajectorySample out;
  if (!valid()) return out;
  if (!(t > 0.0)) t = 0.0;  // also catches NaN
  if (t > total_) t = total_;
  out.t = t;
  // Last piece whose start is <= t.
  const auto it = std::upper_bound(piece_start_.begin(), piece_start_.end(), t);
  const std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - piece_start_.begin()) - 1));
  const double tau = std::clamp(t - piece_start_[k], 0.0, durations_[k]);
  for (int d = 0; d < dim_; ++d) {
    const double* c = &coeffs_[(k * static_cast<std::size_t>(dim_) + static_cast<std::size_t>(d)) *
                               static_cast<std::size_t>(order1_)];
    // Horner for the value and the first three derivatives (acc holds p''/2, jrk p'''/6).
    double pos = 0.0, vel = 0.0, acc = 0.0, jrk = 0.0;
    for (int j = order1_ - 1; j >= 0; --j) {
      jrk = jrk * tau + acc;
      acc = acc * tau + vel;
      vel = vel * tau + pos;
      pos = pos * tau + c[j];
    }
    out.position[d] = pos;
    out.velocity[d] = vel;
    out.acceleration[d] = 2.0 * acc;
    out.jerk[d] = 6.0 * jrk;
  }
  return out;
}

}  // namespace trajectory
}  // namespace ucon
