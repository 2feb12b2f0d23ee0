#include "ucon/channels.hpp"

namespace ucon {
namespace channels {

const std::vector<ChannelInfo>& all() {
  static const std::vector<ChannelInfo> kAll = {
      {kLidarPoints, "ucon.point_cloud_t", 50.0, "lidar_driver",
       "one LiDAR frame, sensor time, per-point time offsets"},
      {kLidarImu, "ucon.imu_t", 200.0, "lidar_driver", "Mid-360 IMU in SI units"},
      {kLidarStatus, "ucon.process_status_t", 1.0, "lidar_driver",
       "packets, points, frames, CRC errors, lost packets, time sync"},
      {kRobotPose, "ucon.robot_pose_t", 100.0, "simulator | odometry", "robot pose and velocity"},
      {kOdometryPose, "ucon.robot_pose_t", 200.0, "odometry",
       "the odometry's pose when another source publishes ROBOT_POSE (comparison runs)"},
      {kOdometryStatus, "ucon.odometry_status_t", 50.0, "odometry",
       "per LiDAR frame: result, residuals, constraint per axis, biases, IMU gaps"},
      {kOdometryHealth, "ucon.process_status_t", 1.0, "odometry", "process health, timings, counters"},
      {kPerceptionObjects, "ucon.tracked_objects_t", 50.0, "perception",
       "tracked dynamic objects with 6x6 covariance"},
      {kPerceptionStatic, "ucon.static_points_t", 50.0, "perception",
       "static points with sensor origin, world frame"},
      {kPerceptionStatus, "ucon.process_status_t", 1.0, "perception", "per-stage timings, counts"},
      {kNavGoal, "ucon.nav_goal_t", 0.0, "operator | deploy/ucon", "navigation goal"},
      {kPlannerTrajectory, "ucon.trajectory_t", 10.0, "planner", "MINCO trajectory pieces"},
      {kPlannerStatus, "ucon.process_status_t", 1.0, "planner", "timings, iterations, result"},
      {kBaseWheelCmd, "ucon.wheel_cmd_t", 100.0, "base_controller", "Mecanum wheel speeds"},
      {kBaseStatus, "ucon.base_status_t", 10.0, "base_controller",
       "tracking error, saturation, watchdog state"},
      {kBaseEstop, "ucon.estop_t", 0.0, "operator", "emergency stop request"},
      {kBaseControllerStatus, "ucon.process_status_t", 1.0, "base_controller", "process health"},
      {kSimGroundTruth, "ucon.sim_ground_truth_t", 50.0, "simulator",
       "obstacles, robot, collisions (evaluation only)"},
      {kSimStatus, "ucon.process_status_t", 1.0, "simulator", "packets sent, real-time factor"},
      {kLoggerStatus, "ucon.process_status_t", 1.0, "logger", "messages and bytes per channel"},
      {kLogMetadata, "ucon.log_metadata_t", 0.0, "logger", "first event of each log file"},
      {kProcStatus, "ucon.supervisor_status_t", 1.0, "deploy/ucon",
       "pid, state, restarts, CPU, RSS per process"},
  };
  return kAll;
}

const ChannelInfo* find(const std::string& name) {
  for (const auto& c : all()) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

}  // namespace channels
}  // namespace ucon
