// ucon-bench-nav --faults: the spec's grammar and its translation into the bus's faults.
#include "faults.hpp"

#include <gtest/gtest.h>

namespace nav = ucon::bench::nav;

TEST(BenchNavFaults, GivenAFullSpecThenEveryKeyIsRead) {
  nav::FaultSpec f;
  std::string err;
  ASSERT_TRUE(nav::parseFaults("drop=0.05,delay=10,jitter=20,channel=ROBOT_.*,kill=planner@20,restart=2", &f, &err))
      << err;
  EXPECT_DOUBLE_EQ(f.drop, 0.05);
  EXPECT_DOUBLE_EQ(f.delay_ms, 10.0);
  EXPECT_DOUBLE_EQ(f.jitter_ms, 20.0);
  EXPECT_EQ(f.channels, "ROBOT_.*");
  ASSERT_EQ(f.kills.size(), 1u);
  EXPECT_EQ(f.kills[0].node, "planner");
  EXPECT_DOUBLE_EQ(f.kills[0].at_s, 20.0);
  EXPECT_DOUBLE_EQ(f.kills[0].restart_s, 2.0);

  ucon::replay::BusFaults b;
  ASSERT_TRUE(nav::toBusFaults(
      f, 42, [](const std::string& n) { return n == "planner" ? 2 : -1; }, &b, &err))
      << err;
  EXPECT_EQ(b.delay_us, 10000);
  EXPECT_EQ(b.jitter_us, 20000);
  EXPECT_EQ(b.seed, 42u);
  ASSERT_EQ(b.kills.size(), 1u);
  EXPECT_EQ(b.kills[0].node, 2u);
  EXPECT_EQ(b.kills[0].at_us, 20000000);
  EXPECT_EQ(b.kills[0].restart_after_us, 2000000);
  // A kill of a node that the run does not have.
  EXPECT_FALSE(nav::toBusFaults(f, 1, [](const std::string&) { return -1; }, &b, &err));
  EXPECT_NE(err.find("planner"), std::string::npos) << err;
}

TEST(BenchNavFaults, GivenAKillWithoutRestartThenTheNodeStaysDead) {
  nav::FaultSpec f;
  std::string err;
  ASSERT_TRUE(nav::parseFaults("kill=perception@5", &f, &err)) << err;
  ASSERT_EQ(f.kills.size(), 1u);
  EXPECT_LT(f.kills[0].restart_s, 0.0);
}

TEST(BenchNavFaults, GivenBadSpecsThenEachIsRejectedNamingWhatIsWrong) {
  const struct {
    const char* spec;
    const char* says;
  } cases[] = {{"", "empty"},
               {"drop=1.5", "drop"},
               {"drop=abc", "drop"},
               {"delay=-3", "delay"},
               {"jitter=nan", "jitter"},
               {"channel=(", "channel"},
               {"kill=planner", "kill"},
               {"kill=mission@3", "kill"},
               {"restart=2", "restart"},
               {"kill=planner@3,restart=1,restart=2", "restart"},
               {"loss=0.1", "unknown"},
               {"drop", "key=value"},
               {"drop=0", "no fault"}};
  for (const auto& c : cases) {
    nav::FaultSpec f;
    std::string err;
    EXPECT_FALSE(nav::parseFaults(c.spec, &f, &err)) << c.spec;
    EXPECT_NE(err.find(c.says), std::string::npos) << c.spec << ": " << err;
  }
}
