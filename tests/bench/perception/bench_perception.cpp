// ucon-bench-perception: perception stability on the `pedestrians` scenario (paper Sec. V-B).
// The simulator's Mid-360 packets go through the driver's parser and frame assembly
// into two perception nodes in the same run — UCON and the FAPP-style baseline — and
// CLEAR-MOT compares their tracks with the simulator's ground truth. Prints a table, writes
// JSON, and reports per-frame latency (median, p99) of each node.
//
//   ucon-bench-perception [--json out.json] [--seeds N] [--seed-base B] [--quick]
//
// With --drive the robot drives a planned route through the scene instead (drive_eval.hpp):
// each seed is recorded once in-process, then replayed through every method and scored.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numeric>
#include <memory>
#include <string>
#include <vector>

#include "ucon/config.hpp"
#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/lidar_driver/lidar_driver_node.hpp"
#include "ucon/mot/clear_mot.hpp"
#include "ucon/mot/runtime_frames.hpp"
#include "ucon/perception/outputs.hpp"
#include "ucon/perception/perception_node.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/simulator/scenario_loader.hpp"
#include "ucon/simulator/simulator.hpp"
#include "../bench_util.hpp"
#include "drive_eval.hpp"

namespace {

using ucon::bench::percentile;

struct MethodResult {
  std::string method;
  int64_t seed = 0;
  ucon::mot::ClearMotSummary mot;
  double latency_median_ms = NAN;
  double latency_p99_ms = NAN;
  double points_per_frame = 0.0;  ///< raw points per frame given to the node
  int64_t frames = 0;
  int64_t invalid_frames = 0;
  int64_t reassociations = 0;
  double velocity_error_median = NAN;  ///< matches within 8 m of the robot [m/s]
  double velocity_error_p90 = NAN;
  double velocity_error_over = NAN;    ///< share of those matches off by more than 0.5 m/s
  double velocity_error_over_2sigma = NAN;  ///< share off by more than twice the track's own velocity std
};

struct Method {
  std::string name;
  std::unique_ptr<ucon::perception::PerceptionNode> node;
  ucon::mot::ClearMotAccumulator acc;
  std::vector<double> latency_ms;
  int64_t frames = 0, invalid = 0;
  double points = 0.0;
  std::map<int64_t, int64_t> last_match;  ///< trace: ground-truth id -> last matched track id
  std::vector<double> velocity_error;     ///< |v_track - v_true| of matches within 8 m of the robot [m/s]
  int64_t velocity_over_2sigma = 0;       ///< ... of those, off by more than twice the reported std
};

template <class P>
P loadOrDie(const std::string& path, const char* what) {
  auto p = ucon::runtime::loadConfigFile<P>("bench-perception", path);
  if (!p) {
    std::fprintf(stderr, "bench-perception: cannot load %s config '%s'\n", what, path.c_str());
    std::exit(2);
  }
  return *p;
}

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char b[64];
  std::snprintf(b, sizeof(b), "%.6g", v);
  return b;
}

/// Options of --drive.
struct DriveOptions {
  std::vector<std::string> scenes;
  std::vector<std::string> methods;
  int seeds = 3;
  int64_t seed_base = 1;
  double duration = 60.0;
  bool quick = false, all_gt = false;
  bool parked = false;
  std::string save_logs, json, source_dir, heading;
  std::string pose = "ground_truth";  ///< whose ROBOT_POSE the drive runs on: ground_truth | odometry
  ucon::bench::ScoreOptions score;
};

void mot(std::ostream& js, const ucon::mot::ClearMotSummary& m) {
  js << "{\"mota\": " << num(m.mota) << ", \"idsw\": " << m.num_switches << ", \"fn_rate\": " << num(m.fn_rate)
     << ", \"fp_rate\": " << num(m.fp_rate) << ", \"mismatch_rate\": " << num(m.mismatch_rate)
     << ", \"motp\": " << num(m.motp) << ", \"num_objects\": " << m.num_objects
     << ", \"num_ignored\": " << m.num_ignored << ", \"false_positives\": " << m.num_false_positives
     << ", \"misses\": " << m.num_misses << ", \"fragmentations\": " << m.num_fragmentations << "}";
}

