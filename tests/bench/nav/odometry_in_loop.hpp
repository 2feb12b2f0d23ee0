#pragma once
/// @file odometry_in_loop.hpp
/// `ucon-bench-nav --pose odometry` and `ucon-bench-perception --drive --pose odometry`: the
/// stack navigates on the LiDAR-inertial odometry instead of the simulator's exact pose. The
/// simulator then publishes no ROBOT_POSE; ucon-odometry's node (its replay adapter,
/// deploy/config/odometry.yaml started at the scenario's start) publishes it from the emulated
/// Mid-360's points and IMU, in the same in-process loop.

#include <memory>
#include <string>

#include "ucon/replay/node_adapter.hpp"
#include "ucon/simulator/params.hpp"
#include "ucon/world/scenario.hpp"

namespace ucon {
namespace bench {

/// The odometry node for the loop (add it to the nodes fed), started at the scenario's start,
/// with `sim` switched to pose_source "none". nullptr and `error` when its config is missing
/// or bad.
std::unique_ptr<replay::NodeAdapter> odometryInLoop(const std::string& config_dir, const world::Scenario& scenario,
                                                    simulator::SimulatorParams* sim, std::string* error);
/// The same from odometry.yaml's text (`path` names it in errors).
std::unique_ptr<replay::NodeAdapter> odometryInLoopFromText(const std::string& yaml, const std::string& path,
                                                            const world::Scenario& scenario,
                                                            simulator::SimulatorParams* sim, std::string* error);

}  // namespace bench
}  // namespace ucon
