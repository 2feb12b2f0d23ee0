// ucon-bench-odometry: the LiDAR-inertial odometry's accuracy and speed on simulated runs, with
// its two baselines in the same run. Per scenario, in-process and in simulation time only
// (ucon::replay::recordSimulatedRun): the simulator emulates the Mid-360 (points and IMU
// packets, IMU noise, biases and bias walk), the lidar driver assembles frames, and the
// robot drives the scenario's goals with perception, planner and base controller on the
// simulator's exact pose (so every estimator sees the same sensor data). After a 1 s
// standstill the goals are sent. Three estimators listen:
//   - lio:        ucon-odometry's node (procs/odometry, common/lio), timed per frame and pose;
//   - imu_only:   the same filter without LiDAR updates (dead reckoning from the standstill);
//   - lidar_only: LiDAR-only odometry (same map and planes, constant-velocity prior, no IMU).
// Each is compared with SIM_GROUND_TRUTH: relative pose error over 10 m segments (% and
// deg/10 m), absolute trajectory error after aligning the first pose, final drift. Prints a
// table and medians; --json writes them with the git revision, the machine and the command.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/cpu_time.hpp"
#include "ucon/lio/lidar_only_odometry.hpp"
#include "ucon/lio/lio_odometry.hpp"
#include "ucon/lio/trajectory_metrics.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/odometry/json_text.hpp"
#include "ucon/odometry/log_trajectories.hpp"
#include "ucon/odometry/odometry_node.hpp"
#include "ucon/odometry/params.hpp"
#include "ucon/replay/node_adapter.hpp"
#include "ucon/replay/sim_recorder.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/simulator/scenario_loader.hpp"
#include "../bench_util.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif

namespace {

namespace rp = ucon::replay;
namespace ch = ucon::channels;
using ucon::bench::percentile;
using Clock = std::chrono::steady_clock;

using ucon::odometry::jsonString;
std::string num(double x) { return ucon::odometry::jsonNumber(x); }

double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

std::string shell(const std::string& cmd) {
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof(buf), p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

std::string cpuModel() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

/// Sends the scenario's goals after a standstill of `delay_s`: the next one when the robot
/// (ground truth) is within `tolerance` of the current one, re-sent every second.
class GoalSequencer : public rp::NodeAdapter {
 public:
  GoalSequencer(std::vector<Eigen::Vector2d> goals, double delay_s, double tolerance)
      : goals_(std::move(goals)), delay_us_(static_cast<int64_t>(delay_s * 1e6)), tol_(tolerance) {}
  std::string name() const override { return "goals"; }
  std::vector<std::string> inputChannels() const override { return {ch::kSimGroundTruth}; }
  std::vector<std::string> outputChannels() const override { return {ch::kNavGoal}; }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return {{"reached", static_cast<int64_t>(k_)}}; }
  rp::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>* out) override {
    if (channel != ch::kSimGroundTruth) return rp::FeedResult::kIgnored;
    ucon::sim_ground_truth_t g;
    if (!rp::decodeExact(data, size, &g)) return rp::FeedResult::kDecodeError;
    if (t_first_ < 0) t_first_ = g.utime;
    if (g.utime - t_first_ < delay_us_ || k_ >= goals_.size()) return rp::FeedResult::kHandled;
    if ((Eigen::Vector2d(g.robot_x, g.robot_y) - goals_[k_]).norm() < tol_) {
      ++k_;
      last_sent_ = -1;
      if (k_ >= goals_.size()) {
        done_at_ = g.utime;
        return rp::FeedResult::kHandled;
      }
    }
    if (last_sent_ < 0 || g.utime - last_sent_ >= 1000000) {
      ucon::nav_goal_t m{};
      m.utime = g.utime;
      m.seq = seq_++;
      m.goal_id = static_cast<int64_t>(k_) + 1;
      m.action = ucon::nav_goal_t::ACTION_GO;
      m.x = goals_[k_].x();
      m.y = goals_[k_].y();
      m.yaw = NAN;
      m.tolerance = tol_;
      m.max_speed = 0.0;
      out->push_back(rp::encodeOutput(ch::kNavGoal, m));
      last_sent_ = g.utime;
    }
    return rp::FeedResult::kHandled;
  }
  bool done(int64_t now, int64_t settle_us) const { return done_at_ > 0 && now - done_at_ >= settle_us; }
  int reached() const { return static_cast<int>(k_); }
  int64_t last_utime_ = 0;

