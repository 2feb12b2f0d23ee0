#pragma once
/// @file mission_node.hpp
/// The mission of a simulated run: sends the scenario's goals one after another on NAV_GOAL,
/// watches the robot reach them, keeps score (collisions, clearance, speed, CLEAR-MOT of the
/// tracked objects against ground truth, CPU per process) and says when the run is over.
/// Time comes from ROBOT_POSE utime (simulation time); no I/O, no wall clock.

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ucon/config.hpp"
#include "ucon/mot/clear_mot.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/process_status_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/supervisor_status_t.hpp"
#include "ucon/tracked_objects_t.hpp"

namespace ucon {
namespace mission {

struct MissionParams {
  double goal_tolerance = 0.4;     ///< goal reached within this distance [m], (0, 10]
  double resend_period_s = 1.0;    ///< NAV_GOAL is re-sent this often until reached [s], [0.1, 60]
  double mot_threshold = 1.0;      ///< CLEAR-MOT match distance [m], (0, 10]
  double min_visible = 0.1;        ///< ground-truth objects less visible than this are not scored, [0, 1]
  double max_gt_lag_s = 0.011;     ///< a tracked-object frame is scored against ground truth this close in time [s]
  double settle_s = 2.0;           ///< wait this long at the last goal before ending [s], [0, 60]

  void read(ConfigReader& r) {
    r.read("goal_tolerance", goal_tolerance, 1e-3, 10.0);
    r.read("resend_period_s", resend_period_s, 0.1, 60.0);
    r.read("mot_threshold", mot_threshold, 1e-3, 10.0);
    r.read("min_visible", min_visible, 0.0, 1.0);
    r.read("max_gt_lag_s", max_gt_lag_s, 1e-4, 1.0);
    r.read("settle_s", settle_s, 0.0, 60.0);
  }
};

/// What a run achieved.
struct MissionSummary {
  int goals_total = 0;
  int goals_reached = 0;
  double sim_time_s = 0.0;         ///< simulated time from the first pose to the end [s]
  double time_to_goals_s = NAN;    ///< until the last goal was reached [s]; NaN if not all
  int collisions = 0;              ///< collision episodes (simulator's count)
  double min_clearance_m = NAN;    ///< smallest robot-obstacle surface distance [m]
  double mean_speed = 0.0;         ///< path length / time while moving towards goals [m/s]
  double path_length_m = 0.0;
  mot::ClearMotSummary mot;        ///< tracked objects vs ground truth
  double planning_ms_median = NAN; ///< median of the planner's reported per-plan median [ms]
  std::map<std::string, double> cpu_percent;  ///< mean CPU per process [% of one core]
  std::map<std::string, double> rss_mb;       ///< last RSS per process [MiB]
  bool loop = false;               ///< the goals were driven in a loop (see MissionNode)
  int laps = 0;                    ///< loops completed: every goal and back to the start
  /// Without a loop: every goal reached, no collision. In a loop: at least one lap, no collision.
  bool success() const {
    return collisions == 0 && (loop ? laps >= 1 : goals_reached == goals_total);
  }
};

class MissionNode {
 public:
  /// `goals` in the world frame [m]; `duration_s` > 0 ends the run after that much simulated
  /// time, 0 = run until all goals are reached. With `loop`, after the last goal the robot is
  /// sent back to where it was first seen, then through the goals again, lap after lap, until
  /// the duration (0 = until stopped): a long run that keeps every process busy.
  MissionNode(const MissionParams& params, std::vector<Eigen::Vector2d> goals, double duration_s,
              bool loop = false);

  /// Advances time; returns a goal to publish when one is due (first, next, or re-send).
  std::optional<nav_goal_t> onPose(const robot_pose_t& pose);
  void onGroundTruth(const sim_ground_truth_t& gt);
  void onObjects(const tracked_objects_t& objects);
  void onPlannerStatus(const process_status_t& status);
  void onProcStatus(const supervisor_status_t& status);

  /// True once all goals were reached (and settled) or the duration has passed.
  /// A loop ends only at the duration.
  bool done() const { return done_; }
  /// Why the run ended ("all goals reached", "duration reached"), empty while running.
  const std::string& endReason() const { return end_reason_; }
  /// One line for the terminal: sim time, speed, tracked objects, planning time, distance to goal.
  std::string statusLine() const;
  MissionSummary summary() const;
  /// Multi-line human-readable summary.
  static std::string format(const MissionSummary& s, const std::string& end_reason);
  /// The summary as one JSON object.
  static std::string toJson(const MissionSummary& s, const std::string& end_reason);

 private:
  nav_goal_t goalMessage(int64_t utime);
  void scoreFrame(const tracked_objects_t& objects, const sim_ground_truth_t& gt);

  MissionParams params_;
  std::vector<Eigen::Vector2d> goals_;
  double duration_s_;
  bool loop_;
  int laps_ = 0;
  int reached_total_ = 0;  // goals reached over all laps
  std::size_t current_ = 0;
  int64_t first_utime_ = 0;
  int64_t now_ = 0;
  int64_t last_sent_ = 0;
  int64_t reached_all_utime_ = 0;
  int64_t goal_seq_ = 0;
  bool done_ = false;
  std::string end_reason_;
  Eigen::Vector2d last_pos_ = Eigen::Vector2d::Zero();
  bool has_pos_ = false;
  double speed_ = 0.0;
  double path_length_ = 0.0;
  double moving_time_ = 0.0;
  int collisions_ = 0;
  double min_clearance_ = NAN;
  int tracked_ = 0;
  std::vector<sim_ground_truth_t> gt_recent_;
  std::vector<tracked_objects_t> objects_pending_;
  mot::ClearMotAccumulator mot_;
  std::vector<double> plan_ms_;
  std::map<std::string, std::pair<double, int>> cpu_;  // sum, count
  std::map<std::string, double> rss_;
};

}  // namespace mission
}  // namespace ucon
