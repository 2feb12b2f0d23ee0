// LogWriter: rotation never splits an event, the metadata event comes first in every file,
// the disk guard stops writing; the channel filter and the seq reader.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ucon/logger/log_writer.hpp"

namespace fs = std::filesystem;
using ucon::logger::LogWriter;
using ucon::logger::WriteResult;

namespace {

struct Event {
  std::string channel;
  std::vector<uint8_t> data;
  int64_t utime;
};

std::vector<Event> readAll(const std::string& path) {
  std::vector<Event> out;
  lcm::LogFile f(path, "r");
  EXPECT_TRUE(f.good()) << path;
  while (const lcm::LogEvent* e = f.readNextEvent()) {
    const auto* d = static_cast<const uint8_t*>(e->data);
    out.push_back({e->channel, std::vector<uint8_t>(d, d + e->datalen), e->timestamp});
  }
  return out;
}

class LogWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ucon_logwriter_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::vector<uint8_t> meta(int index, int64_t) { return {'M', static_cast<uint8_t>(index)}; }
  fs::path dir_;
};

}  // namespace

TEST_F(LogWriterTest, GivenSmallSizeLimitWhenWritingThenFilesRotateBetweenEventsAndLoseNothing) {
  ucon::logger::LogWriterLimits lim;
  lim.max_file_bytes = 4000;
  lim.min_free_bytes = 0;
  LogWriter w(dir_.string(), "t", lim, "LOG_METADATA", meta, nullptr);
  std::vector<Event> in;
  int rotations = 0;
  for (int i = 0; i < 200; ++i) {
    Event e{"CH" + std::to_string(i % 3), std::vector<uint8_t>(10 + (i * 37) % 300, uint8_t(i)), 1000 + i};
    in.push_back(e);
    auto r = w.write(e.channel, e.data.data(), e.data.size(), e.utime);
    ASSERT_NE(r, WriteResult::kIoError) << w.lastError();
    rotations += r == WriteResult::kRotated;
  }
  w.close();
  ASSERT_GT(w.files().size(), 3u);
  EXPECT_EQ(static_cast<std::size_t>(rotations), w.files().size() - 1);
  std::vector<Event> out;
  for (std::size_t k = 0; k < w.files().size(); ++k) {
    EXPECT_LE(fs::file_size(w.files()[k]), 4000u) << "file " << k << " exceeds the size limit";
    auto ev = readAll(w.files()[k]);
    ASSERT_FALSE(ev.empty());
    EXPECT_EQ(ev[0].channel, "LOG_METADATA") << "metadata must be the first event of file " << k;
    EXPECT_EQ(ev[0].data[1], k);
    out.insert(out.end(), ev.begin() + 1, ev.end());
  }
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(out[i].channel, in[i].channel);
    EXPECT_EQ(out[i].data, in[i].data);
    EXPECT_EQ(out[i].utime, in[i].utime);
  }
}

TEST_F(LogWriterTest, GivenDurationLimitThenANewFileStartsAfterIt) {
  ucon::logger::LogWriterLimits lim;
  lim.max_file_us = 1000000;
  lim.min_free_bytes = 0;
  LogWriter w(dir_.string(), "t", lim, "LOG_METADATA", meta, nullptr);
  uint8_t b[24] = {0};
  for (int i = 0; i < 25; ++i) w.write("X", b, sizeof(b), 10000000 + i * 100000);  // 2.5 s
  w.close();
  EXPECT_EQ(w.files().size(), 3u);
}

TEST_F(LogWriterTest, GivenLowDiskThenWritingStopsWithAStatus) {
  ucon::logger::LogWriterLimits lim;
  lim.min_free_bytes = 1 << 20;
  int64_t free_bytes = 10 << 20;
  LogWriter w(dir_.string(), "t", lim, "LOG_METADATA", meta, [&] { return free_bytes; });
  uint8_t b[24] = {0};
  EXPECT_EQ(w.write("X", b, sizeof(b), 1), WriteResult::kOk);
  free_bytes = 1000;
  // The guard is checked periodically and on every write once low.
  int low = 0;
  for (int i = 0; i < 100; ++i) low += w.write("X", b, sizeof(b), 2 + i) == WriteResult::kDiskLow;
  EXPECT_GE(low, 30);
  EXPECT_TRUE(w.diskLow());
  EXPECT_STREQ(ucon::logger::toString(WriteResult::kDiskLow), "disk space below the limit: not writing");
}

TEST(ChannelFilter, GivenIncludeAndExcludeThenOnlyMatchingChannelsPass) {
  ucon::logger::ChannelFilter f("LIDAR_.*|ROBOT_POSE", "LIDAR_IMU");
  EXPECT_TRUE(f.accepts("LIDAR_POINTS"));
  EXPECT_FALSE(f.accepts("LIDAR_IMU"));
  EXPECT_TRUE(f.accepts("ROBOT_POSE"));
  EXPECT_FALSE(f.accepts("ROBOT_POSE2"));
  EXPECT_FALSE(f.accepts("PLANNER_TRAJECTORY"));
  ucon::logger::ChannelFilter all(".*", "");
  EXPECT_TRUE(all.accepts("ANYTHING"));
}

TEST(SeqField, GivenAnEncodedMessageThenSeqIsReadFromBytes16To23) {
  std::vector<uint8_t> b(24, 0);
  b[22] = 0x01;
  b[23] = 0x02;
  int64_t seq = 0;
  ASSERT_TRUE(ucon::logger::readSeqField(b.data(), b.size(), &seq));
  EXPECT_EQ(seq, 0x0102);
  EXPECT_FALSE(ucon::logger::readSeqField(b.data(), 23, &seq));
}
