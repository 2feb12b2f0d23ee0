#include <gtest/gtest.h>

#include <cmath>

#include "ucon/status_report.hpp"

TEST(StatusReport, GivenCountsTimingsAndGaugesThenTheMessageHoldsThemInOrder) {
  ucon::StatusReport r("perception");
  r.count("frames");
  r.count("frames", 2);
  r.count("drops");
  r.time("cluster", 3.0);
  r.time("cluster", 1.0);
  r.time("cluster", 2.0);
  r.time("assoc", 0.5);
  r.set("tracks", 4);
  r.setHealth(ucon::process_status_t::HEALTH_WARN, "stale pose");
  auto m = r.build(123, 456);
  EXPECT_EQ(m.name, "perception");
  EXPECT_EQ(m.utime, 123);
  EXPECT_EQ(m.seq, 0);
  ASSERT_EQ(m.num_counters, 2);
  EXPECT_EQ(m.counter_names[0], "frames");
  EXPECT_EQ(m.counter_values[0], 3);
  ASSERT_EQ(m.num_timings, 2);
  EXPECT_EQ(m.timing_names[0], "cluster");
  EXPECT_DOUBLE_EQ(m.timing_median_ms[0], 2.0);
  EXPECT_DOUBLE_EQ(m.timing_max_ms[0], 3.0);
  EXPECT_EQ(m.values[0], 4.0);
  EXPECT_EQ(m.health, ucon::process_status_t::HEALTH_WARN);

  // Timings are per period: the next message has none, counters stay totals.
  auto m2 = r.build(124, 457);
  EXPECT_EQ(m2.seq, 1);
  EXPECT_TRUE(std::isnan(m2.timing_median_ms[0]));
  EXPECT_EQ(m2.counter_values[0], 3);
}

TEST(StatusReport, GivenAnEvenNumberOfSamplesThenTheMedianIsTheMidpoint) {
  std::vector<double> v = {4, 1, 3, 2};
  EXPECT_DOUBLE_EQ(ucon::medianInPlace(v), 2.5);
  std::vector<double> e;
  EXPECT_TRUE(std::isnan(ucon::medianInPlace(e)));
}
