// The driver node: frames cut on sensor-time boundaries, udp_cnt gaps, malformed packets
// counted and dropped, extrinsic and filters, IMU in SI units.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "stream_helpers.hpp"
#include "ucon/lidar_driver/lidar_driver_node.hpp"

using namespace ucon::lidar_driver;
using driver_test::makeStream;
using driver_test::plainParams;
namespace livox = ucon::livox;

namespace {
// Feeds all packets; returns every published cloud (and the flushed last one if `flush`).
std::vector<ucon::point_cloud_t> feed(LidarDriverNode& node, const std::vector<std::vector<uint8_t>>& pkts,
                                      bool flush = false) {
  std::vector<ucon::point_cloud_t> clouds;
  DriverOutputs out;
  for (const auto& p : pkts) {
    node.onDatagram(p.data(), p.size(), out);
    for (auto& c : out.clouds) clouds.push_back(std::move(c));
  }
  if (flush) {
    if (auto c = node.flush()) clouds.push_back(std::move(*c));
  }
  return clouds;
}
}  // namespace

TEST(LidarDriverNode, GivenA50HzStreamThenFramesAreCutOnSensorTimeBoundaries) {
  // 200 000 points/s = 5 us apart; 96-point packets span 480 us; start at t = 10 s + 1 ms.
  const uint64_t t0 = 10'001'000'000ull;
  const auto pkts = makeStream(300, t0, 5000);  // 28 800 points = 144 ms
  LidarDriverNode node(plainParams());
  const auto clouds = feed(node, pkts, /*flush=*/true);
  // Boundaries every 20 ms: [10.000,10.020) holds 19 ms of points, then full frames, then the rest.
  ASSERT_EQ(clouds.size(), 8u);
  int64_t total = 0;
  for (std::size_t i = 0; i < clouds.size(); ++i) {
    const auto& c = clouds[i];
    EXPECT_EQ(c.seq, static_cast<int64_t>(i));
    EXPECT_EQ(c.frame_id, "lidar");
    EXPECT_EQ(c.time_sync, ucon::point_cloud_t::TIME_PTP);
    EXPECT_EQ(c.num_points, static_cast<int32_t>(c.x.size()));
    EXPECT_EQ(c.t_offset_ns.size(), c.x.size());
    EXPECT_EQ(c.lost_packets, 0);
    total += c.num_points;
    // Every point lies inside this frame's 20 ms window.
    const int64_t k = c.utime * 1000 / 20'000'000;
    for (std::size_t j = 0; j < c.x.size(); ++j) {
      const int64_t t_ns = c.utime * 1000 + c.t_offset_ns[j];
      EXPECT_EQ(t_ns / 20'000'000, k) << "frame " << i << " point " << j;
    }
  }
  EXPECT_EQ(total, 300 * 96);
  EXPECT_EQ(clouds[0].utime, 10'001'000);            // first point
  EXPECT_EQ(clouds[0].num_points, 19'000 / 5);       // 19 ms of points at 5 us
  for (int i = 1; i <= 6; ++i) {
    EXPECT_EQ(clouds[i].num_points, 4000) << i;      // full 20 ms frames
    EXPECT_EQ(clouds[i].utime, 10'000'000 + 20'000 * i) << i;
    EXPECT_EQ(clouds[i].duration_us, 19'995 / 1) << i;  // last point 19.995 ms after the first
  }
  EXPECT_EQ(node.counters().frames, 8);
  EXPECT_EQ(node.counters().points, 300 * 96);
  EXPECT_EQ(node.counters().points_published, 300 * 96);
  EXPECT_EQ(node.counters().lost_packets, 0);
}

TEST(LidarDriverNode, GivenPointsThenCoordinatesReflectivityAndTimesAreCarriedIntoTheCloud) {
  const auto pkts = makeStream(2, 1'000'000'000ull, 5000);
  LidarDriverNode node(plainParams());
  const auto clouds = feed(node, pkts, true);
  ASSERT_EQ(clouds.size(), 1u);
  const auto& c = clouds[0];
  ASSERT_EQ(c.num_points, 192);
  for (int j = 0; j < 192; ++j) {
    EXPECT_NEAR(c.x[j], 1.0 + (j % 10), 1e-6);
    EXPECT_NEAR(c.y[j], 0.5, 1e-6);
    EXPECT_NEAR(c.z[j], -0.25, 1e-6);
    EXPECT_EQ(static_cast<uint8_t>(c.reflectivity[j]), j % 256);
    EXPECT_EQ(c.t_offset_ns[j], 5000 * j);
  }
  EXPECT_EQ(c.utime, 1'000'000);
}

TEST(LidarDriverNode, GivenDroppedPacketsThenUdpCntGapsAreCountedOnTheFrameAndTheStatus) {
  auto pkts = makeStream(100, 2'000'000'000ull, 5000);  // frames of 20 ms = 41.67 packets
  // Drop packets 10, 11 (frame 0) and 60 (frame 1).
  std::vector<std::vector<uint8_t>> sent;
  for (int k = 0; k < 100; ++k) {
    if (k == 10 || k == 11 || k == 60) continue;
    sent.push_back(pkts[static_cast<std::size_t>(k)]);
  }
  LidarDriverNode node(plainParams());
  const auto clouds = feed(node, sent, true);
  ASSERT_EQ(clouds.size(), 3u);
  EXPECT_EQ(clouds[0].lost_packets, 2);
  EXPECT_EQ(clouds[1].lost_packets, 1);
  EXPECT_EQ(clouds[2].lost_packets, 0);
  EXPECT_EQ(node.counters().lost_packets, 3);
  EXPECT_EQ(node.counters().point_packets, 97);
  EXPECT_EQ(clouds[0].num_points + clouds[1].num_points + clouds[2].num_points, 97 * 96);
}

TEST(LidarDriverNode, GivenAGapAtASensorFrameChangeThenLostPacketsAreCountedFromTheRestartedUdpCnt) {
  // Sensor frames of 10 packets; the first 3 packets of sensor frame 1 are lost.
  auto pkts = makeStream(20, 3'000'000'000ull, 5000, 96, 10);
  pkts.erase(pkts.begin() + 10, pkts.begin() + 13);
  LidarDriverNode node(plainParams());
  feed(node, pkts, true);
  EXPECT_EQ(node.counters().lost_packets, 3);
  EXPECT_EQ(node.counters().out_of_order_packets, 0);
}

TEST(LidarDriverNode, GivenADuplicatedPacketThenItIsCountedOutOfOrderAndItsPointsAreNotRepeated) {
  auto pkts = makeStream(6, 4'000'000'000ull, 5000);
  pkts.insert(pkts.begin() + 4, pkts[2]);  // replay of packet 2 after packet 3
  LidarDriverNode node(plainParams());
  const auto clouds = feed(node, pkts, true);
  EXPECT_EQ(node.counters().out_of_order_packets, 1);
  EXPECT_EQ(node.counters().lost_packets, 0);
  ASSERT_EQ(clouds.size(), 1u);
  EXPECT_EQ(clouds[0].num_points, 6 * 96);  // the replayed packet is dropped
  EXPECT_EQ(node.counters().points_late, 96);
}

TEST(LidarDriverNode, GivenMalformedPacketsThenEachIsCountedAndDroppedAndTheStreamContinues) {
  // Nine good packets first: the sensor's crc32 is then known to be filled in (kCrcTrustAfter),
  // so a packet whose crc32 no longer matches is corrupt and dropped.
  auto pkts = makeStream(12, 5'000'000'000ull, 5000);
  std::vector<std::vector<uint8_t>> bad;
  bad.push_back({});                                   // empty
  bad.push_back(std::vector<uint8_t>(20, 0xAB));       // truncated header
  auto b = pkts[1]; b[0] = 3; bad.push_back(b);        // version
  b = pkts[1]; b.pop_back(); bad.push_back(b);         // length
  b = pkts[1]; b[10] = 9; bad.push_back(b);            // data type
  b = pkts[9]; b[100] ^= 0x20; bad.push_back(b);       // crc
  std::vector<std::vector<uint8_t>> stream(pkts.begin(), pkts.begin() + 9);
  for (auto& x : bad) stream.push_back(x);
  stream.push_back(pkts[9]);
  stream.push_back(pkts[10]);
  stream.push_back(pkts[11]);
  LidarDriverNode node(plainParams());
  DriverOutputs out;
  int non_ok = 0;
  for (const auto& p : stream) {
    if (node.onDatagram(p.data(), p.size(), out) != livox::ParseStatus::kOk) {
      ++non_ok;
      EXPECT_TRUE(out.clouds.empty());
      EXPECT_FALSE(out.imu.has_value());
    }
  }
  node.onOversizeDatagram();
  EXPECT_EQ(non_ok, 6);
  const auto& c = node.counters();
  EXPECT_EQ(c.crc_errors, 1);
  EXPECT_EQ(c.malformed, 6);  // 5 above + the oversize datagram
  EXPECT_EQ(c.datagrams, 19);
  EXPECT_EQ(c.by_status[static_cast<int>(livox::ParseStatus::kTruncatedHeader)], 2);
  EXPECT_EQ(c.by_status[static_cast<int>(livox::ParseStatus::kBadLength)], 2);
  EXPECT_EQ(c.by_status[static_cast<int>(livox::ParseStatus::kBadVersion)], 1);
  EXPECT_EQ(c.by_status[static_cast<int>(livox::ParseStatus::kUnknownDataType)], 1);
  EXPECT_EQ(c.point_packets, 12);
  auto last = node.flush();
  ASSERT_TRUE(last);
  EXPECT_EQ(last->num_points, 12 * 96);
  EXPECT_EQ(c.lost_packets, 0);
  // The status carries the counters under their documented names.
  ucon::StatusReport rep("lidar_driver");
  node.report(rep);
  EXPECT_EQ(rep.counter("crc_errors"), 1);
  EXPECT_EQ(rep.counter("malformed"), 6);
  EXPECT_EQ(rep.counter("packets"), 12);
  EXPECT_EQ(rep.counter("invalid_bad_version"), 1);
}

TEST(LidarDriverNode, GivenAnUpsideDownMountThenTheExtrinsicMapsSensorPointsIntoTheBaseFrame) {
  DriverParams p = plainParams();
  p.frame.apply_extrinsic = true;
  p.sensors[0].xyz = {0.1, 0.0, 0.45};
  p.sensors[0].rpy_deg = {180.0, 0.0, 90.0};  // upside down, then turned left by 90 deg
  const auto pkts = makeStream(1, 1'000'000'000ull, 5000);
  LidarDriverNode node(p);
  const auto clouds = feed(node, pkts, true);
  ASSERT_EQ(clouds.size(), 1u);
  const auto& c = clouds[0];
  EXPECT_EQ(c.frame_id, "base");
  // The sensor origin travels with the cloud: one sensor, no per-point index.
  ASSERT_EQ(c.num_sensors, 1);
  EXPECT_EQ(c.sensor_ids[0], int64_t{0x7F000001});
  EXPECT_EQ(c.sensor_id, int64_t{0x7F000001});
  EXPECT_FLOAT_EQ(c.origin_x[0], 0.1f);
  EXPECT_FLOAT_EQ(c.origin_y[0], 0.0f);
  EXPECT_FLOAT_EQ(c.origin_z[0], 0.45f);
  EXPECT_EQ(c.num_point_sensors, 0);
  EXPECT_TRUE(c.point_sensor.empty());
  // Rx(180): (x, y, z) -> (x, -y, -z); Rz(90): (a, b, c) -> (-b, a, c); then + xyz.
  for (int j = 0; j < c.num_points; ++j) {
    const double x = 1.0 + (j % 10), y = 0.5, z = -0.25;
    EXPECT_NEAR(c.x[j], y + 0.1, 1e-5);
    EXPECT_NEAR(c.y[j], x, 1e-5);
    EXPECT_NEAR(c.z[j], -z + 0.45, 1e-5);
  }
}

TEST(LidarDriverNode, GivenRangeAndTagConfidenceFiltersThenFilteredPointsAreDroppedAndCounted) {
  DriverParams p = plainParams();
  p.filter.min_range_m = 2.5;   // drops x = 1, 2 (range ~1.15, ~2.07)
  p.filter.max_range_m = 8.5;   // drops x = 9, 10
  p.filter.drop_rain_fog_dust_level = 2;
  p.filter.drop_other_noise_level = 3;
  using livox::MidTag;
  std::vector<livox::LidarPoint> pts;
  for (int i = 0; i < 10; ++i) {
    uint8_t tag = MidTag::make(1, 0, 0);  // sticking 1: kept (its level is 0)
    if (i == 4) tag = MidTag::make(0, 2, 0);  // rain/fog/dust 2: dropped
    if (i == 5) tag = MidTag::make(0, 1, 0);  // rain/fog/dust 1: below the level, kept
    if (i == 6) tag = MidTag::make(0, 0, 3);  // other noise 3: dropped
    if (i == 7) tag = MidTag::make(0, 3, 2) | 0xC0;  // reserved bits ignored; rain 3: dropped
    pts.push_back({1.0f + i, 0.5f, -0.25f, 0, tag});
  }
  pts.push_back({0, 0, 0, 0, 0});  // "no return"
  livox::PacketInfo info;
  info.timestamp_ns = 1'000'000'000ull;
  std::vector<uint8_t> b;
  ASSERT_EQ(livox::encodePointPacket(info, livox::DataType::kCartesianHigh, pts, b), livox::EncodeStatus::kOk);
  LidarDriverNode node(p);
  DriverOutputs out;
  node.onDatagram(b.data(), b.size(), out);
  auto c = node.flush();
  ASSERT_TRUE(c);
  // Kept: x = 3, 4, 6 (x = 5, 7, 8 flagged at or above their level).
  ASSERT_EQ(c->num_points, 3);
  const float expect_x[3] = {3, 4, 6};
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(c->x[j], expect_x[j], 1e-6);
  EXPECT_EQ(node.counters().points_range_filtered, 5);
  EXPECT_EQ(node.counters().points_tag_filtered, 3);
  // Level 1 drops every flagged point.
  p.filter.drop_rain_fog_dust_level = 0;
  p.filter.drop_other_noise_level = 0;
  p.filter.drop_sticking_level = 1;
  LidarDriverNode strict(p);
  strict.onDatagram(b.data(), b.size(), out);
  EXPECT_EQ(strict.counters().points_tag_filtered, 2);  // x = 3, 4 (sticking 1); 9, 10 out of range
}

TEST(LidarDriverNode, GivenAnImuPacketThenImuIsPublishedInSiUnitsAndRotatedWithTheExtrinsic) {
  DriverParams p = plainParams();
  p.frame.apply_extrinsic = true;
  p.sensors[0].rpy_deg = {180.0, 0.0, 0.0};
  LidarDriverNode node(p);
  livox::PacketInfo info;
  info.timestamp_ns = 7'000'123'456ull;
  std::vector<uint8_t> b;
  // Upside down at rest: the sensor feels +1 g along its -z.
  ASSERT_EQ(livox::encodeImuPacket(info, livox::ImuSample{0.1f, 0.2f, 0.3f, 0.0f, 0.0f, -9.80665f}, b),
            livox::EncodeStatus::kOk);
  DriverOutputs out;
  ASSERT_EQ(node.onDatagram(b.data(), b.size(), out), livox::ParseStatus::kOk);
  ASSERT_TRUE(out.imu);
  EXPECT_EQ(out.imu->utime, 7'000'123);
  EXPECT_EQ(out.imu->seq, 0);
  EXPECT_EQ(out.imu->frame_id, "base");
  EXPECT_NEAR(out.imu->acc_z, 9.80665, 1e-4);  // base frame: +1 g up
  EXPECT_NEAR(out.imu->gyro_x, 0.1, 1e-6);
  EXPECT_NEAR(out.imu->gyro_y, -0.2, 1e-6);
  EXPECT_NEAR(out.imu->gyro_z, -0.3, 1e-6);
  EXPECT_TRUE(out.clouds.empty());
  EXPECT_EQ(node.counters().imu_packets, 1);
  node.onDatagram(b.data(), b.size(), out);
  EXPECT_EQ(out.imu->seq, 1);
}

TEST(LidarDriverNode, GivenRates10And20HzThenFramesHoldTheMatchingNumberOfPoints) {
  for (int rate : {10, 20}) {
    DriverParams p = plainParams();
    p.frame.rate_hz = rate;
    LidarDriverNode node(p);
    // Start exactly on a boundary; 0.5 s of points at 200 kHz.
    const auto clouds = feed(node, makeStream(1042, 20'000'000'000ull, 5000), false);
    const int32_t per_frame = 200'000 / rate;
    ASSERT_GE(clouds.size(), 4u) << rate;
    for (const auto& c : clouds) EXPECT_EQ(c.num_points, per_frame) << rate;
  }
}

TEST(LidarDriverNode, GivenTheSensorClockJumpingBackThenAssemblyRestartsAndLatePointsAreDropped) {
  LidarDriverNode node(plainParams());
  auto a = makeStream(50, 100'000'000'000ull, 5000);  // t = 100 s
  auto late = makeStream(1, 100'000'000'000ull, 5000);  // 24 ms behind the end of a
  auto reset = makeStream(50, 5'000'000'000ull, 5000);  // t = 5 s: rebooted sensor
  feed(node, a);
  auto r1 = feed(node, late);
  EXPECT_TRUE(r1.empty());
  EXPECT_EQ(node.counters().points_late, 96);
  auto r2 = feed(node, reset, true);
  EXPECT_EQ(node.counters().time_resets, 1);
  ASSERT_FALSE(r2.empty());
  EXPECT_LT(r2.back().utime, 6'000'000);
}

TEST(LidarDriverNode, GivenTheSameInputTwiceThenTheOutputsAreIdentical) {
  const auto pkts = makeStream(120, 9'000'000'000ull, 5000);
  LidarDriverNode a(plainParams()), b(plainParams());
  const auto ca = feed(a, pkts, true), cb = feed(b, pkts, true);
  ASSERT_EQ(ca.size(), cb.size());
  for (std::size_t i = 0; i < ca.size(); ++i) {
    std::vector<uint8_t> ea(static_cast<std::size_t>(ca[i].getEncodedSize())),
        eb(static_cast<std::size_t>(cb[i].getEncodedSize()));
    ca[i].encode(ea.data(), 0, static_cast<int>(ea.size()));
    cb[i].encode(eb.data(), 0, static_cast<int>(eb.size()));
    EXPECT_EQ(ea, eb) << i;
  }
}

TEST(LidarDriverNode, GivenASensorRebootWithSynchronisedTimeThenRestartedCountersAreAcceptedNotDropped) {
  LidarDriverNode node(plainParams());
  auto before = makeStream(50, 30'000'000'000ull, 5000);  // udp_cnt 0..49
  auto after = makeStream(50, 32'000'000'000ull, 5000);   // 2 s later, udp_cnt from 0 again
  const auto c1 = feed(node, before);
  const auto c2 = feed(node, after, true);
  EXPECT_FALSE(c1.empty());
  EXPECT_FALSE(c2.empty());
  EXPECT_EQ(node.counters().out_of_order_packets, 0);
  EXPECT_EQ(node.counters().points_late, 0);
  EXPECT_EQ(node.counters().lost_packets, 0);
  EXPECT_EQ(node.counters().points_published, 100 * 96);
  EXPECT_EQ(node.counters().time_resets, 0);
}

TEST(LidarDriverNode, GivenTheCrc32FieldThenZeroIsNeverCheckedAndAMismatchDropsOnlyOnceTheFieldIsTrusted) {
  auto pkts = makeStream(40, 6'000'000'000ull, 5000);
  const auto corrupt = [](std::vector<uint8_t> b) {
    b[24] ^= 0x5A;  // a non-zero crc32 that does not match
    return b;
  };
  const auto zero = [](std::vector<uint8_t> b) {
    for (int i = 24; i < 28; ++i) b[static_cast<std::size_t>(i)] = 0;
    return b;
  };
  LidarDriverNode node(plainParams());
  DriverOutputs out;
  // A firmware that leaves the field 0: nothing is lost.
  for (int k = 0; k < 10; ++k) EXPECT_EQ(node.onDatagram(zero(pkts[k]).data(), pkts[k].size(), out), livox::ParseStatus::kOk);
  EXPECT_EQ(node.counters().crc_absent, 10);
  // Mismatches before the field has ever matched: kept (the sensor may fill it differently).
  for (int k = 10; k < 13; ++k) {
    const auto b = corrupt(pkts[k]);
    EXPECT_EQ(node.onDatagram(b.data(), b.size(), out), livox::ParseStatus::kOk);
  }
  EXPECT_EQ(node.counters().crc_mismatches_kept, 3);
  EXPECT_EQ(node.counters().crc_errors, 0);
  // kCrcTrustAfter matches in a row: from now on a mismatch is a corrupt packet, dropped alone.
  for (int k = 13; k < 13 + kCrcTrustAfter; ++k) node.onDatagram(pkts[k].data(), pkts[k].size(), out);
  const auto bad = corrupt(pkts[21]);
  EXPECT_EQ(node.onDatagram(bad.data(), bad.size(), out), livox::ParseStatus::kBadCrc);
  EXPECT_EQ(node.counters().crc_errors, 1);
  EXPECT_EQ(node.onDatagram(pkts[22].data(), pkts[22].size(), out), livox::ParseStatus::kOk);
  EXPECT_EQ(node.counters().lost_packets, 1) << "the dropped packet is a gap in udp_cnt";
  // kCrcTrustAfter mismatches in a row: the sensor changed how it fills the field; keep again.
  int dropped = 0;
  for (int k = 23; k < 23 + kCrcTrustAfter + 2; ++k) {
    const auto b = corrupt(pkts[k]);
    if (node.onDatagram(b.data(), b.size(), out) == livox::ParseStatus::kBadCrc) ++dropped;
  }
  EXPECT_EQ(dropped, kCrcTrustAfter - 1);
  EXPECT_EQ(node.counters().crc_mismatches_kept, 3 + 3);
}

namespace {
// Two sensors: 0 at the front (ip 127.0.0.1), 1 at the back turned around (127.0.0.2).
DriverParams twoSensors() {
  DriverParams p = plainParams();
  p.frame.apply_extrinsic = true;
  p.sensors.resize(2);
  p.sensors[0].ip = "127.0.0.1";
  p.sensors[0].xyz = {0.2, 0.0, 0.4};
  p.sensors[0].rpy_deg = {0.0, 0.0, 0.0};
  p.sensors[1].ip = "127.0.0.2";
  p.sensors[1].xyz = {-0.2, 0.0, 0.3};
  p.sensors[1].rpy_deg = {0.0, 0.0, 180.0};
  p.sensors[1].imu = false;
  return p;
}
}  // namespace

TEST(LidarDriverNode, GivenTwoSensorsThenEachPeriodIsOneFrameInTheBodyFrameWithEachPointsSensor) {
  LidarDriverNode node(twoSensors());
  const auto a = makeStream(120, 10'000'000'000ull, 5000);
  const auto b = makeStream(120, 10'000'000'000ull, 5000);
  std::vector<ucon::point_cloud_t> clouds;
  DriverOutputs out;
  for (std::size_t k = 0; k < a.size(); ++k) {
    // Sensor 1's packets arrive a little later than sensor 0's (3 packets = 1.4 ms).
    node.onDatagram(0, a[k].data(), a[k].size(), 0, out);
    for (auto& c : out.clouds) clouds.push_back(std::move(c));
    if (k >= 3) {
      node.onDatagram(1, b[k - 3].data(), b[k - 3].size(), 0, out);
      for (auto& c : out.clouds) clouds.push_back(std::move(c));
    }
  }
  for (std::size_t k = a.size() - 3; k < b.size(); ++k) {
    node.onDatagram(1, b[k].data(), b[k].size(), 0, out);
    for (auto& c : out.clouds) clouds.push_back(std::move(c));
  }
  for (auto& c : node.flushAll()) clouds.push_back(std::move(c));
  // 120 packets x 0.48 ms = 57.6 ms: frames [10.00, 10.02), [10.02, 10.04), [10.04, 10.0576).
  ASSERT_EQ(clouds.size(), 3u);
  EXPECT_EQ(node.counters().points_late, 0);
  int64_t total = 0;
  for (const auto& c : clouds) {
    EXPECT_EQ(c.frame_id, "base");
    EXPECT_EQ(c.sensor_id, 0) << "several sensors: see sensor_ids";
    ASSERT_EQ(c.num_sensors, 2);
    EXPECT_EQ(c.sensor_ids[1], int64_t{0x7F000002});
    EXPECT_FLOAT_EQ(c.origin_x[0], 0.2f);
    EXPECT_FLOAT_EQ(c.origin_x[1], -0.2f);
    EXPECT_FLOAT_EQ(c.origin_z[1], 0.3f);
    ASSERT_EQ(c.num_point_sensors, c.num_points);
    int from0 = 0, from1 = 0;
    for (int j = 0; j < c.num_points; ++j) {
      const int s = c.point_sensor[j];
      // Sensor point (x, 0.5, -0.25), x in 1..10: sensor 0 maps it ahead, sensor 1 behind.
      if (s == 0) {
        ++from0;
        EXPECT_GT(c.x[j], 1.0f);
        EXPECT_NEAR(c.z[j], 0.15f, 1e-5f);
      } else {
        ++from1;
        EXPECT_LT(c.x[j], -1.0f);
        EXPECT_NEAR(c.y[j], -0.5f, 1e-5f);
        EXPECT_NEAR(c.z[j], 0.05f, 1e-5f);
      }
      EXPECT_GE(c.t_offset_ns[j], 0);
      EXPECT_EQ((c.utime * 1000 + c.t_offset_ns[j]) / 20'000'000, c.utime * 1000 / 20'000'000);
    }
    EXPECT_EQ(from0, from1) << "both sensors' points of the period are in the frame";
    total += c.num_points;
  }
  EXPECT_EQ(total, 2 * 120 * 96);
  EXPECT_EQ(clouds[0].num_points, 2 * 4000);
  EXPECT_EQ(clouds[1].num_points, 2 * 4000);
}

TEST(LidarDriverNode, GivenASensorThatStopsThenFramesGoOnWithoutItAfterTheMergeWait) {
  DriverParams p = twoSensors();
  p.frame.merge_wait_s = 0.05;
  LidarDriverNode node(p);
  const auto a = makeStream(400, 20'000'000'000ull, 5000);  // 192 ms
  const auto b = makeStream(30, 20'000'000'000ull, 5000);   // 14.4 ms, then silent
  std::vector<ucon::point_cloud_t> clouds;
  DriverOutputs out;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (k < b.size()) node.onDatagram(1, b[k].data(), b[k].size(), 0, out);
    for (auto& c : out.clouds) clouds.push_back(std::move(c));
    node.onDatagram(0, a[k].data(), a[k].size(), 0, out);
    for (auto& c : out.clouds) clouds.push_back(std::move(c));
  }
  // Without sensor 1 the frames wait 50 ms of sensor 0's time, then go: by 192 ms at least the
  // frames ending before 192 - 50 ms are out.
  ASSERT_GE(clouds.size(), 7u);
  EXPECT_EQ(clouds[0].num_points, 4000 + 30 * 96);
  EXPECT_EQ(clouds[1].num_points, 4000);
}

TEST(LidarDriverNode, GivenHostReceiveTimesThenTheClockOffsetIsEstimatedAndUnsyncedClocksAreAligned) {
  LidarDriverNode node(twoSensors());
  // Sensor 0: time since power-on 100 s; sensor 1: powered 7 s earlier (107 s). The host
  // clock reads 1.7e9 s; packets arrive 0.3 ms after they are sent (plus jitter).
  const int64_t host0 = 1'700'000'000'000'000'000;
  const auto a = makeStream(300, 100'000'000'000ull, 5000, 96, 1000, livox::TimeType::kNone);
  const auto b = makeStream(300, 107'000'000'000ull, 5000, 96, 1000, livox::TimeType::kNone);
  std::vector<ucon::point_cloud_t> clouds;
  DriverOutputs out;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const int64_t sent = static_cast<int64_t>(k) * 480'000 + 480'000;  // after the last point
    const int64_t jitter = (k * 7919) % 5 * 100'000;
    node.onDatagram(0, a[k].data(), a[k].size(), host0 + sent + 300'000 + jitter, out);
    for (auto& c : out.clouds) clouds.push_back(std::move(c));
    node.onDatagram(1, b[k].data(), b[k].size(), host0 + sent + 300'000 + (jitter ^ 100'000), out);
    for (auto& c : out.clouds) clouds.push_back(std::move(c));
  }
  const auto& s0 = node.stream(0);
  ASSERT_TRUE(s0.offset_valid);
  EXPECT_NEAR(static_cast<double>(s0.host_minus_sensor_ns), static_cast<double>(host0 - 100'000'000'000 + 300'000), 1e5);
  EXPECT_EQ(s0.time_sync, ucon::point_cloud_t::TIME_NONE);
  // Sensor 1's times are moved onto sensor 0's clock: -7 s, within the delay jitter.
  EXPECT_NEAR(static_cast<double>(node.stream(1).correction_ns), -7e9, 2e5);
  ASSERT_GE(clouds.size(), 5u);
  for (std::size_t i = 1; i < clouds.size(); ++i) {
    int from1 = 0;
    for (int j = 0; j < clouds[i].num_points; ++j) from1 += clouds[i].point_sensor[j];
    EXPECT_GT(from1, 3000) << "frame " << i << " holds sensor 1's points of the same period";
    EXPECT_LT(clouds[i].utime, 101'000'000);
  }
  ucon::StatusReport rep("lidar_driver");
  node.report(rep);
  const auto msg = rep.build(1, 1);
  double corr_ms = 0.0;
  for (int i = 0; i < msg.num_values; ++i) {
    if (msg.value_names[i] == "clock_correction_ms_s1") corr_ms = msg.values[i];
  }
  EXPECT_NEAR(corr_ms, -7000.0, 0.2);
}
