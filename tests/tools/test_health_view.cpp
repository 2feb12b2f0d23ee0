// The health view of `deploy/ucon status`: which counters are faults, the latest status per
// process, silent processes named, the text people read.
#include <gtest/gtest.h>

#include "ucon/tools/health_view.hpp"

using ucon::process_status_t;
using ucon::tools::HealthView;
using ucon::tools::isFaultCounter;

namespace {
process_status_t status(const std::string& name, int8_t health, const std::string& message,
                        std::vector<std::pair<std::string, int64_t>> counters) {
  process_status_t m{};
  m.utime = 1;
  m.name = name;
  m.health = health;
  m.message = message;
  for (const auto& [n, v] : counters) {
    m.counter_names.push_back(n);
    m.counter_values.push_back(v);
  }
  m.num_counters = static_cast<int32_t>(counters.size());
  return m;
}
}  // namespace

TEST(HealthView, GivenTheNodesCounterNamesThenFaultsAreTheOnesThatNameSomethingGoingWrong) {
  for (const char* fault : {"frames_stale_pose", "frames_no_pose", "decode_errors", "publish_errors",
                            "stops_pose_stale", "stops_trajectory_stale", "stops_trajectory_expired",
                            "result_stop_stale_objects", "result_stop_no_pose", "objects_msgs_rejected",
                            "poses_invalid", "poses_bad", "ticks_skipped", "cmd_timeouts", "crc_errors",
                            "trajectories_out_of_order", "points_non_finite", "static_points_nan",
                            "messages_older", "packets_dropped", "imu_gaps", "reinitialisations", "collisions",
                            "lost_packets", "time_resets", "unknown_type", "imu_wrong_frame"}) {
    EXPECT_TRUE(isFaultCounter(fault)) << fault;
  }
  for (const char* plain : {"frames_in", "frames_processed", "ticks", "plans", "result_ok", "poses_in",
                            "tracks_created", "saturated_ticks", "stops_estop", "nano_frames", "staleness_ms_x",
                            "errorless", "result_stop_no_feasible", "goals_repeated", "plan_restarts_from_pose"}) {
    EXPECT_FALSE(isFaultCounter(plain)) << plain;
  }
}

TEST(HealthView, GivenTwoMessagesFromAProcessThenTheLatestCountsAndZeroOrPlainCountersAreLeftOut) {
  HealthView v;
  v.add("PLANNER_STATUS", status("planner", process_status_t::HEALTH_OK, "", {{"plans", 10}}));
  v.add("PLANNER_STATUS", status("planner", process_status_t::HEALTH_ERROR, "moving obstacles stale or missing: stopping",
                                 {{"plans", 12}, {"result_stop_stale_objects", 2}, {"objects_msgs_rejected", 0}}));
  const auto e = v.entries({});
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].name, "planner");
  EXPECT_EQ(e[0].health, process_status_t::HEALTH_ERROR);
  EXPECT_EQ(e[0].message, "moving obstacles stale or missing: stopping");
  ASSERT_EQ(e[0].faults.size(), 1u);
  EXPECT_EQ(e[0].faults[0].first, "result_stop_stale_objects");
  EXPECT_EQ(e[0].faults[0].second, 2);
  EXPECT_EQ(e[0].messages, 2);
}

TEST(HealthView, GivenExpectedNamesThenSilentOnesAreListedFirstInOrderAndOthersFollowByName) {
  HealthView v;
  v.add("SIM_STATUS", status("simulator", process_status_t::HEALTH_OK, "", {}));
  v.add("BASE_CONTROLLER_STATUS", status("base_controller", process_status_t::HEALTH_WARN, "watchdog: pose stale",
                                         {{"stops_pose_stale", 1}, {"ticks", 900}}));
  v.add("LOGGER_STATUS", status("", process_status_t::HEALTH_OK, "", {}));
  const auto e = v.entries({"base_controller", "odometry"});
  ASSERT_EQ(e.size(), 4u);
  EXPECT_EQ(e[0].name, "base_controller");
  EXPECT_EQ(e[1].name, "odometry");
  EXPECT_EQ(e[1].messages, 0);
  EXPECT_EQ(e[2].name, "LOGGER_STATUS");  // no name in the message: its channel
  EXPECT_EQ(e[3].name, "simulator");

  const std::string text = v.format({"base_controller", "odometry"}, 1.5);
  EXPECT_NE(text.find("base_controller    WARN   watchdog: pose stale\n"), std::string::npos) << text;
  EXPECT_NE(text.find("faults: stops_pose_stale=1\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("ticks="), std::string::npos) << text;
  EXPECT_NE(text.find("odometry           -      no status heard in 1.5 s\n"), std::string::npos) << text;
  EXPECT_NE(text.find("simulator          OK     -\n"), std::string::npos) << text;
}

TEST(HealthView, GivenAMessageWithFewerValuesThanNamesThenOnlyThePairsAreRead) {
  HealthView v;
  process_status_t m = status("x", process_status_t::HEALTH_OK, "", {{"a_dropped", 3}, {"b_dropped", 4}});
  m.counter_values.pop_back();  // num_counters says 2: never read past what is there
  v.add("X_STATUS", m);
  ASSERT_EQ(v.entries({})[0].faults.size(), 1u);
}
