#include <gtest/gtest.h>

#include "ucon/lidar_driver/sequence_tracker.hpp"

using ucon::lidar_driver::SequenceTracker;

TEST(SequenceTracker, GivenConsecutiveCountsThenNothingIsLost) {
  SequenceTracker t;
  for (int i = 0; i < 10; ++i) {
    const auto r = t.observe(0, static_cast<uint16_t>(i));
    EXPECT_EQ(r.lost, 0);
    EXPECT_FALSE(r.out_of_order);
  }
}

TEST(SequenceTracker, GivenAGapInsideAFrameThenTheMissingCountIsReported) {
  SequenceTracker t;
  t.observe(3, 5);
  EXPECT_EQ(t.observe(3, 9).lost, 3);
  EXPECT_EQ(t.observe(3, 10).lost, 0);
}

TEST(SequenceTracker, GivenUdpCntWrappingAt65536ThenItIsNotAGap) {
  SequenceTracker t;
  t.observe(1, 65535);
  EXPECT_EQ(t.observe(1, 0).lost, 0);
  EXPECT_EQ(t.observe(1, 2).lost, 1);
}

TEST(SequenceTracker, GivenAFrameChangeThenRestartingAtZeroOrContinuingAreBothClean) {
  SequenceTracker t;
  t.observe(0, 207);
  EXPECT_EQ(t.observe(1, 0).lost, 0);    // restart
  t.observe(1, 207);
  EXPECT_EQ(t.observe(2, 208).lost, 0);  // running counter
  EXPECT_EQ(t.observe(3, 4).lost, 4);    // restart that lost 0..3
}

TEST(SequenceTracker, GivenAnOlderCountThenItIsOutOfOrderAndTheReferenceStays) {
  SequenceTracker t;
  t.observe(0, 10);
  const auto r = t.observe(0, 8);
  EXPECT_TRUE(r.out_of_order);
  EXPECT_EQ(r.lost, 0);
  EXPECT_EQ(t.observe(0, 11).lost, 0);
}
