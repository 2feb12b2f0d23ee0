// LCM events -> MCAP: topics, schemas, the time policy (log time = message utime; untimed and
// wall-clock messages take the clock), bad events counted and left out.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>

#include "mcap_test_reader.hpp"
#include "ucon/foxglove/lcm_json.hpp"
#include "ucon/foxglove/mcap_export.hpp"
#include "ucon/log_metadata_t.hpp"
#include "ucon/process_status_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/supervisor_status_t.hpp"

namespace fg = ucon::foxglove;
using nlohmann::json;

namespace {

template <class T>
std::vector<uint8_t> encode(const T& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

fg::ViewParams params() {
  std::ifstream f("deploy/config/planner.yaml");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string err;
  return fg::viewParamsFromPlannerYaml(ss.str(), "planner.yaml", &err).value();
}

ucon::robot_pose_t pose(int64_t utime) {
  ucon::robot_pose_t p{};
  p.utime = utime;
  p.valid = 1;
  p.qw = 1.0;
  return p;
}

struct Exported {
  std::string bytes;
  fg::ExportStats stats;
};

Exported run(const std::vector<std::pair<std::string, std::vector<uint8_t>>>& events, fg::ExportOptions opt = {}) {
  Exported e;
  fg::McapWriter w([&](const uint8_t* d, std::size_t n) {
    e.bytes.append(reinterpret_cast<const char*>(d), n);
    return true;
  }, fg::McapWriterOptions{});
  EXPECT_TRUE(w.start());
  fg::McapExporter x(&w, params(), opt);
  for (const auto& [ch, data] : events) EXPECT_TRUE(x.add(ch, data.data(), data.size()));
  EXPECT_TRUE(x.finish());
  e.stats = x.stats();
  return e;
}

}  // namespace

TEST(McapExport, GivenWallClockAndTimedMessagesWhenExportedThenLogTimeIsMessageTime) {
  ucon::log_metadata_t meta{};
  meta.utime = 1'700'000'000'000'000;  // wall clock
  meta.run_name = "r";
  ucon::supervisor_status_t procs{};
  procs.utime = 1'700'000'000'500'000;  // wall clock
  ucon::process_status_t st{};
  st.utime = 0;  // no input yet: invalid
  ucon::process_status_t logger{};
  logger.utime = 1'700'000'000'900'000;  // a process stamping its status with the wall clock
  ucon::process_status_t planner{};
  planner.utime = 2'005'000;  // message time: kept
  ucon::process_status_t early{};
  early.utime = 1'990'000;  // logged before the first pose, with a good time of its own
  const auto f = mcap_test::parse(run({{"LOG_METADATA", encode(meta)},
                                       {"LOGGER_STATUS", encode(logger)},
                                       {"LIDAR_STATUS", encode(early)},
                                       {"ROBOT_POSE", encode(pose(2'000'000))},
                                       {"PROC_STATUS", encode(procs)},
                                       {"PLANNER_STATUS", encode(st)},
                                       {"PERCEPTION_STATUS", encode(planner)},
                                       {"LOGGER_STATUS", encode(logger)},
                                       {"ROBOT_POSE", encode(pose(2'010'000))}})
                                      .bytes);
  ASSERT_TRUE(f.errors.empty()) << f.errors.front();
  std::map<std::string, std::vector<uint64_t>> times;
  for (const auto& m : f.messages) times[f.channels.at(m.channel).topic].push_back(m.log_time);
  EXPECT_EQ(times["LOG_METADATA"], std::vector<uint64_t>{2'000'000'000});  // waited for the first timed message
  EXPECT_EQ(times["ROBOT_POSE"], (std::vector<uint64_t>{2'000'000'000, 2'010'000'000}));
  EXPECT_EQ(times["PROC_STATUS"], std::vector<uint64_t>{2'000'000'000});
  EXPECT_EQ(times["PLANNER_STATUS"], std::vector<uint64_t>{2'000'000'000});
  EXPECT_EQ(times["PERCEPTION_STATUS"], std::vector<uint64_t>{2'005'000'000});
  EXPECT_EQ(times["LIDAR_STATUS"], std::vector<uint64_t>{1'990'000'000});  // waited, kept its own
  // Wall clock among simulation time: where it was logged (before the first pose: its time).
  EXPECT_EQ(times["LOGGER_STATUS"], (std::vector<uint64_t>{2'000'000'000, 2'005'000'000}));
  EXPECT_EQ(times["/tf"].size(), 2u);
  EXPECT_EQ(times["/robot_pose"].size(), 2u);
  // The raw JSON keeps the wall-clock utime.
  for (const auto& m : f.messages) {
    if (f.channels.at(m.channel).topic == "LOG_METADATA") {
      EXPECT_EQ(json::parse(m.data)["utime"], meta.utime);
    }
  }
  // LOG_METADATA came first in the log and is first in the file.
  EXPECT_EQ(f.channels.at(f.messages.front().channel).topic, "LOG_METADATA");
}

TEST(MessageClock, GivenTheTimeBaseAndOthersWhenTimedThenOnlyTheTimeBaseMovesTheClockFar) {
  const auto* pose_type = fg::findLcmTypeByName("ucon.robot_pose_t");
  const auto* status_type = fg::findLcmTypeByName("ucon.process_status_t");
  auto status = [](int64_t utime) {
    ucon::process_status_t s{};
    s.utime = utime;
    return encode(s);
  };
  fg::MessageClock clock;
  auto s1 = status(5'000'000);
  EXPECT_FALSE(clock.timeOf(*status_type, s1.data(), s1.size()).has_value());  // no clock yet
  auto p1 = encode(pose(1'000'000));
  EXPECT_EQ(clock.timeOf(*pose_type, p1.data(), p1.size()), 1'000'000);
  EXPECT_EQ(clock.timeOf(*status_type, s1.data(), s1.size()), 5'000'000);  // within the window: kept
  auto far = status(1'000'000 + fg::MessageClock::kWindowUs + 10'000'000);
  EXPECT_EQ(clock.timeOf(*status_type, far.data(), far.size()), 5'000'000);  // out of it: the clock
  auto back = encode(pose(500'000));  // the time base may jump (a new run in the same log)
  EXPECT_EQ(clock.timeOf(*pose_type, back.data(), back.size()), 500'000);
  EXPECT_EQ(clock.now(), 500'000);
  EXPECT_TRUE(fg::MessageClock::isTimeBase(*fg::findLcmTypeByName("ucon.point_cloud_t")));
  EXPECT_FALSE(fg::MessageClock::isTimeBase(*status_type));
}

TEST(McapExport, GivenChannelsWhenExportedThenRawTopicsCarryTheirTypeSchemaAndViewsFoxglovesOwn) {
  const auto e = run({{"ROBOT_POSE", encode(pose(1'000'000))}, {"GT_POSE", encode(pose(1'000'000))}});
  const auto f = mcap_test::parse(e.bytes);
  ASSERT_TRUE(f.errors.empty()) << f.errors.front();
  std::map<std::string, std::string> schema_of;
  for (const auto& [id, ch] : f.channels) {
    EXPECT_EQ(ch.encoding, "json");
    schema_of[ch.topic] = f.schemas.at(ch.schema).name;
    EXPECT_EQ(f.schemas.at(ch.schema).encoding, "jsonschema");
  }
  EXPECT_EQ(schema_of["ROBOT_POSE"], "ucon.robot_pose_t");
  EXPECT_EQ(schema_of["GT_POSE"], "ucon.robot_pose_t");
  EXPECT_EQ(schema_of["/tf"], "foxglove.FrameTransform");
  EXPECT_EQ(schema_of["/robot_pose"], "foxglove.PoseInFrame");
  EXPECT_EQ(schema_of["/gt_pose"], "foxglove.PoseInFrame");
  // One schema record per schema, shared by the channels that use it.
  EXPECT_EQ(f.stat_schemas, 3);
  // ROBOT_POSE: raw, /tf, /robot_pose; GT_POSE: raw, /gt_pose (only ROBOT_POSE moves `base`).
  EXPECT_EQ(e.stats.messages, 5);
}

TEST(McapExport, GivenUnknownAndUndecodableEventsWhenExportedThenCountedAndLeftOut) {
  auto garbage = encode(pose(1'000'000));
  garbage[0] ^= 0xFF;
  auto truncated = encode(pose(1'000'000));
  truncated.resize(truncated.size() - 5);
  const auto e = run({{"NOISE", garbage}, {"ROBOT_POSE", truncated}, {"ROBOT_POSE", encode(pose(1'000'000))}});
  EXPECT_EQ(e.stats.unknown_type.at("NOISE"), 1);
  EXPECT_EQ(e.stats.undecodable.at("ROBOT_POSE"), 1);
  const auto f = mcap_test::parse(e.bytes);
  ASSERT_TRUE(f.errors.empty()) << f.errors.front();
  EXPECT_EQ(f.stat_messages, 3u);  // ROBOT_POSE, /tf, /robot_pose of the good event
}

TEST(McapExport, GivenNoTimeBaseWhenExportedThenMessagesKeepTheirOwnTimeOrZero) {
  ucon::log_metadata_t meta{};
  meta.utime = 1'700'000'000'000'000;
  ucon::process_status_t st{};
  st.utime = 3'000'000;
  const auto e = run({{"LOG_METADATA", encode(meta)}, {"LCM_SELF_TEST", std::vector<uint8_t>(8, 1)},
                      {"PLANNER_STATUS", encode(st)}});
  EXPECT_TRUE(e.stats.unknown_type.empty());  // LCM's self test is left out silently
  const auto f = mcap_test::parse(e.bytes);
  ASSERT_TRUE(f.errors.empty()) << f.errors.front();
  ASSERT_EQ(f.messages.size(), 3u);  // LOG_METADATA, PLANNER_STATUS and its view
  EXPECT_EQ(f.messages[0].log_time, 0u);
  EXPECT_EQ(f.messages[1].log_time, 3'000'000'000u);
}

TEST(McapExport, GivenOptionsWhenExportingThenRawOrViewsCanBeLeftOut) {
  fg::ExportOptions only_views;
  only_views.raw_json = false;
  auto f = mcap_test::parse(run({{"ROBOT_POSE", encode(pose(1'000'000))}}, only_views).bytes);
  EXPECT_EQ(f.stat_messages, 2u);
  fg::ExportOptions only_raw;
  only_raw.foxglove = false;
  f = mcap_test::parse(run({{"ROBOT_POSE", encode(pose(1'000'000))}}, only_raw).bytes);
  EXPECT_EQ(f.stat_messages, 1u);
}
