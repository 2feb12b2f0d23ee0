#include "ucon/livox/packet_parser.hpp"

#include <cmath>

#include "le.hpp"
#include "ucon/livox/crc.hpp"

namespace ucon {
namespace livox {

const char* toString(ParseStatus status) {
  switch (status) {
    case ParseStatus::kOk: return "ok";
    case ParseStatus::kTruncatedHeader: return "truncated_header";
    case ParseStatus::kBadVersion: return "bad_version";
    case ParseStatus::kBadLength: return "bad_length";
    case ParseStatus::kUnknownDataType: return "unknown_data_type";
    case ParseStatus::kBadCrc: return "bad_crc";
    case ParseStatus::kNonFinite: return "non_finite";
    case ParseStatus::kBadValue: return "bad_value";
  }
  return "unknown";
}

const char* toString(CrcCheck c) {
  switch (c) {
    case CrcCheck::kAbsent: return "absent";
    case CrcCheck::kMatch: return "match";
    case CrcCheck::kMismatch: return "mismatch";
  }
  return "unknown";
}

namespace {

constexpr uint64_t kMaxTimestampNs = (uint64_t{1} << 62);  // ~146 years

// Sin/cos tables over 0.01-degree steps: spherical records are exact multiples, so a table
// lookup replaces four libm calls per point (set up once, compute often).
struct TrigTable {
  std::vector<float> sin_v, cos_v;
  TrigTable() : sin_v(36001), cos_v(36001) {
    for (int i = 0; i <= 36000; ++i) {
      const double a = static_cast<double>(i) * (3.14159265358979323846 / 18000.0);
      sin_v[i] = static_cast<float>(std::sin(a));
      cos_v[i] = static_cast<float>(std::cos(a));
    }
  }
};
const TrigTable& trig() {
  static const TrigTable t;
  return t;
}

}  // namespace

ParseStatus parsePacket(const uint8_t* data, std::size_t size, ParsedPacket& out) {
  out.points.clear();
  out.bad_points = 0;
  if (data == nullptr || size < kPointHeaderSize) return ParseStatus::kTruncatedHeader;
  out.header = readHeader(data);
  const PacketHeader& h = out.header;
  if (h.version != 0) return ParseStatus::kBadVersion;
  if (h.length != size) return ParseStatus::kBadLength;
  if (!isKnownDataType(h.data_type)) return ParseStatus::kUnknownDataType;
  const std::size_t rec = recordSize(h.data_type);
  const bool imu = h.data_type == static_cast<uint8_t>(DataType::kImu);
  if (imu && h.dot_num != 1) return ParseStatus::kBadLength;
  if (kPointHeaderSize + static_cast<std::size_t>(h.dot_num) * rec != size) {
    return ParseStatus::kBadLength;
  }
  if (h.crc32 == 0) {
    out.crc = CrcCheck::kAbsent;
  } else {
    out.crc = crc32(data + kCrcStart, size - kCrcStart) == h.crc32 ? CrcCheck::kMatch
                                                                   : CrcCheck::kMismatch;
  }
  // Later stages keep times as int64 ns and add per-point offsets (< 2^23 ns): a timestamp
  // that would overflow is not a sensor time.
  if (h.timestamp_ns > kMaxTimestampNs) return ParseStatus::kBadValue;
  out.type = static_cast<DataType>(h.data_type);
  const uint8_t* p = data + kPointHeaderSize;

  if (imu) {
    float v[6];
    for (int i = 0; i < 6; ++i) {
      v[i] = le::load<float>(p + 4 * i);
      if (!std::isfinite(v[i])) return ParseStatus::kNonFinite;
    }
    const float g = static_cast<float>(kStandardGravity);
    out.imu = ImuSample{v[0], v[1], v[2], v[3] * g, v[4] * g, v[5] * g};
    // A finite value in g can still overflow float once scaled.
    if (!std::isfinite(out.imu.acc_x) || !std::isfinite(out.imu.acc_y) ||
        !std::isfinite(out.imu.acc_z)) {
      return ParseStatus::kNonFinite;
    }
    return ParseStatus::kOk;
  }

  const std::size_t n = h.dot_num;
  out.points.resize(n);
  ParsedPoint* q = out.points.data();
  // Point i is at timestamp + i * time_interval / dot_num (time_interval in 0.1 us).
  const uint64_t span_ns = static_cast<uint64_t>(h.time_interval) * 100u;
  const uint64_t t0 = h.timestamp_ns;
  switch (out.type) {
    case DataType::kCartesianHigh:
      for (std::size_t i = 0; i < n; ++i, p += 14) {
        q[i].x = static_cast<float>(le::load<int32_t>(p)) * 1e-3f;
        q[i].y = static_cast<float>(le::load<int32_t>(p + 4)) * 1e-3f;
        q[i].z = static_cast<float>(le::load<int32_t>(p + 8)) * 1e-3f;
        q[i].reflectivity = p[12];
        q[i].tag = p[13];
        q[i].time_ns = t0 + span_ns * i / n;
      }
      break;
    case DataType::kCartesianLow:
      for (std::size_t i = 0; i < n; ++i, p += 8) {
        q[i].x = static_cast<float>(le::load<int16_t>(p)) * 1e-2f;
        q[i].y = static_cast<float>(le::load<int16_t>(p + 2)) * 1e-2f;
        q[i].z = static_cast<float>(le::load<int16_t>(p + 4)) * 1e-2f;
        q[i].reflectivity = p[6];
        q[i].tag = p[7];
        q[i].time_ns = t0 + span_ns * i / n;
      }
      break;
    case DataType::kSpherical: {
      // theta in [0, 180] deg from +z, phi in [0, 360] deg (360 is a documented value, the
      // same direction as 0). A record outside these is not a measurement: it alone is left
      // out, counted in bad_points.
      const TrigTable& t = trig();
      std::size_t kept = 0;
      for (std::size_t i = 0; i < n; ++i, p += 10) {
        const uint16_t theta = le::load<uint16_t>(p + 4);
        const uint16_t phi = le::load<uint16_t>(p + 6);
        if (theta > 18000 || phi > 36000) {
          ++out.bad_points;
          continue;
        }
        const float d = static_cast<float>(le::load<uint32_t>(p)) * 1e-3f;
        const float st = t.sin_v[theta], ct = t.cos_v[theta];
        ParsedPoint& o = q[kept++];
        o.x = d * st * t.cos_v[phi];
        o.y = d * st * t.sin_v[phi];
        o.z = d * ct;
        o.reflectivity = p[8];
        o.tag = p[9];
        o.time_ns = t0 + span_ns * i / n;
      }
      out.points.resize(kept);
      break;
    }
    case DataType::kImu:
      break;
  }
  return ParseStatus::kOk;
}

}  // namespace livox
}  // namespace ucon
