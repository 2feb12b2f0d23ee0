#include "ucon/livox/point_packet.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "le.hpp"
#include "ucon/livox/crc.hpp"

namespace ucon {
namespace livox {

bool isKnownDataType(uint8_t data_type) { return data_type <= 3; }

std::size_t recordSize(uint8_t data_type) {
  switch (data_type) {
    case 0: return 24;
    case 1: return 14;
    case 2: return 8;
    case 3: return 10;
    default: return 0;
  }
}

const char* toString(DataType type) {
  switch (type) {
    case DataType::kImu: return "imu";
    case DataType::kCartesianHigh: return "cartesian_high";
    case DataType::kCartesianLow: return "cartesian_low";
    case DataType::kSpherical: return "spherical";
  }
  return "unknown";
}

const char* toString(EncodeStatus status) {
  switch (status) {
    case EncodeStatus::kOk: return "ok";
    case EncodeStatus::kUnknownDataType: return "unknown_data_type";
    case EncodeStatus::kTooManyPoints: return "too_many_points";
    case EncodeStatus::kNonFinite: return "non_finite";
    case EncodeStatus::kOutOfRange: return "out_of_range";
  }
  return "unknown";
}

void writeHeader(const PacketHeader& h, uint8_t* out) {
  out[0] = h.version;
  le::store<uint16_t>(out + 1, h.length);
  le::store<uint16_t>(out + 3, h.time_interval);
  le::store<uint16_t>(out + 5, h.dot_num);
  le::store<uint16_t>(out + 7, h.udp_cnt);
  out[9] = h.frame_cnt;
  out[10] = h.data_type;
  out[11] = h.time_type;
  std::memcpy(out + 12, h.reserved.data(), h.reserved.size());
  le::store<uint32_t>(out + 24, h.crc32);
  le::store<uint64_t>(out + 28, h.timestamp_ns);
}

PacketHeader readHeader(const uint8_t* in) {
  PacketHeader h;
  h.version = in[0];
  h.length = le::load<uint16_t>(in + 1);
  h.time_interval = le::load<uint16_t>(in + 3);
  h.dot_num = le::load<uint16_t>(in + 5);
  h.udp_cnt = le::load<uint16_t>(in + 7);
  h.frame_cnt = in[9];
  h.data_type = in[10];
  h.time_type = in[11];
  std::memcpy(h.reserved.data(), in + 12, h.reserved.size());
  h.crc32 = le::load<uint32_t>(in + 24);
  h.timestamp_ns = le::load<uint64_t>(in + 28);
  return h;
}

namespace {

constexpr double kRadToDeg = 57.295779513082320876798;

// Rounds v * scale to an integer of type I; false if non-finite or out of I's range.
template <class I>
bool toFixed(float v, double scale, I& out) {
  const double s = std::round(static_cast<double>(v) * scale);
  if (!(s >= static_cast<double>(std::numeric_limits<I>::min()) &&
        s <= static_cast<double>(std::numeric_limits<I>::max()))) {
    return false;
  }
  out = static_cast<I>(s);
  return true;
}

void finishPacket(const PacketInfo& info, uint8_t data_type, uint16_t dot_num,
                  std::vector<uint8_t>& out) {
  PacketHeader h;
  h.version = info.version;
  h.length = static_cast<uint16_t>(out.size());
  h.time_interval = info.time_interval;
  h.dot_num = dot_num;
  h.udp_cnt = info.udp_cnt;
  h.frame_cnt = info.frame_cnt;
  h.data_type = data_type;
  h.time_type = static_cast<uint8_t>(info.time_type);
  h.timestamp_ns = info.timestamp_ns;
  writeHeader(h, out.data());
  const uint32_t c = crc32(out.data() + kCrcStart, out.size() - kCrcStart);
  le::store<uint32_t>(out.data() + kCrcOffset, c);
}

}  // namespace

EncodeStatus encodePointPacket(const PacketInfo& info, DataType type, const LidarPoint* points,
                               std::size_t n, std::vector<uint8_t>& out) {
  out.clear();
  const uint8_t dt = static_cast<uint8_t>(type);
  if (type == DataType::kImu || !isKnownDataType(dt)) return EncodeStatus::kUnknownDataType;
  const std::size_t rec = recordSize(dt);
  if (n > (kMaxPacketSize - kPointHeaderSize) / rec) return EncodeStatus::kTooManyPoints;
  out.resize(kPointHeaderSize + n * rec);
  uint8_t* p = out.data() + kPointHeaderSize;
  for (std::size_t i = 0; i < n; ++i, p += rec) {
    const LidarPoint& pt = points[i];
    if (!std::isfinite(pt.x) || !std::isfinite(pt.y) || !std::isfinite(pt.z)) {
      out.clear();
      return EncodeStatus::kNonFinite;
    }
    bool ok = true;
    if (type == DataType::kCartesianHigh) {
      int32_t x = 0, y = 0, z = 0;
      ok = toFixed(pt.x, 1000.0, x) && toFixed(pt.y, 1000.0, y) && toFixed(pt.z, 1000.0, z);
      le::store(p, x);
      le::store(p + 4, y);
      le::store(p + 8, z);
      p[12] = pt.reflectivity;
      p[13] = pt.tag;
    } else if (type == DataType::kCartesianLow) {
      int16_t x = 0, y = 0, z = 0;
      ok = toFixed(pt.x, 100.0, x) && toFixed(pt.y, 100.0, y) && toFixed(pt.z, 100.0, z);
      le::store(p, x);
      le::store(p + 2, y);
      le::store(p + 4, z);
      p[6] = pt.reflectivity;
      p[7] = pt.tag;
    } else {
      // Spherical: theta from +z, phi the azimuth from +x, both in 0.01 deg.
      const double x = pt.x, y = pt.y, z = pt.z;
      const double d = std::sqrt(x * x + y * y + z * z);
      uint32_t depth = 0;
      ok = toFixed(static_cast<float>(d), 1000.0, depth);
      uint16_t theta = 0, phi = 0;
      if (ok && d > 0) {
        const double th_deg = std::acos(std::max(-1.0, std::min(1.0, z / d))) * kRadToDeg;
        double ph_deg = std::atan2(y, x) * kRadToDeg;
        if (ph_deg < 0) ph_deg += 360.0;
        long th = std::lround(th_deg * 100.0);
        long ph = std::lround(ph_deg * 100.0);
        if (ph >= 36000) ph -= 36000;
        theta = static_cast<uint16_t>(std::min(th, 18000L));
        phi = static_cast<uint16_t>(ph);
      }
      le::store(p, depth);
      le::store(p + 4, theta);
      le::store(p + 6, phi);
      p[8] = pt.reflectivity;
      p[9] = pt.tag;
    }
    if (!ok) {
      out.clear();
      return EncodeStatus::kOutOfRange;
    }
  }
  finishPacket(info, dt, static_cast<uint16_t>(n), out);
  return EncodeStatus::kOk;
}

EncodeStatus encodeImuPacket(const PacketInfo& info, const ImuSample& s, std::vector<uint8_t>& out) {
  out.clear();
  const float v[6] = {s.gyro_x, s.gyro_y, s.gyro_z,
                      static_cast<float>(s.acc_x / kStandardGravity),
                      static_cast<float>(s.acc_y / kStandardGravity),
                      static_cast<float>(s.acc_z / kStandardGravity)};
  for (float f : v) {
    if (!std::isfinite(f)) return EncodeStatus::kNonFinite;
  }
  out.resize(kPointHeaderSize + 24);
  for (int i = 0; i < 6; ++i) le::store(out.data() + kPointHeaderSize + 4 * i, v[i]);
  finishPacket(info, static_cast<uint8_t>(DataType::kImu), 1, out);
  return EncodeStatus::kOk;
}

}  // namespace livox
}  // namespace ucon
