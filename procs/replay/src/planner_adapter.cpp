// planner in lock step, wired by its binding (ucon/planner/binding.hpp). The solver's
// wall-clock budget is switched off (a recorded robot config may have it on): with it the
// result depends on the machine's speed and a replay could not be deterministic.
#include <vector>

#include "adapters.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/planner/binding.hpp"
#include "ucon/replay/bound_adapter.hpp"

namespace ucon {
namespace replay {

std::unique_ptr<NodeAdapter> makePlannerAdapter(const std::string& yaml, const std::string& source,
                                                std::string* error) {
  auto p = adapterParams<planner::PlannerParams, false>(yaml, source, error);
  if (!p) return nullptr;
  p->optimizer.use_time_budget = false;  // determinism over timeliness (see above)
  auto a = std::make_unique<BoundAdapter<planner::BoundPlanner>>(
      planner::binding(), std::make_unique<planner::BoundPlanner>(*p),
      [](const planner::BoundPlanner& n, const FeedCounts& c) {
        int64_t inputs = 0;
        for (const auto& [ch, k] : c.in) inputs += k;
        std::vector<std::pair<std::string, int64_t>> out{{"inputs", inputs},
                                                         {"plans", n.plan_cycles},
                                                         {"trajectories_out", c.outputs(channels::kPlannerTrajectory)},
                                                         {"decode_errors", c.decode_errors}};
        // What the planner did when a new plan failed its check, and why it failed (its own
        // status counters).
        for (const char* k : {"result_kept_previous", "result_stop_no_feasible", "least_bad_plans", "evasive_plans",
                              "evasive_manoeuvres", "evasion_kept", "rejected_limit_violation",
                              "rejected_dynamic_collision", "rejected_static_collision"})
          out.emplace_back(k, n.status.counter(k));
        return out;
      });
  a->helperCpu([](const planner::BoundPlanner& n) { return n.node.map().helperCpuSeconds(); });
  return a;
}

}  // namespace replay
}  // namespace ucon
