#include "ucon/runtime/log_reader.hpp"

#include <cerrno>
#include <cstring>

namespace ucon {
namespace runtime {

namespace {
constexpr uint32_t kSync = 0xEDA1DA01u;
constexpr int64_t kMaxChannel = 256;             // LCM allows 63; be lenient
constexpr int64_t kMaxData = int64_t{1} << 30;   // 1 GiB: anything larger is corruption

uint64_t be(const uint8_t* p, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}
void putBe(uint8_t* p, uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) {
    p[i] = static_cast<uint8_t>(v & 0xFF);
    v >>= 8;
  }
}
}  // namespace

const char* toString(LogReadStatus s) {
  switch (s) {
    case LogReadStatus::kOk: return "ok";
    case LogReadStatus::kEnd: return "end of log";
    case LogReadStatus::kOpenFailed: return "cannot open";
    case LogReadStatus::kBadSync: return "not an LCM log event (bad sync word)";
    case LogReadStatus::kTruncated: return "truncated event";
    case LogReadStatus::kBadLength: return "impossible channel or data length";
  }
  return "?";
}

LogReader::~LogReader() {
  if (f_) std::fclose(f_);
}

bool LogReader::open(const std::string& path) {
  path_ = path;
  f_ = std::fopen(path.c_str(), "rb");
  if (!f_) {
    error_ = path + ": cannot open: " + std::strerror(errno);
    return false;
  }
  return true;
}

LogReadStatus LogReader::fail(LogReadStatus s, int64_t offset, const std::string& what) {
  error_ = path_ + ": " + toString(s) + (what.empty() ? "" : " (" + what + ")") +
           " at byte offset " + std::to_string(offset);
  return s;
}

LogReadStatus LogReader::next(LogEvent* ev) {
  if (!f_) return fail(LogReadStatus::kOpenFailed, 0, "not open");
  const int64_t start = offset_;
  uint8_t hdr[28];
  const std::size_t got = std::fread(hdr, 1, sizeof(hdr), f_);
  if (got == 0) return LogReadStatus::kEnd;
  if (got >= 4 && static_cast<uint32_t>(be(hdr, 4)) != kSync) {
    return fail(LogReadStatus::kBadSync, start, "");
  }
  if (got < sizeof(hdr)) {
    return fail(LogReadStatus::kTruncated, start,
                "header has " + std::to_string(got) + " of 28 bytes");
  }
  const int64_t channel_len = static_cast<int32_t>(be(hdr + 20, 4));
  const int64_t data_len = static_cast<int32_t>(be(hdr + 24, 4));
  if (channel_len <= 0 || channel_len > kMaxChannel || data_len < 0 || data_len > kMaxData) {
    return fail(LogReadStatus::kBadLength, start,
                "channel " + std::to_string(channel_len) + " B, data " + std::to_string(data_len) + " B");
  }
  ev->offset = start;
  ev->event_number = static_cast<int64_t>(be(hdr + 4, 8));
  ev->timestamp = static_cast<int64_t>(be(hdr + 12, 8));
  ev->channel.resize(static_cast<std::size_t>(channel_len));
  ev->data.resize(static_cast<std::size_t>(data_len));
  if (std::fread(&ev->channel[0], 1, ev->channel.size(), f_) != ev->channel.size() ||
      (data_len > 0 && std::fread(ev->data.data(), 1, ev->data.size(), f_) != ev->data.size())) {
    return fail(LogReadStatus::kTruncated, start,
                "event needs " + std::to_string(28 + channel_len + data_len) + " bytes");
  }
  offset_ = start + 28 + channel_len + data_len;
  return LogReadStatus::kOk;
}

LogWriterFile::~LogWriterFile() { close(); }

bool LogWriterFile::open(const std::string& path, std::string* error) {
  close();
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_ && error) *error = path + ": cannot create: " + std::strerror(errno);
  next_event_ = 0;
  return f_ != nullptr;
}

bool LogWriterFile::write(const std::string& channel, const void* data, std::size_t size,
                          int64_t timestamp) {
  if (!f_) return false;
  uint8_t hdr[28];
  putBe(hdr, kSync, 4);
  putBe(hdr + 4, static_cast<uint64_t>(next_event_++), 8);
  putBe(hdr + 12, static_cast<uint64_t>(timestamp), 8);
  putBe(hdr + 20, channel.size(), 4);
  putBe(hdr + 24, size, 4);
  return std::fwrite(hdr, 1, sizeof(hdr), f_) == sizeof(hdr) &&
         std::fwrite(channel.data(), 1, channel.size(), f_) == channel.size() &&
         (size == 0 || std::fwrite(data, 1, size, f_) == size);
}

void LogWriterFile::close() {
  if (f_) {
    std::fclose(f_);
    f_ = nullptr;
  }
}

}  // namespace runtime
}  // namespace ucon
