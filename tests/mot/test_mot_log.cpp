// ucon-mot --log: ground truth and tracks written to a real LCM log with lcm::LogFile are
// paired by utime and evaluated; a truncated or foreign file gives a clear error.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "ucon/mot/mot_log.hpp"
#include "ucon/channels.hpp"
#include "../support/test_support.hpp"

namespace {

std::string tempPath(const std::string& name) {
  return "/tmp/ucon_test_mot_" + std::to_string(::getpid()) + "_" + name;
}

template <class Msg>
void write(lcm::LogFile& log, const std::string& channel, const Msg& m, int64_t t) {
  ucon::test::writeLogEvent(log, channel, m, t);
}

ucon::sim_ground_truth_t gtAt(int64_t utime, double x) {
  ucon::sim_ground_truth_t g{};
  g.utime = utime;
  g.scenario = "test";
  ucon::sim_object_t o{};
  o.id = 1;
  o.x = x;
  o.y = 0.0;
  o.vx = 1.0;  // 1 m/s along x
  o.radius = 0.3;
  o.height = 1.7;
  g.objects.push_back(o);
  g.num_objects = 1;
  return g;
}

ucon::tracked_objects_t tracksAt(int64_t utime, int64_t id, double x, bool valid = true) {
  ucon::tracked_objects_t t{};
  t.utime = utime;
  t.valid = valid;
  t.frame_id = "world";
  ucon::tracked_object_t o{};
  o.id = id;
  o.state = ucon::tracked_object_t::STATE_CONFIRMED;
  o.x = x;
  t.objects.push_back(o);
  t.num_objects = 1;
  return t;
}

// Four frames at 50 Hz: track 5, then 5, then 6 (switch), then an invalid frame (miss).
std::string writeRun(const std::string& name) {
  const std::string path = tempPath(name);
  lcm::LogFile log(path, "w");
  EXPECT_TRUE(log.good());
  for (int k = 0; k < 4; ++k) {
    const int64_t t = 1000000 + k * 20000;
    write(log, ucon::channels::kSimGroundTruth, gtAt(t, 0.02 * k), t);
    // The perception frame is 4 ms later than ground truth: ground truth is extrapolated.
    const int64_t id = k < 2 ? 5 : 6;
    write(log, ucon::channels::kPerceptionObjects,
          tracksAt(t + 4000, id, 0.02 * k + 0.004 + 0.1, k != 3), t + 5000);
  }
  write(log, "OTHER", gtAt(1, 0.0), 1);
  return path;
}

}  // namespace

TEST(MotLog, GivenALogWithGroundTruthAndTracksThenFramesArePairedAndCounted) {
  const std::string path = writeRun("ok.lcm");
  ucon::mot::LogEvalOptions opt;
  ucon::mot::LogMatchStats st;
  std::string err;
  const auto s = ucon::mot::evaluateLog(path, opt, &st, &err);
  ASSERT_TRUE(s) << err;
  EXPECT_EQ(st.frames_evaluated, 4);
  EXPECT_EQ(st.invalid_frames, 1);
  EXPECT_EQ(s->num_objects, 4);
  EXPECT_EQ(s->num_matches, 3);
  EXPECT_EQ(s->num_switches, 1);
  EXPECT_EQ(s->num_misses, 1);
  // Each matched track is 0.1 m ahead of the extrapolated ground truth.
  EXPECT_NEAR(s->motp, 0.1, 1e-9);
  EXPECT_NEAR(s->mota, 1.0 - 2.0 / 4.0, 1e-12);
  std::remove(path.c_str());
}

TEST(MotLog, GivenATruncatedLogThenAClearErrorIsReturnedUnlessAllowed) {
  const std::string path = writeRun("trunc.lcm");
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  // Cut in the middle of the last event.
  const std::string cut = tempPath("cut.lcm");
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 40);
  ucon::mot::LogEvalOptions opt;
  ucon::mot::LogMatchStats st;
  std::string err;
  EXPECT_FALSE(ucon::mot::evaluateLog(cut, opt, &st, &err));
  EXPECT_NE(err.find("truncated"), std::string::npos) << err;
  opt.allow_truncated = true;
  const auto s = ucon::mot::evaluateLog(cut, opt, &st, &err);
  ASSERT_TRUE(s) << err;
  EXPECT_TRUE(st.truncated);
  EXPECT_EQ(st.frames_evaluated, 4);
  std::remove(path.c_str());
  std::remove(cut.c_str());
}

