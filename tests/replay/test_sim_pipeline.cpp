// The recorder's pipelined bus (RecorderConfig::async_delay_us, used by ucon-bench-nav): nodes
// on worker threads of their own get their inputs in bus order and their outputs are
// published a fixed delay after the input that caused them, so a run depends on its inputs
// only, never on how fast a worker happens to be.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <random>
#include <set>
#include <stdexcept>
#include <thread>

#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/replay/node_adapter.hpp"
#include "ucon/replay/sim_recorder.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/simulator/scenario_loader.hpp"

namespace rp = ucon::replay;

namespace {

const std::string kSource = UCON_SOURCE_DIR;

template <class P>
P loadDeploy(const std::string& file) {
  std::string err;
  auto text = ucon::runtime::readTextFile(kSource + "/deploy/config/" + file, &err);
  EXPECT_TRUE(text.has_value()) << err;
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<P>(text.value_or(""), file, &errors);
  EXPECT_TRUE(p.has_value());
  return p.value_or(P{});
}

rp::RecorderConfig baseConfig(double duration_s) {
  rp::RecorderConfig c;
  c.sim = loadDeploy<ucon::simulator::SimulatorParams>("simulator.yaml");
  c.driver = loadDeploy<ucon::lidar_driver::DriverParams>("lidar_driver.yaml");
  std::string err;
  auto sc = ucon::simulator::loadScenario("crossing", kSource + "/deploy/scenarios", -1, ucon::runtime::readTextFile, &err);
  EXPECT_TRUE(sc.has_value()) << err;
  if (sc) c.scenario = *sc;
  c.duration_s = duration_s;
  return c;
}

// Publishes, for every message on `in`, one message on `out` whose bytes are the input's
// utime (8 bytes) and whose utime is that utime. Optionally sleeps a random while first (a
// slow or jittery worker) or throws on the n-th input.
class EchoNode : public rp::NodeAdapter {
 public:
  EchoNode(std::string in, std::string out, int max_sleep_us = 0, int throw_at = -1)
      : in_(std::move(in)), out_(std::move(out)), max_sleep_us_(max_sleep_us), throw_at_(throw_at) {}
  std::string name() const override { return "echo:" + out_; }
  std::vector<std::string> inputChannels() const override { return {in_}; }
  std::vector<std::string> outputChannels() const override { return {out_}; }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return {}; }
  rp::FeedResult feed(const std::string&, const uint8_t* data, std::size_t size,
                      std::vector<rp::OutputMessage>* out) override {
    if (seen_++ == throw_at_) throw std::runtime_error("echo failed on purpose");
    if (max_sleep_us_ > 0)
      std::this_thread::sleep_for(std::chrono::microseconds(std::uniform_int_distribution<int>(0, max_sleep_us_)(rng_)));
    int64_t utime = 0;
    if (in_ == ucon::channels::kRobotPose) {
      ucon::robot_pose_t p{};
      if (!rp::decodeExact(data, size, &p)) return rp::FeedResult::kDecodeError;
      utime = p.utime;
    } else {
      if (size != sizeof(utime)) return rp::FeedResult::kDecodeError;
      std::memcpy(&utime, data, sizeof(utime));
    }
    rp::OutputMessage o;
    o.channel = out_;
    o.utime = utime;
    o.data.resize(sizeof(utime));
    std::memcpy(o.data.data(), &utime, sizeof(utime));
    out->push_back(std::move(o));
    return rp::FeedResult::kHandled;
  }

 private:
  std::string in_, out_;
  int max_sleep_us_, throw_at_;
  int seen_ = 0;
  std::mt19937 rng_{std::random_device{}()};
};

struct Event {
  std::string channel;
  int64_t utime;
  bool operator==(const Event& o) const { return channel == o.channel && utime == o.utime; }
};

