#include "ucon/simulator/control_responder.hpp"

#include <algorithm>

namespace ucon {
namespace simulator {

using livox::CommandId;
using livox::CommandType;
using livox::ControlFrame;
using livox::Key;

ControlResponder::ControlResponder(SensorState initial, std::array<uint8_t, 4> sensor_ip,
                                   uint16_t command_port, std::string serial)
    : state_(initial), sensor_ip_(sensor_ip), command_port_(command_port), serial_(std::move(serial)) {}

std::optional<std::vector<uint8_t>> ControlResponder::handle(const uint8_t* data, std::size_t size,
                                                            bool* broadcast) {
  if (broadcast) *broadcast = false;
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
      if (broadcast) *broadcast = true;
      break;
    }
    case CommandId::kSetKeyValue:
      ack = handleSet(req);
      break;
    case CommandId::kQuery: {
      livox::QueryAck q;
      const auto keys = livox::parseQueryRequest(req);
      if (!keys) {
        q.ret_code = 1;
      } else {
        for (uint16_t k : *keys) {
          livox::KeyValue kv{k, {}};
          switch (static_cast<Key>(k)) {
            case Key::kSerialNumber:
              kv.value.assign(16, 0);
              std::copy(serial_.begin(), serial_.begin() + static_cast<std::ptrdiff_t>(std::min<std::size_t>(16, serial_.size())),
                        kv.value.begin());
              break;
            case Key::kFirmwareVersion: kv.value = {0, 0, 0, 1}; break;  // "0.0.0.1": an emulator
            case Key::kCurrentWorkState: kv.value = {state_.work_mode}; break;
            case Key::kTimeSyncType: kv.value = {0}; break;  // never synchronised
            case Key::kPointDataType: kv.value = {state_.data_type}; break;
            case Key::kPatternMode: kv.value = {state_.pattern_mode}; break;
            default: continue;  // not emulated: left out of the answer
          }
          q.values.push_back(std::move(kv));
        }
      }
      ack = livox::makeQueryAck(req.seq, q);
      break;
    }
    default: {
      // Push (sensor to host only), reboot, upgrade: not emulated. Ack with a non-zero return code so a driver that
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
      case Key::kStateInfoHostIpConfig: {
        const auto c = livox::parseHostIpConfig(kv);  // kept; push messages are not emulated
        ok = c.has_value();
        if (ok) {
          next.push_host_ip = c->host_ip;
          next.push_host_port = c->host_port;
        }
        break;
      }
      case Key::kWorkMode: {
        // A Mid-360 is set to 0x01 (sampling) or 0x02 (idle) only; 0x03 is not one of its states.
        const auto m = livox::parseWorkMode(kv);
        ok = m.has_value() && livox::isSettableWorkMode(*m);
        if (ok) next.work_mode = *m;
        break;
      }
      case Key::kPatternMode:
        ok = kv.value.size() == 1 && kv.value[0] <= 2;
        if (ok) next.pattern_mode = kv.value[0];
        break;
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
