#pragma once
/// @file test_support.hpp
/// Helpers the tests share: start a built executable as a child process and wait for it, write
/// one message into an LCM log file.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <thread>
#include <string>
#include <vector>

namespace ucon {
namespace test {

/// Forks and execs args[0] with args; with a non-empty `log`, its stdout and stderr go to that
/// file (created or truncated). Returns the child's pid (exit 127 if the exec failed).
inline pid_t spawn(const std::vector<std::string>& args, const std::string& log = "") {
  const pid_t pid = fork();
  if (pid == 0) {
    if (!log.empty()) {
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
      }
    }
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

/// Waits up to `limit_s` for child `pid` to exit; returns its exit code (128 + signal if a
/// signal ended it), or -1 after killing it when it did not exit in time.
inline int waitExit(pid_t pid, double limit_s) {
  const auto t0 = std::chrono::steady_clock::now();
  int st = 0;
  while (waitpid(pid, &st, WNOHANG) != pid) {
    if (std::chrono::steady_clock::now() - t0 > std::chrono::duration<double>(limit_s)) {
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

/// Appends one encoded message as an event of `channel` at `utime` [us] to an open log.
template <class Msg>
void writeLogEvent(lcm::LogFile& log, const std::string& channel, const Msg& m, int64_t utime) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  lcm::LogEvent ev;
  ev.eventnum = 0;
  ev.timestamp = utime;
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(buf.size());
  ev.data = buf.data();
  ASSERT_EQ(log.writeEvent(&ev), 0);
}

}  // namespace test
}  // namespace ucon
