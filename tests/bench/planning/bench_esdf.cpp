// ucon-bench-esdf: cost of the planner's map on a benchmark world (bench:110:<seed>): ESDF box
// rebuild, incremental update after a few changed cells, interpolated distance queries, and ray
// insertion of LiDAR-like scans of the world's obstacles from a moving sensor.
// Prints medians (wall clock; other processes on the machine add noise).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
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
  // Ray insertion: every 0.1 s (the planner's static_insert_period_s) about as many static
  // returns as perception sends in that time (~4000), cast from a sensor 0.5 m up that moves
  // 0.1 m per insertion, rays spread over the Mid-360's elevations (-7..52 degrees).
  std::vector<double> insertion;
  int64_t returns = 0;
  {
    ucon::planner::EsdfMap scan_map(params->map);
    const int rays = 12000, insertions = 20 * repeats;
    for (int i = 0; i < insertions; ++i) {
      const ucon::world::Vec3 o(-20.0 + 0.1 * i, 0.3, 0.5);
      std::vector<Eigen::Vector3f> pts;
      for (int k = 0; k < rays; ++k) {
        const double u = (k + 0.5) / rays, az = 2.399963229728653 * (k + 7 * i);  // golden angle
        const double el = (-7.0 + 59.0 * u) * M_PI / 180.0;
        const ucon::world::Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
        const auto hit = w.castRay(o, d, 15.0);
        if (hit.kind != ucon::world::HitKind::kStatic) continue;
        const ucon::world::Vec3 p = o + d * hit.range;
        if (p.z() < 0.15 || p.z() > 2.2) continue;
        pts.emplace_back(float(p.x()), float(p.y()), float(p.z()));
      }
      returns += int64_t(pts.size());
      const auto t0 = Clock::now();
      scan_map.insert(Eigen::Vector3d(o.x(), o.y(), o.z()), pts, params->map.max_range);
      const auto t1 = Clock::now();
      if (i >= insertions / 4) insertion.push_back(ms(t0, t1));  // after the map has filled in
    }
    returns /= insertions;
  }
  const auto& sl = map.slice();
  std::printf("ESDF map: resolution %.2f m, box %d x %d cells, band %.2f..%.2f m, max distance %.1f m\n",
              params->map.resolution, sl.nx, sl.ny, params->map.band_z_min, params->map.band_z_max,
              params->map.max_distance);
  std::printf("  static map fill (160 obstacles): %.1f ms\n", ms(t_fill0, t_fill1));
  std::printf("  box rebuild + slice: median %.2f ms\n", median(rebuild));
  std::printf("  incremental update (20 cells) + slice: median %.2f ms\n", median(incremental));
  std::printf("  distance + gradient query: median %.1f ns\n", median(query_ns));
  std::printf("  ray insertion of %lld static returns from a moving sensor: median %.2f ms\n",
              static_cast<long long>(returns), median(insertion));
  return 0;
}
