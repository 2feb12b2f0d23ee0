// ucon-bench-nav: the whole navigation stack in-process and in lock step (issue 8). Per run:
// the Simulator emulates the Mid-360 (Livox UDP datagrams, as the live simulator sends them),
// the lidar driver node parses them and assembles point frames, then perception, planner and
// base controller nodes run through their replay adapters on a zero-latency bus
// (ucon::replay::recordSimulatedRun, the same loop as ucon-sim-record); BASE_WHEEL_CMD drives
// the simulator's Mecanum plant. The mission (ucon::mission::MissionNode, as in `deploy/ucon
// sim`) sends the scenario's goals on NAV_GOAL. Time is simulation utime only; the wall clock
// only measures stage latencies and the speed relative to real time.
//
// A run succeeds when every goal is reached within the timeout with no collision; it stops at
// the goal, at the first collision or at the timeout. Prints a table and writes JSON
// {"results": [{"n_dynamic", "runs", "success_rate", "collisions", "time_to_goal_s",
//               "realtime_factor", "tracking_recall", "velocity_error_mps", "velocity_error_over_std",
//               "acquisition": {"arrivals", "tracked", "tracked_within_0_25_s", "median_delay_s"},
//               "young_tracks": {"samples", "velocity_rms_error_mps", "velocity_error_over_std"},
//               "mota", "idsw", "fn_rate", "fp_rate", "motp",
//               "latency_ms": {"driver", "perception", "planner", "controller"}}]}
// (tracking_recall: median over runs of the share of visible movers within 10 m with a track
// within 0.7 m; velocity_error_mps: median over runs of the mean |v_track - v_mover| of those
// within 5 m of the robot; velocity_error_over_std: median over runs of the rms of that error over
// the rms of the standard deviation the track states for it, 1 for a consistent covariance;
// young_tracks: the same pooled over every run's samples of tracks at most 15 frames old, whose
// velocities the planner predicts with when a mover has just come into view).
//
// --planner-model sector,no_uncertainty,fapp runs every seed once per obstacle model (the
// methods of Table II in the whole stack) and compares each with the first on the same seeds
// (McNemar's test, the paired difference with its 95 % interval); --check-growth K sets the
// covariance growth that all models share outside the cost (post-check, fallback) to K.
//
// This file: the command line, the runs on a pool of threads, the table and the JSON. One run's
// loop is in run.cpp, what a run measures (the mission in the loop, tracking quality, the
// result and the table's rows) in metrics.cpp, the stage timer and the perception probe with
// its --oracle-* diagnoses in probes.cpp.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "../bench_util.hpp"
#include "../planning/paired_stats.hpp"
#include "metrics.hpp"
#include "planner_variant.hpp"
#include "run.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/replay/node_adapter.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/trajopt/sector_minco.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif

