#pragma once
/// @file test_support.hpp
/// Helpers the tests share: start a built executable as a child process, write one message
/// into an LCM log file.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <fcntl.h>
#include <sys/types.h>
#include <unistd.h>

#include <cstdint>
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
