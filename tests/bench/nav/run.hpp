#pragma once
/// @file run.hpp
/// One bench nav run: the world `bench:<N_d>:<seed>` with the whole stack in the loop
/// (ucon::replay::recordSimulatedRun), the probes around the nodes and the mission sending the
/// scenario's goals.

#include <cstdint>
#include <map>
#include <string>

#include "faults.hpp"
#include "metrics.hpp"
#include "probes.hpp"
#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/mission/mission_node.hpp"
#include "ucon/simulator/params.hpp"

namespace ucon::bench::nav {

/// Everything a run needs that is read once from files.
struct Setup {
  simulator::SimulatorParams sim;
  lidar_driver::DriverParams driver;
  mission::MissionParams mission;
  std::map<std::string, std::string> node_yaml;  // node name -> YAML text
  std::string config_dir, scenario_dir;
  std::string pose = "ground_truth";  ///< --pose: ground_truth | odometry (odometry_in_loop.hpp)
  FaultSpec faults;                   ///< --faults (faults.hpp); none by default
  double perception_max_coast = 1.5;  ///< perception.yaml tracks.max_coast: the line-of-sight oracle's coasting [s]
};

/// How the nodes share the machine: pipelined (perception and planner on threads of their
/// own, as their processes run on the robot, with fixed delivery latencies) or serial (one
/// thread, zero-latency bus).
struct Pipeline {
  bool serial = false;
  int64_t perception_delay_us = 20000;  ///< one LiDAR frame period: a frame's objects are out before the next frame
  int64_t planner_delay_us = 30000;     ///< planner.yaml latency_s: a plan is delivered when it starts
};

/// Runs bench:<n_dynamic>:<seed> until every goal is reached, the first collision or
/// `timeout_s` of simulated time. Never throws; a run that cannot be set up has ok = false.
RunResult runOne(const Setup& setup, int n_dynamic, uint64_t seed, double timeout_s, const Oracle& oracle,
                 const Pipeline& pipeline);

}  // namespace ucon::bench::nav
