#include "ucon/replay/sim_recorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <stdexcept>

#include "ucon/channels.hpp"
#include "ucon/lidar_driver/lidar_driver_node.hpp"
#include "ucon/log_metadata_t.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/simulator/simulator.hpp"
#include "ucon/trajectory/quintic_hermite.hpp"
#include "ucon/trajectory_t.hpp"
#include "ucon/wheel_cmd_t.hpp"

#include "async_node.hpp"

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

void validateFaults(const BusFaults& f, std::size_t n_nodes) {
  if (!(f.drop >= 0.0 && f.drop <= 1.0)) throw std::invalid_argument("faults: drop must be in [0, 1]");
  if (f.delay_us < 0 || f.jitter_us < 0) throw std::invalid_argument("faults: delay and jitter must be >= 0");
  try {
    if (!f.channels.empty()) std::regex(f.channels, std::regex::ECMAScript);
  } catch (const std::regex_error& e) {
    throw std::invalid_argument("faults: channel pattern '" + f.channels + "' is not a regular expression: " +
                                e.what());
  }
  for (const auto& k : f.kills) {
    if (k.node >= n_nodes) throw std::invalid_argument("faults: kill of node " + std::to_string(k.node) + ": no such node");
    if (k.at_us < 0) throw std::invalid_argument("faults: kill time must be >= 0");
    if (k.restart_after_us >= 0 && !f.restart) throw std::invalid_argument("faults: a restart needs the restart function");
  }
}

// splitmix64: the fault decisions' hash (BusFaults).
uint64_t mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

class Bus {
 public:
  Bus(const std::vector<NodeAdapter*>& nodes, const std::map<std::size_t, int64_t>& async_delay_us,
      std::function<void(bool)> on_wait, const BusFaults& faults, const EventSink& sink, simulator::Simulator& sim,
      RecordSummary& summary)
      : nodes_(nodes),
        delays_(async_delay_us),
        on_wait_(std::move(on_wait)),
        faults_(faults),
        sink_(sink),
        sim_(sim),
        summary_(summary),
        async_(nodes.size()),
        killed_(nodes.size(), false),
        kill_state_(faults.kills.size(), 0) {
    // Input channels are read once, here: no call into a node from this thread while a
    // worker may be inside it, and no channel list built per message.
    for (NodeAdapter* n : nodes) inputs_.push_back(n->inputChannels());
    for (const auto& [i, d] : async_delay_us) async_[i] = std::make_unique<AsyncNode>(nodes[i], d);
    if (!faults_.channels.empty()) channel_re_ = std::regex(faults_.channels, std::regex::ECMAScript);
  }

  // Bus time of what is published now (the step being run) [us]; the first one is the start.
  void setTime(int64_t t) {
    if (!started_) t0_ = t, started_ = true;
    now_ = t;
  }

  // Publishes one message: to the log, to every consumer (their outputs depth first; an async
  // node's are queued for later), and wheel commands to the simulated base. With faults, each
  // delivery may be lost or late.
  void publish(const std::string& channel, int64_t utime, const std::vector<uint8_t>& data) {
    sink_(channel, utime, data);
    ++summary_.messages[channel];
    const uint64_t index = published_++;
    const bool affected = faults_.any() && affects(channel);
    if (channel == channels::kBaseWheelCmd) offer(kBase, index, affected, channel, utime, data);
    for (std::size_t k = 0; k < nodes_.size(); ++k) {
      if (std::find(inputs_[k].begin(), inputs_[k].end(), channel) == inputs_[k].end()) continue;
      offer(k, index, affected, channel, utime, data);
    }
  }
  template <class Msg>
  void publish(const std::string& channel, const Msg& m) {
    publish(channel, m.utime, encode(m));
  }