 private:
  std::vector<Eigen::Vector2d> goals_;
  int64_t delay_us_;
  double tol_;
  std::size_t k_ = 0;
  int64_t t_first_ = -1, last_sent_ = -1, seq_ = 0, done_at_ = -1;
};

/// The three estimators on the same sensor stream, and the ground truth.
class EstimatorProbe : public rp::NodeAdapter {
 public:
  EstimatorProbe(const ucon::odometry::OdometryParams& p)
      : node_(p), imu_only_(p.lio, ucon::lio::LioOdometry::Options{false}), lidar_only_(p.lio), t_(p.lio.imu_position) {}
  std::string name() const override { return "estimators"; }
  std::vector<std::string> inputChannels() const override { return {ch::kLidarImu, ch::kLidarPoints, ch::kSimGroundTruth}; }
  std::vector<std::string> outputChannels() const override { return {}; }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return {}; }

  rp::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>*) override {
    if (channel == ch::kLidarImu) {
      ucon::imu_t m;
      if (!rp::decodeExact(data, size, &m)) return rp::FeedResult::kDecodeError;
      // The odometry as its process runs it: the pose first, then the frames it unlocks.
      const double c0 = ucon::threadCpuSeconds();
      const auto t0 = Clock::now();
      const auto out = node_.onImu(m);
      const auto t1 = Clock::now();
      const double c1 = ucon::threadCpuSeconds();
      const auto frames = node_.processFrames();
      const auto t2 = Clock::now();
      const double c2 = ucon::threadCpuSeconds();
      cpu_s_ += c2 - c0;
      if (out.pose) {
        pose_ms_.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        truth_.onPose(*out.pose);
      }
      take(frames, std::chrono::duration<double, std::milli>(t2 - t1).count(), (c2 - c1) * 1e3);
      if (auto e = imu_only_.addImu(ucon::odometry::toImuSample(m))) {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = e->x.R;
        T.translation() = imu_only_.basePosition(e->x);
        imu_only_traj_.push_back({e->t_ns / 1000, T});
      }
    } else if (channel == ch::kLidarPoints) {
      ucon::point_cloud_t c;
      if (!rp::decodeExact(data, size, &c)) return rp::FeedResult::kDecodeError;
      const double c0 = ucon::threadCpuSeconds();
      const auto t0 = Clock::now();
      const auto out = node_.onPoints(c);
      const auto t1 = Clock::now();
      const double c1 = ucon::threadCpuSeconds();
      cpu_s_ += c1 - c0;
      take(out, std::chrono::duration<double, std::milli>(t1 - t0).count(), (c1 - c0) * 1e3);
      points_.push_back(c.num_points);
      if (lidar_only_started_ || node_.estimator().phase() == ucon::lio::Phase::kRunning) {
        // The LiDAR-only baseline starts with the odometry (the robot at rest at its start).
        lidar_only_started_ = true;
        const double l0 = ucon::threadCpuSeconds();
        const auto r = lidar_only_.addFrame(ucon::odometry::toPointFrame(c, nullptr));
        lidar_only_cpu_s_ += ucon::threadCpuSeconds() - l0;
        lidar_only_traj_.push_back({r.t_ns / 1000, r.T});
      }
    } else if (channel == ch::kSimGroundTruth) {
      ucon::sim_ground_truth_t g;
      if (!rp::decodeExact(data, size, &g)) return rp::FeedResult::kDecodeError;
      truth_.onGroundTruth(g);
    } else {
      return rp::FeedResult::kIgnored;
    }
    return rp::FeedResult::kHandled;
  }

  ucon::odometry::OdometryNode node_;
  ucon::lio::LioOdometry imu_only_;
  ucon::lio::LidarOnlyOdometry lidar_only_;
  Eigen::Vector3d t_;
  bool lidar_only_started_ = false;
  ucon::odometry::LogTrajectories truth_;  // ground truth, the odometry's valid poses, its statuses
  std::vector<ucon::lio::TimedPose> imu_only_traj_, lidar_only_traj_;
  std::vector<double> frame_ms_, frame_cpu_ms_, pose_ms_, points_;
  double cpu_s_ = 0.0, lidar_only_cpu_s_ = 0.0;

 private:
  void take(const ucon::odometry::OdometryOutput& o, double ms, double cpu_ms) {
    bool ran = false;
    for (const auto& s : o.statuses) {
      truth_.onStatus(s);
      ran = ran || s.result == ucon::odometry_status_t::RESULT_UPDATED;
    }
    if (ran) {
      frame_ms_.push_back(ms);
      frame_cpu_ms_.push_back(cpu_ms);
    }
  }
};

