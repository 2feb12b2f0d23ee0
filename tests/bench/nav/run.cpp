#include "run.hpp"

#include "odometry_in_loop.hpp"

#include <exception>
#include <memory>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/cpu_time.hpp"
#include "ucon/replay/sim_recorder.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/simulator/scenario_loader.hpp"
#include "ucon/world/world.hpp"

namespace ucon::bench::nav {

RunResult runOne(const Setup& setup, int n_dynamic, uint64_t seed, double timeout_s, const Oracle& oracle,
                 const Pipeline& pipeline) {
  RunResult res;
  res.n_dynamic = n_dynamic;
  res.seed = seed;
  const std::string spec = "bench:" + std::to_string(n_dynamic) + ":" + std::to_string(seed);
  std::string err;
  auto sc = simulator::loadScenario(spec, setup.scenario_dir, -1, runtime::readTextFile, &err);
  if (!sc) {
    res.error = spec + ": " + err;
    return res;
  }
  if (sc->robot.goals.empty()) {
    res.error = spec + ": the scenario has no goal";
    return res;
  }

  std::vector<std::unique_ptr<rp::NodeAdapter>> owned;
  std::vector<std::unique_ptr<TimedAdapter>> timed;
  const struct {
    const char* node;
    int stage;
    const char* unit;
    bool on_input;
  } kNodes[] = {{"perception", 1, channels::kLidarPoints, true},
                {"planner", 2, channels::kPlannerTrajectory, false},
                {"base_controller", 3, channels::kBaseWheelCmd, false}};
  PerceptionProbe* perception_probe = nullptr;
  std::vector<rp::NodeAdapter*> stage_nodes;  // what the loop feeds, per stage
  for (const auto& n : kNodes) {
    auto a = rp::makeAdapter(n.node, setup.node_yaml.at(n.node), setup.config_dir + "/" + n.node + ".yaml", &err);
    if (!a) {
      res.error = err;
      return res;
    }
    timed.push_back(std::make_unique<TimedAdapter>(a.get(), &res.stages[n.stage], n.unit, n.on_input));
    owned.push_back(std::move(a));
    rp::NodeAdapter* node = timed.back().get();
    if (n.stage == 1) {
      // Outside the timing: the probe's own work is not perception's latency.
      auto w = std::make_unique<PerceptionProbe>(node, 12.0, oracle, setup.perception_max_coast);
      perception_probe = w.get();
      node = w.get();
      owned.push_back(std::move(w));
    }
    stage_nodes.push_back(node);
  }
  const world::World statics_world(*sc);  // the collision report's static obstacles
  MissionAdapter mission(setup.mission, sc->robot.goals, timeout_s, &statics_world);

  // Mission first: a pose that reaches a goal updates it before the planner sees the pose.
  std::vector<rp::NodeAdapter*> loop{&mission};
  for (auto* n : stage_nodes) loop.push_back(n);

  rp::RecorderConfig cfg;
  cfg.sim = setup.sim;
  cfg.driver = setup.driver;
  cfg.scenario = *sc;
  std::unique_ptr<rp::NodeAdapter> odometry;
  if (setup.pose == "odometry") {
    if (!(odometry = ucon::bench::odometryInLoop(setup.config_dir, *sc, &cfg.sim, &res.error))) return res;
    loop.push_back(odometry.get());
  }
  if (setup.faults.any()) {
    // A restarted node is a new adapter from the same config behind the same timer (and probe).
    cfg.faults.restart = [&](std::size_t k) -> rp::NodeAdapter* {
      const std::string name = loop[k]->name();
      std::string why;
      if (name == "odometry") {
        simulator::SimulatorParams sim = setup.sim;
        auto a = ucon::bench::odometryInLoop(setup.config_dir, *sc, &sim, &why);
        if (!a) return nullptr;
        owned.push_back(std::move(a));
        return owned.back().get();
      }
      for (std::size_t i = 0; i < timed.size(); ++i) {
        if (kNodes[i].node != name) continue;
        auto a = rp::makeAdapter(name, setup.node_yaml.at(name), setup.config_dir + "/" + name + ".yaml", &why);
        if (!a) return nullptr;
        timed[i]->setInner(a.get());
        owned.push_back(std::move(a));
        return loop[k];
      }
      return nullptr;
    };
    const auto index = [&](const std::string& name) {
      for (std::size_t k = 1; k < loop.size(); ++k)  // loop[0] is the mission: the operator, not killed
        if (loop[k]->name() == name) return int(k);
      return -1;
    };
    if (!toBusFaults(setup.faults, seed, index, &cfg.faults, &res.error)) return res;
  }
  cfg.duration_s = timeout_s + 0.1;  // the mission ends the run at timeout_s of pose time
  cfg.send_goal = false;             // the mission sends the goals
  cfg.scripted_plan = false;         // the planner plans
  StageTimes& drv = res.stages[0];
  Clock::time_point drv_t0;
  double frame_ms = 0.0;
  cfg.before_driver = [&] { drv_t0 = Clock::now(); };
  cfg.after_driver = [&](std::size_t frames) {
    const double ms = msSince(drv_t0);
    drv.total_ms += ms;
    frame_ms += ms;
    if (frames > 0) {  // parse + assembly time of the datagrams of one frame
      drv.samples_ms.push_back(frame_ms);
      frame_ms = 0.0;
    }
  };
  cfg.stop = [&] { return mission.reachedAll() || mission.collided() || mission.timedOut(); };
  Clock::time_point wait_t0;
  if (!pipeline.serial) {
    cfg.async_delay_us[1] = pipeline.perception_delay_us;  // loop = mission, perception, planner, controller
    cfg.async_delay_us[2] = pipeline.planner_delay_us;
    cfg.on_wait = [&](bool waiting) {
      if (waiting)
        wait_t0 = Clock::now();
      else
        res.wait_s += msSince(wait_t0) * 1e-3;
    };
  }

  const auto t0 = Clock::now();
  const double cpu0 = threadCpuSeconds();
  rp::RecordSummary s;
  try {
    s = rp::recordSimulatedRun(cfg, loop, [](const std::string&, int64_t, const std::vector<uint8_t>&) {});
  } catch (const std::exception& e) {  // a node that threw, a restart that failed
    res.error = spec + ": " + e.what();
    return res;
  }
  res.wall_s = msSince(t0) * 1e-3;
  res.recall = mission.tracking().recall();
  res.acquire_s = mission.tracking().acquisition.delays();
  res.acquire_missed = mission.tracking().acquisition.missed();
  res.mot = mission.clearMot();
  res.velocity_error = mission.tracking().velocityError();
  res.velocity_error_over_std = mission.tracking().velocityErrorOverStd();
  res.young = mission.tracking().young;
  if (perception_probe) {
    res.leaked_static = perception_probe->leakedPoints();
    res.static_points = perception_probe->staticPoints();
  }
  res.cpu_s = threadCpuSeconds() - cpu0 + s.worker_cpu_s;
  for (const rp::NodeAdapter* n : stage_nodes) res.cpu_s += n->helperCpuSeconds();  // the map's helper thread
  res.collision_with = mission.collisionWith() + mission.history();
  res.hit_mover = mission.hitMover();
  res.hit_tracking = mission.hitTracking();
  res.hit_through_static = mission.hitThroughStatic();
  res.close_total = mission.tracking().close_total;
  res.close_through_static = mission.tracking().close_through_static;
  res.plan_tally = planTally(stage_nodes[1]->counters());
  res.robot_speed_at_hit = mission.robotSpeedAtHit();
  res.ok = true;
  res.faults_dropped = s.faults_dropped;
  res.faults_delayed = s.faults_delayed;
  res.faults_killed = s.faults_killed_deliveries + s.faults_killed_outputs;
  res.faults_restarts = s.faults_restarts;
  res.sim_s = s.sim_time_s;
  res.messages = s.messages;
  res.wheel_cmds_applied = s.wheel_cmds_applied;
  res.min_clearance = s.min_clearance;
  const Eigen::Vector2d goal = sc->robot.goals.back();
  res.dist_start_goal = (sc->robot.start - goal).norm();
  res.dist_left = (Eigen::Vector2d(s.final_x, s.final_y) - goal).norm();
  res.dist_from_start = (Eigen::Vector2d(s.final_x, s.final_y) - sc->robot.start).norm();
  const auto ms = mission.summary();
  res.collision = s.collision_episodes > 0 || mission.collided();
  res.success = mission.reachedAll() && !res.collision;
  res.timeout = !mission.reachedAll() && !res.collision;
  if (mission.reachedAll()) res.time_to_goal_s = ms.time_to_goals_s;
  return res;
}

}  // namespace ucon::bench::nav
