#include <gtest/gtest.h>

#include "ucon/message_clock.hpp"

using ucon::MessageClock;

TEST(MessageClock, GivenMessagesThenNowFollowsTheNewestAndNeverGoesBack) {
  MessageClock c;
  EXPECT_FALSE(c.started());
  EXPECT_EQ(c.observe(1000), MessageClock::Observation::kAdvanced);
  EXPECT_EQ(c.observe(3000), MessageClock::Observation::kAdvanced);
  EXPECT_EQ(c.observe(2000), MessageClock::Observation::kOlder);
  EXPECT_EQ(c.observe(3000), MessageClock::Observation::kSame);
  EXPECT_EQ(c.observe(0), MessageClock::Observation::kInvalid);
  EXPECT_EQ(c.observe(-5), MessageClock::Observation::kInvalid);
  EXPECT_EQ(c.now(), 3000);
  EXPECT_EQ(c.olderCount(), 1);
  EXPECT_EQ(c.invalidCount(), 2);
  EXPECT_NEAR(c.ageSeconds(1000), 0.002, 1e-12);
  EXPECT_GT(c.ageSeconds(0), 1e9);
}
