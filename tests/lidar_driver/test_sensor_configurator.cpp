// The control path as a state machine: requests, retries, acks, discovery, and the failure
// message when nothing answers.
#include <gtest/gtest.h>

#include "ucon/lidar_driver/sensor_configurator.hpp"

using namespace ucon::lidar_driver;
namespace livox = ucon::livox;

namespace {
DriverParams params(bool discovery) {
  DriverParams p;
  p.network.host_ip = "127.0.0.1";
  p.network.sensor_ip = "127.0.0.2";
  p.network.discovery = discovery;
  p.network.discovery_address = "127.0.0.255";
  p.network.sensor_discovery_port = 57090;
  p.network.sensor_command_port = 57091;
  p.network.host_point_port = 57092;
  p.network.host_imu_port = 57093;
  p.network.sensor_point_port = 56300;
  p.network.sensor_imu_port = 56400;
  p.control.timeout_s = 2.0;
  p.control.retry_interval_s = 0.5;
  return p;
}
livox::ControlFrame decode(const OutgoingDatagram& d) {
  livox::ControlFrame f;
  EXPECT_EQ(livox::decodeControlFrame(d.bytes, f), livox::ControlStatus::kOk);
  return f;
}
void deliver(SensorConfigurator& c, const livox::ControlFrame& f, double t) {
  const auto b = livox::encodeControlFrame(f);
  c.onDatagram(b.data(), b.size(), t);
}
}  // namespace

TEST(SensorConfigurator, GivenAConfiguredIpThenItSendsHostPortsAndWorkModeAndRetriesUntilAcked) {
  SensorConfigurator c(params(false));
  EXPECT_EQ(c.state(), SensorConfigurator::State::kConfiguring);
  auto out = c.poll(100.0);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].ip, (std::array<uint8_t, 4>{127, 0, 0, 2}));
  EXPECT_EQ(out[0].port, 57091);
  const auto req = decode(out[0]);
  auto kvs = livox::parseSetKeyValueRequest(req);
  ASSERT_TRUE(kvs);
  ASSERT_EQ(kvs->size(), 4u);
  const auto pts = livox::parseHostIpConfig((*kvs)[0]);
  ASSERT_TRUE(pts);
  EXPECT_EQ((*kvs)[0].key, static_cast<uint16_t>(livox::Key::kPointDataHostIpConfig));
  EXPECT_EQ(pts->host_ip, (std::array<uint8_t, 4>{127, 0, 0, 1}));
  EXPECT_EQ(pts->host_port, 57092);
  EXPECT_EQ(livox::parseHostIpConfig((*kvs)[1])->host_port, 57093);
  EXPECT_EQ((*kvs)[2].key, static_cast<uint16_t>(livox::Key::kImuDataEnable));
  EXPECT_EQ(livox::parseWorkMode((*kvs)[3]), std::optional<uint8_t>(0x01));

  EXPECT_TRUE(c.poll(100.2).empty());   // before the retry interval
  auto again = c.poll(100.5);           // retry with the same request
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].bytes, out[0].bytes);

  deliver(c, livox::makeSetKeyValueAck(req.seq + 1, {}), 100.6);  // wrong seq: ignored
  EXPECT_EQ(c.state(), SensorConfigurator::State::kConfiguring);
  EXPECT_EQ(c.ignoredDatagrams(), 1);
  const uint8_t junk[5] = {1, 2, 3, 4, 5};
  c.onDatagram(junk, sizeof(junk), 100.6);
  EXPECT_EQ(c.ignoredDatagrams(), 2);
  deliver(c, livox::makeSetKeyValueAck(req.seq, {}), 100.7);
  EXPECT_EQ(c.state(), SensorConfigurator::State::kDone);
  EXPECT_TRUE(c.poll(101.0).empty());
  EXPECT_EQ(c.requestsSent(), 2);
}

TEST(SensorConfigurator, GivenDiscoveryThenTheAckedAddressAndPortAreConfigured) {
  SensorConfigurator c(params(true));
  EXPECT_EQ(c.state(), SensorConfigurator::State::kDiscovering);
  auto out = c.poll(0.0);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].ip, (std::array<uint8_t, 4>{127, 0, 0, 255}));
  EXPECT_EQ(out[0].port, 57090);
  const auto req = decode(out[0]);
  EXPECT_EQ(req.cmd_id, static_cast<uint16_t>(livox::CommandId::kDiscovery));
  livox::DiscoveryInfo info;
  info.serial = "SIM0000000001";
  info.lidar_ip = {10, 1, 2, 3};
  info.cmd_port = 57095;
  deliver(c, livox::makeDiscoveryAck(req.seq, info), 0.1);
  EXPECT_EQ(c.state(), SensorConfigurator::State::kConfiguring);
  EXPECT_EQ(c.serial(), "SIM0000000001");
  out = c.poll(0.1);  // configuration goes out at once, to the discovered sensor
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].ip, info.lidar_ip);
  EXPECT_EQ(out[0].port, 57095);
  EXPECT_TRUE(livox::parseSetKeyValueRequest(decode(out[0])));
}

TEST(SensorConfigurator, GivenNoAnswerThenItFailsAtTheTimeoutNamingTheSensorAndWhatToCheck) {
  SensorConfigurator c(params(false));
  int sent = 0;
  for (double t = 0; t < 1.99; t += 0.05) sent += static_cast<int>(c.poll(t).size());
  EXPECT_EQ(c.state(), SensorConfigurator::State::kConfiguring);
  EXPECT_EQ(sent, 4);  // t = 0, 0.5, 1.0, 1.5
  c.poll(2.0);
  ASSERT_EQ(c.state(), SensorConfigurator::State::kFailed);
  const std::string& m = c.failure();
  EXPECT_NE(m.find("127.0.0.2:57091"), std::string::npos) << m;
  EXPECT_NE(m.find("sensor_ip"), std::string::npos) << m;
  EXPECT_NE(m.find("firewall"), std::string::npos) << m;
  EXPECT_NE(m.find("2.0 s"), std::string::npos) << m;

  SensorConfigurator d(params(true));
  d.poll(0.0);
  d.poll(2.5);
  ASSERT_EQ(d.state(), SensorConfigurator::State::kFailed);
  EXPECT_NE(d.failure().find("discovery request sent to 127.0.0.255:57090"), std::string::npos) << d.failure();
}

TEST(SensorConfigurator, GivenARejectingAckThenItFailsNamingTheKey) {
  SensorConfigurator c(params(false));
  const auto req = decode(c.poll(0.0).at(0));
  deliver(c, livox::makeSetKeyValueAck(req.seq, livox::SetKeyValueAck{2, 0x0006}), 0.1);
  ASSERT_EQ(c.state(), SensorConfigurator::State::kFailed);
  EXPECT_NE(c.failure().find("0x0006"), std::string::npos) << c.failure();
}
