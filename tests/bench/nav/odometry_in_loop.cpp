#include "odometry_in_loop.hpp"

#include "ucon/channels.hpp"
#include "ucon/odometry/params.hpp"
#include "ucon/runtime/config_file.hpp"

namespace ucon {
namespace bench {

std::unique_ptr<replay::NodeAdapter> odometryInLoop(const std::string& config_dir, const world::Scenario& scenario,
                                                    simulator::SimulatorParams* sim, std::string* error) {
  const std::string path = config_dir + "/odometry.yaml";
  const auto text = runtime::readTextFile(path, error);
  if (!text) return nullptr;
  return odometryInLoopFromText(*text, path, scenario, sim, error);
}

std::unique_ptr<replay::NodeAdapter> odometryInLoopFromText(const std::string& yaml, const std::string& path,
                                                            const world::Scenario& scenario,
                                                            simulator::SimulatorParams* sim, std::string* error) {
  const auto started = odometry::withInitialPose(
      yaml, Eigen::Vector3d(scenario.robot.start.x(), scenario.robot.start.y(), scenario.robot.start_yaw));
  if (!started) {
    if (error) *error = path + ": no init.pose line to start the odometry at the scenario's start";
    return nullptr;
  }
  auto a = replay::makeAdapter("odometry", *started, path, error);
  if (!a) return nullptr;
  if (a->outputChannels().empty() || a->outputChannels().front() != channels::kRobotPose) {
    if (error) *error = path + ": pose_channel must be ROBOT_POSE for the stack to navigate on it";
    return nullptr;
  }
  sim->pose_source = "none";
  return a;
}

}  // namespace bench
}  // namespace ucon
