#include "ucon/replay/sim_recorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ucon/channels.hpp"
#include "ucon/lidar_driver/lidar_driver_node.hpp"
#include "ucon/log_metadata_t.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/simulator/simulator.hpp"
#include "ucon/trajectory/quintic_hermite.hpp"
#include "ucon/trajectory_t.hpp"
#include "ucon/wheel_cmd_t.hpp"

namespace ucon {
namespace replay {

namespace {

template <class Msg>
std::vector<uint8_t> encode(const Msg& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

// A minimum-jerk straight drive from `from` toward `to` (at most max_len metres), starting at
// `t0`: s(tau) = L (10 tau^3 - 15 tau^4 + 6 tau^5), peak speed 1.875 L / T = `speed`.
trajectory_t scriptedPlan(int64_t t0, const Eigen::Vector2d& from, const Eigen::Vector2d& to, double speed,
                          double max_len) {
  Eigen::Vector2d d = to - from;
  const double dist = d.norm();
  const double L = std::min(dist, max_len);
  const Eigen::Vector2d u = dist > 1e-9 ? Eigen::Vector2d(d / dist) : Eigen::Vector2d(1.0, 0.0);
  const double T = std::max(1.0, 1.875 * L / speed);
  std::vector<trajectory::KnotState> knots;
  const int n = std::max(2, static_cast<int>(std::ceil(T / 0.25)));
  for (int i = 0; i <= n; ++i) {
    const double t = T * i / n, tau = t / T;
    const double s = L * (10 * std::pow(tau, 3) - 15 * std::pow(tau, 4) + 6 * std::pow(tau, 5));
    const double ds = L / T * (30 * tau * tau - 60 * std::pow(tau, 3) + 30 * std::pow(tau, 4));
    const double dds = L / (T * T) * (60 * tau - 180 * tau * tau + 120 * std::pow(tau, 3));
    trajectory::KnotState k;
    k.t = t;
    k.position << from.x() + u.x() * s, from.y() + u.y() * s, 0.0;
    k.velocity << u.x() * ds, u.y() * ds, 0.0;
    k.acceleration << u.x() * dds, u.y() * dds, 0.0;
    knots.push_back(k);
  }
  trajectory::PiecewisePolynomial pp;
  trajectory::buildQuinticHermite(t0, knots, 2, &pp);
  trajectory_t m{};
  m.utime = t0;
  m.plan_id = 1;
  m.goal_id = 1;
  m.status = trajectory_t::STATUS_OK;
  m.yaw = std::numeric_limits<double>::quiet_NaN();
  pp.toMessage(&m);
  return m;
}

class Bus {
 public:
  Bus(const std::vector<NodeAdapter*>& nodes, const EventSink& sink, simulator::Simulator& sim,
      RecordSummary& summary)
      : nodes_(nodes), sink_(sink), sim_(sim), summary_(summary) {}

  // Publishes one message: to the log, to every consumer (their outputs depth first), and
  // wheel commands to the simulated base.
  void publish(const std::string& channel, int64_t utime, const std::vector<uint8_t>& data) {
    sink_(channel, utime, data);
    ++summary_.messages[channel];
    if (channel == channels::kBaseWheelCmd) {
      wheel_cmd_t c;
      if (decodeExact(data.data(), data.size(), &c) && sim_.onWheelCmd(c)) ++summary_.wheel_cmds_applied;
    }
    for (NodeAdapter* n : nodes_) {
      if (!n->consumes(channel)) continue;
      std::vector<OutputMessage> outs;
      n->feed(channel, data.data(), data.size(), &outs);
      for (const auto& o : outs) publish(o.channel, o.utime, o.data);
    }
  }
  template <class Msg>
  void publish(const std::string& channel, const Msg& m) {
    publish(channel, m.utime, encode(m));
  }

 private:
  const std::vector<NodeAdapter*>& nodes_;
  const EventSink& sink_;
  simulator::Simulator& sim_;
  RecordSummary& summary_;
};

}  // namespace

RecordSummary recordSimulatedRun(const RecorderConfig& config, const std::vector<NodeAdapter*>& nodes,
                                 const EventSink& sink) {
  RecordSummary summary;
  simulator::SimOptions opts;
  opts.make_packets = true;
  simulator::Simulator sim(config.sim, config.scenario, opts);
  // The driver sees the emulated sensor at 127.0.0.1, as the live process does.
  lidar_driver::LidarDriverNode driver(config.driver, int64_t{0x7F000001});
  Bus bus(nodes, sink, sim, summary);

  const int64_t t0 = sim.utime();
  if (!config.metadata.empty()) {
    log_metadata_t m{};
    m.utime = t0;
    m.seq = 0;
    m.run_name = "sim-record";
    m.git_revision = "";
    m.host = "in-process";
    m.profile = "sim-record";
    for (const auto& [k, v] : config.metadata) {
      m.keys.push_back(k);
      m.values.push_back(v);
    }
    m.num_entries = static_cast<int32_t>(m.keys.size());
    bus.publish(channels::kLogMetadata, m);
  }
  const Eigen::Vector2d start = config.scenario.robot.start;
  const Eigen::Vector2d goal =
      config.scenario.robot.goals.empty() ? start + Eigen::Vector2d(config.scripted_length, 0.0)
                                          : config.scenario.robot.goals.front();
  if (config.send_goal) {
    nav_goal_t g{};
    g.utime = t0;
    g.seq = 0;
    g.goal_id = 1;
    g.action = nav_goal_t::ACTION_GO;
    g.x = goal.x();
    g.y = goal.y();
    g.yaw = std::numeric_limits<double>::quiet_NaN();
    g.tolerance = 0.3;
    g.max_speed = 0.0;
    bus.publish(channels::kNavGoal, g);
  }
  // The scripted plan starts once the first pose is out (the controller needs a pose).
  const int64_t plan_t0 = t0 + 20000;
  trajectory_t plan{};
  if (config.scripted_plan) {
    plan = scriptedPlan(plan_t0, start, goal, config.scripted_speed, config.scripted_length);
  }
  int64_t next_plan = plan_t0, plan_seq = 0;

  const int64_t end = t0 + static_cast<int64_t>(std::llround(config.duration_s * 1e6));
  simulator::SimOutputs out;
  lidar_driver::DriverOutputs dout;
  auto toDriver = [&](const simulator::Datagram& d) {
    if (config.before_driver) config.before_driver();
    driver.onDatagram(d.bytes.data(), d.bytes.size(), dout);
    if (config.after_driver) config.after_driver(dout.clouds.size());
  };
  int64_t last_t = t0;
  for (int64_t t = t0 + config.step_us; t <= end; t += config.step_us) {
    out.clear();
    sim.advanceTo(t, out);
    // Fixed order within a step: driver outputs (frames completed, IMU), poses, ground truth,
    // then the scripted plan.
    for (const auto& d : out.point_packets) {
      toDriver(d);
      for (const auto& c : dout.clouds) bus.publish(channels::kLidarPoints, c);
    }
    for (const auto& d : out.imu_packets) {
      toDriver(d);
      for (const auto& c : dout.clouds) bus.publish(channels::kLidarPoints, c);
      if (dout.imu) bus.publish(channels::kLidarImu, *dout.imu);
    }
    for (const auto& p : out.poses) bus.publish(channels::kRobotPose, p);
    for (const auto& g : out.ground_truth) bus.publish(channels::kSimGroundTruth, g);
    if (config.scripted_plan && t >= next_plan) {
      trajectory_t m = plan;
      m.utime = t;
      m.seq = plan_seq++;
      bus.publish(channels::kPlannerTrajectory, m);
      next_plan += 100000;  // 10 Hz, as the planner
    }
    last_t = t;
    if (config.stop && config.stop()) break;
  }
  summary.sim_time_s = static_cast<double>(last_t - t0) * 1e-6;
  summary.collision_episodes = sim.counters().collision_episodes;
  summary.final_x = sim.robot().x;
  summary.final_y = sim.robot().y;
  summary.min_clearance = sim.minClearance();
  return summary;
}

}  // namespace replay
}  // namespace ucon