  // Runs what is due at or before the current bus time: kills and restarts, late deliveries
  // (by due time, then bus order), then the async nodes' outputs (by due time, then node
  // order, then production order: a stable sort of the node-by-node list).
  void deliverDue() {
    applyKills();
    while (!late_.empty() && late_.front().due <= now_) {
      std::pop_heap(late_.begin(), late_.end(), Late::later);
      Late l = std::move(late_.back());
      late_.pop_back();
      if (l.node != kBase && killed_[l.node]) {
        ++summary_.faults_killed_deliveries;
        continue;
      }
      deliver(l.node, l.channel, l.utime, l.data);
    }
    due_.clear();
    for (std::size_t k = 0; k < async_.size(); ++k) {
      if (!async_[k]) continue;
      async_[k]->takeDue(now_, &scratch_, on_wait_);
      if (killed_[k]) {  // what a killed process had in flight never goes out
        summary_.faults_killed_outputs += int64_t(scratch_.size());
        scratch_.clear();
        continue;
      }
      for (auto& d : scratch_) due_.push_back(std::move(d));
      scratch_.clear();
    }
    if (due_.empty()) return;
    std::stable_sort(due_.begin(), due_.end(),
                     [](const AsyncNode::Due& a, const AsyncNode::Due& b) { return a.due < b.due; });
    for (const auto& p : due_) publish(p.msg.channel, p.msg.utime, p.msg.data);
  }

  // Stops and joins the workers (each handles its queued inputs first, their outputs not
  // delivered: see AsyncNode::stop); returns their CPU seconds, those of restarted ones included.
  double stopWorkers() {
    double cpu = retired_cpu_s_;
    for (auto& a : async_)
      if (a) cpu += a->stop();
    return cpu;
  }

 private:
  static constexpr std::size_t kBase = std::numeric_limits<std::size_t>::max();  // the simulated base

  // A late delivery; a heap ordered by due time, then bus order.
  struct Late {
    int64_t due;
    uint64_t order;
    std::size_t node;
    std::string channel;
    int64_t utime;
    std::vector<uint8_t> data;
    static bool later(const Late& a, const Late& b) { return a.due != b.due ? a.due > b.due : a.order > b.order; }
  };

  bool affects(const std::string& channel) {
    // The simulator's ground truth is the harness's measurement, not a message of the robot.
    if (channel == channels::kSimGroundTruth || channel == channels::kLogMetadata) return false;
    if (faults_.channels.empty()) return true;
    const auto it = affects_.find(channel);
    if (it != affects_.end()) return it->second;
    return affects_[channel] = std::regex_match(channel, channel_re_);
  }

  // One delivery of message `index` to consumer `k`: lost, late or now.
  void offer(std::size_t k, uint64_t index, bool affected, const std::string& channel, int64_t utime,
             const std::vector<uint8_t>& data) {
    if (k != kBase && killed_[k]) {
      ++summary_.faults_killed_deliveries;
      return;
    }
    if (affected) {
      const uint64_t h = mix(mix(mix(faults_.seed) ^ index) ^ uint64_t(k));
      if (faults_.drop > 0.0 && double(h >> 11) * 0x1.0p-53 < faults_.drop) {
        ++summary_.faults_dropped;
        return;
      }
      int64_t late = faults_.delay_us;
      if (faults_.jitter_us > 0) late += int64_t(mix(h) % uint64_t(faults_.jitter_us + 1));
      if (late > 0) {
        late_.push_back({now_ + late, late_order_++, k, channel, utime, data});
        std::push_heap(late_.begin(), late_.end(), Late::later);
        ++summary_.faults_delayed;
        return;
      }
    }
    deliver(k, channel, utime, data);
  }

  void deliver(std::size_t k, const std::string& channel, int64_t utime, const std::vector<uint8_t>& data) {
    (void)utime;
    if (k == kBase) {
      wheel_cmd_t c;
      if (decodeExact(data.data(), data.size(), &c) && sim_.onWheelCmd(c)) ++summary_.wheel_cmds_applied;
      return;
    }
    if (async_[k]) {
      async_[k]->push(now_, channel, data);
      return;
    }
    std::vector<OutputMessage> outs;
    nodes_[k]->feed(channel, data.data(), data.size(), &outs);
    for (const auto& o : outs) publish(o.channel, o.utime, o.data);
  }

