#include "ucon/mission/mission_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "ucon/status_report.hpp"

namespace ucon {
namespace mission {

namespace {
constexpr std::size_t kGtBuffer = 100;   // ~2 s of ground truth at 50 Hz
constexpr int64_t kPendingMaxUs = 500000;

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof(b), f, v);
  return b;
}

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char b[64];
  std::snprintf(b, sizeof(b), "%.6g", v);
  return b;
}
}  // namespace

MissionNode::MissionNode(const MissionParams& params, std::vector<Eigen::Vector2d> goals,
                         double duration_s, bool loop)
    : params_(params), goals_(std::move(goals)), duration_s_(duration_s), loop_(loop) {}

nav_goal_t MissionNode::goalMessage(int64_t utime) {
  nav_goal_t g{};
  g.utime = utime;
  g.seq = goal_seq_++;
  // Numbered in the order they are driven: a goal of the second lap is a new goal.
  g.goal_id = static_cast<int64_t>(reached_total_) + 1;
  g.action = nav_goal_t::ACTION_GO;
  g.x = goals_[current_].x();
  g.y = goals_[current_].y();
  g.yaw = std::numeric_limits<double>::quiet_NaN();
  g.tolerance = params_.goal_tolerance;
  g.max_speed = 0.0;
  return g;
}

std::optional<nav_goal_t> MissionNode::onPose(const robot_pose_t& pose) {
  if (done_ || !pose.valid || pose.utime <= now_ || !std::isfinite(pose.x) || !std::isfinite(pose.y)) {
    return std::nullopt;
  }
  const Eigen::Vector2d p(pose.x, pose.y);
  if (first_utime_ == 0) {
    first_utime_ = pose.utime;
    if (loop_) goals_.push_back(p);  // each lap ends where the robot started
  }
  const double dt = now_ == 0 ? 0.0 : (pose.utime - now_) * 1e-6;
  now_ = pose.utime;
  speed_ = std::hypot(pose.vx, pose.vy);
  if (has_pos_ && current_ < goals_.size()) {
    path_length_ += (p - last_pos_).norm();
    moving_time_ += dt;
  }
  last_pos_ = p;
  has_pos_ = true;

  const double elapsed = (now_ - first_utime_) * 1e-6;
  if (duration_s_ > 0 && elapsed >= duration_s_) {
    done_ = true;
    end_reason_ = "duration reached";
    return std::nullopt;
  }
  if (current_ < goals_.size() && (p - goals_[current_]).norm() <= params_.goal_tolerance) {
    ++current_;
    ++reached_total_;
    last_sent_ = 0;  // send the next goal at once
    if (current_ == goals_.size()) {
      if (reached_all_utime_ == 0) reached_all_utime_ = now_;
      if (loop_) {
        ++laps_;
        current_ = 0;
      }
    }
  }
  if (current_ == goals_.size()) {
    if ((now_ - reached_all_utime_) * 1e-6 >= params_.settle_s) {
      done_ = true;
      end_reason_ = "all goals reached";
    }
    return std::nullopt;
  }
  if (last_sent_ == 0 || (now_ - last_sent_) * 1e-6 >= params_.resend_period_s) {
    last_sent_ = now_;
    return goalMessage(now_);
  }
  return std::nullopt;
}

void MissionNode::onGroundTruth(const sim_ground_truth_t& gt) {
  collisions_ = std::max(collisions_, static_cast<int>(gt.num_collisions));
  if (std::isfinite(gt.min_clearance) && gt.min_clearance < 1e8) min_clearance_ = gt.min_clearance;
  gt_recent_.push_back(gt);
  if (gt_recent_.size() > kGtBuffer) gt_recent_.erase(gt_recent_.begin());
  // Score the object frames that were waiting for this ground truth.
  auto it = objects_pending_.begin();
  while (it != objects_pending_.end()) {
    if (std::llabs(it->utime - gt.utime) <= static_cast<int64_t>(params_.max_gt_lag_s * 1e6)) {
      scoreFrame(*it, gt);
      it = objects_pending_.erase(it);
    } else if (gt.utime - it->utime > kPendingMaxUs) {
      it = objects_pending_.erase(it);
    } else {
      ++it;
    }
  }
}

