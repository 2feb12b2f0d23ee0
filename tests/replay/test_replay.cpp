// Deterministic replay: a simulated run recorded in-process (no LCM) replays through every
// built node twice with byte-identical outputs that equal what the node published while the
// run was recorded; the golden scenario's outputs match tests/data/replay; damaged logs give
// an error naming the byte offset, never a crash or a half-written output.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "replay_test_support.hpp"
#include "ucon/channels.hpp"
#include "ucon/replay/node_adapter.hpp"
#include "ucon/replay/record_to_log.hpp"
#include "ucon/replay/replay_runner.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/log_compare.hpp"
#include "ucon/runtime/log_reader.hpp"

namespace rp = ucon::replay;
namespace rt = ucon::runtime;
using replay_test::readBytes;
using replay_test::TempDir;
using replay_test::writeBytes;

namespace {

const std::string kSource = UCON_SOURCE_DIR;

rp::RecordingSpec spec(const std::string& scenario, double duration, const std::vector<std::string>& nodes) {
  rp::RecordingSpec s;
  s.scenario = scenario;
  s.duration_s = duration;
  s.nodes = nodes;
  s.config_dir = kSource + "/deploy/config";
  s.scenario_dir = kSource + "/deploy/scenarios";
  return s;
}

std::unique_ptr<rp::NodeAdapter> adapterFromLog(const std::string& log, const std::string& node) {
  std::string err;
  auto yaml = rp::configFromLog(log, node, &err);
  EXPECT_TRUE(yaml.has_value()) << err;
  if (!yaml) return nullptr;
  auto a = rp::makeAdapter(node, *yaml, log, &err);
  EXPECT_NE(a, nullptr) << err;
  return a;
}

std::unique_ptr<rp::NodeAdapter> adapterFromDeploy(const std::string& node) {
  std::string err;
  const std::string path = kSource + "/deploy/config/" + node + ".yaml";
  auto yaml = rt::readTextFile(path, &err);
  EXPECT_TRUE(yaml.has_value()) << err;
  auto a = rp::makeAdapter(node, yaml.value_or(""), path, &err);
  EXPECT_NE(a, nullptr) << err;
  return a;
}

// Byte offsets of every event of a log.
std::vector<int64_t> eventOffsets(const std::string& path) {
  rt::LogReader r;
  EXPECT_TRUE(r.open(path));
  std::vector<int64_t> out;
  rt::LogEvent e;
  while (r.next(&e) == rt::LogReadStatus::kOk) out.push_back(e.offset);
  return out;
}

// A short base-controller run (0.6 s simulated) for the error tests.
std::string shortRun(const TempDir& dir) {
  const std::string path = dir.file("short.lcm");
  std::string err;
  EXPECT_TRUE(rp::recordToLog(spec("crossing", 0.6, {"base_controller"}), path, nullptr, &err)) << err;
  return path;
}

}  // namespace

TEST(SimRecorder, GivenTheSameSpecWhenRecordedTwiceThenTheLogsAreByteIdenticalAndHoldEveryChannel) {
  TempDir dir;
  // The base follows the scripted plan (no planner in the loop), so the robot moves.
  const auto s = spec("crossing", 2.0, {"base_controller"});
  rp::RecordSummary a, b;
  std::string err;
  ASSERT_TRUE(rp::recordToLog(s, dir.file("a.lcm"), &a, &err)) << err;
  ASSERT_TRUE(rp::recordToLog(s, dir.file("b.lcm"), &b, &err)) << err;
  const auto ba = readBytes(dir.file("a.lcm"));
  EXPECT_GT(ba.size(), 1000000u);
  EXPECT_TRUE(ba == readBytes(dir.file("b.lcm")));
  // 2 s of simulation: 100 Hz poses, 50 Hz frames and ground truth, 200 Hz IMU, 100 Hz commands.
  EXPECT_EQ(a.messages[ucon::channels::kRobotPose], 200 + 1);
  EXPECT_NEAR(static_cast<double>(a.messages[ucon::channels::kLidarPoints]), 100.0, 1.0);
  EXPECT_NEAR(static_cast<double>(a.messages[ucon::channels::kLidarImu]), 400.0, 1.0);
  EXPECT_EQ(a.messages[ucon::channels::kSimGroundTruth], 100 + 1);
  EXPECT_NEAR(static_cast<double>(a.messages[ucon::channels::kBaseWheelCmd]), 200.0, 2.0);
  EXPECT_EQ(a.messages[ucon::channels::kLogMetadata], 1);
  // The loop is closed: the base moved toward the goal (+x in the crossing scenario).
  EXPECT_GT(a.final_x, 0.3);
  EXPECT_GT(a.wheel_cmds_applied, 150);
}

