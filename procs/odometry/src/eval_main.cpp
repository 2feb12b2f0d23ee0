// ucon-odom-eval: the odometry's accuracy on a log with SIM_GROUND_TRUTH: relative pose error
// over 10 m segments (translation in % of distance, rotation in deg per 10 m), absolute
// trajectory error after aligning the first pose, final drift, and what the odometry did with
// its frames (ODOMETRY_STATUS). Exit status: 0 evaluated, 1 nothing to compare, 2 bad input.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "ucon/channels.hpp"
#include "ucon/odometry/json_text.hpp"
#include "ucon/odometry/log_trajectories.hpp"
#include "ucon/runtime/log_reader.hpp"

namespace {

using ucon::odometry::jsonString;
std::string num(double x) { return ucon::odometry::jsonNumber(x); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Odometry accuracy of an LCM log against its SIM_GROUND_TRUTH (RPE over 10 m segments, ATE, drift)."};
  std::string path, pose_channel = ucon::channels::kRobotPose;
  bool json = false;
  ucon::lio::MetricsOptions mo;
  app.add_option("log", path, "LCM log with SIM_GROUND_TRUTH and ROBOT_POSE")->required();
  app.add_flag("--json", json, "print JSON instead of a table");
  app.add_option("--channel", pose_channel, "channel of the estimated pose (ucon.robot_pose_t)");
  app.add_option("--segment", mo.segment_m, "RPE segment length [m]")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  ucon::runtime::LogReader reader;
  if (!reader.open(path)) {
    std::fprintf(stderr, "ucon-odom-eval: %s\n", reader.error().c_str());
    return 2;
  }
  ucon::odometry::LogTrajectories tr;
  ucon::runtime::LogEvent ev;
  int64_t undecodable = 0;
  ucon::runtime::LogReadStatus st;
  while ((st = reader.next(&ev)) == ucon::runtime::LogReadStatus::kOk) {
    const int n = static_cast<int>(ev.data.size());
    if (ev.channel == ucon::channels::kSimGroundTruth) {
      ucon::sim_ground_truth_t m;
      if (m.decode(ev.data.data(), 0, n) != n) ++undecodable; else tr.onGroundTruth(m);
    } else if (ev.channel == pose_channel) {
      ucon::robot_pose_t m;
      if (m.decode(ev.data.data(), 0, n) != n) ++undecodable; else tr.onPose(m);
    } else if (ev.channel == ucon::channels::kOdometryStatus) {
      ucon::odometry_status_t m;
      if (m.decode(ev.data.data(), 0, n) != n) ++undecodable; else tr.onStatus(m);
    }
  }
  if (st != ucon::runtime::LogReadStatus::kEnd) {
    std::fprintf(stderr, "ucon-odom-eval: %s\n", reader.error().c_str());
    return 2;
  }
  if (tr.truth().empty() || tr.estimate().empty()) {
    std::fprintf(stderr, "ucon-odom-eval: %s: %zu SIM_GROUND_TRUTH and %zu valid %s messages: nothing to compare\n",
                 path.c_str(), tr.truth().size(), tr.estimate().size(), pose_channel.c_str());
    return 1;
  }
  const ucon::lio::TrajectoryErrors e = ucon::lio::evaluateTrajectory(tr.truth(), tr.estimate(), mo);
  const double valid_pct = tr.poses() > 0 ? 100.0 * double(tr.poses() - tr.posesInvalid()) / double(tr.poses()) : NAN;
  if (json) {
    std::printf("{\"log\": %s, \"pose_channel\": %s, \"path_length_m\": %s, \"segments\": %d, "
                "\"rpe_translation_pct\": %s, \"rpe_translation_pct_median\": %s, \"rpe_translation_pct_max\": %s, "
                "\"rpe_rotation_deg_per_10m\": %s, \"rpe_rotation_deg_per_10m_median\": %s, "
                "\"ate_rmse_m\": %s, \"ate_max_m\": %s, \"final_drift_m\": %s, \"final_drift_pct\": %s, "
                "\"final_yaw_error_deg\": %s, \"truth_poses\": %d, \"matched\": %d, \"poses\": %lld, "
                "\"poses_valid_pct\": %s, \"frames\": {",
                jsonString(path).c_str(), jsonString(pose_channel).c_str(), num(e.path_length_m).c_str(), e.segments,
                num(e.rpe_translation_pct).c_str(), num(e.rpe_translation_pct_median).c_str(),
                num(e.rpe_translation_pct_max).c_str(), num(e.rpe_rotation_deg_per_10m).c_str(),
                num(e.rpe_rotation_deg_per_10m_median).c_str(), num(e.ate_rmse_m).c_str(), num(e.ate_max_m).c_str(),
                num(e.final_drift_m).c_str(), num(e.final_drift_pct).c_str(), num(e.final_yaw_error_deg).c_str(),
                e.truth_poses, e.matched, static_cast<long long>(tr.poses()), num(valid_pct).c_str());
    bool first = true;
    for (int r = 0; r < static_cast<int>(tr.results().size()); ++r) {
      if (tr.results()[static_cast<std::size_t>(r)] == 0) continue;
      std::printf("%s%s: %lld", first ? "" : ", ", jsonString(ucon::odometry::resultName(r)).c_str(),
                  static_cast<long long>(tr.results()[static_cast<std::size_t>(r)]));
      first = false;
    }
    std::printf("}, \"residual_rms_median_m\": %s, \"points_matched_median\": %s}\n",
                num(tr.medianResidualRms()).c_str(), num(tr.medianPointsMatched()).c_str());
  } else {
    std::printf("%s: %s against SIM_GROUND_TRUTH\n", path.c_str(), pose_channel.c_str());
    std::printf("  path            %.2f m (%d of %d ground-truth poses matched)\n", e.path_length_m, e.matched,
                e.truth_poses);
    if (e.segments > 0)
      std::printf("  RPE %4.1f m      translation %.3f %% (median %.3f, max %.3f), rotation %.3f deg/10 m (median %.3f); %d segments\n",
                  mo.segment_m, e.rpe_translation_pct, e.rpe_translation_pct_median, e.rpe_translation_pct_max,
                  e.rpe_rotation_deg_per_10m, e.rpe_rotation_deg_per_10m_median, e.segments);
    else
      std::printf("  RPE             path shorter than %.1f m: no segment\n", mo.segment_m);
    std::printf("  ATE             rmse %.3f m, max %.3f m (first pose aligned)\n", e.ate_rmse_m, e.ate_max_m);
    std::printf("  final drift     %.3f m (%.3f %% of the path), heading %.3f deg\n", e.final_drift_m, e.final_drift_pct,
                e.final_yaw_error_deg);
    std::printf("  poses           %lld, %.1f %% valid\n", static_cast<long long>(tr.poses()), valid_pct);
    if (tr.statuses() > 0) {
      std::printf("  frames         ");
      for (int r = 0; r < static_cast<int>(tr.results().size()); ++r)
        if (tr.results()[static_cast<std::size_t>(r)] > 0)
          std::printf(" %s %lld;", ucon::odometry::resultName(r), static_cast<long long>(tr.results()[static_cast<std::size_t>(r)]));
      std::printf(" median residual rms %.3f m, %.0f points matched\n", tr.medianResidualRms(), tr.medianPointsMatched());
    }
  }
  if (undecodable > 0) std::fprintf(stderr, "ucon-odom-eval: %lld undecodable messages skipped\n", static_cast<long long>(undecodable));
  return 0;
}
