// The control path as a state machine: broadcast discovery retried every second without end,
// each configuration key set by its own acknowledged command, retries, rejections, several
// sensors, and the failure message when control.timeout_s is set.
#include <gtest/gtest.h>

#include "ucon/lidar_driver/sensor_configurator.hpp"

using namespace ucon::lidar_driver;
namespace livox = ucon::livox;
using Phase = SensorControlState::Phase;
using Ip = std::array<uint8_t, 4>;

namespace {
const Ip kSensor{192, 168, 1, 100};
const Ip kSensor2{192, 168, 1, 101};

DriverParams params(bool discovery, int sensors = 1) {
  DriverParams p;
  p.network.host_ip = "192.168.1.50";
  p.network.discovery = discovery;
  p.control.timeout_s = 0.0;
  p.control.retry_interval_s = 1.0;
  p.sensors.clear();
  for (int i = 0; i < sensors; ++i) {
    SensorParams s;
    s.ip = i == 0 ? "192.168.1.100" : "192.168.1.101";
    s.imu = i == 0;
    p.sensors.push_back(s);
  }
  return p;
}
livox::ControlFrame decode(const OutgoingDatagram& d) {
  livox::ControlFrame f;
  EXPECT_EQ(livox::decodeControlFrame(d.bytes, f), livox::ControlStatus::kOk);
  return f;
}
void answerDiscovery(SensorConfigurator& c, const Ip& from, double t, const std::string& serial = "47MDL9T0020193") {
  livox::DiscoveryInfo info;
  info.serial = serial;
  info.lidar_ip = from;
  info.cmd_port = 56100;
  const auto b = livox::encodeControlFrame(livox::makeDiscoveryAck(1234, info));
  c.onDiscoveryDatagram(from, b.data(), b.size(), t);
}
void ack(SensorConfigurator& c, const Ip& from, const livox::ControlFrame& req, double t, uint8_t ret = 0,
         uint16_t key = 0) {
  const auto b = livox::encodeControlFrame(livox::makeSetKeyValueAck(req.seq, {ret, key}));
  c.onCommandDatagram(from, b.data(), b.size(), t);
}
// The single key of a one-key set request.
uint16_t keyOf(const livox::ControlFrame& f) {
  const auto kvs = livox::parseSetKeyValueRequest(f);
  EXPECT_TRUE(kvs && !kvs->empty());
  return kvs && !kvs->empty() ? kvs->front().key : 0xFFFF;
}
}  // namespace

TEST(SensorConfigurator, GivenDiscoveryThenItBroadcastsFromThe56000SocketEverySecondWithoutEnd) {
  SensorConfigurator c(params(true));
  EXPECT_EQ(c.sensor(0).phase, Phase::kDiscovering);
  auto out = c.poll(100.0);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].via, OutgoingDatagram::Via::kDiscovery);
  EXPECT_EQ(out[0].ip, (Ip{255, 255, 255, 255}));
  EXPECT_EQ(out[0].port, 56000);
  const auto f = decode(out[0]);
  EXPECT_EQ(f.cmd_id, 0x0000);
  EXPECT_EQ(f.cmd_type, 0);
  EXPECT_TRUE(f.data.empty());
  EXPECT_TRUE(c.poll(100.5).empty());
  // An hour later it still asks, once a second; nothing has failed (timeout_s 0).
  int sent = 1;
  for (double t = 101.0; t < 3700.0; t += 1.0) sent += static_cast<int>(c.poll(t).size());
  EXPECT_EQ(sent, 3600);
  EXPECT_FALSE(c.failed());
  EXPECT_NE(c.waitingFor().find("no discovery answer"), std::string::npos) << c.waitingFor();
  EXPECT_NE(c.waitingFor().find("0.0.0.0:56000"), std::string::npos) << c.waitingFor();
}

