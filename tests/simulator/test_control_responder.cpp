// The emulated sensor's control path: discovery and set-key-value requests get correctly
// framed acks (decoded with ucon::livox), state changes take effect, bad input is counted.
#include <gtest/gtest.h>

#include "ucon/livox/protocol.hpp"
#include "ucon/simulator/control_responder.hpp"
#include "ucon/simulator/simulator.hpp"

using namespace ucon;
using namespace ucon::simulator;

namespace {

ControlResponder responder() {
  return ControlResponder(SensorState{}, {{127, 0, 0, 1}}, 56100, "SIM360TEST");
}

livox::ControlFrame roundTrip(ControlResponder& r, const livox::ControlFrame& req) {
  const auto bytes = livox::encodeControlFrame(req);
  const auto reply = r.handle(bytes.data(), bytes.size());
  EXPECT_TRUE(reply.has_value());
  livox::ControlFrame ack;
  if (reply) {
    EXPECT_EQ(livox::decodeControlFrame(*reply, ack), livox::ControlStatus::kOk);
  }
  EXPECT_TRUE(livox::isAckOf(ack, req));
  return ack;
}

}  // namespace

TEST(ControlResponder, GivenADiscoveryRequestThenTheAckDescribesAMid360) {
  auto r = responder();
  const auto ack = roundTrip(r, livox::makeDiscoveryRequest(77));
  const auto info = livox::parseDiscoveryAck(ack);
  ASSERT_TRUE(info);
  EXPECT_EQ(info->ret_code, 0);
  EXPECT_EQ(info->dev_type, livox::kDeviceTypeMid360);
  EXPECT_EQ(info->serial, "SIM360TEST");
  EXPECT_EQ(livox::formatIpv4(info->lidar_ip), "127.0.0.1");
  EXPECT_EQ(info->cmd_port, 56100);
  EXPECT_EQ(r.counters().requests, 1);
}

TEST(ControlResponder, GivenHostIpAndWorkModeCommandsThenTheStateChangesAndTheAckIsSuccess) {
  auto r = responder();
  livox::HostIpConfig pc;
  pc.host_ip = {{127, 0, 0, 1}};
  pc.host_port = 57150;
  pc.lidar_port = 56300;
  livox::HostIpConfig ic = pc;
  ic.host_port = 57151;
  const auto ack = roundTrip(r, livox::makeSetKeyValueRequest(
                                    5, {livox::makeHostIpConfig(livox::Key::kPointDataHostIpConfig, pc),
                                        livox::makeHostIpConfig(livox::Key::kImuDataHostIpConfig, ic),
                                        livox::makeWorkMode(livox::WorkMode::kIdle)}));
  const auto res = livox::parseSetKeyValueAck(ack);
  ASSERT_TRUE(res);
  EXPECT_EQ(res->ret_code, 0);
  EXPECT_EQ(r.state().point_host_port, 57150);
  EXPECT_EQ(r.state().imu_host_port, 57151);
  EXPECT_FALSE(r.state().sampling());
  roundTrip(r, livox::makeSetKeyValueRequest(6, {livox::makeWorkMode(livox::WorkMode::kSampling)}));
  EXPECT_TRUE(r.state().sampling());
}

TEST(ControlResponder, GivenAnUnknownKeyThenTheAckNamesItAndNothingChanges) {
  auto r = responder();
  livox::KeyValue bogus;
  bogus.key = 0x7777;
  bogus.value = {1};
  const auto ack = roundTrip(r, livox::makeSetKeyValueRequest(
                                    9, {livox::makeWorkMode(livox::WorkMode::kIdle), bogus}));
  const auto res = livox::parseSetKeyValueAck(ack);
  ASSERT_TRUE(res);
  EXPECT_NE(res->ret_code, 0);
  EXPECT_EQ(res->error_key, 0x7777);
  EXPECT_TRUE(r.state().sampling());  // the whole command was refused
  EXPECT_EQ(r.counters().rejected_keys, 1);
}