TEST(Replay, GivenARecordedRunWhenEachNodeIsReplayedTwiceThenOutputsAreByteIdenticalAndEqualTheRecording) {
  TempDir dir;
  const std::string run = dir.file("run.lcm");
  std::string err;
  // Every built node in the loop (the whole stack when perception and planner exist; with the
  // odometry, the robot's pose comes from it, after its 0.5 s standstill start); 1.5 s of
  // simulation keeps the planner's share of the test to a few seconds.
  ASSERT_TRUE(rp::recordToLog(spec("crossing", 1.5, rp::availableNodes()), run, nullptr, &err)) << err;
  for (const auto& node : rp::availableNodes()) {
    SCOPED_TRACE(node);
    const std::string o1 = dir.file(node + "_1.lcm"), o2 = dir.file(node + "_2.lcm");
    auto a1 = adapterFromLog(run, node);
    auto a2 = adapterFromLog(run, node);
    ASSERT_TRUE(a1 && a2);
    const auto r1 = rp::replayLog(*a1, run, o1);
    const auto r2 = rp::replayLog(*a2, run, o2);
    ASSERT_TRUE(r1.ok) << r1.error;
    ASSERT_TRUE(r2.ok) << r2.error;
    EXPECT_GT(r1.summary.handled, 50);
    EXPECT_GE(r1.summary.outputs, 10);
    EXPECT_EQ(r1.summary.decode_errors, 0);
    const auto b1 = readBytes(o1);
    EXPECT_FALSE(b1.empty());
    EXPECT_TRUE(b1 == readBytes(o2)) << "two replays of the same log differ";
    // The node was in the loop while recording: the replay reproduces what it published.
    const auto c = rt::compareLogs(o1, run, rp::exactChannelRegex(a1->outputChannels()));
    EXPECT_TRUE(c.identical) << c.message;
    EXPECT_EQ(c.events_compared, r1.summary.outputs);
  }
}

TEST(Replay, GivenAChangedNodeConfigThenCompareNamesTheFirstDifferingMessageAndField) {
  TempDir dir;
  const std::string run = shortRun(dir);
  auto ref = adapterFromDeploy("base_controller");
  ASSERT_TRUE(ref);
  ASSERT_TRUE(rp::replayLog(*ref, run, dir.file("ref.lcm")).ok);
  // Same node, a different position gain: the commands must differ, and compare says where.
  std::string err;
  auto yaml = rt::readTextFile(kSource + "/deploy/config/base_controller.yaml", &err);
  ASSERT_TRUE(yaml);
  const auto pos = yaml->find("kp_position:");
  ASSERT_NE(pos, std::string::npos);
  const auto eol = yaml->find('\n', pos);
  yaml->replace(pos, eol - pos, "kp_position: 0.3");
  auto changed = rp::makeAdapter("base_controller", *yaml, "changed", &err);
  ASSERT_TRUE(changed) << err;
  ASSERT_TRUE(rp::replayLog(*changed, run, dir.file("changed.lcm")).ok);
  const auto c = rt::compareLogs(dir.file("changed.lcm"), dir.file("ref.lcm"));
  EXPECT_FALSE(c.identical);
  EXPECT_FALSE(c.error);
  EXPECT_NE(c.message.find("BASE_WHEEL_CMD"), std::string::npos) << c.message;
  EXPECT_NE(c.message.find("field w_"), std::string::npos) << c.message;
}