TEST(SensorConfigurator, GivenAnAnswerThenEachKeyIsSetByItsOwnAcknowledgedCommandInOrder) {
  SensorConfigurator c(params(true));
  c.poll(0.0);
  // Our own broadcast comes back on the 0.0.0.0:56000 socket: it is a request, ignored.
  const auto own = livox::encodeControlFrame(livox::makeDiscoveryRequest(1));
  c.onDiscoveryDatagram({192, 168, 1, 50}, own.data(), own.size(), 0.1);
  EXPECT_EQ(c.sensor(0).phase, Phase::kDiscovering);
  answerDiscovery(c, kSensor, 0.2);
  EXPECT_EQ(c.sensor(0).phase, Phase::kConfiguring);
  EXPECT_EQ(c.sensor(0).serial, "47MDL9T0020193");

  // First where data goes: state-info, point and IMU hosts together, as Livox's SDK sends them.
  auto out = c.poll(0.3);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].via, OutgoingDatagram::Via::kCommand);
  EXPECT_EQ(out[0].ip, kSensor);
  EXPECT_EQ(out[0].port, 56100);
  auto req = decode(out[0]);
  EXPECT_EQ(req.cmd_id, 0x0100);
  auto kvs = *livox::parseSetKeyValueRequest(req);
  ASSERT_EQ(kvs.size(), 3u);
  EXPECT_EQ(kvs[0].key, 0x0005);
  EXPECT_EQ(livox::parseHostIpConfig(kvs[0])->host_port, 56201);
  EXPECT_EQ(livox::parseHostIpConfig(kvs[0])->lidar_port, 56200);
  EXPECT_EQ(kvs[1].key, 0x0006);
  EXPECT_EQ(livox::parseHostIpConfig(kvs[1])->host_ip, (Ip{192, 168, 1, 50}));
  EXPECT_EQ(livox::parseHostIpConfig(kvs[1])->host_port, 56301);
  EXPECT_EQ(kvs[2].key, 0x0007);
  EXPECT_EQ(livox::parseHostIpConfig(kvs[2])->host_port, 56401);
  EXPECT_TRUE(c.poll(0.31).empty()) << "nothing else before the hosts are acknowledged";
  ack(c, kSensor, req, 0.32);
  // Then every other key, each by its own command, all at once (one ignored by the sensor
  // does not hold the others).
  out = c.poll(0.33);
  ASSERT_EQ(out.size(), 5u);
  const uint16_t expected_keys[] = {0x0000, 0x0001, 0x0012, 0x001C, 0x001A};
  const std::vector<uint8_t> expected_values[] = {{1}, {0}, std::vector<uint8_t>(24, 0), {1}, {0x01}};
  std::vector<livox::ControlFrame> reqs;
  for (int k = 0; k < 5; ++k) {
    reqs.push_back(decode(out[static_cast<std::size_t>(k)]));
    ASSERT_EQ(livox::parseSetKeyValueRequest(reqs.back())->size(), 1u);
    EXPECT_EQ(keyOf(reqs.back()), expected_keys[k]) << k;
    EXPECT_EQ(livox::parseSetKeyValueRequest(reqs.back())->front().value, expected_values[k]) << k;
  }
  // Acknowledged in another order than sent: each ack closes its own step.
  for (int k : {4, 0, 3, 1}) ack(c, kSensor, reqs[static_cast<std::size_t>(k)], 0.4);
  EXPECT_EQ(c.sensor(0).phase, Phase::kConfiguring);
  EXPECT_NE(c.waitingFor().find("install attitude"), std::string::npos) << c.waitingFor();
  ack(c, kSensor, reqs[2], 0.5);
  EXPECT_EQ(c.sensor(0).phase, Phase::kDone);
  EXPECT_TRUE(c.allDone());
  EXPECT_TRUE(c.waitingFor().empty());
  EXPECT_TRUE(c.poll(10.0).empty()) << "no more discovery once every sensor answered";
}

TEST(SensorConfigurator, GivenNoAckThenTheStepIsResentWithANewSeqAndALateAckStillCounts) {
  SensorConfigurator c(params(false));
  EXPECT_EQ(c.sensor(0).phase, Phase::kConfiguring);
  auto first = c.poll(0.0);
  ASSERT_EQ(first.size(), 1u);
  EXPECT_TRUE(c.poll(0.9).empty());
  auto again = c.poll(1.0);
  ASSERT_EQ(again.size(), 1u);
  const auto r1 = decode(first[0]), r2 = decode(again[0]);
  EXPECT_NE(r1.seq, r2.seq);
  EXPECT_EQ(keyOf(r1), keyOf(r2));
  // An ack from another address, or to a seq never sent, does nothing.
  ack(c, kSensor2, r2, 1.1);
  auto bogus = r2;
  bogus.seq = 999999;
  ack(c, kSensor, bogus, 1.1);
  EXPECT_EQ(c.sensor(0).step, 0);
  EXPECT_EQ(c.ignoredDatagrams(), 2);
  ack(c, kSensor, r1, 1.2);  // the slow answer to the first attempt
  EXPECT_EQ(c.sensor(0).step, 1);
  EXPECT_NE(c.waitingFor().find("point data type"), std::string::npos) << c.waitingFor();
  EXPECT_NE(c.waitingFor().find("work mode"), std::string::npos) << c.waitingFor();
}