struct Setup {
  std::string config_dir, scenario_dir;
  ucon::simulator::SimulatorParams sim;
  ucon::lidar_driver::DriverParams driver;
  std::map<std::string, std::string> yaml;
  double timeout_s = 0.0;  // 0 = the scenario's duration
};

struct Result {
  std::string scenario, error;
  double sim_s = 0, wall_s = 0, path_m = 0;
  int goals = 0, reached = 0;
  std::map<std::string, ucon::lio::TrajectoryErrors> errors;  // lio, imu_only, lidar_only
  double frame_ms_median = NAN, frame_ms_p99 = NAN, frame_cpu_ms_median = NAN, frame_cpu_ms_p99 = NAN, pose_ms_median = NAN, pose_ms_p99 = NAN, pose_ms_max = NAN;
  double points_median = NAN, cpu_pct = NAN, lidar_only_cpu_pct = NAN, valid_pct = NAN;
  int64_t updated = 0, not_updated = 0;
};

Result runOne(const Setup& setup, const std::string& spec, bool verbose) {
  Result res;
  res.scenario = spec;
  std::string err;
  auto sc = ucon::simulator::loadScenario(spec, setup.scenario_dir, -1, ucon::runtime::readTextFile, &err);
  if (!sc) return res.error = err, res;
  res.goals = static_cast<int>(sc->robot.goals.size());

  std::vector<std::unique_ptr<rp::NodeAdapter>> owned;
  std::vector<rp::NodeAdapter*> loop;
  auto goals = std::make_unique<GoalSequencer>(sc->robot.goals, 1.0, 0.5);
  GoalSequencer* seq = goals.get();
  loop.push_back(seq);
  owned.push_back(std::move(goals));
  for (const char* n : {"perception", "planner", "base_controller"}) {
    auto a = rp::makeAdapter(n, setup.yaml.at(n), setup.config_dir + "/" + n + ".yaml", &err);
    if (!a) return res.error = err, res;
    loop.push_back(a.get());
    owned.push_back(std::move(a));
  }
  const auto odo_yaml = ucon::odometry::withInitialPose(
      setup.yaml.at("odometry"), Eigen::Vector3d(sc->robot.start.x(), sc->robot.start.y(), sc->robot.start_yaw));
  std::vector<ucon::ConfigError> errors;
  const auto op = odo_yaml ? ucon::loadParams<ucon::odometry::OdometryParams>(*odo_yaml, "odometry.yaml", &errors)
                           : std::nullopt;
  if (!op) return res.error = "odometry.yaml does not load", res;
  auto probe = std::make_unique<EstimatorProbe>(*op);
  EstimatorProbe* est = probe.get();
  loop.push_back(est);
  owned.push_back(std::move(probe));

  rp::RecorderConfig cfg;
  cfg.sim = setup.sim;
  cfg.sim.pose_source = "ground_truth";  // the robot drives on the exact pose; the estimators only listen
  cfg.driver = setup.driver;
  cfg.scenario = *sc;
  cfg.duration_s = setup.timeout_s > 0 ? setup.timeout_s : sc->duration_s;
  cfg.send_goal = false;
  cfg.scripted_plan = false;
  int64_t now = 0;
  cfg.stop = [&] { return seq->done(now, 500000); };
  // The sequencer sees ground truth; the stop hook reads the time from the last pose it saw.
  const auto t0 = Clock::now();
  const rp::RecordSummary s = rp::recordSimulatedRun(
      cfg, loop, [&](const std::string& channel, int64_t utime, const std::vector<uint8_t>&) {
        if (channel == ch::kSimGroundTruth) now = utime;
      });
  res.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  res.sim_s = s.sim_time_s;
  res.reached = seq->reached();

  const auto& truth = est->truth_.truth();
  res.errors["lio"] = ucon::lio::evaluateTrajectory(truth, est->truth_.estimate());
  res.errors["imu_only"] = ucon::lio::evaluateTrajectory(truth, est->imu_only_traj_);
  res.errors["lidar_only"] = ucon::lio::evaluateTrajectory(truth, est->lidar_only_traj_);
  res.path_m = res.errors["lio"].path_length_m;
  res.frame_ms_median = percentile(est->frame_ms_, 0.5);
  res.frame_ms_p99 = percentile(est->frame_ms_, 0.99);
  res.frame_cpu_ms_median = percentile(est->frame_cpu_ms_, 0.5);
  res.frame_cpu_ms_p99 = percentile(est->frame_cpu_ms_, 0.99);
  res.pose_ms_median = percentile(est->pose_ms_, 0.5);
  res.pose_ms_p99 = percentile(est->pose_ms_, 0.99);
  res.pose_ms_max = percentile(est->pose_ms_, 1.0);
  res.points_median = percentile(est->points_, 0.5);
  res.cpu_pct = res.sim_s > 0 ? 100.0 * est->cpu_s_ / res.sim_s : NAN;
  res.lidar_only_cpu_pct = res.sim_s > 0 ? 100.0 * est->lidar_only_cpu_s_ / res.sim_s : NAN;
  const auto& tr = est->truth_;
  res.valid_pct = tr.poses() > 0 ? 100.0 * double(tr.poses() - tr.posesInvalid()) / double(tr.poses()) : NAN;
  res.updated = tr.results()[ucon::odometry_status_t::RESULT_UPDATED];
  for (int r = 0; r < 9; ++r)
    if (r != ucon::odometry_status_t::RESULT_UPDATED && r != ucon::odometry_status_t::RESULT_NOT_INITIALISED &&
        r != ucon::odometry_status_t::RESULT_MAP_STARTED)
      res.not_updated += tr.results()[static_cast<std::size_t>(r)];
  if (verbose) {
    std::string frames;
    for (int r = 0; r < 9; ++r)
      if (tr.results()[static_cast<std::size_t>(r)] > 0)
        frames += std::string(frames.empty() ? "" : ", ") + ucon::odometry::resultName(r) + " " +
                  std::to_string(tr.results()[static_cast<std::size_t>(r)]);
    std::printf("  %s: %.1f s simulated in %.1f s, %d/%d goals, %zu truth / %zu lio / %zu imu-only / %zu lidar-only "
                "poses; lio frames: %s\n",
                spec.c_str(), res.sim_s, res.wall_s, res.reached, res.goals, truth.size(), tr.estimate().size(),
                est->imu_only_traj_.size(), est->lidar_only_traj_.size(), frames.c_str());
    std::fflush(stdout);
  }
  return res;
}