namespace {

using namespace ucon::bench::nav;
using ucon::bench::percentile;
using ucon::bench::split;

std::string num(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.6g", x);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "UCON full-stack navigation benchmark: simulated Mid-360 packets -> driver -> perception -> planner -> "
      "base controller -> Mecanum plant, in-process, on bench:<N_d>:<seed>."};
  std::string json_path;
  int seeds = 10;
  uint64_t seed_base = 1;
  std::string densities = "50,80,110";
  int jobs = 1;
  bool quick = false, verbose = false;
  Oracle oracle;
  Pipeline pipeline;
  double timeout_s = 120.0;
  Setup setup;
  setup.config_dir = std::string(UCON_SOURCE_DIR) + "/deploy/config";
  setup.scenario_dir = std::string(UCON_SOURCE_DIR) + "/deploy/scenarios";
  app.add_option("--json", json_path, "write results as JSON to this file");
  app.add_option("--seeds", seeds, "worlds per density (seeds B .. B+N-1)")->check(CLI::PositiveNumber);
  app.add_option("--seed-base", seed_base, "first seed");
  app.add_option("--densities", densities, "comma list of moving-obstacle counts N_d");
  app.add_option("--jobs", jobs, "parallel runs (threads)")->check(CLI::PositiveNumber);
  app.add_flag("--quick", quick,
               "pipeline check for ctest: 1 seed at N_d = 50, 20 s timeout; exit 1 only if the pipeline breaks");
  app.add_option("--timeout", timeout_s, "simulated seconds allowed per run [s]")->check(CLI::PositiveNumber);
  app.add_option("--config-dir", setup.config_dir,
                 "folder of simulator.yaml, lidar_driver.yaml, perception.yaml, planner.yaml, "
                 "base_controller.yaml, mission.yaml");
  app.add_option("--scenario-dir", setup.scenario_dir, "folder of the builtin scenarios");
  app.add_flag("--verbose", verbose, "one line per run as it ends");
  app.add_flag("--oracle-objects", oracle.objects,
               "diagnosis: the planner gets the ground-truth movers within 12 m instead of perception's tracks");
  app.add_flag("--oracle-line-of-sight", oracle.line_of_sight,
               "diagnosis, with --oracle-objects: only the movers the sensor sees (30 % of the body in view), those "
               "hidden since coasted at their last seen velocity for perception.yaml's tracks.max_coast: a tracker "
               "perfect on what a line-of-sight sensor sees");
  app.add_option("--oracle-delay", oracle.delay_s,
                 "diagnosis, with --oracle-line-of-sight: a mover is given once it has been in view this long [s] "
                 "(how soon perception must hold a mover that comes into view)")
      ->check(CLI::Range(0.0, 5.0));
  app.add_flag("--oracle-velocity", oracle.velocity,
               "diagnosis: perception's tracks, each with the velocity of the ground-truth mover within 0.8 m");
  app.add_flag("--oracle-static", oracle.static_map,
               "diagnosis: points within 0.25 m of a mover are removed from PERCEPTION_STATIC");
  app.add_option("--pose", setup.pose, "robot pose: ground_truth (the simulator's) | odometry (LiDAR-inertial)")
      ->check(CLI::IsMember({"ground_truth", "odometry"}));
  std::vector<std::string> models;
  app.add_option("--planner-model", models,
                 "obstacle model(s) of the planner, comma list of sector | no_uncertainty | fapp: every seed runs "
                 "once per model, each compared with the first on the same seeds (default: planner.yaml's)")
      ->delimiter(',')
      ->check(CLI::IsMember({"sector", "no_uncertainty", "fapp"}));
  double check_growth = -1.0;
  app.add_option("--check-growth", check_growth,
                 "set the covariance growth every model shares outside the cost (optimizer.check_uncertainty_k "
                 "and fallback.uncertainty_k, in std) to this for all (default: planner.yaml's)")
      ->check(CLI::Range(0.0, 5.0));
  std::string faults;
  app.add_option("--faults", faults,
                 "inject faults on the bus and run every seed with and without them: "
                 "drop=P,delay=MS,jitter=MS[,channel=REGEX] and/or kill=NODE@T[,restart=S] (NODE: perception, "
                 "planner, base_controller, odometry; T, S in seconds)");
  app.add_flag("--serial", pipeline.serial,
               "run every node on the loop's thread with a zero-latency bus (default: perception and planner "
               "on threads of their own, outputs delivered after a fixed latency)");
  CLI11_PARSE(app, argc, argv);
  if (oracle.delay_s > 0.0 && !oracle.line_of_sight) {
    std::fprintf(stderr, "ucon-bench-nav: --oracle-delay applies to --oracle-line-of-sight; give both\n");
    return 2;
  }
  if (oracle.line_of_sight && !oracle.objects) {
    std::fprintf(stderr, "ucon-bench-nav: --oracle-line-of-sight chooses which movers --oracle-objects gives; give both\n");
    return 2;
  }
  if (quick) {
    if (app.count("--seeds") == 0) seeds = 1;
    if (app.count("--densities") == 0) densities = "50";
    if (app.count("--timeout") == 0) timeout_s = 20.0;
    verbose = true;
  }

