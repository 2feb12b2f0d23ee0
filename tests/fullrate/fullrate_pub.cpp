// ucon-fullrate-pub: publishes the channels of the processes that are not run in the
// full-rate logging test (perception, planner, the operator, optionally the base controller)
// at their nominal rates with realistic sizes, seq counting from 0, until SIGINT/SIGTERM; then
// prints "published <channel> <count>" per channel. Paced on absolute wall-clock deadlines, so
// a late wake-up publishes the missed messages instead of slipping the rate.
#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "ucon/base_status_t.hpp"
#include "ucon/channels.hpp"
#include "ucon/estop_t.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/process_status_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/trajectory_t.hpp"
#include "ucon/wheel_cmd_t.hpp"

namespace {

using Clock = std::chrono::steady_clock;

using Publisher = std::function<int(lcm::LCM&, const std::string&, int64_t seq, int64_t utime)>;

struct Stream {
  std::string channel;
  double rate_hz = 1.0;
  Publisher publish;
  int64_t seq = 0;
  int64_t errors = 0;
  Clock::time_point next;
};

template <class Msg>
int pub(lcm::LCM& lcm, const std::string& ch, const Msg& m) {
  return lcm.publish(ch, &m);
}

ucon::process_status_t status(const std::string& name, int64_t seq, int64_t utime) {
  ucon::process_status_t s{};
  s.utime = utime;
  s.seq = seq;
  s.wall_utime = utime;
  s.name = name;
  s.health = ucon::process_status_t::HEALTH_OK;
  for (int i = 0; i < 12; ++i) {
    s.counter_names.push_back("counter_" + std::to_string(i));
    s.counter_values.push_back(seq * i);
  }
  s.num_counters = 12;
  for (int i = 0; i < 6; ++i) {
    s.timing_names.push_back("stage_" + std::to_string(i));
    s.timing_median_ms.push_back(1.0 + i);
    s.timing_max_ms.push_back(2.0 + i);
  }
  s.num_timings = 6;
  s.num_values = 0;
  return s;
}

Publisher statusOf(const std::string& name) {
  return [name](lcm::LCM& l, const std::string& ch, int64_t seq, int64_t t) { return pub(l, ch, status(name, seq, t)); };
}

}  // namespace

