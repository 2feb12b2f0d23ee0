#include "ucon/base_controller/serial_frame.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace base_controller {

uint16_t crc16CcittFalse(const uint8_t* data, std::size_t n) {
  uint16_t crc = 0xFFFF;
  for (std::size_t i = 0; i < n; ++i) {
    crc = static_cast<uint16_t>(crc ^ (static_cast<uint16_t>(data[i]) << 8));
    for (int b = 0; b < 8; ++b) {
      crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021) : static_cast<uint16_t>(crc << 1);
    }
  }
  return crc;
}

std::array<double, 4> WheelFrame::speeds() const {
  return {raw[0] * kWheelSpeedLsb, raw[1] * kWheelSpeedLsb, raw[2] * kWheelSpeedLsb,
          raw[3] * kWheelSpeedLsb};
}

std::array<uint8_t, kWheelFrameSize> encodeWheelFrame(uint16_t seq, bool enable,
                                                      const std::array<double, 4>& speeds,
                                                      int* clamped) {
  std::array<int16_t, 4> raw{};
  int n_clamped = 0;
  const bool finite = std::all_of(speeds.begin(), speeds.end(), [](double v) { return std::isfinite(v); });
  if (!finite) enable = false;
  for (std::size_t i = 0; i < 4 && finite; ++i) {
    const double counts = std::round(speeds[i] / kWheelSpeedLsb);
    const double c = std::clamp(counts, -32767.0, 32767.0);
    if (c != counts) ++n_clamped;
    raw[i] = static_cast<int16_t>(c);
  }
  if (clamped) *clamped = n_clamped;
  std::array<uint8_t, kWheelFrameSize> f{};
  f[0] = kWheelFrameSync0;
  f[1] = kWheelFrameSync1;
  f[2] = kWheelFrameVersion;
  f[3] = enable ? 1 : 0;
  f[4] = static_cast<uint8_t>(seq & 0xFF);
  f[5] = static_cast<uint8_t>(seq >> 8);
  for (std::size_t i = 0; i < 4; ++i) {
    const uint16_t u = static_cast<uint16_t>(raw[i]);
    f[6 + 2 * i] = static_cast<uint8_t>(u & 0xFF);
    f[7 + 2 * i] = static_cast<uint8_t>(u >> 8);
  }
  const uint16_t crc = crc16CcittFalse(f.data(), 14);
  f[14] = static_cast<uint8_t>(crc & 0xFF);
  f[15] = static_cast<uint8_t>(crc >> 8);
  return f;
}

const char* toString(FrameStatus s) {
  switch (s) {
    case FrameStatus::kOk: return "ok";
    case FrameStatus::kTooShort: return "too short";
    case FrameStatus::kBadSync: return "bad sync";
    case FrameStatus::kBadVersion: return "bad version";
    case FrameStatus::kBadCrc: return "bad crc";
  }
  return "unknown";
}

FrameStatus decodeWheelFrame(const uint8_t* d, std::size_t n, WheelFrame* out) {
  if (d == nullptr || n < kWheelFrameSize) return FrameStatus::kTooShort;
  if (d[0] != kWheelFrameSync0 || d[1] != kWheelFrameSync1) return FrameStatus::kBadSync;
  const uint16_t crc = static_cast<uint16_t>(d[14] | (d[15] << 8));
  if (crc != crc16CcittFalse(d, 14)) return FrameStatus::kBadCrc;
  if (d[2] != kWheelFrameVersion) return FrameStatus::kBadVersion;
  if (out) {
    out->enable = (d[3] & 1) != 0;
    out->seq = static_cast<uint16_t>(d[4] | (d[5] << 8));
    for (std::size_t i = 0; i < 4; ++i) {
      out->raw[i] = static_cast<int16_t>(static_cast<uint16_t>(d[6 + 2 * i] | (d[7 + 2 * i] << 8)));
    }
  }
  return FrameStatus::kOk;
}

std::vector<WheelFrame> WheelFrameParser::feed(const uint8_t* data, std::size_t n) {
  std::vector<WheelFrame> frames;
  for (std::size_t i = 0; i < n; ++i) {
    buf_.push_back(data[i]);
    // Keep the buffer starting at a (possible) sync word.
    while (!buf_.empty()) {
      if (buf_[0] != kWheelFrameSync0 || (buf_.size() >= 2 && buf_[1] != kWheelFrameSync1)) {
        buf_.erase(buf_.begin());
        ++skipped_;
        continue;
      }
      break;
    }
    if (buf_.size() < kWheelFrameSize) continue;
    WheelFrame f;
    const FrameStatus st = decodeWheelFrame(buf_.data(), buf_.size(), &f);
    if (st == FrameStatus::kOk) {
      frames.push_back(f);
      buf_.clear();
    } else {
      // Drop the false sync byte and rescan what was buffered behind it.
      if (st == FrameStatus::kBadCrc) ++crc_errors_;
      std::vector<uint8_t> rest(buf_.begin() + 1, buf_.end());
      buf_.clear();
      ++skipped_;
      const std::vector<WheelFrame> more = feed(rest.data(), rest.size());
      frames.insert(frames.end(), more.begin(), more.end());
    }
  }
  return frames;
}

}  // namespace base_controller
}  // namespace ucon
