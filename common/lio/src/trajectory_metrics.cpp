#include "ucon/lio/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ucon {
namespace lio {

namespace {
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  const double hi = *mid;
  const double lo = *std::max_element(v.begin(), mid);
  return 0.5 * (lo + hi);
}

double mean(const std::vector<double>& v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double angleOf(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }
}  // namespace

std::optional<Eigen::Isometry3d> interpolatePose(const std::vector<TimedPose>& tr, int64_t utime, int64_t max_gap_us) {
  if (tr.empty() || utime < tr.front().utime || utime > tr.back().utime) return std::nullopt;
  const auto it = std::lower_bound(tr.begin(), tr.end(), utime,
                                   [](const TimedPose& p, int64_t t) { return p.utime < t; });
  if (it->utime == utime) return it->T;
  const TimedPose& b = *it;
  const TimedPose& a = *(it - 1);
  if (b.utime - a.utime > max_gap_us) return std::nullopt;
  const double s = static_cast<double>(utime - a.utime) / static_cast<double>(b.utime - a.utime);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(a.T.linear()).slerp(s, Eigen::Quaterniond(b.T.linear())).toRotationMatrix();
  T.translation() = (1.0 - s) * a.T.translation() + s * b.T.translation();
  return T;
}

TrajectoryErrors evaluateTrajectory(const std::vector<TimedPose>& truth, const std::vector<TimedPose>& estimate,
                                    const MetricsOptions& o) {
  TrajectoryErrors e;
  e.truth_poses = static_cast<int>(truth.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Eigen::Isometry3d> G, S;
  for (const TimedPose& g : truth) {
    const auto s = interpolatePose(estimate, g.utime, o.max_gap_us);
    if (!s) continue;
    G.push_back(g.T);
    S.push_back(*s);
  }
  e.matched = static_cast<int>(G.size());
  if (G.empty()) {
    e.rpe_translation_pct = e.rpe_translation_pct_median = e.rpe_translation_pct_max = nan;
    e.rpe_rotation_deg_per_10m = e.rpe_rotation_deg_per_10m_median = nan;
    e.ate_rmse_m = e.ate_max_m = e.final_drift_m = e.final_drift_pct = e.final_yaw_error_deg = nan;
    return e;
  }
  std::vector<double> dist(G.size(), 0.0);
  for (std::size_t i = 1; i < G.size(); ++i)
    dist[i] = dist[i - 1] + (G[i].translation() - G[i - 1].translation()).norm();
  e.path_length_m = dist.back();

  const Eigen::Isometry3d align = G.front() * S.front().inverse();
  double sum2 = 0.0;
  for (std::size_t i = 0; i < G.size(); ++i) {
    const double err = (G[i].translation() - (align * S[i]).translation()).norm();
    sum2 += err * err;
    e.ate_max_m = std::max(e.ate_max_m, err);
  }
  e.ate_rmse_m = std::sqrt(sum2 / static_cast<double>(G.size()));
  const Eigen::Isometry3d last = align * S.back();
  e.final_drift_m = (G.back().translation() - last.translation()).norm();
  e.final_drift_pct = e.path_length_m > 0.0 ? 100.0 * e.final_drift_m / e.path_length_m : nan;
  const Eigen::Matrix3d dR = G.back().linear().transpose() * last.linear();
  e.final_yaw_error_deg = std::atan2(dR(1, 0), dR(0, 0)) * kRadToDeg;

  std::vector<double> tr, rot;
  std::size_t j = 0;
  for (double start = 0.0; start + o.segment_m <= e.path_length_m; start += o.segment_step_m) {
    const std::size_t i = static_cast<std::size_t>(std::lower_bound(dist.begin(), dist.end(), start) - dist.begin());
    j = std::max(j, i);
    while (j < G.size() && dist[j] - dist[i] < o.segment_m) ++j;
    if (j >= G.size()) break;
    const double len = dist[j] - dist[i];
    const Eigen::Isometry3d E = (G[i].inverse() * G[j]).inverse() * (S[i].inverse() * S[j]);
    tr.push_back(100.0 * E.translation().norm() / len);
    rot.push_back(angleOf(E.linear()) * kRadToDeg / len * 10.0);
  }
  e.segments = static_cast<int>(tr.size());
  e.rpe_translation_pct = mean(tr);
  e.rpe_translation_pct_median = median(tr);
  e.rpe_translation_pct_max = tr.empty() ? nan : *std::max_element(tr.begin(), tr.end());
  e.rpe_rotation_deg_per_10m = mean(rot);
  e.rpe_rotation_deg_per_10m_median = median(rot);
  return e;
}

}  // namespace lio
}  // namespace ucon