std::vector<Event> run(const rp::RecorderConfig& c, const std::vector<rp::NodeAdapter*>& nodes) {
  std::vector<Event> events;
  rp::recordSimulatedRun(c, nodes, [&](const std::string& ch, int64_t utime, const std::vector<uint8_t>&) {
    if (ch == ucon::channels::kRobotPose || ch == "ECHO_A" || ch == "ECHO_B") events.push_back({ch, utime});
  });
  return events;
}

}  // namespace

TEST(SimPipeline, GivenAsyncNodesThenEachOutputIsPublishedItsDelayAfterItsInputAlsoAlongAChain) {
  // A: ROBOT_POSE -> ECHO_A on a worker, 20 ms; B: ECHO_A -> ECHO_B on another, 30 ms.
  EchoNode a(ucon::channels::kRobotPose, "ECHO_A"), b("ECHO_A", "ECHO_B");
  auto c = baseConfig(1.0);
  c.async_delay_us = {{0, 20000}, {1, 30000}};
  const auto ev = run(c, {&a, &b});
  // Poses (100 Hz) are published at bus time = their utime, except the first (the loop's
  // first step, 1 ms later); due async outputs come first in their step.
  int64_t last_pose = -1, first_pose = -1;
  std::set<int64_t> poses, echoed_a, echoed_b;
  for (const auto& e : ev) {
    if (e.channel == ucon::channels::kRobotPose) {
      if (first_pose < 0) first_pose = e.utime;
      last_pose = e.utime;
      poses.insert(e.utime);
      continue;
    }
    const bool is_a = e.channel == "ECHO_A";
    (is_a ? echoed_a : echoed_b).insert(e.utime);
    const int64_t delay = is_a ? 20000 : 50000;  // B's input is A's output, 20 ms after the pose
    if (e.utime == first_pose) {
      EXPECT_EQ(last_pose, e.utime + delay) << e.channel;  // due 1 ms after that pose
    } else {
      // Published in the step it fell due, before that step's pose: after the pose 10 ms before.
      EXPECT_EQ(last_pose, e.utime + delay - 10000) << e.channel << " " << e.utime;
    }
  }
  // Every pose early enough for its output to fall due before the end was echoed, once.
  for (int64_t p : poses) {
    EXPECT_EQ(echoed_a.count(p), p + 20000 <= last_pose ? 1u : 0u) << p;
    EXPECT_EQ(echoed_b.count(p), p + 50000 <= last_pose ? 1u : 0u) << p;
  }
  EXPECT_GT(echoed_b.size(), 90u);
}

TEST(SimPipeline, GivenJitteryWorkersThenTheMessageOrderIsTheSameAsWithInstantOnes) {
  auto c = baseConfig(0.5);
  c.async_delay_us = {{0, 20000}, {1, 30000}};
  EchoNode fast_a(ucon::channels::kRobotPose, "ECHO_A"), fast_b("ECHO_A", "ECHO_B");
  const auto reference = run(c, {&fast_a, &fast_b});
  ASSERT_GT(reference.size(), 100u);
  for (int k = 0; k < 3; ++k) {
    EchoNode slow_a(ucon::channels::kRobotPose, "ECHO_A", 3000), slow_b("ECHO_A", "ECHO_B", 3000);
    EXPECT_TRUE(run(c, {&slow_a, &slow_b}) == reference) << k;
  }
  // Serial (no async nodes): zero latency, a different order, the same messages.
  EchoNode sa(ucon::channels::kRobotPose, "ECHO_A"), sb("ECHO_A", "ECHO_B");
  auto serial = c;
  serial.async_delay_us.clear();
  const auto s = run(serial, {&sa, &sb});
  EXPECT_FALSE(s == reference);
  std::size_t echoes = 0;
  for (const auto& e : s) echoes += e.channel != ucon::channels::kRobotPose;
  EXPECT_GT(echoes, 0u);
}

