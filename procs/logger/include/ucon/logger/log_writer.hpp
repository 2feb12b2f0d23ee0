#pragma once
/// @file log_writer.hpp
/// Writes LCM events into standard LCM log files (readable by lcm-logplayer and
/// lcm-logplayer-gui) with rotation by size and by duration. Rotation happens only between
/// events, so an event is never split across files. Every file starts with a metadata event.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <regex>
#include <string>
#include <vector>

namespace lcm {
class LogFile;
}

namespace ucon {
namespace logger {

/// Which channels are recorded: matches `include` and does not match `exclude` (whole name).
class ChannelFilter {
 public:
  ChannelFilter(const std::string& include, const std::string& exclude);
  bool accepts(const std::string& channel);

 private:
  std::regex include_;
  std::regex exclude_;
  bool has_exclude_;
  std::map<std::string, bool> cache_;
};

/// Per-channel message and byte counts, and sequence gaps read from the `seq` field that every
/// top-level ucon message carries right after `utime` (bytes 16..23 of the encoding).
struct ChannelStats {
  int64_t messages = 0;
  int64_t bytes = 0;
  int64_t seq_gaps = 0;     ///< messages missing according to the seq field
  int64_t last_seq = -1;
};

/// Reads the big-endian int64 `seq` of a ucon message; false if the buffer is too short.
bool readSeqField(const uint8_t* data, std::size_t size, int64_t* seq);

/// Result of one write.
enum class WriteResult { kOk, kRotated, kDiskLow, kIoError };
const char* toString(WriteResult r);

struct LogWriterLimits {
  int64_t max_file_bytes = int64_t{1} << 30;
  int64_t max_file_us = 600 * 1000000LL;
  int64_t min_free_bytes = 512LL << 20;
};

class LogWriter {
 public:
  /// Metadata event written first in every file: (channel, encoded bytes) for file `index`.
  using MetadataFn = std::function<std::vector<uint8_t>(int index, int64_t wall_utime)>;
  /// Free bytes on the log folder's file system (injectable for tests).
  using FreeSpaceFn = std::function<int64_t()>;

  LogWriter(std::string dir, std::string run_name, LogWriterLimits limits, std::string metadata_channel,
            MetadataFn metadata, FreeSpaceFn free_space);
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  /// Writes one event with its receive time [us]; opens/rotates files as needed.
  WriteResult write(const std::string& channel, const uint8_t* data, std::size_t size,
                    int64_t recv_utime);
  void flush();
  /// Closes the current file (complete events only).
  void close();

  const std::vector<std::string>& files() const { return files_; }
  int64_t bytesInFile() const { return file_bytes_; }
  bool diskLow() const { return disk_low_; }
  std::string lastError() const { return last_error_; }

 private:
  bool openNext(int64_t utime);

  std::string dir_;
  std::string run_name_;
  LogWriterLimits limits_;
  std::string metadata_channel_;
  MetadataFn metadata_;
  FreeSpaceFn free_space_;
  std::unique_ptr<lcm::LogFile> file_;
  std::vector<std::string> files_;
  std::string stamp_;
  int64_t file_bytes_ = 0;
  int64_t file_start_us_ = 0;
  int64_t writes_since_space_check_ = 0;
  bool disk_low_ = false;
  std::string last_error_;
};

}  // namespace logger
}  // namespace ucon
