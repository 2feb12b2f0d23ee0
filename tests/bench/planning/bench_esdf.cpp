// ucon-bench-esdf: cost of the planner's map on a benchmark world (bench:110:<seed>): ESDF box
// rebuild, incremental update after a few changed cells, and interpolated distance queries.
// Prints medians (wall clock; other processes on the machine add noise).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "ucon/config.hpp"
#include "ucon/planner/esdf_map.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/world/bench_generator.hpp"
#include "ucon/world/world.hpp"

namespace {
using Clock = std::chrono::steady_clock;
double ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ESDF map timings on a benchmark world."};
  std::string config = std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml";
  int repeats = 10;
  app.add_option("--config", config, "planner YAML (section map is used)");
  app.add_option("--repeats", repeats, "repetitions per measurement")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  std::ifstream f(config);
  std::stringstream ss;
  ss << f.rdbuf();
  std::vector<ucon::ConfigError> errors;
  auto params = ucon::loadParams<ucon::planner::PlannerParams>(ss.str(), config, &errors);
  if (!params) {
    for (const auto& e : errors) std::fprintf(stderr, "%s\n", e.toString().c_str());
    return 2;
  }
  const auto sc = ucon::world::generateBench(110, 1);
  ucon::world::World w(sc);
  ucon::planner::EsdfMap map(params->map);
  const auto t_fill0 = Clock::now();
  for (const auto& s : sc.statics) {
    if (s.kind == ucon::world::ShapeKind::kCylinder) {
      map.addCylinder(s.center.x(), s.center.y(), s.radius);
    } else {
      const double r = s.half_size.norm();
      map.addCylinder(s.center.x(), s.center.y(), r);  // bounding circle: timing only
    }
  }
  const auto t_fill1 = Clock::now();
  std::vector<double> rebuild, incremental, query_ns;
  for (int i = 0; i < repeats; ++i) {
    const Eigen::Vector2d c(-20.0 + 4.0 * i, 0.3 * i);
    auto t0 = Clock::now();
    map.update(c, true);
    auto t1 = Clock::now();
    rebuild.push_back(ms(t0, t1));
    // A few changed cells near the robot, then an incremental update.
    for (int k = 0; k < 20; ++k) map.setCell(Eigen::Vector3d(c.x() + 2.0 + 0.1 * k, c.y() + 1.0, 0.35), i % 2 == 0);
    t0 = Clock::now();
    map.update(c);
    t1 = Clock::now();
    incremental.push_back(ms(t0, t1));
    double sink = 0.0;
    Eigen::Vector2d g;
    const int n = 100000;
    t0 = Clock::now();
    for (int q = 0; q < n; ++q) sink += map.distance(c.x() - 5.0 + 1e-4 * q, c.y() + 3.0 * std::sin(1e-3 * q), &g);
    t1 = Clock::now();
    query_ns.push_back(ms(t0, t1) * 1e6 / n + 0.0 * sink);
  }
  const auto& sl = map.slice();
  std::printf("ESDF map: resolution %.2f m, box %d x %d cells, band %.2f..%.2f m, max distance %.1f m\n",
              params->map.resolution, sl.nx, sl.ny, params->map.band_z_min, params->map.band_z_max,
              params->map.max_distance);
  std::printf("  static map fill (160 obstacles): %.1f ms\n", ms(t_fill0, t_fill1));
  std::printf("  box rebuild + slice: median %.2f ms\n", median(rebuild));
  std::printf("  incremental update (20 cells) + slice: median %.2f ms\n", median(incremental));
  std::printf("  distance + gradient query: median %.1f ns\n", median(query_ns));
  return 0;
}
