// Control frames: byte layout against a hand-derived frame, round trips of every helper, and
// corrupted frames rejected with their status.
#include <gtest/gtest.h>

#include "ucon/livox/control.hpp"
#include "ucon/livox/crc.hpp"

using namespace ucon::livox;

TEST(LivoxControl, GivenADiscoveryRequestThenTheBytesFollowTheSdk2Layout) {
  const std::vector<uint8_t> b = encodeControlFrame(makeDiscoveryRequest(0x01020304));
  ASSERT_EQ(b.size(), 24u);
  EXPECT_EQ(b[0], 0xAA);
  EXPECT_EQ(b[1], 0);
  EXPECT_EQ(b[2], 24);  // length, little-endian
  EXPECT_EQ(b[3], 0);
  EXPECT_EQ(b[4], 0x04);  // seq
  EXPECT_EQ(b[7], 0x01);
  EXPECT_EQ(b[8], 0x00);  // cmd_id 0x0000
  EXPECT_EQ(b[9], 0x00);
  EXPECT_EQ(b[10], 0);  // request
  EXPECT_EQ(b[11], 0);  // from host
  for (int i = 12; i < 18; ++i) EXPECT_EQ(b[i], 0) << i;
  const uint16_t c16 = crc16CcittFalse(b.data(), 18);
  EXPECT_EQ(b[18], c16 & 0xFF);
  EXPECT_EQ(b[19], c16 >> 8);
  // crc32 of empty data is 0.
  EXPECT_EQ(b[20] | b[21] | b[22] | b[23], 0);
}

TEST(LivoxControl, GivenASetKeyValueRequestThenItRoundTripsThroughBytes) {
  HostIpConfig pts{{127, 0, 0, 1}, 57001, 56300};
  HostIpConfig imu{{127, 0, 0, 1}, 57002, 56400};
  const std::vector<KeyValue> kvs = {makeHostIpConfig(Key::kPointDataHostIpConfig, pts),
                                     makeHostIpConfig(Key::kImuDataHostIpConfig, imu),
                                     makeWorkMode(WorkMode::kSampling)};
  const ControlFrame req = makeSetKeyValueRequest(77, kvs);
  const std::vector<uint8_t> bytes = encodeControlFrame(req);
  // 24 header + 4 list header + (4+8) + (4+8) + (4+1)
  ASSERT_EQ(bytes.size(), 24u + 4 + 12 + 12 + 5);
  EXPECT_EQ(bytes[8], 0x00);  // cmd 0x0100 little-endian
  EXPECT_EQ(bytes[9], 0x01);
  EXPECT_EQ(bytes[24], 3);  // key_num
  EXPECT_EQ(bytes[28], 0x06);  // first key 0x0006
  EXPECT_EQ(bytes[30], 8);     // its length

  ControlFrame back;
  ASSERT_EQ(decodeControlFrame(bytes, back), ControlStatus::kOk);
  EXPECT_EQ(back.seq, 77u);
  auto list = parseSetKeyValueRequest(back);
  ASSERT_TRUE(list.has_value());
  ASSERT_EQ(list->size(), 3u);
  EXPECT_EQ((*list)[0], kvs[0]);
  auto p = parseHostIpConfig((*list)[0]);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->host_ip, pts.host_ip);
  EXPECT_EQ(p->host_port, 57001);
  EXPECT_EQ(p->lidar_port, 56300);
  EXPECT_EQ((*list)[1].key, 0x0007);
  EXPECT_EQ((*list)[2].key, 0x001A);
  EXPECT_EQ(parseWorkMode((*list)[2]), std::optional<uint8_t>(0x01));
  EXPECT_FALSE(parseSetKeyValueAck(back));  // a request is not an ack
}

