// ucon-mot as a process: MOTChallenge files with --json, and a clear non-zero exit on bad input.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace {
struct Result {
  int code;
  std::string out;
};
Result run(const std::string& args) {
  const std::string cmd = std::string(UCON_BIN_DIR) + "/ucon-mot " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[512];
  while (p && fgets(buf, sizeof(buf), p)) out += buf;
  const int st = p ? pclose(p) : -1;
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}
std::string tmp(const std::string& n) { return "/tmp/ucon_test_mot_cli_" + std::to_string(::getpid()) + n; }
}  // namespace

TEST(MotCli, GivenMotChallengeFilesWithJsonThenOneObjectWithTheMetricsIsPrinted) {
  std::ofstream(tmp("gt.txt")) << "1,1,0,0,10,10,-1,-1,-1,-1\n2,1,0,0,10,10,-1,-1,-1,-1\n";
  std::ofstream(tmp("pr.txt")) << "1,7,0,0,10,10,-1\n2,8,1,0,10,10,-1\n";
  const auto r = run("--gt " + tmp("gt.txt") + " --pred " + tmp("pr.txt") + " --iou 0.5 --json");
  EXPECT_EQ(r.code, 0) << r.out;
  // Frame 2: IoU 90/110 >= 0.5 -> a match with a switch (7 -> 8): MOTA = 1 - 1/2.
  EXPECT_NE(r.out.find("\"mota\": 0.5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"idsw\": 1"), std::string::npos) << r.out;
  for (const char* k : {"\"motp\"", "\"fp\": 0", "\"fn\": 0", "\"num_objects\": 2", "\"recall\": 1", "\"precision\": 1"})
    EXPECT_NE(r.out.find(k), std::string::npos) << k << " in " << r.out;
  const auto table = run("--gt " + tmp("gt.txt") + " --pred " + tmp("pr.txt"));
  EXPECT_EQ(table.code, 0);
  EXPECT_NE(table.out.find("MOTA"), std::string::npos) << table.out;
  std::remove(tmp("gt.txt").c_str());
  std::remove(tmp("pr.txt").c_str());
}

TEST(MotCli, GivenBadInputThenTheExitIsNonZeroAndTheMessageSaysWhy) {
  std::ofstream(tmp("bad.txt")) << "1,1,zero,0,10,10\n";
  auto r = run("--gt " + tmp("bad.txt") + " --pred " + tmp("bad.txt"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find(":1:"), std::string::npos) << r.out;
  r = run("--log " + tmp("bad.txt"));
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("not an LCM log"), std::string::npos) << r.out;
  r = run("--log /nonexistent/run.lcm");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("cannot open"), std::string::npos) << r.out;
  r = run("");
  EXPECT_NE(r.code, 0);
  std::remove(tmp("bad.txt").c_str());
}