void MissionNode::onObjects(const tracked_objects_t& objects) {
  tracked_ = 0;
  for (const auto& o : objects.objects) tracked_ += o.state == tracked_object_t::STATE_CONFIRMED ||
                                                    o.state == tracked_object_t::STATE_COASTING;
  if (!objects.valid) return;
  const sim_ground_truth_t* best = nullptr;
  int64_t best_dt = std::numeric_limits<int64_t>::max();
  for (const auto& g : gt_recent_) {
    const int64_t d = std::llabs(g.utime - objects.utime);
    if (d < best_dt) {
      best_dt = d;
      best = &g;
    }
  }
  if (best && best_dt <= static_cast<int64_t>(params_.max_gt_lag_s * 1e6)) {
    scoreFrame(objects, *best);
  } else {
    objects_pending_.push_back(objects);
  }
}

void MissionNode::scoreFrame(const tracked_objects_t& objects, const sim_ground_truth_t& gt) {
  std::vector<mot::PointXY> truth, hyp;
  std::vector<char> ignored;
  for (const auto& o : gt.objects) {
    truth.push_back({o.id, o.x, o.y});
    // NaN visibility = not computed: score the object.
    ignored.push_back(std::isfinite(o.visible) && o.visible < params_.min_visible);
  }
  for (const auto& o : objects.objects) {
    // Tentative tracks are not reported as objects yet (as a planner would not act on them).
    if (o.state == tracked_object_t::STATE_CONFIRMED || o.state == tracked_object_t::STATE_COASTING) {
      hyp.push_back({o.id, o.x, o.y});
    }
  }
  mot_.updateXY(truth, hyp, params_.mot_threshold, &ignored);
}

void MissionNode::onPlannerStatus(const process_status_t& status) {
  for (int i = 0; i < status.num_timings && i < static_cast<int>(status.timing_names.size()); ++i) {
    if (status.timing_names[i] == "plan_total" && std::isfinite(status.timing_median_ms[i])) {
      plan_ms_.push_back(status.timing_median_ms[i]);
    }
  }
}

void MissionNode::onProcStatus(const supervisor_status_t& status) {
  for (const auto& p : status.procs) {
    if (std::isfinite(p.cpu_percent)) {
      auto& c = cpu_[p.name];
      c.first += p.cpu_percent;
      c.second += 1;
    }
    if (p.rss_kb > 0) rss_[p.name] = p.rss_kb / 1024.0;
  }
}

std::string MissionNode::statusLine() const {
  const double t = first_utime_ ? (now_ - first_utime_) * 1e-6 : 0.0;
  std::string dist = "-";
  if (has_pos_ && current_ < goals_.size()) dist = fmt("%.1f m", (last_pos_ - goals_[current_]).norm());
  std::vector<double> plan = plan_ms_;
  const double plan_ms = plan.empty() ? NAN : plan.back();
  std::ostringstream os;
  os << "t=" << fmt("%.1f", t) << " s  speed " << fmt("%.2f", speed_) << " m/s  "
     << (loop_ ? "lap " + std::to_string(laps_ + 1) + " " : std::string()) << "goal "
     << std::min(current_ + 1, goals_.size()) << "/" << goals_.size() << " at " << dist
     << "  tracked " << tracked_ << "  plan " << fmt("%.2f ms", plan_ms) << "  collisions "
     << collisions_;
  return os.str();
}