TEST(LivoxControl, GivenAcksThenTheyMatchTheirRequestAndCarryTheirFields) {
  const ControlFrame req = makeDiscoveryRequest(5);
  DiscoveryInfo info;
  info.serial = "47MDL9K0020123";
  info.lidar_ip = {127, 0, 0, 1};
  info.cmd_port = 57010;
  std::vector<uint8_t> bytes = encodeControlFrame(makeDiscoveryAck(5, info));
  ASSERT_EQ(bytes.size(), 48u);
  ControlFrame ack;
  ASSERT_EQ(decodeControlFrame(bytes, ack), ControlStatus::kOk);
  EXPECT_TRUE(isAckOf(ack, req));
  EXPECT_FALSE(isAckOf(ack, makeDiscoveryRequest(6)));
  EXPECT_FALSE(isAckOf(req, req));  // a request is not its own ack
  auto got = parseDiscoveryAck(ack);
  ASSERT_TRUE(got);
  EXPECT_EQ(got->serial, info.serial);
  EXPECT_EQ(got->lidar_ip, info.lidar_ip);
  EXPECT_EQ(got->cmd_port, 57010);
  EXPECT_EQ(got->dev_type, kDeviceTypeMid360);
  EXPECT_EQ(got->ret_code, 0);

  const ControlFrame set_req = makeSetKeyValueRequest(9, {makeWorkMode(WorkMode::kSampling)});
  bytes = encodeControlFrame(makeSetKeyValueAck(9, SetKeyValueAck{1, 0x001A}));
  ASSERT_EQ(decodeControlFrame(bytes, ack), ControlStatus::kOk);
  EXPECT_TRUE(isAckOf(ack, set_req));
  auto sa = parseSetKeyValueAck(ack);
  ASSERT_TRUE(sa);
  EXPECT_EQ(sa->ret_code, 1);
  EXPECT_EQ(sa->error_key, 0x001A);
  EXPECT_FALSE(parseDiscoveryAck(ack));
}

TEST(LivoxControl, GivenCorruptedFramesThenEachIsRejectedWithItsStatus) {
  const std::vector<uint8_t> good =
      encodeControlFrame(makeSetKeyValueRequest(3, {makeWorkMode(WorkMode::kSampling)}));
  ControlFrame out;
  ASSERT_EQ(decodeControlFrame(good, out), ControlStatus::kOk);
  struct Case {
    const char* name;
    std::vector<uint8_t> bytes;
    ControlStatus expected;
  };
  std::vector<Case> cases;
  cases.push_back({"empty", {}, ControlStatus::kTruncated});
  cases.push_back({"23 bytes", std::vector<uint8_t>(good.begin(), good.begin() + 23), ControlStatus::kTruncated});
  auto b = good; b[0] = 0x55; cases.push_back({"sof", b, ControlStatus::kBadSof});
  b = good; b[1] = 1; cases.push_back({"version", b, ControlStatus::kBadVersion});
  b = good; b.push_back(0); cases.push_back({"trailing byte", b, ControlStatus::kBadLength});
  b = good; b[5] ^= 1; cases.push_back({"seq bit flip", b, ControlStatus::kBadHeaderCrc});
  b = good; b[12] = 9; cases.push_back({"reserved byte", b, ControlStatus::kBadHeaderCrc});
  b = good; b.back() ^= 1; cases.push_back({"data bit flip", b, ControlStatus::kBadDataCrc});
  b = good; b[21] ^= 1; cases.push_back({"crc32 field", b, ControlStatus::kBadDataCrc});
  for (const auto& c : cases) {
    EXPECT_EQ(decodeControlFrame(c.bytes, out), c.expected) << c.name << ": " << toString(decodeControlFrame(c.bytes, out));
  }
  EXPECT_EQ(decodeControlFrame(nullptr, 30, out), ControlStatus::kTruncated);
}

TEST(LivoxControl, GivenMalformedKeyValueListsThenTheyAreRejected) {
  const std::vector<uint8_t> good = encodeKeyValueList({makeWorkMode(WorkMode::kIdle)});
  ASSERT_TRUE(decodeKeyValueList(good));
  auto b = good; b.pop_back();
  EXPECT_FALSE(decodeKeyValueList(b)) << "value cut short";
  b = good; b.push_back(0);
  EXPECT_FALSE(decodeKeyValueList(b)) << "trailing bytes";
  b = good; b[0] = 5;
  EXPECT_FALSE(decodeKeyValueList(b)) << "count larger than entries";
  EXPECT_FALSE(decodeKeyValueList({1, 0}));
  EXPECT_FALSE(parseHostIpConfig(makeWorkMode(WorkMode::kSampling)));
}