  // kill_state_: 0 not yet killed, 1 killed, 2 restarted (or killed for good and done).
  void applyKills() {
    for (std::size_t i = 0; i < faults_.kills.size(); ++i) {
      const BusFaults::Kill& kl = faults_.kills[i];
      const std::size_t k = kl.node;
      if (kill_state_[i] == 0 && now_ >= t0_ + kl.at_us) {
        killed_[k] = true;
        kill_state_[i] = 1;
      }
      if (kill_state_[i] == 1 && kl.restart_after_us >= 0 && now_ >= t0_ + kl.at_us + kl.restart_after_us) {
        // The old process is gone: its worker ends (nothing of it is published) and a new
        // node with an empty state takes the inputs from now on.
        if (async_[k]) retired_cpu_s_ += async_[k]->stop();
        NodeAdapter* fresh = faults_.restart(k);
        if (fresh == nullptr) throw std::runtime_error("restart of node " + nodes_[k]->name() + " failed");
        nodes_[k] = fresh;
        inputs_[k] = fresh->inputChannels();
        if (async_[k]) async_[k] = std::make_unique<AsyncNode>(fresh, delays_.at(k));
        killed_[k] = false;
        kill_state_[i] = 2;
        ++summary_.faults_restarts;
      }
    }
  }

  std::vector<NodeAdapter*> nodes_;               // restarts replace entries
  std::vector<std::vector<std::string>> inputs_;  // per node: its input channels
  std::map<std::size_t, int64_t> delays_;
  std::function<void(bool)> on_wait_;
  const BusFaults& faults_;
  std::regex channel_re_;
  std::map<std::string, bool> affects_;
  const EventSink& sink_;
  simulator::Simulator& sim_;
  RecordSummary& summary_;
  std::vector<std::unique_ptr<AsyncNode>> async_;
  std::vector<AsyncNode::Due> scratch_;
  std::vector<AsyncNode::Due> due_;
  std::vector<Late> late_;
  std::vector<bool> killed_;
  std::vector<int> kill_state_;
  uint64_t published_ = 0, late_order_ = 0;
  double retired_cpu_s_ = 0.0;
  int64_t now_ = 0, t0_ = 0;
  bool started_ = false;
};

}  // namespace

RecordSummary recordSimulatedRun(const RecorderConfig& config, const std::vector<NodeAdapter*>& nodes,
                                 const EventSink& sink) {
  RecordSummary summary;
  simulator::SimOptions opts;
  opts.make_packets = true;
  simulator::Simulator sim(config.sim, config.scenario, opts);
  // The driver sees the emulated sensor at 127.0.0.1, as the live process does.
  lidar_driver::LidarDriverNode driver(config.driver);
  for (const auto& [i, d] : config.async_delay_us) {
    if (i >= nodes.size()) throw std::invalid_argument("async_delay_us: no node " + std::to_string(i));
    if (d < config.step_us) throw std::invalid_argument("async_delay_us: delay below step_us for " + nodes[i]->name());
  }
  validateFaults(config.faults, nodes.size());
  Bus bus(nodes, config.async_delay_us, config.on_wait, config.faults, sink, sim, summary);

  const int64_t t0 = sim.utime();
  bus.setTime(t0);
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
    bus.setTime(t);
    bus.deliverDue();
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
  summary.worker_cpu_s = bus.stopWorkers();
  summary.sim_time_s = static_cast<double>(last_t - t0) * 1e-6;
  summary.collision_episodes = sim.counters().collision_episodes;
  summary.final_x = sim.robot().x;
  summary.final_y = sim.robot().y;
  summary.min_clearance = sim.minClearance();
  return summary;
}

}  // namespace replay
}  // namespace ucon