TEST(SimPipeline, GivenAFailingWorkerOrABadDelayThenTheRunThrowsAClearError) {
  auto c = baseConfig(0.5);
  EchoNode bad(ucon::channels::kRobotPose, "ECHO_A", 0, 5);
  c.async_delay_us = {{0, 20000}};
  try {
    run(c, {&bad});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("echo failed on purpose"), std::string::npos) << e.what();
  }
  EchoNode ok(ucon::channels::kRobotPose, "ECHO_A");
  c.async_delay_us = {{0, 500}};  // below the 1 ms step
  EXPECT_THROW(run(c, {&ok}), std::invalid_argument);
  c.async_delay_us = {{3, 20000}};  // no such node
  EXPECT_THROW(run(c, {&ok}), std::invalid_argument);
}

// ---- Faults on the bus (RecorderConfig::faults, ucon-bench-nav --faults) ----

namespace {

// Utimes of the poses published and of the echoes, in bus order, and the run's summary.
struct FaultRun {
  std::vector<Event> events;
  rp::RecordSummary summary;
  std::vector<int64_t> poses() const {
    std::vector<int64_t> v;
    for (const auto& e : events)
      if (e.channel == ucon::channels::kRobotPose) v.push_back(e.utime);
    return v;
  }
  std::vector<int64_t> echoes(const std::string& ch) const {
    std::vector<int64_t> v;
    for (const auto& e : events)
      if (e.channel == ch) v.push_back(e.utime);
    return v;
  }
};

FaultRun runFaults(const rp::RecorderConfig& c, const std::vector<rp::NodeAdapter*>& nodes) {
  FaultRun r;
  r.summary = rp::recordSimulatedRun(c, nodes, [&](const std::string& ch, int64_t utime, const std::vector<uint8_t>&) {
    if (ch == ucon::channels::kRobotPose || ch == "ECHO_A" || ch == "ECHO_B") r.events.push_back({ch, utime});
  });
  return r;
}

}  // namespace

TEST(SimFaults, GivenLossThenTheDropsFollowTheSeedAndTheLogKeepsWhatWasPublished) {
  auto c = baseConfig(1.0);
  c.faults.drop = 0.3;
  c.faults.seed = 7;
  EchoNode a(ucon::channels::kRobotPose, "ECHO_A");
  const FaultRun r = runFaults(c, {&a});
  const auto poses = r.poses(), echoes = r.echoes("ECHO_A");
  ASSERT_GT(poses.size(), 90u);  // the log has every pose: a loss is the consumer's
  EXPECT_EQ(r.summary.faults_dropped, int64_t(poses.size() - echoes.size()));
  const double kept = double(echoes.size()) / double(poses.size());
  EXPECT_GT(kept, 0.55);
  EXPECT_LT(kept, 0.85);
  // The same seed drops the same messages; another seed others.
  EchoNode a2(ucon::channels::kRobotPose, "ECHO_A");
  EXPECT_EQ(runFaults(c, {&a2}).echoes("ECHO_A"), echoes);
  c.faults.seed = 8;
  EchoNode a3(ucon::channels::kRobotPose, "ECHO_A");
  EXPECT_NE(runFaults(c, {&a3}).echoes("ECHO_A"), echoes);
  // Everything lost.
  c.faults.drop = 1.0;
  EchoNode a4(ucon::channels::kRobotPose, "ECHO_A");
  EXPECT_TRUE(runFaults(c, {&a4}).echoes("ECHO_A").empty());
}

TEST(SimFaults, GivenDelayAndJitterThenDeliveriesAreLateAndMayOvertakeEachOther) {
  auto c = baseConfig(0.5);
  c.faults.delay_us = 5000;  // half a pose period
  EchoNode a(ucon::channels::kRobotPose, "ECHO_A");
  const FaultRun r = runFaults(c, {&a});
  // Each echo goes out when its pose reaches the node, 5 ms after the pose: after that pose
  // and before the next one.
  int64_t last_pose = -1;
  int echoes = 0;
  for (const auto& e : r.events) {
    if (e.channel == ucon::channels::kRobotPose) {
      last_pose = e.utime;
    } else {
      EXPECT_EQ(e.utime, last_pose);
      ++echoes;
    }
  }
  EXPECT_GT(echoes, 40);
  EXPECT_EQ(r.summary.faults_delayed, int64_t(r.poses().size()));
  // 30 ms of jitter on 10 ms poses: some arrive after a later one.
  c.faults.delay_us = 0;
  c.faults.jitter_us = 30000;
  EchoNode b(ucon::channels::kRobotPose, "ECHO_A");
  const auto jittered = runFaults(c, {&b}).echoes("ECHO_A");
  ASSERT_GT(jittered.size(), 30u);
  EXPECT_FALSE(std::is_sorted(jittered.begin(), jittered.end()));
}

