// The node loop helper: publish/subscribe over memq://, decode errors counted, status
// published, exit on request; a bad LCM URL gives a clear error and a non-zero exit.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "ucon/nav_goal_t.hpp"
#include "ucon/process_status_t.hpp"
#include "ucon/runtime/node_runtime.hpp"

using ucon::runtime::NodeRuntime;

TEST(NodeRuntime, GivenMemqWhenAMessageIsPublishedThenTheHandlerGetsItAndTheLoopExits) {
  ucon::runtime::resetExitFlag();
  std::string err;
  auto rt = NodeRuntime::open("test", "memq://", &err);
  ASSERT_TRUE(rt) << err;
  int received = 0;
  int64_t goal_id = 0;
  rt->subscribe<ucon::nav_goal_t>("NAV_GOAL", [&](const ucon::nav_goal_t& g, const std::string& ch) {
    ++received;
    goal_id = g.goal_id;
    EXPECT_EQ(ch, "NAV_GOAL");
  });
  int statuses = 0;
  rt->subscribe<ucon::process_status_t>(
      "TEST_STATUS", [&](const ucon::process_status_t& s, const std::string&) {
        ++statuses;
        EXPECT_EQ(s.name, "test");
        EXPECT_EQ(s.utime, 77);
      });
  ucon::StatusReport report("test");
  rt->setStatus("TEST_STATUS", 0.0, [&]() -> ucon::StatusReport& { return report; }, [] { return int64_t{77}; });

  ucon::nav_goal_t g{};
  g.goal_id = 9;
  rt->publish("NAV_GOAL", g);
  // Garbage on the same channel is counted and dropped.
  const char junk[] = "not an lcm message";
  rt->lcm().publish("NAV_GOAL", junk, sizeof(junk));

  int ticks = 0;
  const int rc = rt->spin(10, [&] {
    if (++ticks >= 5) ucon::runtime::requestExit();
  });
  EXPECT_EQ(rc, 0);
  EXPECT_EQ(received, 1);
  EXPECT_EQ(goal_id, 9);
  EXPECT_EQ(rt->counter("decode_errors"), 1);
  EXPECT_EQ(report.counter("decode_errors"), 1);  // the runtime's counters go into the status
  EXPECT_GE(statuses, 1);
  ucon::runtime::resetExitFlag();
}

TEST(NodeRuntime, GivenMalformedUrlsThenOpenFailsWithAClearMessage) {
  for (const char* url : {"udpm://not-an-ip:7667", "bogus://x", "udpm://10.0.0.1:7667",
                          "udpm://239.255.76.67:99999"}) {
    std::string err;
    auto rt = NodeRuntime::open("test", url, &err);
    EXPECT_FALSE(rt) << url;
    EXPECT_NE(err.find(url), std::string::npos) << err;
  }
}

TEST(NodeRuntime, GivenABadUrlThenAProcessExitsNonZeroAndSaysWhy) {
  const std::string cmd = std::string(UCON_BIN_DIR) +
                          "/ucon-goal --x 1 --y 2 --lcm-url 'bogus://nowhere' 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char buf[256];
  while (fgets(buf, sizeof(buf), p)) out += buf;
  const int status = pclose(p);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("bogus://nowhere"), std::string::npos) << out;
  EXPECT_NE(out.find("error"), std::string::npos) << out;
}

namespace {
// A node for the binding test: counts goals, echoes each on TEST_ECHO, ticks after each input.
struct EchoNode {
  int goals = 0;
  int ticks = 0;
  int64_t now = 0;
  ucon::StatusReport status{"echo"};
};
const ucon::runtime::Output<ucon::nav_goal_t> kEcho{"TEST_ECHO"};

ucon::runtime::NodeBinding<EchoNode> echoBinding() {
  using ucon::runtime::Outbox;
  ucon::runtime::NodeBinding<EchoNode> b;
  b.name = "echo";
  b.inputs = {ucon::runtime::input<ucon::nav_goal_t, EchoNode>(
      "NAV_GOAL", [](EchoNode& n, const ucon::nav_goal_t& g, Outbox& out) {
        ++n.goals;
        n.now = g.utime;
        out.publish(kEcho, g);
      })};
  b.outputs = {kEcho.channel};
  b.tick_rule = ucon::runtime::TickRule::afterInput(5);
  b.tick = [](EchoNode& n, int64_t, Outbox&) { ++n.ticks; };
  b.clock = [](const EchoNode& n) { return n.now; };
  b.status_channel = "ECHO_STATUS";
  b.status_period_s = 0.0;
  b.status = [](EchoNode& n) -> ucon::StatusReport& {
    n.status.setCounter("goals", n.goals);
    return n.status;
  };
  b.done = [](const EchoNode& n) { return n.goals >= 2; };
  return b;
}
}  // namespace