MissionSummary MissionNode::summary() const {
  MissionSummary s;
  s.loop = loop_;
  s.laps = laps_;
  s.goals_reached = reached_total_;
  // In a loop, the goals driven so far and the one under way.
  s.goals_total = loop_ ? reached_total_ + 1 : static_cast<int>(goals_.size());
  s.sim_time_s = first_utime_ ? (now_ - first_utime_) * 1e-6 : 0.0;
  if (reached_all_utime_) s.time_to_goals_s = (reached_all_utime_ - first_utime_) * 1e-6;
  s.collisions = collisions_;
  s.min_clearance_m = min_clearance_;
  s.path_length_m = path_length_;
  s.mean_speed = moving_time_ > 0 ? path_length_ / moving_time_ : 0.0;
  s.mot = mot_.summary();
  std::vector<double> plan = plan_ms_;
  s.planning_ms_median = medianInPlace(plan);
  for (const auto& [name, c] : cpu_) s.cpu_percent[name] = c.first / c.second;
  s.rss_mb = rss_;
  return s;
}

std::string MissionNode::format(const MissionSummary& s, const std::string& end_reason) {
  std::ostringstream os;
  os << "=== run summary (" << end_reason << ") ===\n";
  os << "goals reached      " << s.goals_reached << " / " << s.goals_total
     << (std::isfinite(s.time_to_goals_s) && !s.loop ? " in " + fmt("%.1f", s.time_to_goals_s) + " s" : "")
     << (s.loop ? ", " + std::to_string(s.laps) + " lap(s) (loop)" : std::string()) << "\n";
  os << "collisions         " << s.collisions << "\n";
  os << "min clearance      " << fmt("%.2f m", s.min_clearance_m) << "\n";
  os << "mean speed         " << fmt("%.2f m/s", s.mean_speed) << " over " << fmt("%.1f m", s.path_length_m)
     << "\n";
  os << "tracking (MOTA)    " << fmt("%.1f %%", 100.0 * s.mot.mota) << "  IDSW " << s.mot.num_switches
     << "  FN " << s.mot.num_misses << "  FP " << s.mot.num_false_positives << "  over "
     << s.mot.num_objects << " object-frames\n";
  os << "planning time      " << fmt("%.2f ms", s.planning_ms_median) << " (median)\n";
  if (!s.cpu_percent.empty()) {
    os << "CPU per process    ";
    bool first = true;
    for (const auto& [n, c] : s.cpu_percent) {
      os << (first ? "" : ", ") << n << " " << fmt("%.0f %%", c);
      first = false;
    }
    os << "\n";
  }
  os << "result             " << (s.success() ? "SUCCESS" : "FAILED") << "\n";
  return os.str();
}

std::string MissionNode::toJson(const MissionSummary& s, const std::string& end_reason) {
  std::ostringstream os;
  os << "{\"end_reason\": \"" << end_reason << "\", \"success\": " << (s.success() ? "true" : "false")
     << ", \"goals_total\": " << s.goals_total << ", \"goals_reached\": " << s.goals_reached
     << ", \"loop\": " << (s.loop ? "true" : "false") << ", \"laps\": " << s.laps
     << ", \"sim_time_s\": " << jsonNumber(s.sim_time_s)
     << ", \"time_to_goals_s\": " << jsonNumber(s.time_to_goals_s) << ", \"collisions\": " << s.collisions
     << ", \"min_clearance_m\": " << jsonNumber(s.min_clearance_m)
     << ", \"mean_speed\": " << jsonNumber(s.mean_speed) << ", \"path_length_m\": " << jsonNumber(s.path_length_m)
     << ", \"mota\": " << jsonNumber(s.mot.mota) << ", \"idsw\": " << s.mot.num_switches
     << ", \"fn\": " << s.mot.num_misses << ", \"fp\": " << s.mot.num_false_positives
     << ", \"num_objects\": " << s.mot.num_objects
     << ", \"planning_ms_median\": " << jsonNumber(s.planning_ms_median) << ", \"cpu_percent\": {";
  bool first = true;
  for (const auto& [n, c] : s.cpu_percent) {
    os << (first ? "" : ", ") << "\"" << n << "\": " << jsonNumber(c);
    first = false;
  }
  os << "}}";
  return os.str();
}

}  // namespace mission
}  // namespace ucon