TEST(ControlResponder, GivenMalformedDatagramsThenThereIsNoReplyAndTheyAreCounted) {
  auto r = responder();
  auto good = livox::encodeControlFrame(livox::makeDiscoveryRequest(1));
  std::vector<std::vector<uint8_t>> bad = {{}, {0xAA}, good, good, good};
  bad[2][0] = 0x55;              // bad SOF
  bad[3][20] ^= 0xFF;            // crc32 field
  bad[4].resize(bad[4].size() + 3);  // length mismatch
  for (const auto& b : bad) EXPECT_FALSE(r.handle(b.data(), b.size()).has_value());
  // An ack (not a request) is not answered either.
  auto ack = livox::encodeControlFrame(livox::makeDiscoveryAck(3, livox::DiscoveryInfo{}));
  EXPECT_FALSE(r.handle(ack.data(), ack.size()).has_value());
  EXPECT_EQ(r.counters().malformed, 6);
  EXPECT_EQ(r.counters().requests, 0);
}

TEST(ControlResponder, GivenTheSimulatorThenPacketsFollowTheConfiguredHostAndStopInSleep) {
  SimulatorParams p;
  p.base.geometry.max_wheel_speed = 40;
  world::Scenario s;
  s.name = "empty";
  Simulator sim(p, s);
  SimOutputs out;
  sim.advanceTo(p.start_utime + 10000, out);
  ASSERT_FALSE(out.point_packets.empty());
  EXPECT_EQ(out.point_packets[0].port, 56301);
  livox::HostIpConfig pc;
  pc.host_ip = {{127, 0, 0, 1}};
  pc.host_port = 57160;
  livox::KeyValue type3;
  type3.key = static_cast<uint16_t>(livox::Key::kPointDataType);
  type3.value = {3};
  auto req = livox::encodeControlFrame(livox::makeSetKeyValueRequest(
      1, {livox::makeHostIpConfig(livox::Key::kPointDataHostIpConfig, pc), type3}));
  ASSERT_TRUE(sim.control().handle(req.data(), req.size()));
  out.clear();
  sim.advanceTo(p.start_utime + 20000, out);
  ASSERT_FALSE(out.point_packets.empty());
  EXPECT_EQ(out.point_packets[0].port, 57160);
  livox::ParsedPacket pk;
  ASSERT_EQ(livox::parsePacket(out.point_packets[0].bytes.data(), out.point_packets[0].bytes.size(), pk),
            livox::ParseStatus::kOk);
  EXPECT_EQ(pk.header.data_type, 3);
  req = livox::encodeControlFrame(livox::makeSetKeyValueRequest(2, {livox::makeWorkMode(livox::WorkMode::kIdle)}));
  ASSERT_TRUE(sim.control().handle(req.data(), req.size()));
  out.clear();
  sim.advanceTo(p.start_utime + 40000, out);
  EXPECT_TRUE(out.point_packets.empty());
  EXPECT_TRUE(out.imu_packets.empty());
  EXPECT_FALSE(out.poses.empty());  // the base keeps running
}

TEST(ControlResponder, GivenAWorkModeAMid360DoesNotHaveThenTheCommandIsRejectedLikeTheSensorDoes) {
  auto r = responder();
  for (uint8_t mode : {uint8_t{0x00}, uint8_t{0x03}, uint8_t{0x04}, uint8_t{0x09}}) {
    livox::KeyValue kv{static_cast<uint16_t>(livox::Key::kWorkMode), {mode}};
    const auto ack = roundTrip(r, livox::makeSetKeyValueRequest(20 + mode, {kv}));
    const auto res = livox::parseSetKeyValueAck(ack);
    ASSERT_TRUE(res);
    EXPECT_NE(res->ret_code, 0) << int(mode);
    EXPECT_EQ(res->error_key, 0x001A) << int(mode);
    EXPECT_TRUE(r.state().sampling()) << "unchanged";
  }
  // Data type, pattern and attitude, as the driver sets them at every start, are accepted.
  const auto ack = roundTrip(r, livox::makeSetKeyValueRequest(
                                    40, {livox::makeUint8(livox::Key::kPointDataType, 1),
                                         livox::makeUint8(livox::Key::kPatternMode, 0),
                                         livox::makeInstallAttitude(0, 0, 0, 0, 0, 0)}));
  EXPECT_EQ(livox::parseSetKeyValueAck(ack)->ret_code, 0);
}

