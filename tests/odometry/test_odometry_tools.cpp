// ucon-odometry and ucon-odom-eval as processes: a simulated run recorded in-process with the
// odometry giving the robot's pose (and the base controller driving on it), evaluated by
// ucon-odom-eval; the start pose taken from a scenario; bad flags refused with exit 2.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "../replay/replay_test_support.hpp"
#include "../support/test_support.hpp"
#include "ucon/replay/record_to_log.hpp"

#ifndef UCON_BIN_DIR
#define UCON_BIN_DIR "build/bin"
#endif

namespace {

int runTo(const std::vector<std::string>& args, const std::string& out) {
  const pid_t pid = ucon::test::spawn(args, out);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string readText(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

double jsonNumberAfter(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) return NAN;
  return std::atof(json.c_str() + at + key.size() + 4);
}

}  // namespace

TEST(OdometryTools, GivenARunDrivenOnTheOdometryThenOdomEvalReportsItsAccuracy) {
  replay_test::TempDir dir;
  const std::string log = dir.file("run.lcm");
  ucon::replay::RecordingSpec spec;
  spec.scenario = "crossing";
  spec.duration_s = 3.0;
  spec.nodes = {"odometry", "base_controller"};  // the base drives on the odometry's pose
  spec.config_dir = "deploy/config";
  spec.scenario_dir = "deploy/scenarios";
  std::string err;
  ucon::replay::RecordSummary summary;
  ASSERT_TRUE(ucon::replay::recordToLog(spec, log, &summary, &err)) << err;
  EXPECT_GT(summary.final_x, 0.5) << "the scripted plan drove on the odometry's pose";

  const std::string bin = UCON_BIN_DIR;
  const std::string out = dir.file("eval.json");
  ASSERT_EQ(runTo({bin + "/ucon-odom-eval", log, "--json"}, out), 0) << readText(out);
  const std::string json = readText(out);
  EXPECT_NE(json.find("\"pose_channel\": \"ROBOT_POSE\""), std::string::npos) << json;
  EXPECT_GT(jsonNumberAfter(json, "path_length_m"), 0.5) << json;
  EXPECT_LT(jsonNumberAfter(json, "ate_rmse_m"), 0.05) << json;
  EXPECT_LT(jsonNumberAfter(json, "final_drift_m"), 0.05) << json;
  EXPECT_GT(jsonNumberAfter(json, "updated"), 50) << json;
  EXPECT_EQ(jsonNumberAfter(json, "poses_valid_pct"), 100.0) << json;

  // The table, and a log without the channel: exit 1, saying so.
  ASSERT_EQ(runTo({bin + "/ucon-odom-eval", log}, out), 0);
  EXPECT_NE(readText(out).find("RPE"), std::string::npos) << readText(out);
  EXPECT_EQ(runTo({bin + "/ucon-odom-eval", log, "--channel", "ODOMETRY_POSE"}, out), 1);
  EXPECT_NE(readText(out).find("nothing to compare"), std::string::npos) << readText(out);
  EXPECT_EQ(runTo({bin + "/ucon-odom-eval", dir.file("missing.lcm")}, out), 2);
}

TEST(OdometryTools, GivenAScenarioOrAPoseThenTheStartPoseIsTakenAndBadOnesAreRefused) {
  replay_test::TempDir dir;
  const std::string bin = UCON_BIN_DIR, out = dir.file("out.txt");
  ASSERT_EQ(runTo({bin + "/ucon-odometry", "--scenario", "hall", "--print-start-pose"}, out), 0) << readText(out);
  EXPECT_EQ(readText(out), "0, -10, 0\n");
  ASSERT_EQ(runTo({bin + "/ucon-odometry", "--initial-pose", "1.5,-2,0.25", "--print-start-pose"}, out), 0);
  EXPECT_EQ(readText(out), "1.5, -2, 0.25\n");
  EXPECT_EQ(runTo({bin + "/ucon-odometry", "--initial-pose", "1.5,abc,0", "--print-start-pose"}, out), 2);
  EXPECT_NE(readText(out).find("X,Y,YAW"), std::string::npos) << readText(out);
  EXPECT_EQ(runTo({bin + "/ucon-odometry", "--scenario", "nowhere.yaml", "--print-start-pose"}, out), 2);
  EXPECT_EQ(runTo({bin + "/ucon-odometry", "--config", dir.file("none.yaml")}, out), 2);
}
