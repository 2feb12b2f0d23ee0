#include "ucon/logger/log_writer.hpp"

#include <lcm/lcm-cpp.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>

namespace ucon {
namespace logger {

namespace {
// Size of one event in the log format: sync (4), event number (8), timestamp (8), channel
// length (4), data length (4), channel, data.
int64_t eventBytes(std::size_t channel_len, std::size_t data_len) {
  return 28 + static_cast<int64_t>(channel_len) + static_cast<int64_t>(data_len);
}
}  // namespace

ChannelFilter::ChannelFilter(const std::string& include, const std::string& exclude)
    : include_(include), exclude_(exclude.empty() ? "$^" : exclude), has_exclude_(!exclude.empty()) {}

bool ChannelFilter::accepts(const std::string& channel) {
  auto it = cache_.find(channel);
  if (it != cache_.end()) return it->second;
  const bool ok = std::regex_match(channel, include_) &&
                  !(has_exclude_ && std::regex_match(channel, exclude_));
  cache_[channel] = ok;
  return ok;
}

bool readSeqField(const uint8_t* data, std::size_t size, int64_t* seq) {
  if (size < 24) return false;
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | data[16 + i];
  *seq = static_cast<int64_t>(v);
  return true;
}

const char* toString(WriteResult r) {
  switch (r) {
    case WriteResult::kOk: return "ok";
    case WriteResult::kRotated: return "rotated";
    case WriteResult::kDiskLow: return "disk space below the limit: not writing";
    case WriteResult::kIoError: return "I/O error";
  }
  return "?";
}

LogWriter::LogWriter(std::string dir, std::string run_name, LogWriterLimits limits,
                     std::string metadata_channel, MetadataFn metadata, FreeSpaceFn free_space)
    : dir_(std::move(dir)),
      run_name_(std::move(run_name)),
      limits_(limits),
      metadata_channel_(std::move(metadata_channel)),
      metadata_(std::move(metadata)),
      free_space_(std::move(free_space)) {}

LogWriter::~LogWriter() { close(); }

bool LogWriter::openNext(int64_t utime) {
  close();
  if (stamp_.empty()) {
    std::time_t secs = static_cast<std::time_t>(utime / 1000000);
    std::tm tm{};
    localtime_r(&secs, &tm);
    char buf[32];
    std::strftime(buf, sizeof(buf), "%Y%m%d_%H%M%S", &tm);
    stamp_ = buf;
  }
  const int index = static_cast<int>(files_.size());
  char name[64];
  std::snprintf(name, sizeof(name), "_%s_%03d.lcm", stamp_.c_str(), index);
  const std::string path = dir_ + "/" + run_name_ + name;
  file_ = std::make_unique<lcm::LogFile>(path, "w");
  if (!file_->good()) {
    last_error_ = "cannot create log file " + path + ": " + std::strerror(errno);
    file_.reset();
    return false;
  }
  files_.push_back(path);
  file_bytes_ = 0;
  file_start_us_ = utime;
  if (metadata_) {
    std::vector<uint8_t> meta = metadata_(index, utime);
    lcm::LogEvent ev{};
    ev.timestamp = utime;
    ev.channel = metadata_channel_;
    ev.datalen = static_cast<int32_t>(meta.size());
    ev.data = meta.data();
    if (file_->writeEvent(&ev) != 0) {
      last_error_ = "write failed on " + path + ": " + std::strerror(errno);
      return false;
    }
    file_bytes_ += eventBytes(metadata_channel_.size(), meta.size());
  }
  return true;
}

WriteResult LogWriter::write(const std::string& channel, const uint8_t* data, std::size_t size,
                             int64_t recv_utime) {
  // Check free space every 64 writes (statvfs is cheap, but not free at 250 msg/s).
  if (free_space_ && (writes_since_space_check_++ % 64 == 0 || disk_low_)) {
    disk_low_ = free_space_() < limits_.min_free_bytes + eventBytes(channel.size(), size);
  }
  if (disk_low_) return WriteResult::kDiskLow;

  WriteResult result = WriteResult::kOk;
  const int64_t need = eventBytes(channel.size(), size);
  if (!file_ || (file_bytes_ > 0 && file_bytes_ + need > limits_.max_file_bytes) ||
      recv_utime - file_start_us_ >= limits_.max_file_us) {
    const bool had = static_cast<bool>(file_);
    if (!openNext(recv_utime)) return WriteResult::kIoError;
    if (had) result = WriteResult::kRotated;
  }
  lcm::LogEvent ev{};
  ev.timestamp = recv_utime;
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(size);
  ev.data = const_cast<uint8_t*>(data);
  if (file_->writeEvent(&ev) != 0) {
    last_error_ = std::string("write failed: ") + std::strerror(errno);
    return WriteResult::kIoError;
  }
  file_bytes_ += need;
  return result;
}

void LogWriter::flush() {
  if (file_) std::fflush(file_->getFilePtr());
}

void LogWriter::close() {
  if (file_) {
    std::fflush(file_->getFilePtr());
    file_.reset();  // closes the FILE*
  }
}

}  // namespace logger
}  // namespace ucon
