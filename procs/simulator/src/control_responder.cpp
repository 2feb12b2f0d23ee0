#include "ucon/simulator/control_responder.hpp"

namespace ucon {
namespace simulator {

using livox::CommandId;
using livox::CommandType;
using livox::ControlFrame;
using livox::Key;

ControlResponder::ControlResponder(SensorState initial, std::array<uint8_t, 4> sensor_ip,
                                   uint16_t command_port, std::string serial)
    : state_(initial), sensor_ip_(sensor_ip), command_port_(command_port), serial_(std::move(serial)) {}

std::optional<std::vector<uint8_t>> ControlResponder::handle(const uint8_t* data, std::size_t size) {
  ControlFrame req;
  if (livox::decodeControlFrame(data, size, req) != livox::ControlStatus::kOk ||
      req.cmd_type != static_cast<uint8_t>(CommandType::kRequest)) {
    ++counters_.malformed;
    return std::nullopt;
  }
  ControlFrame ack;
  switch (static_cast<CommandId>(req.cmd_id)) {
    case CommandId::kDiscovery: {
      livox::DiscoveryInfo info;
      info.ret_code = 0;
      info.dev_type = livox::kDeviceTypeMid360;
      info.serial = serial_;
      info.lidar_ip = sensor_ip_;
      info.cmd_port = command_port_;
      ack = livox::makeDiscoveryAck(req.seq, info);
      break;
    }
    case CommandId::kSetKeyValue:
      ack = handleSet(req);
      break;
    default: {
      // Query, push, reboot: not emulated. Ack with a non-zero return code so a driver that
      // sends them learns it at once instead of timing out.
      ++counters_.unsupported;
      ack.seq = req.seq;
      ack.cmd_id = req.cmd_id;
      ack.cmd_type = static_cast<uint8_t>(CommandType::kAck);
      ack.sender = static_cast<uint8_t>(livox::Sender::kLidar);
      ack.data = {1};
      return livox::encodeControlFrame(ack);
    }
  }
  ++counters_.requests;
  return livox::encodeControlFrame(ack);
}

ControlFrame ControlResponder::handleSet(const ControlFrame& req) {
  livox::SetKeyValueAck result;
  const auto kvs = livox::parseSetKeyValueRequest(req);
  if (!kvs) {
    result.ret_code = 1;
    ++counters_.rejected_keys;
    return livox::makeSetKeyValueAck(req.seq, result);
  }
  SensorState next = state_;
  for (const auto& kv : *kvs) {
    bool ok = true;
    switch (static_cast<Key>(kv.key)) {
      case Key::kPointDataHostIpConfig: {
        const auto c = livox::parseHostIpConfig(kv);
        ok = c.has_value() && c->host_port != 0;
        if (ok) {
          next.point_host_ip = c->host_ip;
          next.point_host_port = c->host_port;
        }
        break;
      }
      case Key::kImuDataHostIpConfig: {
        const auto c = livox::parseHostIpConfig(kv);
        ok = c.has_value() && c->host_port != 0;
        if (ok) {
          next.imu_host_ip = c->host_ip;
          next.imu_host_port = c->host_port;
        }
        break;
      }
      case Key::kStateInfoHostIpConfig:
        ok = livox::parseHostIpConfig(kv).has_value();  // push messages are not emulated
        break;
      case Key::kWorkMode: {
        const auto m = livox::parseWorkMode(kv);
        ok = m.has_value() && *m >= 0x01 && *m <= 0x03;
        if (ok) next.work_mode = *m;
        break;
      }
      case Key::kPointDataType:
        ok = kv.value.size() == 1 && kv.value[0] >= 1 && kv.value[0] <= 3;
        if (ok) next.data_type = kv.value[0];
        break;
      case Key::kImuDataEnable:
        ok = kv.value.size() == 1 && kv.value[0] <= 1;
        if (ok) next.imu_enabled = kv.value[0] == 1;
        break;
      case Key::kLidarIpConfig:
        ok = kv.value.size() == 12;  // accepted, the emulator keeps its address
        break;
      case Key::kInstallAttitude:
        ok = kv.value.size() == 24;  // accepted; the emulator reports raw sensor-frame points
        break;
      default:
        ok = false;
    }
    if (!ok) {
      // Like the sensor: the whole command fails and names the first bad key.
      result.ret_code = 1;
      result.error_key = kv.key;
      ++counters_.rejected_keys;
      return livox::makeSetKeyValueAck(req.seq, result);
    }
  }
  state_ = next;
  ++generation_;
  return livox::makeSetKeyValueAck(req.seq, result);
}

}  // namespace simulator
}  // namespace ucon
