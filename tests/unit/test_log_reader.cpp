// The strict log reader: reads what lcm::LogFile writes; truncated and corrupt logs give an
// error with the byte offset instead of a crash or silent skipping.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "ucon/runtime/log_reader.hpp"

namespace fs = std::filesystem;
using ucon::runtime::LogEvent;
using ucon::runtime::LogReader;
using ucon::runtime::LogReadStatus;

namespace {
fs::path tmpFile(const std::string& name) {
  return fs::temp_directory_path() / ("ucon_logreader_" + std::to_string(getpid()) + "_" + name);
}
// Three events written by LCM's own writer: 28 + 2 + 10, 28 + 2 + 20, 28 + 2 + 0 bytes.
fs::path writeLog(const std::string& name) {
  const auto p = tmpFile(name);
  lcm::LogFile f(p.string(), "w");
  std::vector<uint8_t> d(20, 7);
  for (int i = 0; i < 3; ++i) {
    lcm::LogEvent e{};
    e.timestamp = 100 + i;
    e.channel = "C" + std::to_string(i);
    e.datalen = i == 2 ? 0 : 10 * (i + 1);
    e.data = d.data();
    f.writeEvent(&e);
  }
  return p;
}
}  // namespace

TEST(LogReader, GivenAnLcmLogThenEveryEventIsReadWithItsOffset) {
  const auto p = writeLog("ok");
  LogReader r;
  ASSERT_TRUE(r.open(p.string()));
  LogEvent e;
  ASSERT_EQ(r.next(&e), LogReadStatus::kOk);
  EXPECT_EQ(e.channel, "C0");
  EXPECT_EQ(e.data.size(), 10u);
  EXPECT_EQ(e.timestamp, 100);
  EXPECT_EQ(e.offset, 0);
  ASSERT_EQ(r.next(&e), LogReadStatus::kOk);
  EXPECT_EQ(e.offset, 40);
  ASSERT_EQ(r.next(&e), LogReadStatus::kOk);
  EXPECT_EQ(e.data.size(), 0u);
  EXPECT_EQ(r.next(&e), LogReadStatus::kEnd);
  fs::remove(p);
}

TEST(LogReader, GivenATruncatedLogThenTheErrorNamesTheOffsetOfTheBrokenEvent) {
  const auto p = writeLog("trunc");
  fs::resize_file(p, 40 + 28 + 2 + 5);  // second event cut in its data
  LogReader r;
  ASSERT_TRUE(r.open(p.string()));
  LogEvent e;
  ASSERT_EQ(r.next(&e), LogReadStatus::kOk);
  EXPECT_EQ(r.next(&e), LogReadStatus::kTruncated);
  EXPECT_NE(r.error().find("byte offset 40"), std::string::npos) << r.error();
  fs::resize_file(p, 40 + 10);  // cut inside the header
  LogReader r2;
  ASSERT_TRUE(r2.open(p.string()));
  ASSERT_EQ(r2.next(&e), LogReadStatus::kOk);
  EXPECT_EQ(r2.next(&e), LogReadStatus::kTruncated);
  fs::remove(p);
}

TEST(LogReader, GivenCorruptBytesThenBadSyncOrLengthIsReported) {
  const auto p = writeLog("corrupt");
  {
    std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(40);
    f.put(0x00);  // sync word of event 2
  }
  LogReader r;
  ASSERT_TRUE(r.open(p.string()));
  LogEvent e;
  ASSERT_EQ(r.next(&e), LogReadStatus::kOk);
  EXPECT_EQ(r.next(&e), LogReadStatus::kBadSync);
  EXPECT_NE(r.error().find("offset 40"), std::string::npos);
  {
    std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(40);
    f.put(static_cast<char>(0xED));
    f.seekp(40 + 24);
    f.put(0x7F);  // data length ~2 GB
  }
  LogReader r2;
  ASSERT_TRUE(r2.open(p.string()));
  ASSERT_EQ(r2.next(&e), LogReadStatus::kOk);
  EXPECT_EQ(r2.next(&e), LogReadStatus::kBadLength);
  fs::remove(p);
}

TEST(LogReader, GivenAMissingFileOrGarbageThenOpenOrFirstReadFailsClearly) {
  LogReader r;
  EXPECT_FALSE(r.open("/nonexistent/ucon.lcm"));
  EXPECT_NE(r.error().find("/nonexistent/ucon.lcm"), std::string::npos);
  const auto p = tmpFile("garbage");
  std::ofstream(p) << "this is not a log file at all";
  LogReader g;
  ASSERT_TRUE(g.open(p.string()));
  LogEvent e;
  EXPECT_EQ(g.next(&e), LogReadStatus::kBadSync);
  EXPECT_NE(g.error().find("offset 0"), std::string::npos);
  fs::remove(p);
}

TEST(LogWriterFile, GivenEventsThenLcmLogFileReadsThemBack) {
  const auto p = tmpFile("written");
  ucon::runtime::LogWriterFile w;
  std::string err;
  ASSERT_TRUE(w.open(p.string(), &err)) << err;
  const char data[] = "abc";
  ASSERT_TRUE(w.write("X", data, 3, 42));
  ASSERT_TRUE(w.write("YY", data, 0, 43));
  w.close();
  lcm::LogFile f(p.string(), "r");
  const lcm::LogEvent* e = f.readNextEvent();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->channel, "X");
  EXPECT_EQ(e->timestamp, 42);
  EXPECT_EQ(e->datalen, 3);
  e = f.readNextEvent();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->eventnum, 1);
  EXPECT_EQ(f.readNextEvent(), nullptr);
  fs::remove(p);
}

#include "ucon/nav_goal_t.hpp"
#include "ucon/runtime/log_compare.hpp"

namespace {
fs::path writeGoals(const std::string& name, double last_x) {
  const auto p = tmpFile(name);
  ucon::runtime::LogWriterFile w;
  EXPECT_TRUE(w.open(p.string(), nullptr));
  for (int i = 0; i < 3; ++i) {
    ucon::nav_goal_t g{};
    g.utime = i;
    g.seq = i;
    g.x = i == 2 ? last_x : 1.0;
    std::vector<uint8_t> buf(static_cast<std::size_t>(g.getEncodedSize()));
    g.encode(buf.data(), 0, static_cast<int>(buf.size()));
    w.write("NAV_GOAL", buf.data(), buf.size(), 1000 + i * 7);
  }
  return p;
}
}  // namespace

TEST(LogCompare, GivenTwoLogsThenTheFirstDifferingMessageAndFieldAreNamed) {
  const auto a = writeGoals("cmp_a", 5.0), b = writeGoals("cmp_b", 5.0), c = writeGoals("cmp_c", 6.0);
  auto r = ucon::runtime::compareLogs(a.string(), b.string());
  EXPECT_TRUE(r.identical) << r.message;
  EXPECT_EQ(r.events_compared, 3);
  r = ucon::runtime::compareLogs(a.string(), c.string());
  EXPECT_FALSE(r.identical);
  EXPECT_FALSE(r.error);
  EXPECT_NE(r.message.find("event 2 on NAV_GOAL"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("field x: 5 vs 6"), std::string::npos) << r.message;
  fs::resize_file(c, fs::file_size(c) - 3);
  r = ucon::runtime::compareLogs(a.string(), c.string());
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.message.find("byte offset"), std::string::npos) << r.message;
  for (const auto& p : {a, b, c}) fs::remove(p);
}