  std::string err;
  if (!faults.empty() && !parseFaults(faults, &setup.faults, &err)) {
    std::fprintf(stderr, "ucon-bench-nav: --faults: %s\n", err.c_str());
    return 2;
  }
  if (!ucon::runtime::loadConfigFile(setup.config_dir + "/simulator.yaml", &setup.sim, nullptr, &err) ||
      !ucon::runtime::loadConfigFile(setup.config_dir + "/lidar_driver.yaml", &setup.driver, nullptr, &err) ||
      !ucon::runtime::loadConfigFile(setup.config_dir + "/mission.yaml", &setup.mission, nullptr, &err)) {
    std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
    return 2;
  }
  if (const std::string bad = setup.sim.validate(); !bad.empty()) {
    std::fprintf(stderr, "ucon-bench-nav: simulator.yaml: %s\n", bad.c_str());
    return 2;
  }
  for (const char* n : {"perception", "planner", "base_controller"}) {
    const std::string path = setup.config_dir + "/" + n + ".yaml";
    auto t = ucon::runtime::readTextFile(path, &err);
    if (!t) {
      std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
      return 2;
    }
    // Fail early on a bad config or a node missing from this build.
    if (!rp::makeAdapter(n, *t, path, &err)) {
      std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
      return 2;
    }
    setup.node_yaml[n] = *t;
  }
  {
    std::vector<ucon::ConfigError> errors;
    auto p = ucon::loadParams<ucon::perception::PerceptionParams>(setup.node_yaml.at("perception"), "perception.yaml",
                                                                  &errors);
    if (p) setup.perception_max_coast = p->tracks.max_coast;
  }
  // One setup per planner model (--planner-model, --check-growth); the first is the reference.
  if (models.empty()) models.push_back("");
  for (std::size_t a = 0; a < models.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (models[a] == models[b]) {
        std::fprintf(stderr, "ucon-bench-nav: --planner-model names '%s' twice\n", models[a].c_str());
        return 2;
      }
  if (models.size() > 1 && !faults.empty()) {
    std::fprintf(stderr, "ucon-bench-nav: --faults compares each seed with its fault-free run; give one "
                         "--planner-model with it\n");
    return 2;
  }
  std::vector<Setup> variants;
  for (const auto& m : models) {
    Setup v = setup;
    if (!m.empty() || check_growth >= 0.0) {
      if (!plannerVariant(setup.node_yaml.at("planner"), m, check_growth, &v.node_yaml["planner"], &err)) {
        std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
        return 2;
      }
    }
    variants.push_back(std::move(v));
  }
  // The model each variant runs, as its planner.yaml says (the default's name too).
  std::vector<std::string> model_names;
  for (const auto& v : variants) {
    std::vector<ucon::ConfigError> errors;
    auto p = ucon::loadParams<ucon::planner::PlannerParams>(v.node_yaml.at("planner"), "planner.yaml", &errors);
    model_names.push_back(p ? ucon::trajopt::toString(p->optimizer.obstacle_model) : "?");
  }
  {
    // Pipeline latencies: a LiDAR frame period for perception, the planner's own latency_s.
    ucon::planner::PlannerParams pp;
    if (!ucon::runtime::loadConfigFile(setup.config_dir + "/planner.yaml", &pp, nullptr, &err)) {
      std::fprintf(stderr, "ucon-bench-nav: %s\n", err.c_str());
      return 2;
    }
    pipeline.perception_delay_us = std::llround(1e6 / setup.sim.frame_rate_hz);
    pipeline.planner_delay_us = std::max<int64_t>(std::llround(pp.latency_s * 1e6), 1000);
  }
  std::vector<int> density_list;
  for (const auto& d : split(densities)) {
    const int n = std::atoi(d.c_str());
    if (n < 0) {
      std::fprintf(stderr, "ucon-bench-nav: bad density '%s'\n", d.c_str());
      return 2;
    }
    density_list.push_back(n);
  }

  struct Task {
    int n_dynamic;
    uint64_t seed;
    bool faulty;  ///< with --faults: the run with the faults (the other one is its fault-free pair)
    std::size_t variant;  ///< index into `variants` (--planner-model)
  };
  std::vector<Task> tasks;
  std::vector<Setup> fault_free = variants;
  for (auto& v : fault_free) v.faults = FaultSpec{};
  for (int s = 0; s < seeds; ++s)
    for (int d : density_list)
      for (std::size_t v = 0; v < variants.size(); ++v) {
        tasks.push_back({d, seed_base + uint64_t(s), false, v});
        if (setup.faults.any()) tasks.push_back({d, seed_base + uint64_t(s), true, v});
      }
  const bool several = variants.size() > 1;
  auto modelTag = [&](std::size_t v) { return several ? " " + model_names[v] : std::string(); };
  std::vector<RunResult> results(tasks.size());
  std::atomic<std::size_t> next{0};
  std::mutex print_mutex;
  const auto bench_t0 = Clock::now();
  auto worker = [&] {
    for (std::size_t i = next++; i < tasks.size(); i = next++) {
      const Task& task = tasks[i];
      results[i] = runOne(task.faulty ? variants[task.variant] : fault_free[task.variant], task.n_dynamic, task.seed,
                          timeout_s, oracle, pipeline);
      const auto& r = results[i];
      if (verbose || !r.ok) {
        std::lock_guard<std::mutex> lock(print_mutex);
        if (!r.ok) {
          std::printf("N_d=%3d seed=%4llu%s%s ERROR %s\n", r.n_dynamic, (unsigned long long)r.seed,
                      modelTag(task.variant).c_str(), task.faulty ? " faults" : "", r.error.c_str());
        } else {
          std::printf("N_d=%3d seed=%4llu%s%s %-9s t_goal=%6.1fs sim=%6.1fs wall=%6.1fs rtf=%5.2f left=%5.1fm "
                      "clear=%5.2fm frames=%lld plans=%lld leak=%.1f/s recall=%.2f verr=%.2f mota=%.2f idsw=%lld | med ms drv %.3f per %.2f pln %.2f ctl %.3f | cpu rtf %.2f%s%s%s\n",
                      r.n_dynamic, (unsigned long long)r.seed, modelTag(task.variant).c_str(),
                      task.faulty ? " faults" : "",
                      r.success ? "success" : (r.collision ? "COLLISION" : "timeout"), r.time_to_goal_s, r.sim_s,
                      r.wall_s, r.wall_s > 0 ? r.sim_s / r.wall_s : NAN, r.dist_left, r.min_clearance,
                      (long long)(r.messages.count(ucon::channels::kLidarPoints) ? r.messages.at(ucon::channels::kLidarPoints) : 0),
                      (long long)(r.messages.count(ucon::channels::kPlannerTrajectory) ? r.messages.at(ucon::channels::kPlannerTrajectory) : 0),
                      r.sim_s > 0 ? r.leaked_static / r.sim_s : NAN, r.recall, r.velocity_error,
                      r.mot.num_objects > 0 ? r.mot.mota : NAN, (long long)r.mot.num_switches, percentile(r.stages[0].samples_ms, 0.5), percentile(r.stages[1].samples_ms, 0.5),
                      percentile(r.stages[2].samples_ms, 0.5), percentile(r.stages[3].samples_ms, 0.5),
                      r.cpu_s > 0 ? r.sim_s / r.cpu_s : NAN, r.plan_tally.c_str(), r.collision ? " | hit " : "",
                      r.collision ? (r.collision_with + " at robot speed " + num(r.robot_speed_at_hit) + " m/s").c_str() : "");
        }
        std::fflush(stdout);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, jobs); ++j) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  const double bench_wall_s = msSince(bench_t0) * 1e-3;

  std::vector<Row> rows;
  int rc = 0;
  for (std::size_t v = 0; v < variants.size(); ++v)
  for (int d : density_list) {
    Row row;
    row.n_dynamic = d;
    row.model = model_names[v];
    for (std::size_t i = 0; i < results.size(); ++i) {
      const auto& r = results[i];
      if (r.n_dynamic != d || tasks[i].faulty || tasks[i].variant != v) continue;
      std::string why;
      if (r.pipelineBroken(&why)) {
        std::fprintf(stderr, "ucon-bench-nav: pipeline broken at bench:%d:%llu: %s\n", d,
                     (unsigned long long)r.seed, why.c_str());
        rc = 1;
      }
      if (r.ok) row.add(r);
    }
    rows.push_back(std::move(row));
  }
  // A row's name in the tables: N_d, with the model when several run.
  auto label = [&](const Row& r) {
    char buf[48];
    if (several)
      std::snprintf(buf, sizeof(buf), "%14s %3d", r.model.c_str(), r.n_dynamic);
    else
      std::snprintf(buf, sizeof(buf), "%5d", r.n_dynamic);
    return std::string(buf);
  };
  const std::string label_head = several ? "         model N_d" : "  N_d";
  auto mean = [](const std::vector<double>& v) {
    if (v.empty()) return double(NAN);
    double s = 0.0;
    for (double x : v) s += x;
    return s / double(v.size());
  };

  std::printf("\nFull-stack navigation on bench:<N_d>:<seed> (%d seeds from %llu, timeout %.0f s, %u hardware "
              "threads, %d jobs, %.1f s wall)\n",
              seeds, (unsigned long long)seed_base, timeout_s, std::thread::hardware_concurrency(), jobs,
              bench_wall_s);
  if (pipeline.serial)
    std::printf("serial: every node on the loop's thread, zero-latency bus\n");
  else
    std::printf("pipelined: perception and planner on threads of their own (per run), their outputs delivered "
                "%.0f ms and %.0f ms after their inputs (--serial: one thread)\n",
                1e-3 * double(pipeline.perception_delay_us), 1e-3 * double(pipeline.planner_delay_us));
  if (check_growth >= 0.0)
    std::printf("--check-growth %g: the post-check and the fallback grow every body by %g std of its predicted "
                "position, for every model\n", check_growth, check_growth);
  std::printf("%s %5s | %8s %5s %6s | %9s %9s | %6s %6s | %s\n", label_head.c_str(), "runs", "succ[%]", "coll", "tmout",
              "t_goal[s]", "t_goal_md", "RT x", "RT cpu", "median latency [ms]: driver/frame  perception/frame  "
              "planner/plan  controller/tick");
  for (const auto& r : rows) {
    std::printf("%s %5d | %8.1f %5d %6d | %9.1f %9.1f | %6.2f %6.2f | %8.3f %8.2f %8.2f %8.3f\n", label(r).c_str(), r.runs,
                r.runs ? 100.0 * r.successes / r.runs : NAN, r.collisions, r.timeouts, mean(r.ttg),
                percentile(r.ttg, 0.5), r.wall_s > 0 ? r.sim_s / r.wall_s : NAN,
                r.cpu_s > 0 ? r.sim_s / r.cpu_s : NAN, percentile(r.samples[0], 0.5),
                percentile(r.samples[1], 0.5), percentile(r.samples[2], 0.5), percentile(r.samples[3], 0.5));
  }
  std::printf("(RT x = simulated seconds / wall seconds of the whole loop, simulator included, per run;\n"
              " RT cpu = simulated seconds / CPU seconds of the run's threads together, i.e. of one core doing it all;\n"
              " coll = runs that ended in a collision; t_goal = mean / median over successful runs)\n");
  std::printf("collisions with movers / static obstacles:");
  for (const auto& r : rows)
    std::printf("  %sN_d=%d: %d / %d", several ? (r.model + " ").c_str() : "", r.n_dynamic, r.hit_mover, r.hit_static);
  std::printf("\n");
  std::printf("the movers hit, over the second before (up to 0.3 s before the hit): hidden (under 30 %% of it in the "
              "sensor's view at some moment) / else untracked / tracked poorly / tracked well (within 0.2 m and 0.35 m/s "
              "throughout):");
  for (const auto& r : rows)
    std::printf("  %sN_d=%d: %d / %d / %d / %d", several ? (r.model + " ").c_str() : "", r.n_dynamic, r.hit_hidden,
                r.hit_untracked, r.hit_tracked_poorly, r.hit_tracked_well);
  std::printf("\n");
  std::printf("of those, movers inside a static obstacle within the 2 s before the hit (bench worlds' movers walk through "
              "static obstacles, where no sensor sees them, and come out of them):");
  for (const auto& r : rows)
    std::printf("  %sN_d=%d: %d of %d (%.0f %% of the ground-truth steps of movers within 3 m closing in faster than "
                "0.5 m/s)",
                several ? (r.model + " ").c_str() : "", r.n_dynamic, r.hit_through_static, r.hit_mover,
                r.close_total ? 100.0 * double(r.close_through_static) / double(r.close_total) : NAN);
  std::printf("\n");
  std::printf("tracking, median over runs: recall (visible movers within 10 m with a track within 0.7 m) / "
              "velocity error of those within 5 m [m/s] / that error over the std the tracks state (1: consistent):");
  for (const auto& r : rows)
    std::printf("  %sN_d=%d: %.3f / %.3f / %.2f", several ? (r.model + " ").c_str() : "", r.n_dynamic,
                percentile(r.recall, 0.5), percentile(r.verr, 0.5),
                percentile(r.vcons, 0.5));
  std::printf("\n");
  std::printf("young tracks (at most %d frames old) of movers within 5 m, all runs: samples / rms velocity error [m/s] / "
              "that over the rms std they state (1: consistent):", TrackingTally::kYoungFrames);
  for (const auto& r : rows)
    std::printf("  %sN_d=%d: %lld / %.2f / %.2f", several ? (r.model + " ").c_str() : "", r.n_dynamic,
                static_cast<long long>(r.young.n), r.young.rmsError(), r.young.errorOverStd());
  std::printf("\n");
  std::printf("acquisition (movers coming into view within 6 m with no track within 0.5 m, all runs): arrivals / "
              "tracked within 0.25 s [%%] / median delay of those tracked [s] / left view or range untracked [%%]:");
  for (const auto& r : rows) {
    const auto n = static_cast<double>(r.acquireArrivals());
    std::printf("  %sN_d=%d: %.0f / %.1f / %.2f / %.1f", several ? (r.model + " ").c_str() : "", r.n_dynamic, n,
                n > 0 ? 100.0 * static_cast<double>(r.acquiredWithin(0.25)) / n : NAN, percentile(r.acquire_s, 0.5),
                n > 0 ? 100.0 * static_cast<double>(r.acquire_missed) / n : NAN);
  }
  std::printf("\n");
  std::printf("tracking, CLEAR-MOT median over runs (every mover within %.0f m of the robot, matched within %.0f m; "
              "hidden ones count as misses): MOTA / IDSW / FN / FP / MOTP [m]:",
              MissionAdapter::kMotRange, MissionAdapter::kMotThreshold);
  for (const auto& r : rows)
    std::printf("  %sN_d=%d: %.1f %% / %.0f / %.1f %% / %.1f %% / %.3f", several ? (r.model + " ").c_str() : "",
                r.n_dynamic, 100 * percentile(r.mota, 0.5), percentile(r.idsw, 0.5), 100 * percentile(r.fn_rate, 0.5),
                100 * percentile(r.fp_rate, 0.5), percentile(r.motp, 0.5));
  std::printf("\n");
  if (pipeline.serial)
    std::printf("\nWall time per simulated second [ms] (share of the loop): driver, perception, planner, "
                "controller, simulator+bus\n");
  else
    std::printf("\nWall time per simulated second [ms] (share of the run's wall time): nodes (perception and "
                "planner on their own threads, overlapping the loop), then the loop thread's waits for them and "
                "the rest of the loop thread (simulator+bus)\n");
  for (const auto& r : rows) {
    if (r.sim_s <= 0) continue;
    double on_loop = 0.0;
    std::printf("%s |", label(r).c_str());
    for (int k = 0; k < kNumStages; ++k) {
      if (pipeline.serial || k == 0 || k == 3) on_loop += r.stage_total_ms[k];
      std::printf(" %s %7.1f (%4.1f%%)", kStages[k], r.stage_total_ms[k] / r.sim_s,
                  100.0 * r.stage_total_ms[k] / (1e3 * r.wall_s));
    }
    if (!pipeline.serial) {
      on_loop += 1e3 * r.wait_s;
      std::printf(" | waiting %7.1f (%4.1f%%)", 1e3 * r.wait_s / r.sim_s, 100.0 * r.wait_s / r.wall_s);
    }
    const double rest = 1e3 * r.wall_s - on_loop;
    std::printf(" | rest %7.1f (%4.1f%%)\n", rest / r.sim_s, 100.0 * rest / (1e3 * r.wall_s));
  }
  std::printf("Node wall time per simulated second by input channel [ms]:\n");
  for (const auto& r : rows) {
    if (r.sim_s <= 0) continue;
    std::printf("%s |", label(r).c_str());
    for (int k = 1; k < kNumStages; ++k) {
      for (const auto& [ch, ms] : r.by_input_ms[k]) std::printf(" %s<-%s %.1f", kStages[k], ch.c_str(), ms / r.sim_s);
    }
    std::printf("\n");
  }
  std::printf("p95 latency [ms]:\n");
  for (const auto& r : rows) {
    std::printf("%s |", label(r).c_str());
    for (int k = 0; k < kNumStages; ++k) std::printf(" %s %8.3f", kStages[k], percentile(r.samples[k], 0.95));
    std::printf("\n");
  }

  // --faults: the faulty run of each seed against its fault-free pair.
  struct FaultRow {
    int n_dynamic = 0, runs = 0, successes = 0, hit_mover = 0, hit_static = 0, timeouts = 0;
    int free_successes = 0, lost = 0, won = 0;  ///< lost: fault-free succeeded, faulty did not; won: the reverse
    std::vector<double> ttg, dttg;              ///< faulty time to goal; faulty minus fault-free, both succeeded
    int64_t dropped = 0, delayed = 0, killed = 0, restarts = 0;
  };
  std::vector<FaultRow> fault_rows;
  if (setup.faults.any()) {
    for (int d : density_list) {
      FaultRow f;
      f.n_dynamic = d;
      for (std::size_t i = 0; i + 1 < results.size(); ++i) {
        if (tasks[i].faulty || !tasks[i + 1].faulty || tasks[i].n_dynamic != d) continue;
        const RunResult &a = results[i], &b = results[i + 1];
        if (!a.ok || !b.ok) continue;
        ++f.runs;
        f.successes += b.success;
        f.free_successes += a.success;
        f.timeouts += b.timeout;
        if (b.collision) (b.hit_mover ? f.hit_mover : f.hit_static) += 1;
        f.lost += a.success && !b.success;
        f.won += !a.success && b.success;
        if (b.success) f.ttg.push_back(b.time_to_goal_s);
        if (a.success && b.success) f.dttg.push_back(b.time_to_goal_s - a.time_to_goal_s);
        f.dropped += b.faults_dropped;
        f.delayed += b.faults_delayed;
        f.killed += b.faults_killed;
        f.restarts += b.faults_restarts;
      }
      fault_rows.push_back(f);
    }
    std::printf("\nWith faults '%s' (the same seeds; lost = succeeded without the faults, not with them; won = the "
                "reverse; dt_goal = time to goal with minus without, median over seeds that succeeded both ways)\n",
                setup.faults.text.c_str());
    std::printf("%5s %5s | %8s %8s | %5s %5s | %9s %6s | %9s %10s | per run: %8s %8s %7s %8s\n", "N_d", "runs",
                "succ[%]", "free[%]", "lost", "won", "coll m/s", "tmout", "t_goal_md", "dt_goal_md", "dropped", "late",
                "killed", "restarts");
    for (const auto& f : fault_rows) {
      const double n = f.runs ? double(f.runs) : NAN;
      std::printf("%5d %5d | %8.1f %8.1f | %5d %5d | %3d / %3d %6d | %9.1f %10.2f | per run: %8.0f %8.0f %7.0f %8.1f\n",
                  f.n_dynamic, f.runs, 100.0 * f.successes / n, 100.0 * f.free_successes / n, f.lost, f.won,
                  f.hit_mover, f.hit_static, f.timeouts, percentile(f.ttg, 0.5), percentile(f.dttg, 0.5),
                  double(f.dropped) / n, double(f.delayed) / n, double(f.killed) / n, double(f.restarts) / n);
    }
  }

  // --planner-model with several models: each against the first on the same seeds.
  struct PairRow {
    int n_dynamic = 0;
    std::size_t variant = 0;
    int runs = 0, first_ok = 0, other_ok = 0;
    int only_first = 0, only_other = 0;  ///< seeds only the first model / only this one succeeded on
    int first_hit_mover = 0, other_hit_mover = 0, first_hit_static = 0, other_hit_static = 0;
  };
  std::vector<PairRow> pair_rows;
  if (several) {
    std::map<std::tuple<int, uint64_t, std::size_t>, std::size_t> at;
    for (std::size_t i = 0; i < tasks.size(); ++i)
      if (!tasks[i].faulty) at[{tasks[i].n_dynamic, tasks[i].seed, tasks[i].variant}] = i;
    for (int d : density_list)
      for (std::size_t v = 1; v < variants.size(); ++v) {
        PairRow p;
        p.n_dynamic = d;
        p.variant = v;
        for (int k = 0; k < seeds; ++k) {
          const uint64_t seed = seed_base + uint64_t(k);
          const RunResult& a = results[at.at({d, seed, 0})];
          const RunResult& b = results[at.at({d, seed, v})];
          if (!a.ok || !b.ok) continue;
          ++p.runs;
          p.first_ok += a.success;
          p.other_ok += b.success;
          p.only_first += a.success && !b.success;
          p.only_other += !a.success && b.success;
          if (a.collision) (a.hit_mover ? p.first_hit_mover : p.first_hit_static) += 1;
          if (b.collision) (b.hit_mover ? p.other_hit_mover : p.other_hit_static) += 1;
        }
        pair_rows.push_back(p);
      }
    std::printf("\nPaired on the same seeds, each model against %s (only = seeds that model alone succeeded on; "
                "diff = success of the model minus %s with its 95 %% interval; p = McNemar's exact two-sided "
                "test on the discordant seeds; [lo, hi] = Wilson 95 %% intervals)\n",
                model_names[0].c_str(), model_names[0].c_str());
    std::printf("%5s %14s %5s | %22s %22s | %6s %6s | %23s %7s | %9s %9s\n", "N_d", "model", "runs",
                (model_names[0] + " [%]").c_str(), "model [%]", "only_r", "only_m", "diff [points]", "p",
                "coll ref", "coll mod");
    for (const auto& p : pair_rows) {
      const ucon::bench::Interval wf = ucon::bench::wilson(p.first_ok, p.runs);
      const ucon::bench::Interval wo = ucon::bench::wilson(p.other_ok, p.runs);
      const auto df = ucon::bench::pairedDifference(p.only_other, p.only_first, p.runs);
      const auto mc = ucon::bench::mcnemar(p.only_first, p.only_other);
      const double n = p.runs ? double(p.runs) : NAN;
      std::printf("%5d %14s %5d | %6.1f [%5.1f, %5.1f] %6.1f [%5.1f, %5.1f] | %6d %6d | %+6.1f [%+6.1f, %+6.1f] "
                  "%7.3f | %3d m %2d s %3d m %2d s\n",
                  p.n_dynamic, model_names[p.variant].c_str(), p.runs, 100.0 * p.first_ok / n, 100.0 * wf.lo,
                  100.0 * wf.hi, 100.0 * p.other_ok / n, 100.0 * wo.lo, 100.0 * wo.hi, p.only_first, p.only_other,
                  100.0 * df.diff, 100.0 * df.lo, 100.0 * df.hi, mc.exact_p, p.first_hit_mover, p.first_hit_static,
                  p.other_hit_mover, p.other_hit_static);
    }
  }

  if (!json_path.empty()) {
    std::ofstream js(json_path);
    js << "{\"results\": [";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      js << (i ? ",\n  " : "\n  ") << "{\"n_dynamic\": " << r.n_dynamic << ", \"planner_model\": \"" << r.model
         << "\", \"runs\": " << r.runs
         << ", \"success_rate\": " << num(r.runs ? double(r.successes) / r.runs : NAN)
         << ", \"collisions\": " << r.collisions << ", \"collisions_mover_hidden\": " << r.hit_hidden
         << ", \"collisions_mover_untracked\": " << r.hit_untracked
         << ", \"collisions_mover_tracked_poorly\": " << r.hit_tracked_poorly
         << ", \"collisions_mover_tracked_well\": " << r.hit_tracked_well
         << ", \"collisions_mover_through_static\": " << r.hit_through_static
         << ", \"close_encounters\": {\"steps\": " << r.close_total
         << ", \"inside_static_within_2_s\": " << r.close_through_static << "}"
         << ", \"time_to_goal_s\": " << num(mean(r.ttg))
         << ", \"realtime_factor\": " << num(r.wall_s > 0 ? r.sim_s / r.wall_s : NAN)
         << ", \"realtime_factor_cpu\": " << num(r.cpu_s > 0 ? r.sim_s / r.cpu_s : NAN)
         << ", \"pipelined\": " << (pipeline.serial ? "false" : "true")
         << ", \"tracking_recall\": " << num(percentile(r.recall, 0.5))
         << ", \"velocity_error_mps\": " << num(percentile(r.verr, 0.5))
         << ", \"acquisition\": {\"arrivals\": " << r.acquireArrivals() << ", \"tracked\": " << r.acquire_s.size()
         << ", \"tracked_within_0_25_s\": " << r.acquiredWithin(0.25) << ", \"median_delay_s\": " << num(percentile(r.acquire_s, 0.5)) << "}"
         << ", \"velocity_error_over_std\": " << num(percentile(r.vcons, 0.5))
         << ", \"young_tracks\": {\"samples\": " << r.young.n << ", \"velocity_rms_error_mps\": " << num(r.young.rmsError())
         << ", \"velocity_error_over_std\": " << num(r.young.errorOverStd()) << "}"
         << ", \"mota\": " << num(percentile(r.mota, 0.5)) << ", \"idsw\": " << num(percentile(r.idsw, 0.5))
         << ", \"fn_rate\": " << num(percentile(r.fn_rate, 0.5)) << ", \"fp_rate\": " << num(percentile(r.fp_rate, 0.5))
         << ", \"motp\": " << num(percentile(r.motp, 0.5)) << ", \"latency_ms\": {";
      for (int k = 0; k < kNumStages; ++k) {
        js << (k ? ", " : "") << "\"" << kStages[k] << "\": " << num(percentile(r.samples[k], 0.5));
      }
      js << "}}";
    }
    js << "\n]";
    js << ",\n \"check_growth\": " << (check_growth >= 0.0 ? num(check_growth) : "null");
    js << ",\n \"seed_base\": " << seed_base << ", \"seeds\": " << seeds;
    if (several) {
      js << ",\n \"paired\": {\"reference\": \"" << model_names[0] << "\", \"results\": [";
      for (std::size_t i = 0; i < pair_rows.size(); ++i) {
        const auto& p = pair_rows[i];
        const double n = p.runs ? double(p.runs) : NAN;
        const auto df = ucon::bench::pairedDifference(p.only_other, p.only_first, p.runs);
        const auto mc = ucon::bench::mcnemar(p.only_first, p.only_other);
        js << (i ? ",\n  " : "\n  ") << "{\"n_dynamic\": " << p.n_dynamic << ", \"planner_model\": \""
           << model_names[p.variant] << "\", \"runs\": " << p.runs
           << ", \"success_rate\": " << num(p.other_ok / n) << ", \"reference_success_rate\": " << num(p.first_ok / n)
           << ", \"only_reference\": " << p.only_first << ", \"only_model\": " << p.only_other
           << ", \"difference\": " << num(df.diff) << ", \"difference_ci95\": [" << num(df.lo) << ", " << num(df.hi)
           << "], \"mcnemar_exact_p\": " << num(mc.exact_p) << ", \"collisions_mover\": " << p.other_hit_mover
           << ", \"collisions_static\": " << p.other_hit_static
           << ", \"reference_collisions_mover\": " << p.first_hit_mover
           << ", \"reference_collisions_static\": " << p.first_hit_static << "}";
      }
      js << "\n ]}";
    }
    if (setup.faults.any()) {
      std::string spec;  // JSON string body
      for (const char c : setup.faults.text) {
        if (c == '"' || c == '\\') spec += '\\';
        if (static_cast<unsigned char>(c) >= 0x20) spec += c;
      }
      js << ",\n \"faults\": {\"spec\": \"" << spec << "\", \"results\": [";
      for (std::size_t i = 0; i < fault_rows.size(); ++i) {
        const auto& f = fault_rows[i];
        const double n = f.runs ? double(f.runs) : NAN;
        js << (i ? ",\n  " : "\n  ") << "{\"n_dynamic\": " << f.n_dynamic << ", \"runs\": " << f.runs
           << ", \"success_rate\": " << num(f.successes / n) << ", \"success_rate_fault_free\": "
           << num(f.free_successes / n) << ", \"lost\": " << f.lost << ", \"won\": " << f.won
           << ", \"collisions_mover\": " << f.hit_mover << ", \"collisions_static\": " << f.hit_static
           << ", \"timeouts\": " << f.timeouts << ", \"time_to_goal_s_median\": " << num(percentile(f.ttg, 0.5))
           << ", \"time_to_goal_delta_s_median\": " << num(percentile(f.dttg, 0.5))
           << ", \"per_run\": {\"dropped\": " << num(f.dropped / n) << ", \"late\": " << num(f.delayed / n)
           << ", \"killed\": " << num(f.killed / n) << ", \"restarts\": " << num(f.restarts / n) << "}}";
      }
      js << "\n ]}";
    }
    js << "\n}\n";
    js.close();
    if (!js) {
      std::fprintf(stderr, "ucon-bench-nav: cannot write %s\n", json_path.c_str());
      return 1;
    }
    std::printf("wrote %s\n", json_path.c_str());
  }
  return rc;
}