TEST(LivoxControl, GivenIpv4TextThenItParsesOrIsRejected) {
  EXPECT_EQ(parseIpv4("127.0.0.1"), (std::optional<std::array<uint8_t, 4>>{{127, 0, 0, 1}}));
  EXPECT_EQ(parseIpv4("192.168.1.50")->at(3), 50);
  for (const char* bad : {"", "1.2.3", "1.2.3.4.5", "256.0.0.1", "a.b.c.d", "1..2.3", "1.2.3.4 ", "0001.2.3.4"}) {
    EXPECT_FALSE(parseIpv4(bad)) << bad;
  }
  EXPECT_EQ(formatIpv4({192, 168, 1, 3}), "192.168.1.3");
}

TEST(LivoxControl, GivenAQueryAndItsAckThenBothRoundTripThroughBytes) {
  const ControlFrame q = makeQueryRequest(21, {0x8000, 0x8002});
  const auto qb = encodeControlFrame(q);
  // key_num 2, reserved, then the two keys: 4 + 4 data bytes.
  ASSERT_EQ(qb.size(), kControlHeaderSize + 8);
  EXPECT_EQ(qb[kControlHeaderSize], 2);
  EXPECT_EQ(qb[kControlHeaderSize + 5], 0x80);
  ControlFrame qd;
  ASSERT_EQ(decodeControlFrame(qb, qd), ControlStatus::kOk);
  const auto keys = parseQueryRequest(qd);
  ASSERT_TRUE(keys);
  EXPECT_EQ(*keys, (std::vector<uint16_t>{0x8000, 0x8002}));

  QueryAck ack;
  ack.values = {KeyValue{0x8002, {15, 5, 1, 20}}, KeyValue{0x800C, {1}}};
  const auto ab = encodeControlFrame(makeQueryAck(21, ack));
  // ret_code, key_num (2 bytes), then key, length, value per entry (no reserved field).
  ASSERT_EQ(ab.size(), kControlHeaderSize + 3 + (4 + 4) + (4 + 1));
  ControlFrame ad;
  ASSERT_EQ(decodeControlFrame(ab, ad), ControlStatus::kOk);
  EXPECT_TRUE(isAckOf(ad, q));
  const auto parsed = parseQueryAck(ad);
  ASSERT_TRUE(parsed);
  EXPECT_EQ(parsed->ret_code, 0);
  ASSERT_EQ(parsed->values.size(), 2u);
  const KeyValue* fw = findKey(parsed->values, Key::kFirmwareVersion);
  ASSERT_NE(fw, nullptr);
  EXPECT_EQ(fw->value, (std::vector<uint8_t>{15, 5, 1, 20}));
  EXPECT_EQ(findKey(parsed->values, Key::kSerialNumber), nullptr);
  // A truncated list is refused.
  ad.data.pop_back();
  EXPECT_FALSE(parseQueryAck(ad));
}

TEST(LivoxControl, GivenWorkModesThenOnlySamplingAndIdleAreSettableOnAMid360) {
  EXPECT_TRUE(isSettableWorkMode(0x01));
  EXPECT_TRUE(isSettableWorkMode(0x02));
  EXPECT_FALSE(isSettableWorkMode(0x03));  // not a Mid-360 state
  EXPECT_FALSE(isSettableWorkMode(0x00));
  EXPECT_FALSE(isSettableWorkMode(0x04));
  const KeyValue att = makeInstallAttitude(0.0f, 0.0f, 0.0f, 0, 0, 0);
  EXPECT_EQ(att.key, 0x0012);
  EXPECT_EQ(att.value, std::vector<uint8_t>(24, 0));
  const KeyValue dt = makeUint8(Key::kPointDataType, 1);
  EXPECT_EQ(dt.key, 0x0000);
  EXPECT_EQ(dt.value, std::vector<uint8_t>{1});
}