TEST(ReplayErrors, GivenALogTruncatedInsideAnEventThenTheErrorNamesItsByteOffsetAndNoOutputIsLeft) {
  TempDir dir;
  const std::string run = shortRun(dir);
  const auto offsets = eventOffsets(run);
  ASSERT_GT(offsets.size(), 50u);
  auto bytes = readBytes(run);
  for (const int64_t cut : {offsets[40] + 10, offsets[41] - 5}) {
    SCOPED_TRACE(cut);
    std::vector<uint8_t> b(bytes.begin(), bytes.begin() + cut);
    writeBytes(dir.file("cut.lcm"), b);
    auto a = adapterFromDeploy("base_controller");
    const auto r = rp::replayLog(*a, dir.file("cut.lcm"), dir.file("out.lcm"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("truncated event"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("at byte offset " + std::to_string(offsets[40])), std::string::npos) << r.error;
    EXPECT_EQ(r.summary.events, 40);
    EXPECT_FALSE(replay_test::fs::exists(dir.file("out.lcm")));
  }
}

TEST(ReplayErrors, GivenACorruptSyncWordOrLengthThenTheErrorNamesTheDamagedEventsOffset) {
  TempDir dir;
  const std::string run = shortRun(dir);
  const auto offsets = eventOffsets(run);
  const auto good = readBytes(run);
  {
    auto b = good;
    b[offsets[30]] = 0x42;  // sync word
    writeBytes(dir.file("bad.lcm"), b);
    auto a = adapterFromDeploy("base_controller");
    const auto r = rp::replayLog(*a, dir.file("bad.lcm"), dir.file("out.lcm"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("bad sync word"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("byte offset " + std::to_string(offsets[30])), std::string::npos) << r.error;
  }
  {
    auto b = good;
    for (int i = 0; i < 4; ++i) b[offsets[12] + 24 + i] = 0x7F;  // data length ~2 GB
    writeBytes(dir.file("bad.lcm"), b);
    auto a = adapterFromDeploy("base_controller");
    const auto r = rp::replayLog(*a, dir.file("bad.lcm"), dir.file("out.lcm"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("impossible channel or data length"), std::string::npos) << r.error;
    EXPECT_NE(r.error.find("byte offset " + std::to_string(offsets[12])), std::string::npos) << r.error;
  }
  {
    std::vector<uint8_t> garbage(5000);
    for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<uint8_t>(i * 131 + 7);
    writeBytes(dir.file("garbage.lcm"), garbage);
    auto a = adapterFromDeploy("base_controller");
    const auto r = rp::replayLog(*a, dir.file("garbage.lcm"), dir.file("out.lcm"));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("at byte offset 0"), std::string::npos) << r.error;
  }
}

TEST(ReplayErrors, GivenUndecodableMessagesOnInputChannelsThenTheyAreCountedAndTheRestIsReplayed) {
  TempDir dir;
  const std::string run = shortRun(dir);
  // Append garbage on every input channel after the good events.
  {
    rt::LogReader r;
    ASSERT_TRUE(r.open(run));
    rt::LogWriterFile w;
    std::string err;
    ASSERT_TRUE(w.open(dir.file("mixed.lcm"), &err)) << err;
    rt::LogEvent e;
    while (r.next(&e) == rt::LogReadStatus::kOk) w.write(e.channel, e.data.data(), e.data.size(), e.timestamp);
    const uint8_t junk[5] = {1, 2, 3, 4, 5};
    for (const char* ch : {ucon::channels::kRobotPose, ucon::channels::kPlannerTrajectory, ucon::channels::kBaseEstop})
      w.write(ch, junk, sizeof(junk), 0);
    w.write(ucon::channels::kRobotPose, junk, 0, 0);  // empty payload
  }
  auto a = adapterFromDeploy("base_controller");
  auto b = adapterFromDeploy("base_controller");
  const auto mixed = rp::replayLog(*a, dir.file("mixed.lcm"), dir.file("mixed_out.lcm"));
  const auto clean = rp::replayLog(*b, run, dir.file("clean_out.lcm"));
  ASSERT_TRUE(mixed.ok) << mixed.error;
  EXPECT_EQ(mixed.summary.decode_errors, 4);
  EXPECT_TRUE(readBytes(dir.file("mixed_out.lcm")) == readBytes(dir.file("clean_out.lcm")));
}

TEST(ReplayErrors, GivenAnEmptyOrMissingLogThenEmptyOutputOrAClearError) {
  TempDir dir;
  writeBytes(dir.file("empty.lcm"), {});
  auto a = adapterFromDeploy("base_controller");
  const auto r = rp::replayLog(*a, dir.file("empty.lcm"), dir.file("out.lcm"));
  EXPECT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.summary.events, 0);
  const auto m = rp::replayLog(*a, dir.file("nope.lcm"), dir.file("out2.lcm"));
  EXPECT_FALSE(m.ok);
  EXPECT_NE(m.error.find("cannot open"), std::string::npos) << m.error;
}

TEST(ReplayAdapters, GivenAnUnknownNodeOrABadConfigThenNoAdapterAndTheErrorNamesIt) {
  std::string err;
  EXPECT_EQ(rp::makeAdapter("navigator", "", "x", &err), nullptr);
  EXPECT_NE(err.find("unknown node 'navigator'"), std::string::npos) << err;
  auto yaml = rt::readTextFile(kSource + "/deploy/config/base_controller.yaml", &err);
  ASSERT_TRUE(yaml);
  *yaml += "\nno_such_key: 1\n";
  EXPECT_EQ(rp::makeAdapter("base_controller", *yaml, "bad.yaml", &err), nullptr);
  EXPECT_NE(err.find("no_such_key"), std::string::npos) << err;
  // The base controller is always there; every listed node can be made from deploy/config.
  const auto nodes = rp::availableNodes();
  EXPECT_NE(std::find(nodes.begin(), nodes.end(), "base_controller"), nodes.end());
  for (const auto& n : nodes) {
    auto a = adapterFromDeploy(n);
    ASSERT_TRUE(a) << n;
    EXPECT_EQ(a->name(), n);
    EXPECT_FALSE(a->inputChannels().empty());
    EXPECT_FALSE(a->outputChannels().empty());
  }
}

TEST(ReplayGolden, GivenTheGoldenScenarioThenEachNodesOutputsMatchTheReferenceInTestsData) {
  const std::string data = kSource + "/tests/data/replay";
  const auto m = replay_test::readManifest(data + "/MANIFEST");
  ASSERT_TRUE(m.ok) << data << "/MANIFEST missing or unreadable: run scripts/regen-golden.sh";
  const auto nodes = rp::parseNodeList(m.nodes);
  const auto avail = rp::availableNodes();
  for (const auto& n : nodes) {
    if (std::find(avail.begin(), avail.end(), n) == avail.end()) {
      GTEST_SKIP() << "the golden run had node '" << n << "' in the loop; this build lacks it";
    }
  }
  TempDir dir;
  const std::string run = dir.file("golden_input.lcm");
  std::string err;
  ASSERT_TRUE(rp::recordToLog(spec(m.scenario, m.duration_s, nodes), run, nullptr, &err)) << err;

  // The recording itself: if it changed, the outputs cannot match; say so first.
  auto digest = rp::digestLog(run, &err);
  ASSERT_TRUE(digest) << err;
  for (const auto& [ch, expect] : m.input) {
    if (ch == ucon::channels::kLogMetadata) continue;  // holds the config texts, comments included
    char hex[17];
    const auto it = digest->find(ch);
    const long long n = it == digest->end() ? 0 : it->second.events;
    std::snprintf(hex, sizeof(hex), "%016llx",
                  static_cast<unsigned long long>(it == digest->end() ? 0 : it->second.hash));
    EXPECT_TRUE(n == expect.first && expect.second == hex)
        << "the recorded golden input differs on " << ch << " (" << n << " events, " << hex << " vs "
        << expect.first << ", " << expect.second << "): the simulator, the driver, a config or an "
        << "in-loop node changed. If that is intended, run scripts/regen-golden.sh and review the diff.";
  }
  ASSERT_FALSE(m.golden.empty());
  for (const auto& [node, file] : m.golden) {
    SCOPED_TRACE(node);
    if (std::find(avail.begin(), avail.end(), node) == avail.end()) continue;
    auto a = adapterFromLog(run, node);
    ASSERT_TRUE(a);
    const std::string out = dir.file(node + ".lcm");
    const auto r = rp::replayLog(*a, run, out);
    ASSERT_TRUE(r.ok) << r.error;
    const auto c = rt::compareLogs(out, data + "/" + file);
    EXPECT_FALSE(c.error) << c.message;
    EXPECT_TRUE(c.identical) << node << " no longer reproduces tests/data/replay/" << file << ": " << c.message
                             << ". If the change is intended, run scripts/regen-golden.sh.";
    EXPECT_GT(c.events_compared, 10);
  }
}

TEST(ReplayAdapters, GivenGarbageOnEveryInputChannelThenEachNodeCountsADecodeErrorAndPublishesNothing) {
  const uint8_t junk[7] = {0xde, 0xad, 0xbe, 0xef, 0, 1, 2};
  for (const auto& n : rp::availableNodes()) {
    SCOPED_TRACE(n);
    auto a = adapterFromDeploy(n);
    ASSERT_TRUE(a);
    std::vector<rp::OutputMessage> out;
    for (const auto& ch : a->inputChannels()) {
      EXPECT_EQ(a->feed(ch, junk, sizeof(junk), &out), rp::FeedResult::kDecodeError) << ch;
      EXPECT_EQ(a->feed(ch, nullptr, 0, &out), rp::FeedResult::kDecodeError) << ch;
    }
    EXPECT_EQ(a->feed("SOMETHING_ELSE", junk, sizeof(junk), &out), rp::FeedResult::kIgnored);
    EXPECT_TRUE(out.empty());
    int64_t errors = -1;
    for (const auto& [k, v] : a->counters()) {
      if (k == "decode_errors") errors = v;
    }
    EXPECT_EQ(errors, static_cast<int64_t>(2 * a->inputChannels().size()));
  }
}