TEST(MotLog, GivenGarbageInsideTheLogThenItIsReportedAsCorrupt) {
  const std::string path = writeRun("garbage.lcm");
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  // Overwrite the sync word of the second event: the reader must skip to the third.
  const size_t second = bytes.find("\xED\xA1\xDA\x01", 4);
  ASSERT_NE(second, std::string::npos);
  bytes[second] = 'X';
  const std::string bad = tempPath("bad.lcm");
  std::ofstream(bad, std::ios::binary) << bytes;
  ucon::mot::LogEvalOptions opt;
  std::string err;
  EXPECT_FALSE(ucon::mot::evaluateLog(bad, opt, nullptr, &err));
  EXPECT_NE(err.find("corrupt"), std::string::npos) << err;
  std::remove(path.c_str());
  std::remove(bad.c_str());
}

TEST(MotLog, GivenAFileThatIsNotAnLcmLogOrIsMissingThenTheErrorSaysSo) {
  const std::string path = tempPath("text.txt");
  std::ofstream(path) << "hello, not a log\n";
  std::string err;
  EXPECT_FALSE(ucon::mot::evaluateLog(path, {}, nullptr, &err));
  EXPECT_NE(err.find("not an LCM log"), std::string::npos) << err;
  EXPECT_FALSE(ucon::mot::evaluateLog(tempPath("missing.lcm"), {}, nullptr, &err));
  EXPECT_NE(err.find("cannot open"), std::string::npos) << err;
  std::remove(path.c_str());
}

TEST(MotLog, GivenAnObjectsLogThenItsTracksAreEvaluatedAgainstTheFirstLogsGroundTruth) {
  // The run's log holds ground truth and tracks; a second log (a replay's output) holds other
  // tracks: with objects_log set only the second log's tracks count.
  const std::string run = writeRun("run.lcm");
  const std::string replay = tempPath("replay.lcm");
  {
    lcm::LogFile log(replay, "w");
    ASSERT_TRUE(log.good());
    for (int k = 0; k < 4; ++k) {
      const int64_t t = 1000000 + k * 20000;
      write(log, ucon::channels::kPerceptionObjects, tracksAt(t, 9, 0.02 * k), t);  // exact, one id
    }
  }
  ucon::mot::LogEvalOptions opt;
  opt.objects_log = replay;
  ucon::mot::LogMatchStats st;
  std::string err;
  const auto s = ucon::mot::evaluateLog(run, opt, &st, &err);
  ASSERT_TRUE(s) << err;
  EXPECT_EQ(st.frames_evaluated, 4);
  EXPECT_EQ(st.perception_messages, 4);
  EXPECT_EQ(s->num_matches, 4);
  EXPECT_EQ(s->num_switches, 0);
  EXPECT_NEAR(s->mota, 1.0, 1e-12);
  // An objects log without tracks, or a missing one, is an error naming that file.
  opt.objects_log = run + ".missing";
  EXPECT_FALSE(ucon::mot::evaluateLog(run, opt, nullptr, &err));
  EXPECT_NE(err.find(".missing"), std::string::npos) << err;
  const std::string empty = tempPath("empty.lcm");
  {
    lcm::LogFile log(empty, "w");
    write(log, "OTHER", gtAt(1, 0.0), 1);
  }
  opt.objects_log = empty;
  EXPECT_FALSE(ucon::mot::evaluateLog(run, opt, nullptr, &err));
  EXPECT_NE(err.find("no decodable PERCEPTION_OBJECTS"), std::string::npos) << err;
  EXPECT_NE(err.find(empty), std::string::npos) << err;
  std::remove(run.c_str());
  std::remove(replay.c_str());
  std::remove(empty.c_str());
}
