#pragma once
/// @file channels.hpp
/// The one place that names every LCM channel of the runtime, its message type and its
/// nominal rate. Processes use the constants; the README table and lcm-spy follow this list.

#include <string>
#include <vector>

namespace ucon {
namespace channels {

inline constexpr const char* kLidarPoints = "LIDAR_POINTS";            ///< ucon::point_cloud_t
inline constexpr const char* kLidarImu = "LIDAR_IMU";                  ///< ucon::imu_t
inline constexpr const char* kLidarStatus = "LIDAR_STATUS";            ///< ucon::process_status_t
inline constexpr const char* kRobotPose = "ROBOT_POSE";                ///< ucon::robot_pose_t
inline constexpr const char* kOdometryPose = "ODOMETRY_POSE";          ///< ucon::robot_pose_t
inline constexpr const char* kOdometryStatus = "ODOMETRY_STATUS";      ///< ucon::odometry_status_t
inline constexpr const char* kOdometryHealth = "ODOMETRY_HEALTH";      ///< ucon::process_status_t
inline constexpr const char* kPerceptionObjects = "PERCEPTION_OBJECTS";  ///< ucon::tracked_objects_t
inline constexpr const char* kPerceptionStatic = "PERCEPTION_STATIC";  ///< ucon::static_points_t
inline constexpr const char* kPerceptionStatus = "PERCEPTION_STATUS";  ///< ucon::process_status_t
inline constexpr const char* kNavGoal = "NAV_GOAL";                    ///< ucon::nav_goal_t
inline constexpr const char* kPlannerTrajectory = "PLANNER_TRAJECTORY";  ///< ucon::trajectory_t
inline constexpr const char* kPlannerStatus = "PLANNER_STATUS";        ///< ucon::process_status_t
inline constexpr const char* kBaseWheelCmd = "BASE_WHEEL_CMD";         ///< ucon::wheel_cmd_t
inline constexpr const char* kBaseStatus = "BASE_STATUS";              ///< ucon::base_status_t
inline constexpr const char* kBaseEstop = "BASE_ESTOP";                ///< ucon::estop_t
inline constexpr const char* kBaseControllerStatus = "BASE_CONTROLLER_STATUS";  ///< ucon::process_status_t
inline constexpr const char* kSimGroundTruth = "SIM_GROUND_TRUTH";     ///< ucon::sim_ground_truth_t
inline constexpr const char* kSimStatus = "SIM_STATUS";                ///< ucon::process_status_t
inline constexpr const char* kLoggerStatus = "LOGGER_STATUS";          ///< ucon::process_status_t
inline constexpr const char* kLogMetadata = "LOG_METADATA";            ///< ucon::log_metadata_t
inline constexpr const char* kProcStatus = "PROC_STATUS";              ///< ucon::supervisor_status_t

/// Default LCM URL: ttl=0 keeps traffic on this host.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

/// Description of one channel.
struct ChannelInfo {
  std::string name;       ///< channel name on the bus
  std::string type;       ///< LCM type, e.g. "ucon.point_cloud_t"
  double nominal_hz;      ///< nominal publish rate [Hz]; 0 = on demand
  std::string publisher;  ///< process that publishes it
  std::string description;
};

/// Every channel of the runtime, in data-flow order.
const std::vector<ChannelInfo>& all();

/// The entry for `name`, or nullptr if the runtime does not know that channel.
const ChannelInfo* find(const std::string& name);

}  // namespace channels
}  // namespace ucon