const char* const kEstimators[] = {"lio", "imu_only", "lidar_only"};

std::string errorsJson(const ucon::lio::TrajectoryErrors& e) {
  std::ostringstream o;
  o << "{\"rpe_translation_pct\": " << num(e.rpe_translation_pct)
    << ", \"rpe_translation_pct_median\": " << num(e.rpe_translation_pct_median)
    << ", \"rpe_translation_pct_max\": " << num(e.rpe_translation_pct_max)
    << ", \"rpe_rotation_deg_per_10m\": " << num(e.rpe_rotation_deg_per_10m)
    << ", \"rpe_rotation_deg_per_10m_median\": " << num(e.rpe_rotation_deg_per_10m_median)
    << ", \"ate_rmse_m\": " << num(e.ate_rmse_m) << ", \"final_drift_m\": " << num(e.final_drift_m)
    << ", \"final_drift_pct\": " << num(e.final_drift_pct) << ", \"segments\": " << e.segments
    << ", \"matched\": " << e.matched << "}";
  return o.str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "UCON odometry benchmark: LiDAR-inertial odometry vs IMU-only dead reckoning vs LiDAR-only odometry on "
      "simulated runs (RPE over 10 m, ATE, drift, time per frame)."};
  std::string json_path, scenarios = "corridor,hall,pedestrians,crossing,bench:50:1,bench:80:1,bench:110:1";
  bool quick = false, verbose = false;
  Setup setup;
  setup.config_dir = std::string(UCON_SOURCE_DIR) + "/deploy/config";
  setup.scenario_dir = std::string(UCON_SOURCE_DIR) + "/deploy/scenarios";
  app.add_option("--json", json_path, "write results as JSON to this file");
  app.add_option("--scenarios", scenarios, "comma list: corridor | hall | pedestrians | crossing | bench:<N_d>:<seed> | path.yaml");
  app.add_option("--timeout", setup.timeout_s, "simulated seconds per run (default: the scenario's duration)")
      ->check(CLI::PositiveNumber);
  app.add_option("--config-dir", setup.config_dir, "folder of the node configs");
  app.add_option("--scenario-dir", setup.scenario_dir, "folder of the builtin scenarios");
  app.add_flag("--quick", quick, "pipeline check for ctest: crossing for 15 s; exit 1 only if the odometry is broken");
  app.add_flag("--verbose", verbose, "one line per run as it ends");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    if (app.count("--scenarios") == 0) scenarios = "crossing";
    if (app.count("--timeout") == 0) setup.timeout_s = 15.0;
    verbose = true;
  }
  std::string command;
  for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);

  std::string err;
  if (!ucon::runtime::loadConfigFile(setup.config_dir + "/simulator.yaml", &setup.sim, nullptr, &err) ||
      !ucon::runtime::loadConfigFile(setup.config_dir + "/lidar_driver.yaml", &setup.driver, nullptr, &err)) {
    std::fprintf(stderr, "ucon-bench-odometry: %s\n", err.c_str());
    return 2;
  }
  for (const char* n : {"perception", "planner", "base_controller", "odometry"}) {
    auto t = ucon::runtime::readTextFile(setup.config_dir + "/" + n + ".yaml", &err);
    if (!t) {
      std::fprintf(stderr, "ucon-bench-odometry: %s\n", err.c_str());
      return 2;
    }
    setup.yaml[n] = *t;
  }

  std::printf("ucon-bench-odometry: %s\n", scenarios.c_str());
  std::vector<Result> results;
  for (const auto& spec : ucon::bench::split(scenarios)) {
    results.push_back(runOne(setup, spec, verbose));
    if (!results.back().error.empty()) {
      std::fprintf(stderr, "ucon-bench-odometry: %s: %s\n", spec.c_str(), results.back().error.c_str());
      return 2;
    }
  }

  std::printf("\n%-14s %6s %-11s %8s %8s %9s %8s %8s %8s\n", "scenario", "path", "estimator", "RPE %", "RPE med",
              "deg/10m", "ATE m", "drift m", "drift %");
  for (const auto& r : results) {
    bool first = true;
    for (const char* e : kEstimators) {
      const auto& x = r.errors.at(e);
      std::printf("%-14s %6s %-11s %8.3f %8.3f %9.3f %8.3f %8.3f %8.3f\n", first ? r.scenario.c_str() : "",
                  first ? (std::to_string(static_cast<int>(std::lround(r.path_m))) + " m").c_str() : "", e,
                  x.rpe_translation_pct, x.rpe_translation_pct_median, x.rpe_rotation_deg_per_10m, x.ate_rmse_m,
                  x.final_drift_m, x.final_drift_pct);
      first = false;
    }
    std::printf("%-14s %6s lio: frame %.2f ms median, %.2f ms p99 wall (CPU %.2f / %.2f ms; %.0f points in, %lld "
                "updated, %lld not); pose %.3f ms median, %.3f p99, %.3f max; CPU %.1f %% of a core (lidar_only %.1f "
                "%%); %.1f %% valid; %d/%d goals\n",
                "", "", r.frame_ms_median, r.frame_ms_p99, r.frame_cpu_ms_median, r.frame_cpu_ms_p99, r.points_median,
                static_cast<long long>(r.updated),
                static_cast<long long>(r.not_updated), r.pose_ms_median, r.pose_ms_p99, r.pose_ms_max, r.cpu_pct,
                r.lidar_only_cpu_pct, r.valid_pct, r.reached, r.goals);
  }
  // Medians over the runs.
  std::map<std::string, std::map<std::string, double>> summary;
  for (const char* e : kEstimators) {
    std::vector<double> t, rot, ate, drift;
    for (const auto& r : results) {
      const auto& x = r.errors.at(e);
      if (std::isfinite(x.rpe_translation_pct)) t.push_back(x.rpe_translation_pct);
      if (std::isfinite(x.rpe_rotation_deg_per_10m)) rot.push_back(x.rpe_rotation_deg_per_10m);
      ate.push_back(x.ate_rmse_m);
      drift.push_back(x.final_drift_pct);
    }
    summary[e] = {{"rpe_translation_pct", median(t)},
                  {"rpe_rotation_deg_per_10m", median(rot)},
                  {"ate_rmse_m", median(ate)},
                  {"final_drift_pct", median(drift)}};
  }
  std::vector<double> fm, fp, cm, cp, pm, pp;
  for (const auto& r : results) {
    fm.push_back(r.frame_ms_median);
    fp.push_back(r.frame_ms_p99);
    cm.push_back(r.frame_cpu_ms_median);
    cp.push_back(r.frame_cpu_ms_p99);
    pm.push_back(r.pose_ms_median);
    pp.push_back(r.pose_ms_p99);
  }
  std::printf("\nmedians over %zu runs:\n", results.size());
  for (const char* e : kEstimators)
    std::printf("  %-11s RPE %.3f %%, %.3f deg/10 m, ATE %.3f m, final drift %.3f %%\n", e,
                summary[e]["rpe_translation_pct"], summary[e]["rpe_rotation_deg_per_10m"], summary[e]["ate_rmse_m"],
                summary[e]["final_drift_pct"]);
  std::printf("  lio timing  frame %.2f ms median / %.2f ms p99 wall, %.2f / %.2f ms CPU (medians of the runs' "
              "figures); pose %.3f / %.3f ms\n",
              median(fm), median(fp), median(cm), median(cp), median(pm), median(pp));
  std::printf("  (wall-clock figures on a shared machine: %u hardware threads, load average %s)\n",
              std::thread::hardware_concurrency(), shell("cut -d' ' -f1-3 /proc/loadavg").c_str());

  bool broken = false;
  for (const auto& r : results) {
    const auto& x = r.errors.at("lio");
    if (x.matched == 0 || r.updated == 0 || !std::isfinite(x.final_drift_m)) broken = true;
  }
  if (!json_path.empty()) {
    std::ofstream f(json_path);
    if (!f) {
      std::fprintf(stderr, "ucon-bench-odometry: cannot write %s\n", json_path.c_str());
      return 2;
    }
    const std::string rev = shell("git -C '" + std::string(UCON_SOURCE_DIR) + "' rev-parse HEAD 2>/dev/null");
    const std::string dirty =
        shell("git -C '" + std::string(UCON_SOURCE_DIR) + "' status --porcelain --untracked-files=no 2>/dev/null | head -c1");
    f << "{\"benchmark\": \"odometry\", \"command\": " << jsonString(command)
      << ", \"git_revision\": " << jsonString(rev + (dirty.empty() ? "" : "-dirty"))
      << ", \"machine\": {\"cores\": " << std::thread::hardware_concurrency() << ", \"cpu_model\": " << jsonString(cpuModel())
      << ", \"load_average\": " << jsonString(shell("cut -d' ' -f1-3 /proc/loadavg")) << "},\n \"results\": [";
    for (std::size_t i = 0; i < results.size(); ++i) {
      const auto& r = results[i];
      f << (i ? ",\n  " : "\n  ") << "{\"scenario\": " << jsonString(r.scenario) << ", \"sim_s\": " << num(r.sim_s)
        << ", \"wall_s\": " << num(r.wall_s) << ", \"path_m\": " << num(r.path_m) << ", \"goals\": " << r.goals
        << ", \"goals_reached\": " << r.reached << ", \"estimators\": {";
      bool first = true;
      for (const char* e : kEstimators) {
        f << (first ? "" : ", ") << jsonString(e) << ": " << errorsJson(r.errors.at(e));
        first = false;
      }
      f << "}, \"lio\": {\"frame_ms_median\": " << num(r.frame_ms_median) << ", \"frame_ms_p99\": " << num(r.frame_ms_p99)
        << ", \"frame_cpu_ms_median\": " << num(r.frame_cpu_ms_median) << ", \"frame_cpu_ms_p99\": " << num(r.frame_cpu_ms_p99)
        << ", \"pose_ms_median\": " << num(r.pose_ms_median) << ", \"pose_ms_p99\": " << num(r.pose_ms_p99)
        << ", \"pose_ms_max\": " << num(r.pose_ms_max) << ", \"points_per_frame_median\": " << num(r.points_median)
        << ", \"cpu_pct\": " << num(r.cpu_pct) << ", \"valid_pct\": " << num(r.valid_pct)
        << ", \"frames_updated\": " << r.updated << ", \"frames_not_updated\": " << r.not_updated
        << "}, \"lidar_only_cpu_pct\": " << num(r.lidar_only_cpu_pct) << "}";
    }
    f << "\n ],\n \"summary\": {";
    bool first = true;
    for (const char* e : kEstimators) {
      f << (first ? "" : ", ") << jsonString(e) << ": {";
      bool f2 = true;
      for (const auto& [k, v] : summary[e]) {
        f << (f2 ? "" : ", ") << jsonString(k) << ": " << num(v);
        f2 = false;
      }
      f << "}";
      first = false;
    }
    f << ", \"lio_frame_ms_median\": " << num(median(fm)) << ", \"lio_frame_ms_p99\": " << num(median(fp))
      << ", \"lio_frame_cpu_ms_median\": " << num(median(cm)) << ", \"lio_frame_cpu_ms_p99\": " << num(median(cp))
      << ", \"lio_pose_ms_median\": " << num(median(pm)) << ", \"lio_pose_ms_p99\": " << num(median(pp)) << "}}\n";
    std::printf("wrote %s\n", json_path.c_str());
  }
  if (broken) {
    std::fprintf(stderr, "ucon-bench-odometry: the odometry produced no estimate or no update in a run\n");
    return 1;
  }
  return 0;
}
