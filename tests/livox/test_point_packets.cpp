// Point and IMU packets: each data type parsed from hand-built bytes, encoder round trips,
// and a table of malformed packets each rejected with its own status.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>

#include "packet_bytes.hpp"
#include "ucon/livox/packet_parser.hpp"
#include "ucon/livox/point_packet.hpp"

using namespace ucon::livox;
using livox_test::Bytes;
using livox_test::finish;
using livox_test::fixCrc;

TEST(LivoxPointPacket, GivenACartesianHighPacketThenPointsAreInMetresWithPerPointTimes) {
  // 4 points, time_interval 400 (=40 us over 4 points: 10 us apart).
  Bytes p = livox_test::header(1, 4, 400, 7, 3, 1'000'000'000ull);
  const int32_t mm[4][3] = {{1000, -2000, 500}, {-1, 0, 1}, {40000, 1234, -567}, {0, 0, 0}};
  for (int i = 0; i < 4; ++i) {
    p.i32(mm[i][0]);
    p.i32(mm[i][1]);
    p.i32(mm[i][2]);
    p.u8(static_cast<uint8_t>(10 * i));  // reflectivity
    p.u8(static_cast<uint8_t>(i));       // tag
  }
  const auto bytes = finish(p);
  ASSERT_EQ(bytes.size(), 36u + 4 * 14);

  ParsedPacket out;
  ASSERT_EQ(parsePacket(bytes.data(), bytes.size(), out), ParseStatus::kOk);
  EXPECT_EQ(out.type, DataType::kCartesianHigh);
  EXPECT_EQ(out.header.udp_cnt, 7);
  EXPECT_EQ(out.header.frame_cnt, 3);
  EXPECT_EQ(out.header.time_type, 1);
  ASSERT_EQ(out.points.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(out.points[i].x, mm[i][0] * 1e-3, 1e-6);
    EXPECT_NEAR(out.points[i].y, mm[i][1] * 1e-3, 1e-6);
    EXPECT_NEAR(out.points[i].z, mm[i][2] * 1e-3, 1e-6);
    EXPECT_EQ(out.points[i].reflectivity, 10 * i);
    EXPECT_EQ(out.points[i].tag, i);
    EXPECT_EQ(out.points[i].time_ns, 1'000'000'000ull + 10'000ull * i);
  }
}

TEST(LivoxPointPacket, GivenACartesianLowPacketThenCentimetresBecomeMetres) {
  Bytes p = livox_test::header(2, 2, 20, 0, 0, 5000);
  p.i16(150); p.i16(-32768); p.i16(32767); p.u8(255); p.u8(0x10);
  p.i16(-1); p.i16(0); p.i16(1); p.u8(0); p.u8(0);
  const auto bytes = finish(p);
  ASSERT_EQ(bytes.size(), 36u + 2 * 8);
  ParsedPacket out;
  ASSERT_EQ(parsePacket(bytes.data(), bytes.size(), out), ParseStatus::kOk);
  ASSERT_EQ(out.points.size(), 2u);
  EXPECT_NEAR(out.points[0].x, 1.50, 1e-6);
  EXPECT_NEAR(out.points[0].y, -327.68, 1e-4);
  EXPECT_NEAR(out.points[0].z, 327.67, 1e-4);
  EXPECT_EQ(out.points[0].reflectivity, 255);
  EXPECT_EQ(out.points[0].tag, 0x10);
  EXPECT_NEAR(out.points[1].x, -0.01, 1e-7);
  EXPECT_EQ(out.points[0].time_ns, 5000u);
  EXPECT_EQ(out.points[1].time_ns, 5000u + 1000u);  // 20 * 100 ns / 2 points
}

TEST(LivoxPointPacket, GivenASphericalPacketThenThetaIsFromPlusZAndPhiFromPlusX) {
  Bytes p = livox_test::header(3, 4, 0, 0, 0, 42);
  // depth mm, theta, phi (0.01 deg)
  p.u32(2000); p.u16(9000); p.u16(0);     p.u8(1); p.u8(0);  // +x, 2 m
  p.u32(3000); p.u16(9000); p.u16(9000);  p.u8(2); p.u8(0);  // +y, 3 m
  p.u32(1500); p.u16(0);    p.u16(12345); p.u8(3); p.u8(0);  // +z, 1.5 m
  p.u32(1000); p.u16(4500); p.u16(22500); p.u8(4); p.u8(0);  // theta 45, phi 225
  const auto bytes = finish(p);
  ParsedPacket out;
  ASSERT_EQ(parsePacket(bytes.data(), bytes.size(), out), ParseStatus::kOk);
  ASSERT_EQ(out.points.size(), 4u);
  EXPECT_NEAR(out.points[0].x, 2.0, 1e-5);
  EXPECT_NEAR(out.points[0].y, 0.0, 1e-5);
  EXPECT_NEAR(out.points[0].z, 0.0, 1e-5);
  EXPECT_NEAR(out.points[1].x, 0.0, 1e-5);
  EXPECT_NEAR(out.points[1].y, 3.0, 1e-5);
  EXPECT_NEAR(out.points[2].z, 1.5, 1e-5);
  EXPECT_NEAR(out.points[2].x, 0.0, 1e-5);
  const double s = std::sin(M_PI / 4);
  EXPECT_NEAR(out.points[3].x, -s * s, 1e-5);
  EXPECT_NEAR(out.points[3].y, -s * s, 1e-5);
  EXPECT_NEAR(out.points[3].z, s, 1e-5);
  EXPECT_EQ(out.points[3].reflectivity, 4);
  for (const auto& q : out.points) EXPECT_EQ(q.time_ns, 42u);  // time_interval 0
}

TEST(LivoxPointPacket, GivenAnImuPacketThenAccelerationIsConvertedFromGToSi) {
  Bytes p = livox_test::header(0, 1, 0, 9, 0, 123456789);
  p.f32(0.1f); p.f32(-0.2f); p.f32(0.3f);
  p.f32(0.0f); p.f32(0.5f); p.f32(-1.0f);
  const auto bytes = finish(p);
  ASSERT_EQ(bytes.size(), 60u);
  ParsedPacket out;
  ASSERT_EQ(parsePacket(bytes.data(), bytes.size(), out), ParseStatus::kOk);
  EXPECT_EQ(out.type, DataType::kImu);
  EXPECT_TRUE(out.points.empty());
  EXPECT_FLOAT_EQ(out.imu.gyro_x, 0.1f);
  EXPECT_FLOAT_EQ(out.imu.gyro_y, -0.2f);
  EXPECT_FLOAT_EQ(out.imu.gyro_z, 0.3f);
  EXPECT_NEAR(out.imu.acc_x, 0.0, 1e-6);
  EXPECT_NEAR(out.imu.acc_y, 0.5 * 9.80665, 1e-5);
  EXPECT_NEAR(out.imu.acc_z, -9.80665, 1e-5);
  EXPECT_EQ(out.header.timestamp_ns, 123456789u);
  EXPECT_EQ(out.header.udp_cnt, 9);
}

TEST(LivoxPointPacket, GivenTheEncoderThenAFull96PointType1PacketIs1380BytesAndMatchesHandBuiltBytes) {
  std::vector<LidarPoint> pts(96);
  Bytes p = livox_test::header(1, 96, 4800, 12, 200, 987654321ull, 1);
  for (int i = 0; i < 96; ++i) {
    pts[i] = LidarPoint{0.001f * i, -0.5f, 2.25f + 0.01f * i, static_cast<uint8_t>(i),
                        static_cast<uint8_t>(i & 3)};
    p.i32(i);
    p.i32(-500);
    p.i32(2250 + 10 * i);
    p.u8(static_cast<uint8_t>(i));
    p.u8(static_cast<uint8_t>(i & 3));
  }
  PacketInfo info;
  info.timestamp_ns = 987654321ull;
  info.time_interval = 4800;
  info.udp_cnt = 12;
  info.frame_cnt = 200;
  info.time_type = TimeType::kPtp;
  std::vector<uint8_t> enc;
  ASSERT_EQ(encodePointPacket(info, DataType::kCartesianHigh, pts, enc), EncodeStatus::kOk);
  EXPECT_EQ(enc.size(), 1380u);
  EXPECT_EQ(enc, finish(p));
}

TEST(LivoxPointPacket, GivenEveryDataTypeWhenEncodedAndParsedThenPointsSurviveAtTheRecordResolution) {
  std::vector<LidarPoint> pts;
  for (int i = 0; i < 96; ++i) {
    const double a = 0.37 * i, e = -0.1 + 0.01 * i, r = 0.5 + 0.3 * i;
    pts.push_back(LidarPoint{static_cast<float>(r * std::cos(e) * std::cos(a)),
                             static_cast<float>(r * std::cos(e) * std::sin(a)),
                             static_cast<float>(r * std::sin(e)), static_cast<uint8_t>(i), 0});
  }
  const struct { DataType type; double tol; } cases[] = {
      {DataType::kCartesianHigh, 0.0006}, {DataType::kCartesianLow, 0.006},
      // 0.005 deg of angle at up to 29 m is 2.5 mm, plus 0.5 mm of depth
      {DataType::kSpherical, 0.004}};
  for (const auto& c : cases) {
    PacketInfo info;
    info.timestamp_ns = 1;
    std::vector<uint8_t> enc;
    ASSERT_EQ(encodePointPacket(info, c.type, pts, enc), EncodeStatus::kOk) << toString(c.type);
    ParsedPacket out;
    ASSERT_EQ(parsePacket(enc.data(), enc.size(), out), ParseStatus::kOk) << toString(c.type);
    ASSERT_EQ(out.points.size(), pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      EXPECT_NEAR(out.points[i].x, pts[i].x, c.tol) << toString(c.type) << " point " << i;
      EXPECT_NEAR(out.points[i].y, pts[i].y, c.tol) << toString(c.type) << " point " << i;
      EXPECT_NEAR(out.points[i].z, pts[i].z, c.tol) << toString(c.type) << " point " << i;
      EXPECT_EQ(out.points[i].reflectivity, pts[i].reflectivity);
    }
  }
}

TEST(LivoxPointPacket, GivenBadEncoderInputThenTheEncoderRefusesIt) {
  PacketInfo info;
  std::vector<uint8_t> enc;
  std::vector<LidarPoint> nan_pt{{std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 0}};
  EXPECT_EQ(encodePointPacket(info, DataType::kCartesianHigh, nan_pt, enc), EncodeStatus::kNonFinite);
  EXPECT_TRUE(enc.empty());
  std::vector<LidarPoint> far{{400.0f, 0, 0, 0, 0}};  // 40000 cm does not fit int16
  EXPECT_EQ(encodePointPacket(info, DataType::kCartesianLow, far, enc), EncodeStatus::kOutOfRange);
  EXPECT_EQ(encodePointPacket(info, DataType::kImu, far, enc), EncodeStatus::kUnknownDataType);
  std::vector<LidarPoint> many(5000);
  EXPECT_EQ(encodePointPacket(info, DataType::kCartesianHigh, many, enc), EncodeStatus::kTooManyPoints);
  ImuSample bad;
  bad.acc_z = std::numeric_limits<float>::infinity();
  EXPECT_EQ(encodeImuPacket(info, bad, enc), EncodeStatus::kNonFinite);
}

TEST(LivoxPointPacket, GivenAnImuSampleWhenEncodedAndParsedThenItRoundTripsInSiUnits) {
  PacketInfo info;
  info.timestamp_ns = 77;
  ImuSample s{0.01f, 0.02f, -0.03f, 0.1f, -0.2f, 9.81f};
  std::vector<uint8_t> enc;
  ASSERT_EQ(encodeImuPacket(info, s, enc), EncodeStatus::kOk);
  ParsedPacket out;
  ASSERT_EQ(parsePacket(enc.data(), enc.size(), out), ParseStatus::kOk);
  EXPECT_NEAR(out.imu.acc_z, 9.81, 1e-5);
  EXPECT_NEAR(out.imu.acc_y, -0.2, 1e-6);
  EXPECT_FLOAT_EQ(out.imu.gyro_z, -0.03f);
  // On the wire the value is in g.
  float wire_z;
  std::memcpy(&wire_z, enc.data() + 36 + 20, 4);
  EXPECT_NEAR(wire_z, 9.81 / 9.80665, 1e-6);
}

// ---- malformed packets ----

namespace {
std::vector<uint8_t> goodType1(int n = 3) {
  Bytes p = livox_test::header(1, static_cast<uint16_t>(n), 100, 0, 0, 1000);
  for (int i = 0; i < n; ++i) {
    p.i32(1000); p.i32(2000); p.i32(3000); p.u8(1); p.u8(0);
  }
  return finish(p);
}
std::vector<uint8_t> imuWith(float v) {
  Bytes p = livox_test::header(0, 1, 0, 0, 0, 1000);
  p.f32(0); p.f32(v); p.f32(0); p.f32(0); p.f32(0); p.f32(1);
  return finish(p);
}
void setU16(std::vector<uint8_t>& b, std::size_t at, uint16_t v) {
  b[at] = v & 0xFF;
  b[at + 1] = v >> 8;
}
}  // namespace

struct MalformedCase {
  std::string name;
  std::vector<uint8_t> bytes;
  ParseStatus expected;
};

TEST(LivoxPointPacket, GivenATableOfMalformedPacketsThenEachIsRejectedWithItsStatusAndNoPoints) {
  std::vector<MalformedCase> cases;
  cases.push_back({"empty", {}, ParseStatus::kTruncatedHeader});
  {
    auto b = goodType1();
    b.resize(35);
    cases.push_back({"35 bytes", b, ParseStatus::kTruncatedHeader});
  }
  {
    auto b = goodType1();
    b[0] = 1;
    cases.push_back({"version 1", b, ParseStatus::kBadVersion});
  }
  {
    auto b = goodType1();
    b.pop_back();
    cases.push_back({"datagram one byte short of length field", b, ParseStatus::kBadLength});
  }
  {
    auto b = goodType1();
    b.push_back(0);
    cases.push_back({"trailing byte", b, ParseStatus::kBadLength});
  }
  {
    auto b = goodType1(3);
    setU16(b, 5, 4);  // dot_num 4 but 3 records
    cases.push_back({"dot_num larger than records", b, ParseStatus::kBadLength});
  }
  {
    auto b = goodType1(3);
    setU16(b, 5, 0xFFFF);
    cases.push_back({"dot_num 65535", b, ParseStatus::kBadLength});
  }
  {
    auto b = goodType1(3);
    b[10] = 2;  // type 2 records are 8 B, not 14
    cases.push_back({"data type disagrees with record size", b, ParseStatus::kBadLength});
  }
  {
    auto b = goodType1(3);
    b[10] = 7;
    cases.push_back({"unknown data type 7", b, ParseStatus::kUnknownDataType});
  }
  {
    Bytes p = livox_test::header(0, 2, 0, 0, 0, 1);
    for (int i = 0; i < 12; ++i) p.f32(0);
    cases.push_back({"imu with dot_num 2", finish(p), ParseStatus::kBadLength});
  }
  cases.push_back({"imu NaN", imuWith(std::numeric_limits<float>::quiet_NaN()), ParseStatus::kNonFinite});
  cases.push_back({"imu +Inf", imuWith(std::numeric_limits<float>::infinity()), ParseStatus::kNonFinite});
  {
    Bytes p = livox_test::header(0, 1, 0, 0, 0, 1);
    p.f32(0); p.f32(0); p.f32(0); p.f32(0); p.f32(0); p.f32(3.0e38f);  // finite g, Inf in m/s^2
    cases.push_back({"imu acc overflows once scaled", finish(p), ParseStatus::kNonFinite});
  }

  {
    Bytes p = livox_test::header(1, 1, 100, 0, 0, 0xFFFFFFFFFFFFFF00ull);  // found by the fuzzer
    p.i32(1); p.i32(1); p.i32(1); p.u8(0); p.u8(0);
    cases.push_back({"timestamp near 2^64 (times would wrap)", finish(p), ParseStatus::kBadValue});
  }

  ParsedPacket out;
  for (const auto& c : cases) {
    out.points.assign(5, ParsedPoint{});  // stale content must not survive a failure
    const ParseStatus s = parsePacket(c.bytes.data(), c.bytes.size(), out);
    EXPECT_EQ(s, c.expected) << c.name << ": got " << toString(s);
    EXPECT_TRUE(out.points.empty()) << c.name;
  }
  // Null data never crashes.
  EXPECT_EQ(parsePacket(nullptr, 100, out), ParseStatus::kTruncatedHeader);
}

TEST(LivoxPointPacket, GivenTheCrc32FieldThenItIsReportedNotEnforced) {
  // Livox's own tools never check this field: a packet is kept whatever it says, and the
  // receiver learns whether it was absent (0), matching or not.
  ParsedPacket out;
  auto good = goodType1(3);
  ASSERT_EQ(parsePacket(good.data(), good.size(), out), ParseStatus::kOk);
  EXPECT_EQ(out.crc, CrcCheck::kMatch);
  auto zero = good;
  for (int i = 24; i < 28; ++i) zero[i] = 0;
  ASSERT_EQ(parsePacket(zero.data(), zero.size(), out), ParseStatus::kOk);
  EXPECT_EQ(out.crc, CrcCheck::kAbsent);
  EXPECT_EQ(out.points.size(), 3u);
  const std::pair<const char*, std::size_t> flips[] = {{"payload", 40}, {"timestamp", 28}, {"crc", 25}};
  for (const auto& [what, at] : flips) {
    auto b = good;
    b[at] ^= 0x80;
    ASSERT_EQ(parsePacket(b.data(), b.size(), out), ParseStatus::kOk) << what;
    EXPECT_EQ(out.crc, CrcCheck::kMismatch) << what;
  }
  EXPECT_STREQ(toString(CrcCheck::kMismatch), "mismatch");
}

TEST(LivoxPointPacket, GivenSphericalAngleExtremesThenAzimuth360IsValidAndABadRecordDropsOnlyItself) {
  // Records: phi = 36000 (360 deg, documented, same direction as 0), theta = 18001 (not a
  // direction), phi = 36001 (not a direction), and an ordinary one.
  Bytes p = livox_test::header(3, 4, 400, 0, 0, 1000);
  p.u32(2000); p.u16(9000); p.u16(36000); p.u8(7); p.u8(0);
  p.u32(2000); p.u16(18001); p.u16(0); p.u8(8); p.u8(0);
  p.u32(2000); p.u16(9000); p.u16(36001); p.u8(9); p.u8(0);
  p.u32(3000); p.u16(9000); p.u16(9000); p.u8(10); p.u8(0);
  const auto b = finish(p);
  ParsedPacket out;
  ASSERT_EQ(parsePacket(b.data(), b.size(), out), ParseStatus::kOk);
  ASSERT_EQ(out.points.size(), 2u);
  EXPECT_EQ(out.bad_points, 2u);
  EXPECT_NEAR(out.points[0].x, 2.0f, 1e-5f);  // along +x, like phi = 0
  EXPECT_NEAR(out.points[0].y, 0.0f, 1e-5f);
  EXPECT_NEAR(out.points[0].z, 0.0f, 1e-5f);
  EXPECT_EQ(out.points[0].reflectivity, 7);
  EXPECT_NEAR(out.points[1].y, 3.0f, 1e-5f);  // phi 90 deg
  EXPECT_EQ(out.points[1].reflectivity, 10);
  // Each kept point keeps its own time: record 3 of 4 at 3/4 of the 40 us interval.
  EXPECT_EQ(out.points[0].time_ns, 1000u);
  EXPECT_EQ(out.points[1].time_ns, 1000u + 30000u);
}

TEST(LivoxPointPacket, GivenTheMid360TagThenItsThreeConfidenceFieldsAreReadApart) {
  const uint8_t t = MidTag::make(1, 2, 3);
  EXPECT_EQ(t, 0x39);
  EXPECT_EQ(MidTag::sticking(t), 1);
  EXPECT_EQ(MidTag::rainFogDust(t), 2);
  EXPECT_EQ(MidTag::otherNoise(t), 3);
  EXPECT_EQ(MidTag::rainFogDust(0xC0), 0);  // reserved bits 6-7 belong to no field
}

TEST(LivoxPointPacket, GivenEveryStatusThenToStringNamesItDistinctly) {
  const ParseStatus all[] = {ParseStatus::kOk, ParseStatus::kTruncatedHeader, ParseStatus::kBadVersion,
                             ParseStatus::kBadLength, ParseStatus::kUnknownDataType, ParseStatus::kBadCrc,
                             ParseStatus::kNonFinite, ParseStatus::kBadValue};
  std::set<std::string> names;
  for (auto s : all) names.insert(toString(s));
  EXPECT_EQ(names.size(), 8u);
  EXPECT_EQ(std::string(toString(ParseStatus::kBadCrc)), "bad_crc");
}

TEST(LivoxPointPacket, GivenAHeaderWhenWrittenAndReadThenEveryFieldRoundTrips) {
  PacketHeader h;
  h.version = 0;
  h.length = 1380;
  h.time_interval = 4801;
  h.dot_num = 96;
  h.udp_cnt = 65535;
  h.frame_cnt = 255;
  h.data_type = 1;
  h.time_type = 2;
  for (int i = 0; i < 12; ++i) h.reserved[i] = static_cast<uint8_t>(i + 1);
  h.crc32 = 0xDEADBEEF;
  h.timestamp_ns = 0x0102030405060708ull;
  uint8_t buf[36];
  writeHeader(h, buf);
  EXPECT_EQ(buf[1], 1380 & 0xFF);
  EXPECT_EQ(buf[2], 1380 >> 8);
  EXPECT_EQ(buf[28], 0x08);  // little-endian timestamp
  EXPECT_EQ(buf[35], 0x01);
  const PacketHeader r = readHeader(buf);
  EXPECT_EQ(r.length, h.length);
  EXPECT_EQ(r.time_interval, h.time_interval);
  EXPECT_EQ(r.dot_num, h.dot_num);
  EXPECT_EQ(r.udp_cnt, h.udp_cnt);
  EXPECT_EQ(r.frame_cnt, h.frame_cnt);
  EXPECT_EQ(r.data_type, h.data_type);
  EXPECT_EQ(r.time_type, h.time_type);
  EXPECT_EQ(r.reserved, h.reserved);
  EXPECT_EQ(r.crc32, h.crc32);
  EXPECT_EQ(r.timestamp_ns, h.timestamp_ns);
}
