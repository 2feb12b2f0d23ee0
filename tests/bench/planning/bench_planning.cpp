// ucon-bench-planning: the paper's Table II (trajectory optimisation among moving obstacles)
// on this machine, in two protocols on the same worlds:
//  - closed: every (method, N_d, seed) is one closed-loop run (closed_loop.hpp); prints the
//    success rate beside the paper's numbers.
//  - open: the paired open-loop probes of open_loop.hpp (a reference closed loop per (N_d,
//    seed); every method solves the same planner problems; raw plans played against the true
//    motion), with McNemar's test of the sector against each baseline (open_report.hpp).
// Both observe the movers as all seen or in line of sight within a range (observation.hpp).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "closed_loop.hpp"
#include "open_loop.hpp"
#include "open_report.hpp"
#include "../bench_util.hpp"
#include "ucon/config.hpp"
#include "ucon/world/bench_generator.hpp"

namespace {

using ucon::bench::percentile;
using ucon::bench::split;

std::string num(double x, int prec = 4) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", prec + 2, x);
  return buf;
}

/// The paper's Table II (Jetson AGX Orin): {E, t_p [ms], eta [%]} per method and N_d.
struct PaperRow {
  double energy, plan_ms, eta;
};
const std::map<std::string, std::map<int, PaperRow>> kPaper = {
    {"sector", {{50, {1.57, 2.24, 90}}, {80, {1.59, 2.67, 86}}, {110, {1.78, 3.02, 74}}}},
    {"no_uncertainty", {{50, {1.28, 1.87, 84}}, {80, {1.40, 2.03, 74}}, {110, {1.96, 2.85, 60}}}},
    {"fapp", {{50, {1.39, 2.33, 88}}, {80, {1.65, 2.59, 78}}, {110, {2.06, 3.27, 66}}}},
};

