#include <gtest/gtest.h>

#include "ucon/runtime/tick_timer.hpp"

using ucon::runtime::TickTimer;

TEST(TickTimer, GivenLiveModeWhenMessagesStopThenTicksContinueOnWallTimeWithExtrapolatedTime) {
  TickTimer timer(TickTimer::Mode::kLive, 100.0);
  EXPECT_TRUE(timer.due(0).empty());  // nothing before the first message
  timer.observe(5'000'000, 1'000'000);  // message time 5 s received at wall 1 s
  auto t = timer.due(1'000'000);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0], 5'000'000);
  EXPECT_TRUE(timer.due(1'005'000).empty());  // before the next deadline
  EXPECT_EQ(timer.nextWallDeadline(), 1'010'000);
  // No more messages: 300 ms of wall time later the node still gets ticks, 300 ms later in
  // message time, so its watchdog can fire.
  t = timer.due(1'300'000);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0], 5'300'000);
  EXPECT_EQ(timer.nextWallDeadline(), 1'310'000);  // fell behind: no burst of catch-up ticks
}

TEST(TickTimer, GivenMessageModeThenTicksOnEveryPeriodBeforeTheNewestMessage) {
  TickTimer timer(TickTimer::Mode::kMessage, 100.0);
  timer.observe(1'003'000, 0);
  EXPECT_TRUE(timer.due(0).empty());
  timer.observe(1'035'000, 999'999'999);  // wall time is irrelevant
  const auto t = timer.due(0);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0], 1'010'000);
  EXPECT_EQ(t[1], 1'020'000);
  EXPECT_EQ(t[2], 1'030'000);
  timer.observe(1'020'000, 0);  // older: ignored
  EXPECT_TRUE(timer.due(0).empty());
  timer.observe(1'040'000, 0);  // the tick at 1.04 s waits for a later message
  EXPECT_TRUE(timer.due(0).empty());
  timer.observe(1'040'001, 0);
  ASSERT_EQ(timer.due(0).size(), 1u);
}

TEST(TickTimer, GivenAHugeJumpInMessageTimeThenBurstIsCappedAndSkipsCounted) {
  TickTimer timer(TickTimer::Mode::kMessage, 100.0);
  timer.observe(1'000'000, 0);
  timer.observe(1'000'000 + 3600LL * 1'000'000, 0);  // an hour later
  const auto t = timer.due(0);
  EXPECT_EQ(static_cast<int>(t.size()), TickTimer::kMaxBurst);
  EXPECT_EQ(t.back(), 1'000'000 + 3600LL * 1'000'000 - 10'000);  // the last tick before it
  EXPECT_EQ(timer.skippedTicks(), 360000 - TickTimer::kMaxBurst);
}
