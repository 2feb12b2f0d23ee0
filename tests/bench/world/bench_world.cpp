// bench_world: how much of one core the simulated Mid-360 costs.
//  1. World::castRay alone: 200 000 Mid-360 rays (upside-down mount) per simulated second from
//     sensor poses along the robot's straight path, against bench:140:1 = 160 static + 140
//     moving obstacles (300), moving obstacles re-binned every 96 rays (one packet).
//  2. The in-process Simulator (rays + noise + Livox encoding + IMU + plant + ground truth)
//     on the same world and on `pedestrians`: simulated seconds per wall second.
// Medians over repeats; wall clock is used only here, to measure. Also the same rays with the
// sensor upright (rays run farther through the obstacles: the harder case for the grid).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "ucon/simulator/lidar_emulator.hpp"
#include "ucon/simulator/simulator.hpp"
#include "ucon/world/bench_generator.hpp"
#include "ucon/world/scenario_yaml.hpp"

using namespace ucon;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

// Rays per wall second for `rays` rays along the start->goal line of `scen`.
double rayThroughput(const world::Scenario& scen, const simulator::LidarParams& lp, int64_t rays, int64_t* hits) {
  world::World w(scen);
  simulator::LidarEmulator lidar(lp);
  const world::Vec2 a = scen.robot.start, b = scen.robot.goals.empty() ? a : scen.robot.goals[0];
  const Eigen::Isometry3d T_bs = lidar.mount();
  int64_t h = 0;
  const auto t0 = Clock::now();
  for (int64_t k = 0; k < rays; k += 96) {
    const double t = static_cast<double>(k) * 5e-6;
    const double s = std::min(1.0, t / 30.0);
    Eigen::Isometry3d T_wb = Eigen::Isometry3d::Identity();
    const world::Vec2 p = a + s * (b - a);
    T_wb.translation() = Eigen::Vector3d(p.x(), p.y(), 0.0);
    const Eigen::Isometry3d T_ws = T_wb * T_bs;
    w.setTime(t);
    const Eigen::Matrix3d R = T_ws.linear();
    for (int i = 0; i < 96; ++i) {
      const auto hit = w.castRay(T_ws.translation(), R * lidar.direction(static_cast<uint64_t>(k + i)), 40.0);
      h += hit.kind != world::HitKind::kNone;
    }
  }
  const double dt = seconds(t0, Clock::now());
  if (hits) *hits = h;
  return static_cast<double>(rays) / dt;
}

// Simulated seconds per wall second of the whole in-process simulator.
double simulatorSpeed(const world::Scenario& scen, double sim_s, int64_t* packets) {
  simulator::SimulatorParams p;
  p.base.geometry.max_wheel_speed = 40.0;
  simulator::Simulator sim(p, scen);
  simulator::SimOutputs out;
  const auto t0 = Clock::now();
  const int steps = static_cast<int>(sim_s * 100);
  int64_t n = 0;
  for (int k = 1; k <= steps; ++k) {
    out.clear();
    sim.advanceTo(p.start_utime + k * 10000, out);
    n += static_cast<int64_t>(out.point_packets.size());
  }
  const double dt = seconds(t0, Clock::now());
  if (packets) *packets = n;
  return sim_s / dt;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"World ray casting and simulator throughput."};
  bool quick = false;
  int repeats = 5;
  std::string json, scen_path = "deploy/scenarios/pedestrians.yaml";
  app.add_flag("--quick", quick, "one short repeat (ctest)");
  app.add_option("--repeats", repeats, "repeats per measurement (median reported)")->check(CLI::Range(1, 100));
  app.add_option("--json", json, "write results to this JSON file");
  app.add_option("--pedestrians", scen_path, "path of the pedestrians scenario");
  CLI11_PARSE(app, argc, argv);
  if (quick) repeats = 1;

  const world::Scenario bench = world::generateBench(140, 1);
  std::ifstream f(scen_path);
  std::stringstream ss;
  ss << f.rdbuf();
  world::ScenarioError err;
  const auto ped = world::parseScenarioYaml(ss.str(), scen_path, &err);
  if (!ped) {
    std::fprintf(stderr, "bench_world: %s\n", err.toString().c_str());
    return 1;
  }
  simulator::LidarParams lp;
  const int64_t rays = quick ? 40000 : 200000;
  const double sim_s = quick ? 0.2 : 2.0;

  // Harder case: the sensor upright (more rays run far and low through the obstacles).
  simulator::LidarParams up = lp;
  up.mount_rpy_deg = {0.0, 0.0, 0.0};
  std::vector<double> ray_bench, ray_up, ray_ped, sim_bench, sim_ped;
  int64_t hits_bench = 0, hits_up = 0, hits_ped = 0, packets = 0;
  for (int r = 0; r < repeats; ++r) {
    ray_bench.push_back(rayThroughput(bench, lp, rays, &hits_bench));
    ray_up.push_back(rayThroughput(bench, up, rays, &hits_up));
    ray_ped.push_back(rayThroughput(*ped, lp, rays, &hits_ped));
    sim_bench.push_back(simulatorSpeed(bench, sim_s, &packets));
    sim_ped.push_back(simulatorSpeed(*ped, sim_s, nullptr));
  }
  const double ru = median(ray_up);
  const double rb = median(ray_bench), rp = median(ray_ped), sb = median(sim_bench), sp = median(sim_ped);
  std::printf("bench_world (%d repeat%s, medians)\n", repeats, repeats > 1 ? "s" : "");
  std::printf("  castRay, bench:140:1 (300 obstacles): %10.0f rays/s -> %5.1f %% of one core at 200k rays/s (%.0f %% returns)\n",
              rb, 100.0 * 200000.0 / rb, 100.0 * hits_bench / rays);
  std::printf("  castRay, bench:140:1, upright     : %10.0f rays/s -> %5.1f %% of one core at 200k rays/s (%.0f %% returns)\n",
              ru, 100.0 * 200000.0 / ru, 100.0 * hits_up / rays);
  std::printf("  castRay, pedestrians              : %10.0f rays/s -> %5.1f %% of one core at 200k rays/s (%.0f %% returns)\n",
              rp, 100.0 * 200000.0 / rp, 100.0 * hits_ped / rays);
  std::printf("  simulator in-process, bench:140:1 : %6.2f x real time (%5.1f %% of one core at 1x)\n", sb, 100.0 / sb);
  std::printf("  simulator in-process, pedestrians : %6.2f x real time (%5.1f %% of one core at 1x)\n", sp, 100.0 / sp);
  if (!json.empty()) {
    std::ofstream o(json);
    o << "{\n  \"raycast_rays_per_s_bench300\": " << rb << ",\n  \"raycast_core_percent_at_200k_bench300\": "
      << 100.0 * 200000.0 / rb << ",\n  \"raycast_rays_per_s_bench300_upright\": " << ru
      << ",\n  \"raycast_rays_per_s_pedestrians\": " << rp
      << ",\n  \"simulator_realtime_factor_bench300\": " << sb << ",\n  \"simulator_realtime_factor_pedestrians\": " << sp
      << ",\n  \"repeats\": " << repeats << "\n}\n";
  }
  return 0;
}