struct Task {
  std::string method;
  int n_dynamic;
  uint64_t seed;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"UCON planning benchmark: success rate, jerk and planning time among moving obstacles."};
  std::string json_path;
  int seeds = 50;
  uint64_t seed_base = 1;
  std::string methods = "sector,no_uncertainty,fapp";
  std::string densities = "50,80,110";
  int jobs = 1;
  bool quick = false;
  std::string config = std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml";
  double timeout_s = 120.0;
  bool verbose = false;
  bool trace = false;
  double expect_min_success = -1.0;
  std::string protocol = "closed";
  std::string observe = "all";
  double range = 12.0;
  std::string horizons = "3";
  double shuttle_s = 50.0;
  double probe_start_s = 3.0, probe_period_s = 1.0;
  double expect_min_contact_free = -1.0;
  app.add_option("--json", json_path, "write results as JSON to this file");
  app.add_option("--seeds", seeds, "worlds per setting (seeds B .. B+N-1)")->check(CLI::PositiveNumber);
  app.add_option("--seed-base", seed_base, "first seed");
  app.add_option("--methods", methods, "comma list of sector, no_uncertainty, fapp");
  app.add_option("--densities", densities, "comma list of moving-obstacle counts");
  app.add_option("--jobs", jobs, "parallel runs (cores)")->check(CLI::PositiveNumber);
  app.add_flag("--quick", quick, "a few seeds at N_d = 50 and a 60 s timeout (ctest)");
  app.add_option("--config", config, "planner YAML (obstacle model, robot radius and limits are overridden)");
  app.add_option("--timeout-s", timeout_s, "simulated time limit per run [s]")->check(CLI::PositiveNumber);
  app.add_flag("--verbose", verbose, "one line per run");
  app.add_option("--expect-min-success", expect_min_success,
                 "exit 1 if the sector method's success rate is below this (0..1) at any density (ctest)");
  app.add_flag("--trace", trace, "print every plan that did not end OK (use with one seed and --jobs 1)");
  app.add_option("--protocol", protocol, "closed: closed-loop runs to the goal; open: paired open-loop probes (issue 31)")
      ->check(CLI::IsMember({"closed", "open"}));
  app.add_option("--observe", observe, "all: every mover measured every frame; los: only in line of sight within --range")
      ->check(CLI::IsMember({"all", "los"}));
  app.add_option("--range", range, "sensing range with --observe los [m] (FAPP-like: 5)")->check(CLI::PositiveNumber);
  app.add_option("--horizon", horizons,
                 "open: comma list of evaluation horizons [s]; the probes' dynamic cost and check cover each (> 0.5)");
  app.add_option("--shuttle-s", shuttle_s, "open: the reference robot shuttles between start and goal this long [s]")
      ->check(CLI::PositiveNumber);
  app.add_option("--probe-start-s", probe_start_s, "open: first probe this long after the goal is sent [s]")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--probe-period-s", probe_period_s, "open: time between probes [s]")->check(CLI::PositiveNumber);
  app.add_option("--expect-min-contact-free", expect_min_contact_free,
                 "open: exit 1 if any method's contact-free rate is below this (0..1) in any cell (ctest)");
  CLI11_PARSE(app, argc, argv);
  std::string command = "ucon-bench-planning";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  ucon::bench::ObserveMode observe_mode;
  ucon::bench::parseObserveMode(observe, &observe_mode);
  std::vector<double> horizon_list;
  for (const auto& h : split(horizons)) {
    char* end = nullptr;
    const double v = std::strtod(h.c_str(), &end);
    if (end == h.c_str() || *end != '\0' || !(v > 0.5) || !(v <= 20.0)) {
      std::cerr << "ucon-bench-planning: bad --horizon '" << h << "' (seconds, 0.5 < S <= 20)\n";
      return 2;
    }
    horizon_list.push_back(v);
  }
  if (quick) {
    if (app.count("--seeds") == 0) seeds = 2;
    if (app.count("--shuttle-s") == 0) shuttle_s = 15.0;
    if (app.count("--densities") == 0) densities = "50";
    if (app.count("--timeout-s") == 0) timeout_s = 60.0;
  }

  std::ifstream f(config);
  if (!f) {
    std::cerr << "ucon-bench-planning: cannot read " << config << "\n";
    return 2;
  }
  std::stringstream ss;
  ss << f.rdbuf();
  std::vector<ucon::ConfigError> errors;
  auto params = ucon::loadParams<ucon::planner::PlannerParams>(ss.str(), config, &errors);
  if (!params) {
    for (const auto& e : errors) std::cerr << "ucon-bench-planning: " << e.toString() << "\n";
    return 2;
  }
  const auto method_list = split(methods);
  std::vector<int> density_list;
  for (const auto& d : split(densities)) density_list.push_back(std::atoi(d.c_str()));
  for (const auto& m : method_list) {
    ucon::trajopt::ObstacleModel om;
    if (!ucon::trajopt::parseObstacleModel(m, &om)) {
      std::cerr << "ucon-bench-planning: unknown method '" << m << "'\n";
      return 2;
    }
  }

  if (density_list.empty() || method_list.empty() || horizon_list.empty()) {
    std::cerr << "ucon-bench-planning: empty --densities, --methods or --horizon\n";
    return 2;
  }

  if (protocol == "open") {
    if (method_list.size() < 2 || method_list[0] != "sector") {
      std::cerr << "ucon-bench-planning: --protocol open compares the sector with baselines: --methods must start "
                   "with sector and name at least one more\n";
      return 2;
    }
    std::vector<ucon::bench::OpenRunKey> keys;
    for (int d : density_list)
      for (int s = 0; s < seeds; ++s) keys.push_back({d, seed_base + uint64_t(s)});
    std::vector<ucon::bench::OpenLoopResult> runs(keys.size());
    std::atomic<std::size_t> next{0};
    std::mutex print_mutex;
    auto worker = [&] {
      for (std::size_t i = next++; i < keys.size(); i = next++) {
        ucon::bench::OpenLoopConfig oc;
        oc.run.method = "sector";  // the reference policy: the sector planner's closed loop
        oc.run.n_dynamic = keys[i].n_dynamic;
        oc.run.seed = keys[i].seed;
        oc.run.observe = observe_mode;
        oc.run.sensing_range = range;
        oc.run.shuttle_s = shuttle_s;
        oc.run.probe_start_s = probe_start_s;
        oc.run.probe_period_s = probe_period_s;
        oc.methods = method_list;
        oc.horizons = horizon_list;
        runs[i] = ucon::bench::runOpenLoop(*params, oc);
        if (verbose) {
          const auto& r = runs[i];
          std::lock_guard<std::mutex> lock(print_mutex);
          std::printf("N_d=%3d seed=%4llu probes=%zu skipped=%d legs=%d %s tracks=%lld coasting=%lld\n",
                      keys[i].n_dynamic, (unsigned long long)keys[i].seed, r.probes.size(), r.skipped,
                      r.run.goals_reached, r.run.collision ? "REFERENCE COLLISION" : "",
                      (long long)r.run.tracks_started, (long long)r.run.coasting_frames);
          std::fflush(stdout);
        }
      }
    };
    std::vector<std::thread> pool;
    for (int j = 0; j < std::max(1, jobs); ++j) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    const ucon::world::BenchParams bp;
    std::ostringstream settings;
    settings << "\"generator\": \"bench:<N_d>:<seed>\", \"seeds\": " << seeds << ", \"seed_base\": " << seed_base
             << ", \"reference_policy\": \"the sector planner's closed loop, shuttling between start and goal\""
             << ", \"shuttle_s\": " << num(shuttle_s) << ", \"probe_start_s\": " << num(probe_start_s)
             << ", \"probe_period_s\": " << num(probe_period_s) << ", \"observe\": \"" << observe << "\""
             << ", \"sensing_range_m\": " << (observe == "los" ? num(range) : std::string("null"))
             << ", \"observation_hz\": 50, \"observation_noise_std_m\": 0.05"
             << ", \"robot_radius_m\": " << num(bp.robot_radius) << ", \"planner_hz\": " << num(params->rate_hz)
             << ", \"latency_s\": " << num(params->latency_s) << ", \"jobs\": " << jobs;
    if (!ucon::bench::reportOpenLoop(keys, runs, method_list, horizon_list, density_list, command, settings.str(),
                                     json_path))
      return 1;
    int rc = 0;
    if (expect_min_contact_free >= 0.0) {
      const std::size_t nm = method_list.size();
      for (std::size_t h = 0; h < horizon_list.size(); ++h) {
        for (std::size_t m = 0; m < nm; ++m) {
          int64_t n = 0, free = 0;
          for (const auto& r : runs)
            for (const auto& p : r.probes) {
              ++n;
              free += p.outcomes[h * nm + m].contactFree();
            }
          if (n == 0 || double(free) / double(n) < expect_min_contact_free) {
            std::fprintf(stderr, "ucon-bench-planning: %s contact-free %lld of %lld plans at %.1f s, below %.2f\n",
                         method_list[m].c_str(), (long long)free, (long long)n, horizon_list[h],
                         expect_min_contact_free);
            rc = 1;
          }
        }
      }
    }
    return rc;
  }

  // Same worlds for every method: seeds outermost so a partial run compares like with like.
  std::vector<Task> tasks;
  for (int d : density_list)
    for (int s = 0; s < seeds; ++s)
      for (const auto& m : method_list) tasks.push_back({m, d, seed_base + uint64_t(s)});
  std::vector<ucon::bench::RunResult> results(tasks.size());
  std::atomic<std::size_t> next{0};
  std::mutex print_mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < tasks.size(); i = next++) {
      ucon::bench::RunConfig rc;
      rc.method = tasks[i].method;
      rc.n_dynamic = tasks[i].n_dynamic;
      rc.seed = tasks[i].seed;
      rc.timeout_s = timeout_s;
      rc.trace = trace;
      rc.observe = observe_mode;
      rc.sensing_range = range;
      results[i] = ucon::bench::runClosedLoop(*params, rc);
      if (verbose) {
        const auto& r = results[i];
        std::lock_guard<std::mutex> lock(print_mutex);
        std::printf("%-15s N_d=%3d seed=%4llu %s%s t=%6.1fs len=%5.1fm E=%.2f plans=%zu median=%.2fms stops=%d %s\n",
                    rc.method.c_str(), rc.n_dynamic, (unsigned long long)rc.seed,
                    r.success ? "success" : (r.collision ? "COLLISION " : "TIMEOUT"),
                    r.collision ? r.collision_with.c_str() : "", r.time_s, r.path_length, r.jerk_mean,
                    r.plan_ms.size(), percentile(r.plan_ms, 0.5), r.stops, r.counters.c_str());
        std::fflush(stdout);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, jobs); ++j) pool.emplace_back(worker);
  for (auto& t : pool) t.join();

  // Aggregate.
  struct Row {
    std::string method;
    int n_dynamic;
    int runs = 0, successes = 0, collisions = 0, timeouts = 0;
    double jerk_sum = 0.0;
    std::vector<double> plan_ms, plan_cpu_ms, map_ms, front_end_ms, optimize_ms, iterations;
  };
  std::vector<Row> rows;
  for (int d : density_list) {
    for (const auto& m : method_list) {
      Row row;
      row.method = m;
      row.n_dynamic = d;
      for (std::size_t i = 0; i < tasks.size(); ++i) {
        if (tasks[i].method != m || tasks[i].n_dynamic != d) continue;
        const auto& r = results[i];
        ++row.runs;
        row.successes += r.success;
        row.collisions += r.collision;
        row.timeouts += r.timeout;
        row.jerk_sum += r.jerk_mean;
        row.plan_ms.insert(row.plan_ms.end(), r.plan_ms.begin(), r.plan_ms.end());
        row.plan_cpu_ms.insert(row.plan_cpu_ms.end(), r.plan_cpu_ms.begin(), r.plan_cpu_ms.end());
        row.map_ms.insert(row.map_ms.end(), r.map_ms.begin(), r.map_ms.end());
        row.front_end_ms.insert(row.front_end_ms.end(), r.front_end_ms.begin(), r.front_end_ms.end());
        row.optimize_ms.insert(row.optimize_ms.end(), r.optimize_ms.begin(), r.optimize_ms.end());
        row.iterations.insert(row.iterations.end(), r.iterations.begin(), r.iterations.end());
      }
      rows.push_back(std::move(row));
    }
  }

  std::printf("\n%s\nTable II on this machine (%d seeds from %llu, %u hardware threads, %d jobs)\n", command.c_str(), seeds,
              (unsigned long long)seed_base, std::thread::hardware_concurrency(), jobs);
  std::printf("%-15s %5s | %7s %6s %6s %6s %8s %8s %8s | paper: %5s %6s %5s\n", "method", "N_d", "eta[%]",
              "coll", "tmout", "E", "tp_mean", "tp_med", "tp_p95", "eta", "tp", "E");
  for (const auto& r : rows) {
    const double eta = r.runs ? 100.0 * r.successes / r.runs : NAN;
    double mean = NAN;
    if (!r.plan_ms.empty()) {
      mean = 0.0;
      for (double x : r.plan_ms) mean += x;
      mean /= double(r.plan_ms.size());
    }
    std::string paper = "      -      -     -";
    auto pm = kPaper.find(r.method);
    if (pm != kPaper.end()) {
      auto pd = pm->second.find(r.n_dynamic);
      if (pd != pm->second.end()) {
        char buf[64];
        std::snprintf(buf, sizeof(buf), "%5.0f %6.2f %5.2f", pd->second.eta, pd->second.plan_ms, pd->second.energy);
        paper = buf;
      }
    }
    std::printf("%-15s %5d | %7.1f %6d %6d %6.2f %8.2f %8.2f %8.2f | paper: %s\n", r.method.c_str(), r.n_dynamic,
                eta, r.collisions, r.timeouts, r.runs ? r.jerk_sum / r.runs : NAN, mean,
                percentile(r.plan_ms, 0.5), percentile(r.plan_ms, 0.95), paper.c_str());
  }
  std::printf("(paper: Jetson AGX Orin; t_p in ms, E in m/s^3; ours: closed loop, this machine)\n");
  std::printf("\nPlanning stages, median / p95 [ms] and optimiser evaluations; plan p99 / max [ms];\n"
              "plan thread CPU time median / p95 / p99 [ms]\n");
  for (const auto& r : rows) {
    std::printf("%-15s %5d | map %6.2f / %6.2f | front end %6.2f / %6.2f | optimise %6.2f / %6.2f | evals %5.0f / %5.0f | plan %6.2f / %6.2f | cpu %5.2f / %5.2f / %5.2f\n",
                r.method.c_str(), r.n_dynamic, percentile(r.map_ms, 0.5), percentile(r.map_ms, 0.95),
                percentile(r.front_end_ms, 0.5), percentile(r.front_end_ms, 0.95), percentile(r.optimize_ms, 0.5),
                percentile(r.optimize_ms, 0.95), percentile(r.iterations, 0.5), percentile(r.iterations, 0.95),
                percentile(r.plan_ms, 0.99), percentile(r.plan_ms, 1.0), percentile(r.plan_cpu_ms, 0.5),
                percentile(r.plan_cpu_ms, 0.95), percentile(r.plan_cpu_ms, 0.99));
  }

  if (!json_path.empty()) {
    const ucon::world::BenchParams bp;
    std::ofstream js(json_path);
    js << "{\n  \"world\": {\"generator\": \"bench:<N_d>:<seed>\", \"half_size_m\": " << num(bp.half_size)
       << ", \"num_static\": " << bp.num_static << ", \"mover_radius_m\": [" << num(bp.mover_r_min) << ", "
       << num(bp.mover_r_max) << "], \"mover_speed_mps\": [" << num(bp.speed_min) << ", " << num(bp.speed_max)
       << "], \"motions\": [\"constant_velocity\", \"constant_acceleration\", \"sinusoidal\"]"
       << ", \"robot_radius_m\": " << num(bp.robot_radius) << ", \"robot_max_speed_mps\": "
       << num(bp.robot_max_speed) << ", \"robot_max_accel_mps2\": " << num(bp.robot_max_accel)
       << ", \"start_x_m\": " << num(bp.start_x) << ", \"goal_x_m\": " << num(bp.goal_x)
       << ", \"timeout_s\": " << num(timeout_s) << ", \"observation_hz\": 50, \"observation_noise_std_m\": 0.05"
       << ", \"observe\": \"" << observe << "\", \"sensing_range_m\": " << (observe == "los" ? num(range) : std::string("null"))
       << ", \"planner_hz\": " << num(params->rate_hz) << ", \"seeds\": " << seeds << ", \"seed_base\": " << seed_base
       << ", \"jobs\": " << jobs << ", \"static_map\": \"built from the world's static footprints\"},\n"
       << "  \"results\": [\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      double mean = NAN;
      if (!r.plan_ms.empty()) {
        mean = 0.0;
        for (double x : r.plan_ms) mean += x;
        mean /= double(r.plan_ms.size());
      }
      js << "    {\"method\": \"" << r.method << "\", \"n_dynamic\": " << r.n_dynamic << ", \"runs\": " << r.runs
         << ", \"success_rate\": " << num(r.runs ? double(r.successes) / r.runs : NAN)
         << ", \"collisions\": " << r.collisions << ", \"timeouts\": " << r.timeouts
         << ", \"jerk_mean\": " << num(r.runs ? r.jerk_sum / r.runs : NAN) << ", \"plan_ms_mean\": " << num(mean)
         << ", \"plan_ms_median\": " << num(percentile(r.plan_ms, 0.5))
         << ", \"plan_ms_p95\": " << num(percentile(r.plan_ms, 0.95))
         << ", \"plan_cpu_ms_median\": " << num(percentile(r.plan_cpu_ms, 0.5))
         << ", \"plan_cpu_ms_p95\": " << num(percentile(r.plan_cpu_ms, 0.95))
         << ", \"successes\": " << r.successes << "}" << (i + 1 < rows.size() ? "," : "")
         << "\n";
    }
    js << "  ]\n}\n";
    if (!js) {
      std::cerr << "ucon-bench-planning: cannot write " << json_path << "\n";
      return 1;
    }
    std::printf("wrote %s\n", json_path.c_str());
  }
  int rc = 0;
  for (const auto& r : rows) {
    if (r.method == "sector" && r.runs > 0 && double(r.successes) / r.runs < expect_min_success) {
      std::fprintf(stderr, "ucon-bench-planning: sector success %.2f at N_d=%d is below %.2f\n",
                   double(r.successes) / r.runs, r.n_dynamic, expect_min_success);
      rc = 1;
    }
    if (r.runs > 0 && r.plan_ms.empty()) {
      std::fprintf(stderr, "ucon-bench-planning: %s at N_d=%d never ran the optimiser\n", r.method.c_str(),
                   r.n_dynamic);
      rc = 1;
    }
  }
  return rc;
}