TEST(SensorConfigurator, GivenARejectionThenARequiredStepIsRetriedAndAnOptionalOneSkipped) {
  SensorConfigurator c(params(false));
  ack(c, kSensor, decode(c.poll(0.0)[0]), 0.1);  // hosts
  auto out = c.poll(0.2);
  ASSERT_EQ(out.size(), 5u);
  ack(c, kSensor, decode(out[0]), 0.3, 1, 0x0000);  // data type rejected: required
  ack(c, kSensor, decode(out[1]), 0.3, 1, 0x0001);  // pattern rejected: optional, skipped
  const auto w = c.takeWarnings();
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NE(w[0].find("retrying"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("going on without it"), std::string::npos) << w[1];
  for (int k = 2; k < 5; ++k) ack(c, kSensor, decode(out[static_cast<std::size_t>(k)]), 0.3);
  EXPECT_FALSE(c.allDone());
  EXPECT_NE(c.waitingFor().find("point data type"), std::string::npos) << c.waitingFor();
  EXPECT_NE(c.waitingFor().find("ret_code 1 for key 0x0000"), std::string::npos) << c.waitingFor();
  EXPECT_TRUE(c.poll(0.5).empty());
  out = c.poll(1.2);  // retried after the interval
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(keyOf(decode(out[0])), 0x0000);
  ack(c, kSensor, decode(out[0]), 1.3);
  EXPECT_TRUE(c.allDone());
}

TEST(SensorConfigurator, GivenASensorThatIgnoresAnOptionalKeyThenItIsGivenUpAfterThreeRequests) {
  SensorConfigurator c(params(false));
  ack(c, kSensor, decode(c.poll(0.0)[0]), 0.1);
  double t = 0.2;
  for (int round = 0; round < 5 && !c.allDone(); ++round, t += 1.0) {
    for (const auto& d : c.poll(t)) {
      const auto req = decode(d);
      if (keyOf(req) != 0x0012) ack(c, kSensor, req, t);  // never answers the attitude
    }
  }
  EXPECT_TRUE(c.allDone());
  const auto w = c.takeWarnings();
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("no answer to 'install attitude"), std::string::npos) << w[0];
}

TEST(SensorConfigurator, GivenTwoSensorsThenEachIsConfiguredOnItsOwnAndUnlistedOnesAreIgnored) {
  SensorConfigurator c(params(true, 2));
  c.poll(0.0);
  answerDiscovery(c, {192, 168, 1, 177}, 0.1, "STRANGER");
  EXPECT_EQ(c.takeWarnings().size(), 1u);
  answerDiscovery(c, {192, 168, 1, 177}, 0.15, "STRANGER");
  EXPECT_TRUE(c.takeWarnings().empty()) << "said once";
  answerDiscovery(c, kSensor2, 0.2, "SECOND");
  EXPECT_EQ(c.sensor(1).phase, Phase::kConfiguring);
  EXPECT_EQ(c.sensor(0).phase, Phase::kDiscovering);
  auto out = c.poll(0.3);
  ASSERT_EQ(out.size(), 1u);  // sensor 1's first step; the next broadcast is not due yet
  EXPECT_EQ(out[0].ip, kSensor2);
  out = c.poll(1.0);
  ASSERT_EQ(out.size(), 1u);  // the next broadcast, for sensor 0
  EXPECT_EQ(out[0].via, OutgoingDatagram::Via::kDiscovery);
  out = c.poll(1.3);
  ASSERT_EQ(out.size(), 1u);  // sensor 1's retry
  EXPECT_EQ(out[0].ip, kSensor2);
  answerDiscovery(c, kSensor, 1.1);
  for (double t = 1.4; t < 3.0 && !c.allDone(); t += 0.01) {
    for (const auto& d : c.poll(t)) {
      if (d.via == OutgoingDatagram::Via::kCommand) ack(c, d.ip, decode(d), t);
    }
  }
  EXPECT_TRUE(c.allDone());
  // IMU off for the sensor that does not publish it.
  SensorConfigurator c2(params(false, 2));
  for (double t = 0.0; t < 1.0 && !c2.allDone(); t += 0.01) {
    for (const auto& d : c2.poll(t)) {
      const auto req = decode(d);
      if (keyOf(req) == 0x001C) {
        EXPECT_EQ(livox::parseSetKeyValueRequest(req)->front().value,
                  std::vector<uint8_t>{static_cast<uint8_t>(d.ip == kSensor ? 1 : 0)});
      }
      ack(c2, d.ip, req, t);
    }
  }
  EXPECT_TRUE(c2.allDone());
}