TEST(ControlResponder, GivenDiscoveryThenTheAnswerIsMarkedForBroadcastAndAQueryIsAnswered) {
  auto r = responder();
  bool broadcast = false;
  auto req = livox::encodeControlFrame(livox::makeDiscoveryRequest(3));
  ASSERT_TRUE(r.handle(req.data(), req.size(), &broadcast));
  EXPECT_TRUE(broadcast) << "a Mid-360 answers discovery by broadcast";
  req = livox::encodeControlFrame(livox::makeSetKeyValueRequest(4, {livox::makeWorkMode(livox::WorkMode::kIdle)}));
  ASSERT_TRUE(r.handle(req.data(), req.size(), &broadcast));
  EXPECT_FALSE(broadcast);
  const auto q = livox::makeQueryRequest(5, {0x8000, 0x8002, 0x8006, 0x9999});
  const auto ack = roundTrip(r, q);
  const auto res = livox::parseQueryAck(ack);
  ASSERT_TRUE(res);
  ASSERT_EQ(res->values.size(), 3u);  // the unknown key is left out
  EXPECT_EQ(std::string(res->values[0].value.begin(), res->values[0].value.begin() + 10), "SIM360TEST");
  EXPECT_EQ(res->values[1].value.size(), 4u);
  EXPECT_EQ(res->values[2].value, std::vector<uint8_t>{0x02});  // idle, as set above
}

TEST(ControlResponder, GivenAnExtraLidarThenItAnswersOnItsOwnAndSendsItsOwnPointsFromItsMount) {
  SimulatorParams p;
  p.base.geometry.max_wheel_speed = 40;
  ExtraLidarParams e;
  e.sensor_ip = "127.0.0.2";
  e.serial = "SIMREAR";
  e.mount_xyz = {-0.3, 0.0, 0.4};
  e.mount_rpy_deg = {0.0, 0.0, 180.0};
  p.extra_lidars.push_back(e);
  ASSERT_EQ(p.validate(), "");
  world::Scenario s;
  s.name = "empty";
  Simulator sim(p, s);
  ASSERT_EQ(sim.sensorCount(), 2u);
  // Each sensor answers discovery with its own address and serial.
  const auto req = livox::encodeControlFrame(livox::makeDiscoveryRequest(8));
  const auto reply = sim.control(1).handle(req.data(), req.size());
  ASSERT_TRUE(reply);
  livox::ControlFrame f;
  ASSERT_EQ(livox::decodeControlFrame(*reply, f), livox::ControlStatus::kOk);
  EXPECT_EQ(livox::parseDiscoveryAck(f)->serial, "SIMREAR");
  EXPECT_EQ(livox::formatIpv4(livox::parseDiscoveryAck(f)->lidar_ip), "127.0.0.2");
  // Idle on the first sensor does not silence the second.
  const auto idle = livox::encodeControlFrame(livox::makeSetKeyValueRequest(9, {livox::makeWorkMode(livox::WorkMode::kIdle)}));
  ASSERT_TRUE(sim.control(0).handle(idle.data(), idle.size()));
  SimOutputs out;
  sim.advanceTo(p.start_utime + 25000, out);
  int from0 = 0, from1 = 0;
  uint16_t last_cnt = 0;
  for (const auto& d : out.point_packets) {
    (d.sensor == 0 ? from0 : from1) += 1;
    livox::ParsedPacket pk;
    ASSERT_EQ(livox::parsePacket(d.bytes.data(), d.bytes.size(), pk), livox::ParseStatus::kOk);
    if (d.sensor == 1) last_cnt = pk.header.udp_cnt;
  }
  EXPECT_EQ(from0, 0);
  EXPECT_GE(from1, 50);
  EXPECT_LT(last_cnt, 45) << "udp_cnt restarts with each 20 ms frame";
}