TEST(NodeRuntime, GivenABindingWhenRunThenInputsReachTheNodeOutputsAreSentAndStatusCarriesBothCounters) {
  ucon::runtime::resetExitFlag();
  std::string err;
  auto rt = NodeRuntime::open("echo", "memq://", &err);
  ASSERT_TRUE(rt) << err;
  std::vector<int64_t> echoed;
  rt->subscribe<ucon::nav_goal_t>("TEST_ECHO", [&](const ucon::nav_goal_t& g, const std::string&) {
    echoed.push_back(g.goal_id);
  });
  int64_t status_goals = -1, status_decode_errors = -1, status_utime = -1;
  rt->subscribe<ucon::process_status_t>("ECHO_STATUS", [&](const ucon::process_status_t& s, const std::string&) {
    for (int i = 0; i < s.num_counters; ++i) {
      if (s.counter_names[i] == "goals") status_goals = s.counter_values[i];
      if (s.counter_names[i] == "decode_errors") status_decode_errors = s.counter_values[i];
    }
    status_utime = s.utime;
  });
  EchoNode node;
  bool sent = false;
  ucon::runtime::RunOptions options;
  options.after_tick = [&] {
    if (sent) return;
    sent = true;
    const char junk[] = "not a goal";
    rt->lcm().publish("NAV_GOAL", junk, sizeof(junk));
    for (int id : {4, 5}) {
      ucon::nav_goal_t g{};
      g.utime = 1000 * id;
      g.goal_id = id;
      rt->publish("NAV_GOAL", g);
    }
  };
  const int rc = rt->run(echoBinding(), node, options);
  EXPECT_EQ(rc, 0);  // ended by the binding's done()
  EXPECT_EQ(node.goals, 2);
  EXPECT_GE(node.ticks, 2);
  EXPECT_EQ(rt->counter("decode_errors"), 1);
  rt->publishStatus();
  for (int i = 0; i < 20 && (echoed.size() < 2 || status_goals < 2); ++i) rt->handleOnce(10);
  EXPECT_EQ(echoed, (std::vector<int64_t>{4, 5}));
  EXPECT_EQ(status_goals, 2);
  EXPECT_EQ(status_decode_errors, 1);
  EXPECT_EQ(status_utime, 5000);
  ucon::runtime::resetExitFlag();
}

namespace {
// Resident memory of this process [kB], from /proc/self/status.
long residentKb() {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return -1;
  char line[256];
  long kb = -1;
  while (std::fgets(line, sizeof(line), f)) {
    if (std::sscanf(line, "VmRSS: %ld kB", &kb) == 1) break;
  }
  std::fclose(f);
  return kb;
}
}  // namespace

TEST(NodeRuntime, GivenABurstOfAllocationsFreedThenTheLoopHandsThePagesBack) {
  // 64 MB in small blocks, freed but for one block allocated after them, which keeps the heap's
  // top: free() alone cannot give the pages back, the loop's periodic malloc_trim does.
  ucon::runtime::resetExitFlag();
  std::string err;
  auto rt = NodeRuntime::open("test", "memq://", &err);
  ASSERT_TRUE(rt) << err;
  rt->setTrimPeriod(0.05);
  std::vector<char*> blocks;
  for (int i = 0; i < 64 * 256; ++i) {
    char* b = static_cast<char*>(std::malloc(4000));
    std::memset(b, 1, 4000);
    blocks.push_back(b);
  }
  char* pin = static_cast<char*>(std::malloc(4000));
  std::memset(pin, 1, 4000);
  for (char* b : blocks) std::free(b);
  const long before = residentKb();
  int ticks = 0;
  rt->spin(10, [&] {
    if (++ticks >= 15) ucon::runtime::requestExit();  // >= 150 ms: at least two trims
  });
  const long after = residentKb();
  std::printf("resident %ld kB after the free, %ld kB after the loop\n", before, after);
  std::free(pin);
  EXPECT_GT(before - after, 40 * 1024);
  ucon::runtime::resetExitFlag();
}