TEST(SimFaults, GivenAChannelPatternThenOnlyThoseChannelsAreAffected) {
  auto c = baseConfig(0.5);
  c.faults.drop = 1.0;
  c.faults.channels = "ECHO_.*";
  EchoNode a(ucon::channels::kRobotPose, "ECHO_A"), b("ECHO_A", "ECHO_B");
  const FaultRun r = runFaults(c, {&a, &b});
  EXPECT_EQ(r.echoes("ECHO_A").size(), r.poses().size());  // poses reach A
  EXPECT_TRUE(r.echoes("ECHO_B").empty());                  // A's echoes never reach B
}

TEST(SimFaults, GivenAKilledNodeThenItIsSilentUntilItsRestartAndTheNewOneTakesOver) {
  for (const bool async : {false, true}) {
    auto c = baseConfig(0.6);
    if (async) c.async_delay_us = {{0, 20000}};
    c.faults.kills = {{0, 200000, 100000}};  // node 0 dies at 0.2 s, respawns 0.1 s later
    EchoNode first(ucon::channels::kRobotPose, "ECHO_A");
    EchoNode second(ucon::channels::kRobotPose, "ECHO_A");
    int restarts = 0;
    c.faults.restart = [&](std::size_t i) -> rp::NodeAdapter* {
      EXPECT_EQ(i, 0u);
      ++restarts;
      return &second;
    };
    const FaultRun r = runFaults(c, {&first});
    const auto poses = r.poses();
    ASSERT_FALSE(poses.empty());
    const int64_t t0 = poses.front() - 1000;  // the loop's start: the first pose is 1 ms in
    std::set<int64_t> echoed;
    for (int64_t u : r.echoes("ECHO_A")) echoed.insert(u);
    const int64_t delay = async ? 20000 : 0;
    for (int64_t p : poses) {
      const int64_t t = p - t0;
      if (p + delay > poses.back()) continue;  // not due before the end
      if (t + delay < 200000 && t < 200000) {
        EXPECT_EQ(echoed.count(p), 1u) << async << " before the kill " << t;
      } else if (t >= 200000 && t < 300000) {
        EXPECT_EQ(echoed.count(p), 0u) << async << " killed " << t;
      } else if (t >= 300000) {
        EXPECT_EQ(echoed.count(p), 1u) << async << " after the restart " << t;
      }
    }
    EXPECT_EQ(restarts, 1);
    EXPECT_EQ(r.summary.faults_restarts, 1);
    EXPECT_GT(r.summary.faults_killed_deliveries, 5);
  }
}

TEST(SimFaults, GivenBadFaultsThenTheRunThrowsAClearError) {
  EchoNode a(ucon::channels::kRobotPose, "ECHO_A");
  auto c = baseConfig(0.2);
  c.faults.drop = 1.5;
  EXPECT_THROW(runFaults(c, {&a}), std::invalid_argument);
  c.faults.drop = 0.0;
  c.faults.channels = "ECHO_(";
  EXPECT_THROW(runFaults(c, {&a}), std::invalid_argument);
  c.faults.channels.clear();
  c.faults.kills = {{0, 100000, 50000}};  // a restart without the function that makes the node
  EXPECT_THROW(runFaults(c, {&a}), std::invalid_argument);
  c.faults.kills = {{4, 100000, -1}};  // no such node
  EXPECT_THROW(runFaults(c, {&a}), std::invalid_argument);
}