int main(int argc, char** argv) {
  namespace ch = ucon::channels;
  CLI::App app{"Publish synthetic perception/planner/operator (and optionally base) channels at nominal rates."};
  std::string url, list = "perception,planner,operator";
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or the runtime default)");
  app.add_option("--groups", list, "comma separated: perception, planner, operator, base");
  CLI11_PARSE(app, argc, argv);
  std::set<std::string> groups;
  std::stringstream ss(list);
  for (std::string g; std::getline(ss, g, ',');) groups.insert(g);

  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open("fullrate_pub", url, &err);
  if (!rt) {
    std::fprintf(stderr, "ucon-fullrate-pub: %s\n", err.c_str());
    return 1;
  }
  lcm::LCM& lcm = rt->lcm();
  std::vector<Stream> streams;
  auto add = [&](const std::string& channel, double rate_hz, Publisher fn) {
    Stream st;
    st.channel = channel;
    st.rate_hz = rate_hz;
    st.publish = std::move(fn);
    streams.push_back(std::move(st));
  };
  if (groups.count("perception")) {
    add(ch::kPerceptionObjects, 50.0, [](lcm::LCM& l, const std::string& c, int64_t seq, int64_t t) {
                         ucon::tracked_objects_t m{};
                         m.utime = t;
                         m.seq = seq;
                         m.valid = true;
                         m.frame_seq = seq;
                         m.frame_id = "world";
                         for (int i = 0; i < 12; ++i) {
                           ucon::tracked_object_t o{};
                           o.id = i + 1;
                           o.state = ucon::tracked_object_t::STATE_CONFIRMED;
                           o.x = i;
                           o.y = std::sin(seq * 0.01 + i);
                           o.cov_size = 36;
                           o.cov.assign(36, 0.01);
                           o.size_x = o.size_y = 0.5;
                           o.size_z = 1.7;
                           o.num_points = 80;
                           m.objects.push_back(o);
                         }
                         m.num_objects = static_cast<int32_t>(m.objects.size());
                         return pub(l, c, m);
                       });
    add(ch::kPerceptionStatic, 10.0, [](lcm::LCM& l, const std::string& c, int64_t seq, int64_t t) {
                         ucon::static_points_t m{};
                         m.utime = t;
                         m.seq = seq;
                         m.valid = true;
                         m.max_range = 20.0f;
                         m.num_points = 3000;
                         for (int i = 0; i < m.num_points; ++i) {
                           m.x.push_back(0.01f * i);
                           m.y.push_back(0.02f * i);
                           m.z.push_back(0.5f);
                         }
                         return pub(l, c, m);
                       });
    add(ch::kPerceptionStatus, 1.0, statusOf("perception"));
  }
  if (groups.count("planner")) {
    add(ch::kPlannerTrajectory, 10.0, [](lcm::LCM& l, const std::string& c, int64_t seq, int64_t t) {
                         ucon::trajectory_t m{};
                         m.utime = t;
                         m.seq = seq;
                         m.plan_id = seq + 1;
                         m.goal_id = 1;
                         m.status = ucon::trajectory_t::STATUS_INVALID;  // nobody should follow it
                         m.message = "synthetic (full-rate logging test)";
                         m.start_utime = t;
                         m.dim = 2;
                         m.order1 = 6;
                         m.num_pieces = 8;
                         m.durations.assign(8, 0.5);
                         m.num_coeffs = 8 * 2 * 6;
                         m.coeffs.assign(m.num_coeffs, 0.0);
                         m.yaw = NAN;
                         return pub(l, c, m);
                       });
    add(ch::kPlannerStatus, 1.0, statusOf("planner"));
  }
  if (groups.count("operator")) {
    // "On demand" channels, every 5 s: a goal and a released E-stop (harmless).
    add(ch::kNavGoal, 0.2, [](lcm::LCM& l, const std::string& c, int64_t seq, int64_t t) {
                         ucon::nav_goal_t g{};
                         g.utime = t;
                         g.seq = seq;
                         g.goal_id = seq + 1;
                         g.x = 5.0;
                         g.yaw = NAN;
                         g.tolerance = 0.3;
                         return pub(l, c, g);
                       });
    add(ch::kBaseEstop, 0.2, [](lcm::LCM& l, const std::string& c, int64_t seq, int64_t t) {
                         ucon::estop_t e{};
                         e.utime = t;
                         e.seq = seq;
                         e.engaged = false;
                         e.source = "fullrate test";
                         return pub(l, c, e);
                       });
  }
  if (groups.count("base")) {
    add(ch::kBaseWheelCmd, 100.0, [](lcm::LCM& l, const std::string& c, int64_t seq, int64_t t) {
                         ucon::wheel_cmd_t w{};
                         w.utime = t;
                         w.seq = seq;
                         w.enable = false;
                         return pub(l, c, w);
                       });
    add(ch::kBaseStatus, 10.0, [](lcm::LCM& l, const std::string& c, int64_t seq, int64_t t) {
                         ucon::base_status_t s{};
                         s.utime = t;
                         s.seq = seq;
                         s.reason = "synthetic";
                         return pub(l, c, s);
                       });
    add(ch::kBaseControllerStatus, 1.0, statusOf("base_controller"));
  }

  // Message time: the simulator's (latest ROBOT_POSE utime), so that the real base controller
  // in the test sees one clock; wall time until the first pose arrives.
  int64_t sim_utime = 0;
  rt->subscribe<ucon::robot_pose_t>(ch::kRobotPose, [&](const ucon::robot_pose_t& p, const std::string&) {
    sim_utime = std::max(sim_utime, p.utime);
  });
  ucon::runtime::installSignalHandlers();
  const auto start = Clock::now();
  for (auto& s : streams) s.next = start;
  auto wake = start;
  while (!ucon::runtime::exitRequested()) {
    const auto wait_ms = std::chrono::duration_cast<std::chrono::milliseconds>(wake - Clock::now()).count();
    if (wait_ms > 0) rt->handleOnce(static_cast<int>(std::min<int64_t>(wait_ms, 100)));
    const auto now = Clock::now();
    wake = now + std::chrono::milliseconds(100);
    for (auto& s : streams) {
      const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / s.rate_hz));
      while (s.next <= now && !ucon::runtime::exitRequested()) {
        if (s.publish(lcm, s.channel, s.seq, sim_utime > 0 ? sim_utime : ucon::runtime::wallUtime()) != 0) ++s.errors;
        ++s.seq;
        s.next += period;
      }
      wake = std::min(wake, s.next);
    }
  }
  for (const auto& s : streams) {
    std::printf("published %s %lld\n", s.channel.c_str(), static_cast<long long>(s.seq));
    if (s.errors) std::printf("publish_errors %s %lld\n", s.channel.c_str(), static_cast<long long>(s.errors));
  }
  return 0;
}
