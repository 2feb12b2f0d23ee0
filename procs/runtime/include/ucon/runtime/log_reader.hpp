#pragma once
/// @file log_reader.hpp
/// Strict reader of LCM log files. Unlike lcm::LogFile, which silently skips to the next sync
/// word, it stops at the first damaged event and says what is wrong and at which byte offset,
/// so a truncated or corrupt log is reported, never half-read.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace ucon {
namespace runtime {

/// One event of a log.
struct LogEvent {
  int64_t event_number = 0;
  int64_t timestamp = 0;  ///< receive time recorded by the logger [us]
  std::string channel;
  std::vector<uint8_t> data;
  int64_t offset = 0;     ///< byte offset of the event in the file
};

enum class LogReadStatus { kOk, kEnd, kOpenFailed, kBadSync, kTruncated, kBadLength };
const char* toString(LogReadStatus s);

class LogReader {
 public:
  LogReader() = default;
  ~LogReader();
  LogReader(const LogReader&) = delete;
  LogReader& operator=(const LogReader&) = delete;

  /// Opens `path`; false (and error()) if it cannot be read.
  bool open(const std::string& path);
  /// Reads the next event. kEnd at a clean end of file; any other non-kOk status is an error
  /// described by error(), with the byte offset.
  LogReadStatus next(LogEvent* event);
  /// "path: <what> at byte offset N" for the last failure.
  const std::string& error() const { return error_; }

 private:
  LogReadStatus fail(LogReadStatus s, int64_t offset, const std::string& what);
  std::FILE* f_ = nullptr;
  std::string path_;
  std::string error_;
  int64_t offset_ = 0;
};

/// Writes events in the LCM log format (what lcm-logplayer reads).
class LogWriterFile {
 public:
  LogWriterFile() = default;
  ~LogWriterFile();
  LogWriterFile(const LogWriterFile&) = delete;
  LogWriterFile& operator=(const LogWriterFile&) = delete;
  bool open(const std::string& path, std::string* error);
  /// Appends one event; event numbers count from 0.
  bool write(const std::string& channel, const void* data, std::size_t size, int64_t timestamp);
  void close();

 private:
  std::FILE* f_ = nullptr;
  int64_t next_event_ = 0;
};

}  // namespace runtime
}  // namespace ucon
