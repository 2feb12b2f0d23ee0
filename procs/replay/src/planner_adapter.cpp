// planner in lock step: ROBOT_POSE, PERCEPTION_OBJECTS, PERCEPTION_STATIC, NAV_GOAL to their
// handlers, then tick(now) after every message, as ucon-planner's loop does. The solver's
// wall-clock budget is switched off (a recorded robot config may have it on): with it the
// result depends on the machine's speed and a replay could not be deterministic.
#include <vector>

#include "adapters.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/planner/planner_node.hpp"

namespace ucon {
namespace replay {

namespace {

class PlannerAdapter : public NodeAdapter {
 public:
  explicit PlannerAdapter(const planner::PlannerParams& p) : report_("planner"), node_(p, report_) {}

  std::string name() const override { return "planner"; }
  std::vector<std::string> inputChannels() const override {
    return {channels::kRobotPose, channels::kPerceptionObjects, channels::kPerceptionStatic, channels::kNavGoal};
  }
  std::vector<std::string> outputChannels() const override { return {channels::kPlannerTrajectory}; }

  FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                  std::vector<OutputMessage>* out) override {
    if (channel == channels::kRobotPose) {
      robot_pose_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      node_.onPose(m);
    } else if (channel == channels::kPerceptionObjects) {
      tracked_objects_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      node_.onObjects(m);
    } else if (channel == channels::kPerceptionStatic) {
      static_points_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      node_.onStatic(m);
    } else if (channel == channels::kNavGoal) {
      nav_goal_t m;
      if (!decodeExact(data, size, &m)) return decodeError();
      node_.onGoal(m);
    } else {
      return FeedResult::kIgnored;
    }
    ++inputs_;
    const planner::PlannerOutputs o = node_.tick(node_.clock().now());
    if (o.plan) ++plans_;
    if (o.trajectory) {
      out->push_back(encodeOutput(channels::kPlannerTrajectory, *o.trajectory));
      ++trajectories_;
    }
    return FeedResult::kHandled;
  }

  double helperCpuSeconds() const override { return node_.map().helperCpuSeconds(); }

  std::vector<std::pair<std::string, int64_t>> counters() const override {
    std::vector<std::pair<std::string, int64_t>> c{
        {"inputs", inputs_}, {"plans", plans_}, {"trajectories_out", trajectories_}, {"decode_errors", decode_errors_}};
    // What the planner did when a new plan failed its check, and why it failed (its own status counters).
    for (const char* k : {"result_kept_previous", "result_stop_no_feasible", "least_bad_plans", "evasive_plans",
                          "evasive_manoeuvres", "evasion_kept", "rejected_limit_violation", "rejected_dynamic_collision", "rejected_static_collision"})
      c.emplace_back(k, report_.counter(k));
    return c;
  }

 private:
  FeedResult decodeError() {
    ++decode_errors_;
    return FeedResult::kDecodeError;
  }

  StatusReport report_;  // must outlive node_ (declared first)
  planner::PlannerNode node_;
  int64_t inputs_ = 0, plans_ = 0, trajectories_ = 0, decode_errors_ = 0;
};

}  // namespace

std::unique_ptr<NodeAdapter> makePlannerAdapter(const std::string& yaml, const std::string& source,
                                                std::string* error) {
  std::vector<ConfigError> errors;
  auto p = loadParams<planner::PlannerParams>(yaml, source, &errors);
  if (!p) {
    if (error) *error = configErrorText(source, errors);
    return nullptr;
  }
  p->optimizer.use_time_budget = false;  // determinism over timeliness (see above)
  return std::make_unique<PlannerAdapter>(*p);
}

}  // namespace replay
}  // namespace ucon