/// `deploy/ucon bench perception --drive`: record each scene and seed once, score each method
/// by replay (drive_eval.hpp); prints a table per scene and the medians, writes JSON.
int runDrive(const DriveOptions& o, const ucon::simulator::SimulatorParams& sim_params,
             const ucon::lidar_driver::DriverParams& drv_params, const ucon::perception::PerceptionParams& perc_params) {
  namespace b = ucon::bench;
  const std::string cfg = o.source_dir + "/deploy/config/";
  b::DriveConfig dc;
  dc.sim = sim_params;
  dc.driver = drv_params;
  dc.perception = perc_params;
  dc.duration_s = o.duration;
  dc.heading_mode = o.heading;
  dc.parked = o.parked;
  std::string err;
  for (auto [name, text] : {std::pair<const char*, std::string*>{"planner", &dc.planner_yaml},
                            {"base_controller", &dc.base_controller_yaml}}) {
    auto t = ucon::runtime::readTextFile(cfg + name + ".yaml", &err);
    if (!t) {
      std::fprintf(stderr, "bench-perception: %s\n", err.c_str());
      return 2;
    }
    *text = *t;
  }
  if (o.pose == "odometry") {
    auto t = ucon::runtime::readTextFile(cfg + "odometry.yaml", &err);
    if (!t) {
      std::fprintf(stderr, "bench-perception: %s\n", err.c_str());
      return 2;
    }
    dc.odometry_yaml = *t;
  }
  std::vector<ucon::perception::PerceptionParams> params;
  for (const auto& m : o.methods) params.push_back(*b::methodParams(m, perc_params));

  struct Row {
    std::vector<std::string> top_statics;  ///< the static obstacles with the most false positives
    b::DriveStats stats;
    std::string scene;
    int64_t seed;
    b::MethodScore score;
  };
  std::vector<Row> rows;
  for (const std::string& scene : o.scenes) {
    for (int s = 0; s < o.seeds; ++s) {
      const int64_t seed = o.seed_base + s;
      // bench:<N_d> takes the seed as its generator seed; a named scenario as its timeline seed.
      const bool bench_world = scene.rfind("bench:", 0) == 0;
      const std::string spec = bench_world ? scene + ":" + std::to_string(seed) : scene;
      auto sc = ucon::simulator::loadScenario(spec, o.source_dir + "/deploy/scenarios", bench_world ? -1 : seed,
                                              ucon::runtime::readTextFile, &err);
      if (!sc) {
        std::fprintf(stderr, "bench-perception: %s\n", err.c_str());
        return 2;
      }
      if (!o.save_logs.empty()) {
        std::string f = spec;
        std::replace(f.begin(), f.end(), ':', '_');
        std::replace(f.begin(), f.end(), '/', '_');
        dc.save_log = o.save_logs + "/drive_" + f + "_" + std::to_string(seed) + ".lcm";
      }
      const auto t0 = std::chrono::steady_clock::now();
      auto rec = b::recordDrive(dc, *sc, spec, seed, &err);
      if (!rec) {
        std::fprintf(stderr, "bench-perception: %s\n", err.c_str());
        return 2;
      }
      const double rec_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const auto& st = rec->stats;
      std::fprintf(stderr,
                   "%s seed %lld: drove %.1f m in %.1f s (mean %.2f m/s, max %.2f m/s, max yaw rate %.2f rad/s, "
                   "moving %.0f %%, %lld goals, %lld collisions, pose error at most %.3f m), recording %016llx, "
                   "%.1f s wall\n",
                   scene.c_str(), static_cast<long long>(seed), st.path_m, st.sim_s, st.mean_speed, st.max_speed,
                   st.max_yaw_rate, 100 * st.moving_share, static_cast<long long>(st.goals_reached),
                   static_cast<long long>(st.collisions), st.pose_error_max, static_cast<unsigned long long>(st.digest),
                   rec_s);
      b::ScoreOptions score = o.score;
      score.trace_label = scene + ":" + std::to_string(seed);
      const auto scores = b::scoreRecording(*rec, o.methods, params, score);
      for (const auto& sc_m : scores) {
        std::vector<std::pair<int64_t, int>> top;
        for (const auto& [i, k] : sc_m.fp_per_static) top.emplace_back(-k, i);
        std::sort(top.begin(), top.end());
        std::vector<std::string> names;
        for (std::size_t j = 0; j < top.size() && j < 4; ++j) {
          const auto& so = rec->scenario.statics[static_cast<std::size_t>(top[j].second)];
          char buf[160];
          if (so.kind == ucon::world::ShapeKind::kCylinder)
            std::snprintf(buf, sizeof(buf), "cylinder r %.2f at (%.1f, %.1f): %lld", so.radius, so.center.x(),
                          so.center.y(), static_cast<long long>(-top[j].first));
          else
            std::snprintf(buf, sizeof(buf), "box %.1fx%.1f at (%.1f, %.1f): %lld", 2 * so.half_size.x(),
                          2 * so.half_size.y(), so.center.x(), so.center.y(), static_cast<long long>(-top[j].first));
          names.push_back(buf);
        }
        rows.push_back({names, st, scene, seed, sc_m});
        std::fprintf(stderr, "%s seed %lld %s: MOTA %.2f %% (visible %.2f %%) IDSW %lld, %lld track ids\n",
                     scene.c_str(), static_cast<long long>(seed), sc_m.method.c_str(), 100 * sc_m.all.mota,
                     100 * sc_m.visible.mota, static_cast<long long>(sc_m.all.num_switches),
                     static_cast<long long>(sc_m.track_ids));
      }
    }
  }

  const bool vis = !o.all_gt;
  std::printf("\nPerception from a moving robot (--drive, heading %s, pose %s): %d seed(s) from %lld, %.1f s per "
              "drive, CLEAR-MOT threshold %.2f m, movers within %.1f m scored%s\n",
              o.parked ? "parked: no route" : o.heading.empty() ? "as configured" : o.heading.c_str(),
              o.pose.c_str(), o.seeds, static_cast<long long>(o.seed_base),
              o.duration, o.score.threshold_m, o.score.max_range_m,
              vis ? ("; 'vis': only movers with >= " + std::to_string(o.score.min_visible_points) +
                     " LiDAR returns in the node's frames")
                        .c_str()
                  : "");
  std::printf("%-12s %4s %-14s %7s %5s %6s %6s %6s %7s %7s %5s %6s %6s %6s %7s %7s %7s %6s\n", "scene", "seed",
              "method", "MOTA%", "IDSW", "FN%", "FP%", "MOTP_m", "visMOTA", "visIDSW", "visFN", "visFP", "ids",
              "dv_med", "dv_p90", "dv>0.5", "lat_med", "lat99");
  for (const auto& r : rows) {
    const auto& a = r.score.all;
    const auto& v = r.score.visible;
    std::printf("%-12s %4lld %-14s %7.2f %5lld %6.2f %6.2f %6.3f ", r.scene.c_str(), static_cast<long long>(r.seed),
                r.score.method.c_str(), 100 * a.mota, static_cast<long long>(a.num_switches), 100 * a.fn_rate,
                100 * a.fp_rate, a.motp);
    if (vis)
      std::printf("%7.2f %7lld %5.1f %6.2f ", 100 * v.mota, static_cast<long long>(v.num_switches), 100 * v.fn_rate,
                  100 * v.fp_rate);
    else
      std::printf("%7s %7s %5s %6s ", "-", "-", "-", "-");
    std::printf("%6lld %6.3f %7.3f %6.1f%% %7.3f %6.2f\n", static_cast<long long>(r.score.track_ids),
                r.score.velocity_error_median, r.score.velocity_error_p90, 100 * r.score.velocity_error_over,
                r.score.latency_median_ms, r.score.latency_p99_ms);
  }
  std::printf("\nmedian over seeds (latency: wall time per frame on this machine, noisy when it is shared):\n");
  std::map<std::pair<std::string, std::string>, std::vector<const Row*>> by;
  for (const auto& r : rows) by[{r.scene, r.score.method}].push_back(&r);
  for (const auto& [key, rs] : by) {
    std::vector<double> mota, vmota, idsw, vidsw, fn, fp, motp, dv, lat, ids;
    double worst = INFINITY, vworst = INFINITY;
    for (const Row* r : rs) {
      mota.push_back(r->score.all.mota);
      vmota.push_back(r->score.visible.mota);
      worst = std::min(worst, r->score.all.mota);
      vworst = std::min(vworst, r->score.visible.mota);
      idsw.push_back(static_cast<double>(r->score.all.num_switches));
      vidsw.push_back(static_cast<double>(r->score.visible.num_switches));
      fn.push_back(r->score.all.fn_rate);
      fp.push_back(r->score.all.fp_rate);
      motp.push_back(r->score.all.motp);
      dv.push_back(r->score.velocity_error_median);
      lat.push_back(r->score.latency_median_ms);
      ids.push_back(static_cast<double>(r->score.track_ids));
    }
    std::printf("  %-12s %-14s MOTA %.2f %% (min %.2f)  IDSW %.1f  FN %.2f %%  FP %.2f %%  MOTP %.3f m  track ids %.0f",
                key.first.c_str(), key.second.c_str(), 100 * percentile(mota, 0.5), 100 * worst,
                percentile(idsw, 0.5), 100 * percentile(fn, 0.5), 100 * percentile(fp, 0.5), percentile(motp, 0.5),
                percentile(ids, 0.5));
    if (vis)
      std::printf("  | visible: MOTA %.2f %% (min %.2f) IDSW %.1f", 100 * percentile(vmota, 0.5), 100 * vworst,
                  percentile(vidsw, 0.5));
    std::printf("  | dv median %.3f m/s  latency median %.3f ms\n", percentile(dv, 0.5), percentile(lat, 0.5));
  }
  // Where the false positives come from: visibility-aware FP per frame by the robot's motion.
  std::printf("\nfalse positives per frame (visibility-aware) by robot speed [m/s] x yaw rate [rad/s], all seeds:\n");
  const char* sb[3] = {"v<0.1", "v<0.75", "v>=0.75"};
  const char* yb[3] = {"w<0.2", "w<0.6", "w>=0.6"};
  std::map<std::pair<std::string, std::string>, std::pair<std::array<int64_t, 9>, std::array<int64_t, 9>>> fpm;
  for (const auto& r : rows) {
    auto& e = fpm[{r.scene, r.score.method}];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        e.first[3 * i + j] += r.score.fp_frames[i][j];
        e.second[3 * i + j] += r.score.fp_count[i][j];
      }
  }
  for (const auto& [key, e] : fpm) {
    std::printf("  %-12s %-14s", key.first.c_str(), key.second.c_str());
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (e.first[3 * i + j] > 0)
          std::printf(" %s,%s: %.3f (%lld fr)", sb[i], yb[j],
                      static_cast<double>(e.second[3 * i + j]) / static_cast<double>(e.first[3 * i + j]),
                      static_cast<long long>(e.first[3 * i + j]));
    std::printf("\n");
  }

  std::printf("\nvisibility-aware false positives: on static structure (within %.1f m of its footprint) / near a "
              "mover (1.5 m) / elsewhere; the static obstacles with the most:\n",
              o.score.static_fp_distance);
  for (const auto& r : rows) {
    std::printf("  %-12s %4lld %-14s %6lld / %6lld / %6lld; on static: %lld tracks, age %.0f frames, %.2f m/s, "
                "%.0f %% coasting",
                r.scene.c_str(), static_cast<long long>(r.seed), r.score.method.c_str(),
                static_cast<long long>(r.score.fp_on_static), static_cast<long long>(r.score.fp_near_mover),
                static_cast<long long>(r.score.fp_elsewhere), static_cast<long long>(r.score.fp_static_tracks),
                r.score.fp_static_age_median, r.score.fp_static_speed_median, 100 * r.score.fp_static_coasting_share);
    for (const auto& n : r.top_statics) std::printf("  [%s]", n.c_str());
    std::printf("\n");
  }

  std::printf("\nvisibility-aware misses by cause, all seeds (object-frames of visible movers left unmatched; "
              "first cause that applies, by the mover's range: < 6 / 6-9 / 9-12 / >= 12 m):\n");
  std::map<std::pair<std::string, std::string>, std::array<std::array<int64_t, ucon::bench::kMissRangeBands>, ucon::bench::kMissCauses>> mc;
  for (const auto& r : rows) {
    auto& e = mc[{r.scene, r.score.method}];
    for (int c = 0; c < ucon::bench::kMissCauses; ++c)
      for (int b = 0; b < ucon::bench::kMissRangeBands; ++b) e[c][b] += r.score.miss_causes[c][b];
  }
  for (const auto& [key, e] : mc) {
    int64_t total = 0;
    for (const auto& c : e) total = std::accumulate(c.begin(), c.end(), total);
    std::printf("  %-12s %-14s %lld missed\n", key.first.c_str(), key.second.c_str(), static_cast<long long>(total));
    for (int c = 0; c < ucon::bench::kMissCauses; ++c) {
      const int64_t n = std::accumulate(e[c].begin(), e[c].end(), int64_t{0});
      std::printf("      %-20s %5.1f %%  %6lld / %6lld / %6lld / %6lld\n", ucon::bench::missCauseName(static_cast<ucon::bench::MissCause>(c)),
                  total > 0 ? 100.0 * static_cast<double>(n) / static_cast<double>(total) : 0.0,
                  static_cast<long long>(e[c][0]), static_cast<long long>(e[c][1]), static_cast<long long>(e[c][2]),
                  static_cast<long long>(e[c][3]));
    }
  }

  std::printf("\nwhat the sensor allowed, all seeds (object-frames of the scored movers with >= %d returns in the "
              "node's frames / >= %d / so within the method's coast time before / so at any time before: the plain "
              "MOTA cannot exceed this / predictable: visible, or where its last view, known exactly, puts it at its "
              "velocity then or at rest, within the match distance):\n",
              o.score.min_visible_points, ucon::bench::kWellSeenPoints);
  std::map<std::pair<std::string, std::string>, ucon::bench::MethodScore::SensorShare> ss;
  for (const auto& r : rows) ss[{r.scene, r.score.method}] += r.score.sensor;
  for (const auto& [key, e] : ss) {
    const double n = e.objects > 0 ? static_cast<double>(e.objects) : NAN;
    std::printf("  %-12s %-14s %8lld object-frames: visible %5.1f %%, well seen %5.1f %%, held %5.1f %%, seen before "
                "%5.1f %%, predictable %5.1f %%\n",
                key.first.c_str(), key.second.c_str(), static_cast<long long>(e.objects),
                100 * static_cast<double>(e.visible) / n, 100 * static_cast<double>(e.well_seen) / n,
                100 * static_cast<double>(e.held) / n, 100 * static_cast<double>(e.seen) / n,
                100 * static_cast<double>(e.predictable) / n);
  }

  if (!o.json.empty()) {
    std::ofstream js(o.json);
    js << "{\"mode\": \"drive\", \"scenes\": [";
    for (std::size_t i = 0; i < o.scenes.size(); ++i) js << (i ? ", " : "") << "\"" << o.scenes[i] << "\"";
    js << "], \"heading\": \"" << (o.heading.empty() ? "configured" : o.heading)
       << "\", \"pose\": \"" << o.pose << "\", \"parked\": " << (o.parked ? "true" : "false") << ", \"seeds\": " << o.seeds << ", \"seed_base\": " << o.seed_base << ", \"duration_s\": " << num(o.duration)
       << ", \"threshold_m\": " << num(o.score.threshold_m) << ", \"max_range_m\": " << num(o.score.max_range_m)
       << ", \"min_visible_points\": " << o.score.min_visible_points;
    // Medians over seeds per scene and method (the figures of record), the drives, then every
    // run: flat figures first, the full CLEAR-MOT counts of both scores nested.
    js << ", \"summary\": [";
    bool first = true;
    for (const auto& [key, rs] : by) {
      std::vector<double> v[12];
      double worst = INFINITY, vworst = INFINITY;
      for (const Row* r : rs) {
        const auto& a = r->score.all;
        const auto& w = r->score.visible;
        const double f[12] = {a.mota, static_cast<double>(a.num_switches), a.fn_rate, a.fp_rate, a.motp, w.mota,
                              static_cast<double>(w.num_switches), w.fn_rate, w.fp_rate,
                              static_cast<double>(r->score.track_ids), r->score.velocity_error_median,
                              r->score.latency_median_ms};
        for (int k = 0; k < 12; ++k) v[k].push_back(f[k]);
        worst = std::min(worst, a.mota);
        vworst = std::min(vworst, w.mota);
      }
      js << (first ? "\n  " : ",\n  ") << "{\"scene\": \"" << key.first << "\", \"method\": \"" << key.second
         << "\", \"runs\": " << rs.size() << ", \"mota\": " << num(percentile(v[0], 0.5)) << ", \"mota_min\": "
         << num(worst) << ", \"idsw\": " << num(percentile(v[1], 0.5)) << ", \"fn_rate\": "
         << num(percentile(v[2], 0.5)) << ", \"fp_rate\": " << num(percentile(v[3], 0.5)) << ", \"motp\": "
         << num(percentile(v[4], 0.5)) << ", \"vis_mota\": " << num(percentile(v[5], 0.5)) << ", \"vis_mota_min\": "
         << num(vworst) << ", \"vis_idsw\": " << num(percentile(v[6], 0.5)) << ", \"vis_fn_rate\": "
         << num(percentile(v[7], 0.5)) << ", \"vis_fp_rate\": " << num(percentile(v[8], 0.5))
         << ", \"track_ids\": " << num(percentile(v[9], 0.5)) << ", \"velocity_error_median\": "
         << num(percentile(v[10], 0.5)) << ", \"latency_ms_median\": " << num(percentile(v[11], 0.5)) << "}";
      first = false;
    }
    js << "], \"drives\": [";
    first = true;
    for (const auto& r : rows) {
      if (r.score.method != o.methods.front()) continue;
      const auto& st = r.stats;
      char dig[32];
      std::snprintf(dig, sizeof(dig), "%016llx", static_cast<unsigned long long>(st.digest));
      js << (first ? "\n  " : ",\n  ") << "{\"scene\": \"" << r.scene << "\", \"seed\": " << r.seed
         << ", \"sim_s\": " << num(st.sim_s) << ", \"path_m\": " << num(st.path_m)
         << ", \"mean_speed\": " << num(st.mean_speed) << ", \"max_speed\": " << num(st.max_speed)
         << ", \"max_yaw_rate\": " << num(st.max_yaw_rate) << ", \"moving_share\": " << num(st.moving_share)
         << ", \"goals_reached\": " << st.goals_reached << ", \"collisions\": " << st.collisions
         << ", \"pose_error_max_m\": " << num(st.pose_error_max) << ", \"recording_digest\": \"" << dig << "\"}";
      first = false;
    }
    js << "], \"results\": [";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      const auto& a = r.score.all;
      const auto& w = r.score.visible;
      char odig[32];
      std::snprintf(odig, sizeof(odig), "%016llx", static_cast<unsigned long long>(r.score.output_digest));
      js << (i ? ",\n  " : "\n  ") << "{\"scene\": \"" << r.scene << "\", \"seed\": " << r.seed << ", \"method\": \""
         << r.score.method << "\", \"mota\": " << num(a.mota) << ", \"idsw\": " << a.num_switches
         << ", \"fn_rate\": " << num(a.fn_rate) << ", \"fp_rate\": " << num(a.fp_rate) << ", \"motp\": " << num(a.motp)
         << ", \"vis_mota\": " << num(w.mota) << ", \"vis_idsw\": " << w.num_switches
         << ", \"vis_fn_rate\": " << num(w.fn_rate) << ", \"vis_fp_rate\": " << num(w.fp_rate)
         << ", \"track_ids\": " << r.score.track_ids << ", \"velocity_error_median\": " << num(r.score.velocity_error_median)
         << ", \"velocity_error_p90\": " << num(r.score.velocity_error_p90)
         << ", \"velocity_error_over_0_5\": " << num(r.score.velocity_error_over)
         << ", \"latency_ms_median\": " << num(r.score.latency_median_ms)
         << ", \"latency_ms_p99\": " << num(r.score.latency_p99_ms)
         << ", \"fp_on_static\": " << r.score.fp_on_static << ", \"fp_near_mover\": " << r.score.fp_near_mover
         << ", \"fp_elsewhere\": " << r.score.fp_elsewhere << ", \"fp_static_tracks\": " << r.score.fp_static_tracks
         << ", \"fp_static_age_median\": " << num(r.score.fp_static_age_median)
         << ", \"fp_static_speed_median\": " << num(r.score.fp_static_speed_median)
         << ", \"fp_static_coasting_share\": " << num(r.score.fp_static_coasting_share)
         << ", \"frames\": " << r.score.frames
         << ", \"invalid_frames\": " << r.score.invalid_frames << ", \"objects_digest\": \"" << odig << "\", \"all\": ";
      mot(js, a);
      js << ", \"visible\": ";
      mot(js, w);
      js << ", \"miss_causes\": {";
      for (int c = 0; c < ucon::bench::kMissCauses; ++c) {
        js << (c ? ", " : "") << "\"" << ucon::bench::missCauseName(static_cast<ucon::bench::MissCause>(c)) << "\": [";
        for (int b = 0; b < ucon::bench::kMissRangeBands; ++b) js << (b ? ", " : "") << r.score.miss_causes[c][b];
        js << "]";
      }
      js << "}";
      const auto& sh = r.score.sensor;
      js << ", \"sensor\": {\"objects\": " << sh.objects << ", \"visible\": " << sh.visible
         << ", \"well_seen\": " << sh.well_seen << ", \"held\": " << sh.held << ", \"seen\": " << sh.seen << ", \"predictable\": " << sh.predictable << "}";
      js << ", \"fp_top_statics\": [";
      for (std::size_t j = 0; j < r.top_statics.size(); ++j) js << (j ? ", " : "") << "\"" << r.top_statics[j] << "\"";
      js << "], \"fp_by_motion\": {\"speed_bins\": [\"v<0.1\", \"v<0.75\", \"v>=0.75\"], \"yaw_rate_bins\": "
            "[\"w<0.2\", \"w<0.6\", \"w>=0.6\"], \"frames\": [";
      for (int k = 0; k < 9; ++k) js << (k ? ", " : "") << r.score.fp_frames[k / 3][k % 3];
      js << "], \"false_positives\": [";
      for (int k = 0; k < 9; ++k) js << (k ? ", " : "") << r.score.fp_count[k / 3][k % 3];
      js << "]}}";
    }
    js << "\n]}\n";
    if (!js) {
      std::fprintf(stderr, "bench-perception: cannot write '%s'\n", o.json.c_str());
      return 2;
    }
  }
  if (o.quick) {
    // Sanity for ctest: the robot drove, every method published valid frames, UCON tracked.
    bool ok = true;
    for (const auto& r : rows) {
      ok = ok && (o.parked || r.stats.path_m > 2.0) && r.score.frames > 0.9 * o.duration * sim_params.frame_rate_hz &&
           r.score.invalid_frames <= 2;
      if (r.score.method == "ucon") ok = ok && r.score.all.num_objects > 0 && r.score.visible.mota > 0.3;
    }
    std::printf("quick sanity: %s\n", ok ? "ok" : "FAILED");
    return ok ? 0 : 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Perception stability benchmark: UCON vs FAPP-style association on `pedestrians`."};
  std::string json_path, source_dir = UCON_SOURCE_DIR, scenario = "pedestrians";
  int seeds = 3;
  int64_t seed_base = 1;
  bool quick = false;
  double duration = 0.0, threshold = 1.0;
  app.add_option("--json", json_path, "write the results as JSON to this file");
  app.add_option("--seeds", seeds, "number of worlds (seeds B .. B+N-1)")->check(CLI::Range(1, 1000));
  app.add_option("--seed-base", seed_base, "first seed B");
  app.add_flag("--quick", quick, "one short seed (20 s) with sanity checks: the ctest mode");
  app.add_option("--duration", duration, "simulated seconds per run (default: the scenario's, 243 s)");
  app.add_option("--threshold", threshold, "CLEAR-MOT x-y match distance [m]")->check(CLI::PositiveNumber);
  app.add_option("--scenario", scenario, "scenario name or file");
  app.add_option("--source-dir", source_dir, "repository root (configs and scenarios)");
  std::string trace_path;
  bool all_gt = false;
  int frame_rate = 50;
  app.add_option("--frame-rate", frame_rate, "LiDAR frame rate [Hz]: 50 (default), 20 or 10")
      ->check(CLI::IsMember({10, 20, 50}));
  std::vector<std::string> method_names{"ucon", "fapp"};
  app.add_option("--methods", method_names, "methods to run: ucon, fapp, ucon-noreassoc (ablation)")
      ->delimiter(',')
      ->check(CLI::IsMember({"ucon", "fapp", "ucon-noreassoc"}));
  int min_visible = 3;
  app.add_flag("--all-gt", all_gt, "score every ground-truth object, also those the sensor cannot see");
  app.add_option("--min-visible-points", min_visible,
                 "a ground-truth object with fewer LiDAR returns in a frame is not scored")
      ->check(CLI::Range(1, 1000));
  app.add_option("--trace", trace_path,
                 "write every FP, FN, identity switch and velocity error above 0.5 m/s to this text file (with --drive: "
                 "one line each, led by scene:seed and the method; misses of visible movers with their cause, "
                 "visibility-aware false positives)");
  bool drive = false;
  std::string save_logs;
  app.add_flag("--drive", drive,
               "the robot drives a planned route (the scenario's goals and back, planner and base controller "
               "on ground truth); each seed is recorded once, then replayed through every method. --scenario "
               "takes a comma list (pedestrians, bench:50, bench:80, bench:110, a file); default duration 60 s, "
               "methods ucon,fapp,ucon-noreassoc; both the plain and the visibility-aware score are printed");
  app.add_option("--save-logs", save_logs, "--drive: also write each recording as an LCM log into this folder");
  bool parked = false;
  app.add_flag("--parked", parked,
               "--drive: no route, the robot stays at its start (a control run of the same recording and "
               "scoring with the sensor parked)");
  std::string heading;
  app.add_option("--heading", heading,
                 "--drive: the base's heading: hold (keeps it, as shipped) or path (faces its velocity: the "
                 "sensor turns at every goal and along curves); default as in base_controller.yaml")
      ->check(CLI::IsMember({"hold", "path"}));
  std::string pose_source = "ground_truth";
  app.add_option("--pose", pose_source,
                 "--drive: whose ROBOT_POSE the drive runs on: ground_truth (the simulator's) or odometry "
                 "(ucon-odometry on the emulated Mid-360, as on the robot: planner, controller and every "
                 "perception method use it)")
      ->check(CLI::IsMember({"ground_truth", "odometry"}));
  CLI11_PARSE(app, argc, argv);
  std::unique_ptr<FILE, int (*)(FILE*)> trace_file(nullptr, &std::fclose);
  if (!trace_path.empty()) {
    trace_file.reset(std::fopen(trace_path.c_str(), "w"));
    if (!trace_file) {
      std::fprintf(stderr, "bench-perception: cannot write %s\n", trace_path.c_str());
      return 2;
    }
  }
  FILE* trace = trace_file.get();
  if (quick) {
    seeds = 1;
    if (duration <= 0.0) duration = drive ? 8.0 : 20.0;
  }

  const std::string cfg = source_dir + "/deploy/config/";
  auto sim_params = loadOrDie<ucon::simulator::SimulatorParams>(cfg + "simulator.yaml", "simulator");
  auto drv_params = loadOrDie<ucon::lidar_driver::DriverParams>(cfg + "lidar_driver.yaml", "driver");
  auto perc_params = loadOrDie<ucon::perception::PerceptionParams>(cfg + "perception.yaml", "perception");
  if (frame_rate != 50) {
    // 10/20 Hz frames hold 5/2.5 times the points: no accumulation needed.
    sim_params.frame_rate_hz = frame_rate;
    drv_params.frame.rate_hz = frame_rate;
    perc_params.preprocess.accumulate_frames = 1;
  }

  if (drive) {
    DriveOptions o;
    o.scenes = ucon::bench::split(scenario);
    o.methods = app.count("--methods") ? method_names : std::vector<std::string>{"ucon", "fapp", "ucon-noreassoc"};
    o.seeds = seeds;
    o.seed_base = seed_base;
    o.duration = duration > 0.0 ? duration : 60.0;
    o.quick = quick;
    o.all_gt = all_gt;
    o.save_logs = save_logs;
    o.heading = heading;
    o.pose = pose_source;
    o.parked = parked;
    o.json = json_path;
    o.source_dir = source_dir;
    o.score.threshold_m = threshold;
    o.score.max_range_m = perc_params.preprocess.max_range;
    o.score.min_visible_points = min_visible;
    o.score.trace = trace;
    return runDrive(o, sim_params, drv_params, perc_params);
  }

  std::vector<MethodResult> results;
  for (int s = 0; s < seeds; ++s) {
    const int64_t seed = seed_base + s;
    std::string err;
    auto sc = ucon::simulator::loadScenario(scenario, source_dir + "/deploy/scenarios", seed,
                                            ucon::runtime::readTextFile, &err);
    if (!sc) {
      std::fprintf(stderr, "bench-perception: %s\n", err.c_str());
      return 2;
    }
    const double run_s = duration > 0.0 ? duration : sc->duration_s;
    ucon::simulator::SimOptions so;
    so.make_packets = true;
    so.make_frames = false;
    ucon::simulator::Simulator sim(sim_params, *sc, so);
    ucon::lidar_driver::LidarDriverNode driver(drv_params);

    std::vector<Method> methods;
    for (const std::string& m : method_names) {
      auto p = perc_params;
      p.association = m == "fapp" ? "fapp" : "ucon";
      if (m == "ucon-noreassoc") p.reassociation.enabled = false;
      Method mm;
      mm.name = m;
      mm.node = std::make_unique<ucon::perception::PerceptionNode>(p);
      methods.push_back(std::move(mm));
    }
    ucon::mot::RuntimeEvalOptions eval;
    eval.threshold_m = threshold;
    eval.max_range_m = perc_params.preprocess.max_range;
    std::map<int64_t, ucon::sim_ground_truth_t> gts;  // by utime

    ucon::simulator::SimOutputs out;
    ucon::lidar_driver::DriverOutputs dout;
    const int64_t step_us = static_cast<int64_t>(1e6 / sim_params.frame_rate_hz);
    const int64_t end_utime = sim.utime() + static_cast<int64_t>(run_s * 1e6);
    auto handle_cloud = [&](const ucon::point_cloud_t& cloud) {
      // Which ground-truth objects the sensor saw in this frame (>= min_visible_points returns
      // on the body): the others are not scored (KITTI/TrackEval "don't care" objects).
      std::map<int64_t, int> hits;
      if (auto g = gts.find(cloud.utime); g != gts.end()) {
        const double c = std::cos(g->second.robot_yaw), sn = std::sin(g->second.robot_yaw);
        for (int i = 0; i < cloud.num_points; ++i) {
          if (cloud.z[i] < 0.1f) continue;
          const double wx = g->second.robot_x + c * cloud.x[i] - sn * cloud.y[i];
          const double wy = g->second.robot_y + sn * cloud.x[i] + c * cloud.y[i];
          for (const auto& o : g->second.objects)
            if (std::hypot(wx - o.x, wy - o.y) <= o.radius + 0.15 && cloud.z[i] <= o.height + 0.1) ++hits[o.id];
        }
      }
      for (auto& m : methods) {
        const auto t0 = std::chrono::steady_clock::now();
        const auto o = m.node->onPoints(cloud);
        const auto t1 = std::chrono::steady_clock::now();
        if (!o.objects) continue;
        ++m.frames;
        m.points += cloud.num_points;
        m.latency_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        if (!o.objects->valid) ++m.invalid;
        auto g = gts.find(o.objects->utime);
        if (g == gts.end()) {
          // Frames start on ground-truth instants; otherwise take the nearest earlier one.
          g = gts.upper_bound(o.objects->utime);
          if (g == gts.begin()) continue;
          --g;
        }
        const auto gt_now = ucon::mot::groundTruthAt(g->second, o.objects->utime, eval);
        std::vector<char> hidden(gt_now.size(), 0);
        for (std::size_t k = 0; k < gt_now.size(); ++k) hidden[k] = (all_gt || hits[gt_now[k].id] >= min_visible) ? 0 : 1;
        const auto ev = m.acc.updateXY(gt_now, ucon::mot::hypothesesOf(*o.objects, eval), eval.threshold_m,
                                       &hidden);
        // Velocity error of the matches near the robot (what the planner acts on).
        for (const auto& mt : ev.matches) {
          const ucon::sim_object_t* go = nullptr;
          for (const auto& q : g->second.objects)
            if (q.id == mt.first) go = &q;
          if (go == nullptr || std::hypot(go->x - g->second.robot_x, go->y - g->second.robot_y) > 8.0) continue;
          for (const auto& t : o.objects->objects) {
            if (t.id != mt.second) continue;
            const double e = std::hypot(t.vx - go->vx, t.vy - go->vy);
            m.velocity_error.push_back(e);
            // The track's own velocity std (mean of the x and y variances): is the error it
            // reports to the planner the error it has?
            ucon::kalman::Cov6 P;
            const double sv = ucon::perception::covarianceOf(t, &P) ? std::sqrt(0.5 * (P(3, 3) + P(4, 4))) : NAN;
            if (!(e <= 2.0 * sv)) ++m.velocity_over_2sigma;
            if (trace && e > 0.5)
              std::fprintf(trace, "%s dv %.2f gt %lld track %lld err %.2f v %.2f %.2f true %.2f %.2f age %d assoc %d pts %d st %d off %.2f sv %.2f\n",
                           m.name.c_str(), sim.simTime(), static_cast<long long>(mt.first),
                           static_cast<long long>(mt.second), e, t.vx, t.vy, go->vx, go->vy, t.age_frames,
                           t.last_association, t.num_points, int(t.state), std::hypot(t.x - go->x, t.y - go->y), sv);
          }
        }
        if (trace) {
          // One state line per frame: every scored ground-truth object and every published track.
          std::fprintf(trace, "%s frame %.2f", m.name.c_str(), sim.simTime());
          for (std::size_t k = 0; k < gt_now.size(); ++k)
            std::fprintf(trace, " g%lld %.2f %.2f%s", static_cast<long long>(gt_now[k].id), gt_now[k].x, gt_now[k].y,
                         hidden[k] ? "h" : "");
          for (const auto& t : o.objects->objects)
            std::fprintf(trace, " t%lld %.2f %.2f %.2f %.2f a%d", static_cast<long long>(t.id), t.x, t.y, t.vx, t.vy,
                         t.last_association);
          std::fprintf(trace, "\n");
          for (int64_t id : ev.false_positives)
            for (const auto& t : o.objects->objects)
              if (t.id == id)
                std::fprintf(trace, "%s fp %.2f id %lld x %.2f y %.2f v %.2f age %d pts %d assoc %d\n",
                             m.name.c_str(), sim.simTime(),
                             static_cast<long long>(id), t.x, t.y, std::hypot(t.vx, t.vy), t.age_frames,
                             t.num_points, t.last_association);
          for (const auto& sw : ev.switches) {
            const int64_t old_id = m.last_match[sw.first];
            int old_state = 0;
            for (const auto& t : o.objects->objects)
              if (t.id == old_id) old_state = t.state;
            std::fprintf(trace, "%s idsw %.2f gt %lld -> %lld (was %lld, now %s)\n", m.name.c_str(), sim.simTime(),
                         static_cast<long long>(sw.first), static_cast<long long>(sw.second),
                         static_cast<long long>(old_id), old_state == 0 ? "gone" : std::to_string(old_state).c_str());
          }
          for (const auto& mt : ev.matches) m.last_match[mt.first] = mt.second;
          for (int64_t id : ev.misses) {
            // The detection nearest to the missed object: why was it not a track?
            const auto gtp = ucon::mot::groundTruthAt(g->second, o.objects->utime, eval);
            double gx = 0, gy = 0;
            for (const auto& q : gtp)
              if (q.id == id) gx = q.x, gy = q.y;
            const ucon::perception::Detection* best = nullptr;
            double bd = 1e9;
            for (const auto& d : m.node->lastDetections()) {
              const double dd = std::hypot(d.box.center.x() - gx, d.box.center.y() - gy);
              if (dd < bd) bd = dd, best = &d;
            }
            std::fprintf(trace, "%s fn %.2f gt %lld at %.2f %.2f range %.2f", m.name.c_str(), sim.simTime(),
                         static_cast<long long>(id), gx, gy,
                         std::hypot(gx - g->second.robot_x, gy - g->second.robot_y));
            if (best)
              std::fprintf(trace, " det %.2f m pts %zu size %.2f %.2f z %.2f-%.2f ok %d moving %d supp %d",
                           bd, best->indices.size(), best->box.size.x(), best->box.size.y(), best->min_z,
                           best->max_z, best->size_ok, best->moving, best->supported);
            // The nearest published track (any state): matched elsewhere, tentative or too far?
            const ucon::tracked_object_t* nt = nullptr;
            double nd = 1e9;
            for (const auto& t : o.objects->objects) {
              const double dd = std::hypot(t.x - gx, t.y - gy);
              if (dd < nd) nd = dd, nt = &t;
            }
            if (nt)
              std::fprintf(trace, " track %lld %.2f m st %d assoc %d", static_cast<long long>(nt->id), nd,
                           int(nt->state), int(nt->last_association));
            std::fprintf(trace, "\n");
          }
        }
      }
    };
    while (sim.utime() < end_utime) {
      out.clear();
      sim.advanceTo(sim.utime() + step_us, out);
      for (auto& g : out.ground_truth) gts[g.utime] = g;
      for (const auto& pose : out.poses)
        for (auto& m : methods) m.node->onPose(pose);
      for (const auto& d : out.point_packets) {
        driver.onDatagram(d.bytes.data(), d.bytes.size(), dout);
        for (const auto& c : dout.clouds) handle_cloud(c);
      }
      while (!gts.empty() && gts.begin()->first < sim.utime() - 2'000'000) gts.erase(gts.begin());
    }
    for (auto& m : methods) {
      MethodResult r;
      r.method = m.name;
      r.seed = seed;
      r.mot = m.acc.summary();
      r.latency_median_ms = percentile(m.latency_ms, 0.5);
      r.latency_p99_ms = percentile(m.latency_ms, 0.99);
      r.points_per_frame = m.frames ? m.points / static_cast<double>(m.frames) : 0.0;
      r.frames = m.frames;
      r.invalid_frames = m.invalid;
      r.reassociations = m.node->status().counter("reassociations");
      if (!m.velocity_error.empty()) {
        r.velocity_error_median = percentile(m.velocity_error, 0.5);
        r.velocity_error_p90 = percentile(m.velocity_error, 0.9);
        r.velocity_error_over =
            std::count_if(m.velocity_error.begin(), m.velocity_error.end(), [](double e) { return e > 0.5; }) /
            static_cast<double>(m.velocity_error.size());
        r.velocity_error_over_2sigma =
            static_cast<double>(m.velocity_over_2sigma) / static_cast<double>(m.velocity_error.size());
      }
      results.push_back(r);
      {
        // Per-stage medians of the node's own timings (PERCEPTION_STATUS), for the record.
        const auto st = m.node->status().build(0, 0);
        std::string stages;
        for (int i = 0; i < st.num_timings; ++i) {
          char b[64];
          std::snprintf(b, sizeof(b), " %s %.3f/%.1f", st.timing_names[i].c_str(), st.timing_median_ms[i],
                        st.timing_max_ms[i]);
          stages += b;
        }
        std::fprintf(stderr, "seed %lld %s stage median/max [ms]:%s\n", static_cast<long long>(seed),
                     m.name.c_str(), stages.c_str());
      }
      std::fprintf(stderr, "seed %lld %s: MOTA %.2f %% IDSW %lld (%lld frames, %.1f s simulated)\n",
                   static_cast<long long>(seed), m.name.c_str(), 100.0 * r.mot.mota,
                   static_cast<long long>(r.mot.num_switches), static_cast<long long>(r.frames), run_s);
    }
  }

  // Table.
  std::printf("\nPerception stability: scenario %s, %d Hz frames, %d seed(s) from %lld, CLEAR-MOT threshold %.2f m, %s\n",
              scenario.c_str(), frame_rate, seeds, static_cast<long long>(seed_base), threshold,
              all_gt ? "every ground-truth object scored"
                     : ("objects with < " + std::to_string(min_visible) + " LiDAR returns not scored").c_str());
  std::printf("%-6s %5s %8s %6s %8s %8s %9s %8s %8s %10s %8s %7s %8s %8s %7s %8s\n", "method", "seed", "MOTA%",
              "IDSW", "FN%", "FP%", "mismatch%", "MOTP_m", "lat_med", "lat_p99_ms", "pts/frm", "reassoc", "dv_med",
              "dv_p90", "dv>0.5%", "dv>2sd%");
  for (const auto& r : results) {
    std::printf("%-6s %5lld %8.2f %6lld %8.2f %8.2f %9.3f %8.3f %8.3f %10.3f %8.0f %7lld %8.3f %8.3f %7.1f %8.1f\n",
                r.method.c_str(), static_cast<long long>(r.seed), 100 * r.mot.mota,
                static_cast<long long>(r.mot.num_switches), 100 * r.mot.fn_rate, 100 * r.mot.fp_rate,
                100 * r.mot.mismatch_rate, r.mot.motp, r.latency_median_ms, r.latency_p99_ms, r.points_per_frame,
                static_cast<long long>(r.reassociations), r.velocity_error_median, r.velocity_error_p90,
                100 * r.velocity_error_over, 100 * r.velocity_error_over_2sigma);
  }
  // Medians over seeds per method.
  bool targets_met = true;
  std::map<std::string, std::vector<const MethodResult*>> by;
  for (const auto& r : results) by[r.method].push_back(&r);
  std::printf("\nmedian over seeds:\n");
  std::map<std::string, std::pair<double, double>> med;  // mota, idsw
  for (auto& [m, rs] : by) {
    std::vector<double> mota, idsw, lat, p99, dv, dv90;
    for (auto* r : rs) {
      dv.push_back(r->velocity_error_median);
      dv90.push_back(r->velocity_error_p90);
      mota.push_back(r->mot.mota);
      idsw.push_back(static_cast<double>(r->mot.num_switches));
      lat.push_back(r->latency_median_ms);
      p99.push_back(r->latency_p99_ms);
    }
    med[m] = {percentile(mota, 0.5), percentile(idsw, 0.5)};
    std::printf("  %-5s MOTA %.2f %%  IDSW %.1f  latency median %.3f ms  p99 %.3f ms  velocity error within 8 m "
                "median %.3f m/s  p90 %.3f m/s\n",
                m.c_str(), 100 * med[m].first, med[m].second, percentile(lat, 0.5), percentile(p99, 0.5),
                percentile(dv, 0.5), percentile(dv90, 0.5));
  }
  if (!quick) {
    const double scale = duration > 0.0 ? duration / 243.0 : 1.0;
    for (const auto* r : by["ucon"]) {
      const bool latency_ok = frame_rate == 50 ? (r->latency_median_ms <= 5.0 && r->latency_p99_ms <= 10.0)
                                               : r->latency_median_ms <= 15.0;
      const bool ok = r->mot.mota >= 0.90 && r->mot.num_switches <= std::ceil(3 * scale) && latency_ok;
      targets_met = targets_met && ok;
    }
    targets_met = targets_met && med["ucon"].first > med["fapp"].first && med["ucon"].second < med["fapp"].second;
    std::printf("targets (UCON MOTA >= 90 %%, IDSW <= 3 per 243 s, better than fapp on both, latency "
                "median <= 5 ms and p99 <= 10 ms at 50 Hz, median <= 15 ms at 10 Hz): %s\n",
                targets_met ? "met" : "NOT met");
  }

  if (!json_path.empty()) {
    std::ofstream js(json_path);
    js << "{\"scenario\": \"" << scenario << "\", \"threshold_m\": " << num(threshold)
       << ", \"scored\": \"" << (all_gt ? "all" : "visible") << "\", \"min_visible_points\": " << min_visible
       << ", \"frame_rate_hz\": " << frame_rate
       << ", \"duration_s\": " << num(duration > 0 ? duration : 243.0) << ", \"results\": [";
    for (std::size_t i = 0; i < results.size(); ++i) {
      const auto& r = results[i];
      js << (i ? ", " : "") << "{\"method\": \"" << r.method << "\", \"seed\": " << r.seed
         << ", \"mota\": " << num(r.mot.mota) << ", \"idsw\": " << r.mot.num_switches
         << ", \"fn_rate\": " << num(r.mot.fn_rate) << ", \"fp_rate\": " << num(r.mot.fp_rate)
         << ", \"mismatch_rate\": " << num(r.mot.mismatch_rate) << ", \"motp\": " << num(r.mot.motp)
         << ", \"num_objects\": " << r.mot.num_objects << ", \"num_ignored\": " << r.mot.num_ignored
         << ", \"frames\": " << r.frames
         << ", \"invalid_frames\": " << r.invalid_frames << ", \"reassociations\": " << r.reassociations
         << ", \"latency_ms_median\": " << num(r.latency_median_ms)
         << ", \"latency_ms_p99\": " << num(r.latency_p99_ms)
         << ", \"points_per_frame\": " << num(r.points_per_frame)
         << ", \"velocity_error_median\": " << num(r.velocity_error_median)
         << ", \"velocity_error_p90\": " << num(r.velocity_error_p90)
         << ", \"velocity_error_over_0_5\": " << num(r.velocity_error_over)
         << ", \"velocity_error_over_2sigma\": " << num(r.velocity_error_over_2sigma) << "}";
    }
    js << "]}\n";
    if (!js) {
      std::fprintf(stderr, "bench-perception: cannot write '%s'\n", json_path.c_str());
      return 2;
    }
  }

  if (quick) {
    // Sanity for ctest: both methods produced valid frames and UCON tracks the pedestrians.
    bool ok = true;
    for (const auto& r : results) {
      ok = ok && r.frames > 0.9 * duration * sim_params.frame_rate_hz && r.invalid_frames <= 2;
      if (r.method == "ucon") ok = ok && r.mot.mota >= 0.6 && r.mot.num_objects > 0;
    }
    std::printf("quick sanity: %s\n", ok ? "ok" : "FAILED");
    return ok ? 0 : 1;
  }
  return 0;
}
