// The logger as a process: records what is published, metadata first, closes cleanly on
// SIGINT (the file ends on an event boundary), and rejects a bad config naming the key.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "ucon/log_metadata_t.hpp"
#include "ucon/nav_goal_t.hpp"

extern char** environ;
namespace fs = std::filesystem;

namespace {

pid_t spawn(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  EXPECT_EQ(posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ), 0);
  return pid;
}

int waitExit(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

}  // namespace

TEST(LoggerProcess, GivenPublishedMessagesWhenStoppedWithSigintThenTheLogHoldsAllOfThemAfterMetadata) {
  const fs::path dir = fs::temp_directory_path() / ("ucon_logger_proc_" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string url = "udpm://239.255.76.67:7801?ttl=0";
  const pid_t pid = spawn({std::string(UCON_BIN_DIR) + "/ucon-logger", "--config",
                           std::string(UCON_SOURCE_DIR) + "/deploy/config/logger.yaml", "--log-dir",
                           dir.string(), "--run-name", "proc", "--lcm-url", url});
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let it subscribe
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    ucon::nav_goal_t g{};
    g.utime = 1000 + i;
    g.seq = i;
    g.goal_id = i + 1;
    lcm.publish(i % 2 ? "NAV_GOAL" : "OTHER_GOAL", &g);
    if (i % 50 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGINT);
  EXPECT_EQ(waitExit(pid), 0);

  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path());
  ASSERT_EQ(files.size(), 1u);
  lcm::LogFile log(files[0].string(), "r");
  ASSERT_TRUE(log.good());
  const lcm::LogEvent* first = log.readNextEvent();
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->channel, "LOG_METADATA");
  ucon::log_metadata_t meta;
  ASSERT_GT(meta.decode(first->data, 0, first->datalen), 0);
  EXPECT_EQ(meta.run_name, "proc");
  bool has_config = false;
  for (const auto& k : meta.keys) has_config = has_config || k == "config/logger.yaml";
  EXPECT_TRUE(has_config);

  int count = 0;
  int64_t expect = 0;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel == "LOGGER_STATUS") continue;
    ucon::nav_goal_t g;
    ASSERT_EQ(g.decode(e->data, 0, e->datalen), e->datalen);
    EXPECT_EQ(g.seq, expect++) << "messages out of order or lost";
    ++count;
  }
  EXPECT_EQ(count, n);
  fs::remove_all(dir);
}

TEST(LoggerProcess, GivenABadConfigThenItExitsNonZeroNamingTheKey) {
  const fs::path cfg = fs::temp_directory_path() / ("ucon_logger_bad_" + std::to_string(getpid()) + ".yaml");
  std::ifstream in(std::string(UCON_SOURCE_DIR) + "/deploy/config/logger.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("max_file_mb: 1024"), 17, "max_file_mb: -5");
  std::ofstream(cfg) << text;
  const std::string cmd = std::string(UCON_BIN_DIR) + "/ucon-logger --config " + cfg.string() +
                          " --lcm-url memq:// 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[256];
  while (fgets(buf, sizeof(buf), p)) out += buf;
  EXPECT_NE(pclose(p), 0);
  EXPECT_NE(out.find("max_file_mb"), std::string::npos) << out;
  fs::remove(cfg);
}
