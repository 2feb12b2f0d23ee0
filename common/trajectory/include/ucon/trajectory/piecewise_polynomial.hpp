#pragma once
/// @file piecewise_polynomial.hpp
/// Piecewise-polynomial trajectory in the ucon::trajectory_t format (a MINCO solution):
/// piece k covers [T_k, T_k + durations[k]] with T_k = start + sum of the earlier durations,
/// and in local time t in [0, durations[k]] axis d is sum_j coeffs[(k*dim + d)*order1 + j] t^j
/// (piece-major, then axis, then ascending power).

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "ucon/trajectory_t.hpp"

namespace ucon {
namespace trajectory {

/// Why a trajectory is not usable.
enum class TrajectoryStatus {
  kOk,
  kNoPieces,             ///< num_pieces == 0
  kBadDimension,         ///< dim not in [1, 3]
  kBadOrder,             ///< order1 not in [1, kMaxOrder1]
  kSizeMismatch,         ///< num_pieces/num_coeffs/array sizes disagree
  kNonFiniteCoefficient, ///< a coefficient is NaN or Inf
  kBadDuration,          ///< a duration is NaN, Inf, <= 0 or shorter than kMinPieceDuration
  kTooLong,              ///< total duration above kMaxTotalDuration
  kBadStartTime,         ///< start_utime <= 0
  kOverflow,             ///< finite coefficients whose values or derivatives overflow within a piece
};

/// Human-readable name, e.g. "non-finite coefficient".
const char* toString(TrajectoryStatus s);

/// Value, first, second and third derivative of the trajectory at one time. Axes beyond dim
/// are 0.
struct TrajectorySample {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      ///< [m]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< [m/s]
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  ///< [m/s^2]
  Eigen::Vector3d jerk = Eigen::Vector3d::Zero();          ///< [m/s^3]
  double t = 0.0;  ///< time since start_utime after clamping to [0, duration] [s]
};

/// Validated, immutable piecewise polynomial. A default-constructed one is empty (valid() is
/// false) and samples as zero.
class PiecewisePolynomial {
 public:
  static constexpr double kMinPieceDuration = 1e-3;  ///< shortest accepted piece [s]
  static constexpr double kMaxTotalDuration = 1e5;   ///< longest accepted trajectory [s]
  static constexpr int kMaxOrder1 = 16;              ///< most coefficients per axis and piece

  PiecewisePolynomial() = default;

  /// Builds from raw arrays (layout as in trajectory_t). On failure `out` is left unchanged.
  static TrajectoryStatus create(int64_t start_utime, int dim, int order1,
                                 std::vector<double> durations, std::vector<double> coeffs,
                                 PiecewisePolynomial* out);

  /// Checks a message without building anything.
  static TrajectoryStatus validate(const ucon::trajectory_t& msg);

  /// Builds from a message (start_utime, dim, order1, durations, coeffs; the other fields are
  /// the caller's). On failure `out` is left unchanged.
  static TrajectoryStatus fromMessage(const ucon::trajectory_t& msg, PiecewisePolynomial* out);

  /// Writes start_utime, dim, order1, num_pieces, durations, num_coeffs and coeffs into `msg`;
  /// leaves utime, seq, plan_id, goal_id, status, message and yaw as they are.
  void toMessage(ucon::trajectory_t* msg) const;

  /// Samples at absolute time `utime` [us]; times before the start or after the end are
  /// clamped to the ends (so the velocity there is the end velocity of the polynomial).
  TrajectorySample sample(int64_t utime) const;
  /// Samples at `t` seconds after start_utime, clamped to [0, duration()].
  TrajectorySample sampleRelative(double t) const;

  /// Position only, at absolute time [us] (clamped) [m].
  Eigen::Vector3d position(int64_t utime) const { return sample(utime).position; }
  /// Velocity only, at absolute time [us] (clamped) [m/s].
  Eigen::Vector3d velocity(int64_t utime) const { return sample(utime).velocity; }

  bool valid() const { return !durations_.empty(); }
  int64_t startUtime() const { return start_utime_; }
  /// start + total duration, rounded to the microsecond [us].
  int64_t endUtime() const { return end_utime_; }
  /// Sum of the piece durations [s].
  double duration() const { return total_; }
  int dim() const { return dim_; }
  int order1() const { return order1_; }
  int numPieces() const { return static_cast<int>(durations_.size()); }
  const std::vector<double>& durations() const { return durations_; }
  const std::vector<double>& coeffs() const { return coeffs_; }

 private:
  int64_t start_utime_ = 0;
  int64_t end_utime_ = 0;
  int dim_ = 0;
  int order1_ = 0;
  double total_ = 0.0;
  std::vector<double> durations_;
  std::vector<double> piece_start_;  // start of each piece relative to start_utime_ [s]
  std::vector<double> coeffs_;
};

}  // namespace trajectory
}  // namespace ucon