TEST(SensorConfigurator, GivenATimeoutThenItFailsNamingWhatItWaitsFor) {
  DriverParams p = params(true);
  p.control.timeout_s = 2.0;
  SensorConfigurator c(p);
  for (double t = 0.0; t < 2.5 && !c.failed(); t += 0.1) c.poll(t);
  ASSERT_TRUE(c.failed());
  EXPECT_NE(c.failure().find("192.168.1.100"), std::string::npos) << c.failure();
  EXPECT_NE(c.failure().find("no discovery answer"), std::string::npos) << c.failure();
  EXPECT_NE(c.failure().find("192.168.1.50"), std::string::npos) << c.failure();
}

TEST(SensorConfigurator, GivenAnAutoSensorThenTheFirstMid360ToAnswerIsTaken) {
  DriverParams p = params(true);
  p.sensors[0].ip = "auto";
  SensorConfigurator c(p);
  c.poll(0.0);
  EXPECT_EQ(c.indexOf(kSensor2), -1);
  // Another Livox model (dev_type 8 = not a Mid-360) is not taken.
  livox::DiscoveryInfo other;
  other.dev_type = 8;
  const auto b = livox::encodeControlFrame(livox::makeDiscoveryAck(5, other));
  c.onDiscoveryDatagram({192, 168, 1, 200}, b.data(), b.size(), 0.05);
  EXPECT_FALSE(c.sensor(0).ip_known);
  answerDiscovery(c, kSensor2, 0.1);
  EXPECT_TRUE(c.sensor(0).ip_known);
  EXPECT_EQ(c.indexOf(kSensor2), 0);
  EXPECT_EQ(c.poll(0.2).at(0).ip, kSensor2);
}

TEST(SensorConfigurator, GivenTheCheckThenFirmwareAndSerialAreQueriedAndASilentSensorIsRestarted) {
  SensorConfigurator c(params(false), true);
  ack(c, kSensor, decode(c.poll(0.0)[0]), 0.01);
  livox::ControlFrame q;
  for (const auto& d : c.poll(0.02)) {
    const auto f = decode(d);
    if (f.cmd_id == 0x0101) {
      q = f;
    } else {
      ack(c, kSensor, f, 0.03);
    }
  }
  ASSERT_EQ(q.cmd_id, 0x0101);
  livox::QueryAck a;
  std::vector<uint8_t> sn(16, 0);
  const std::string serial = "47MDL9T0020193";
  std::copy(serial.begin(), serial.end(), sn.begin());
  a.values = {{0x8000, sn}, {0x8002, {15, 5, 1, 20}}, {0x800C, {1}}};
  const auto b = livox::encodeControlFrame(livox::makeQueryAck(q.seq, a));
  c.onCommandDatagram(kSensor, b.data(), b.size(), 0.04);
  ASSERT_TRUE(c.allDone());
  EXPECT_EQ(c.sensor(0).firmware, "15.5.1.20");
  EXPECT_EQ(c.sensor(0).serial, serial);
  EXPECT_EQ(c.sensor(0).time_sync_type, 1);
  c.restart(0, 5.0);
  EXPECT_EQ(c.sensor(0).phase, Phase::kConfiguring);
  EXPECT_EQ(keyOf(decode(c.poll(5.0).at(0))), 0x0005);
}
