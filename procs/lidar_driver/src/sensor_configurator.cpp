#include "ucon/lidar_driver/sensor_configurator.hpp"

#include <algorithm>
#include <cstdio>

namespace ucon {
namespace lidar_driver {

using livox::ControlFrame;
using livox::Key;
using Phase = SensorControlState::Phase;

namespace {
enum StepId { kHostConfig, kDataType, kPattern, kAttitude, kImuEnable, kWorkMode, kQueryInfo };

std::string hex4(unsigned v) {
  char b[8];
  std::snprintf(b, sizeof(b), "0x%04X", v & 0xFFFFu);
  return b;
}
}  // namespace

const char* toString(Phase p) {
  switch (p) {
    case Phase::kDiscovering: return "discovering";
    case Phase::kConfiguring: return "configuring";
    case Phase::kDone: return "done";
  }
  return "unknown";
}

SensorConfigurator::SensorConfigurator(const DriverParams& params, bool query_info)
    : params_(params) {
  // The order of StepId; optional steps are skipped (with a warning) when the sensor rejects
  // them or (the info query) does not answer.
  steps_ = {{"host IP/ports for state, points and IMU (keys 0x0005-0x0007)", false, 0},
            {"point data type (key 0x0000)", false, 0},
            {"scan pattern non-repetitive (key 0x0001)", true, 3},
            {"install attitude zero (key 0x0012)", true, 3},
            {"IMU on/off (key 0x001C)", false, 0},
            {"work mode (key 0x001A)", false, 0}};
  if (query_info) steps_.push_back({"serial and firmware query (0x0101)", true, 3});
  host_ip_ = livox::parseIpv4(params_.network.host_ip).value_or(std::array<uint8_t, 4>{});
  for (const SensorParams& sp : params_.sensors) {
    SensorControlState s;
    s.ip_known = !sp.isAuto();
    if (s.ip_known) s.ip = *livox::parseIpv4(sp.ip);
    s.command_port = static_cast<uint16_t>(params_.network.sensor_command_port);
    s.phase = params_.network.discovery ? Phase::kDiscovering : Phase::kConfiguring;
    sensors_.push_back(s);
  }
  step_state_.assign(sensors_.size(), std::vector<StepState>(steps_.size()));
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    if (sensors_[i].phase == Phase::kConfiguring) beginConfiguring(i, 0.0);
  }
}

void SensorConfigurator::beginConfiguring(std::size_t i, double t_s) {
  SensorControlState& s = sensors_[i];
  s.phase = Phase::kConfiguring;
  s.step = 0;
  s.attempts = 0;
  s.last_rejection.clear();
  s.step_done.assign(steps_.size(), false);
  for (StepState& st : step_state_[i]) st = StepState{{}, 0, t_s, {}};
}

std::vector<int> SensorConfigurator::openSteps(std::size_t i) const {
  const SensorControlState& s = sensors_[i];
  std::vector<int> open;
  if (s.phase != Phase::kConfiguring) return open;
  if (!s.step_done[0]) return {0};
  for (int k = 1; k < stepCount(); ++k) {
    if (!s.step_done[static_cast<std::size_t>(k)]) open.push_back(k);
  }
  return open;
}

const char* SensorConfigurator::stepName(int step) const {
  return step >= 0 && step < stepCount() ? steps_[static_cast<std::size_t>(step)].name : "done";
}

int SensorConfigurator::indexOf(const std::array<uint8_t, 4>& ip) const {
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    if (sensors_[i].ip_known && sensors_[i].ip == ip) return static_cast<int>(i);
  }
  return -1;
}

bool SensorConfigurator::allDone() const {
  return std::all_of(sensors_.begin(), sensors_.end(),
                     [](const SensorControlState& s) { return s.phase == Phase::kDone; });
}

std::vector<std::string> SensorConfigurator::takeWarnings() {
  std::vector<std::string> w;
  w.swap(warnings_);
  return w;
}

ControlFrame SensorConfigurator::request(std::size_t i, int step) {
  const NetworkParams& n = params_.network;
  const ControlParams& c = params_.control;
  const SensorParams& sp = params_.sensors[i];
  const uint32_t seq = seq_++;
  switch (step) {
    case kHostConfig: {
      const auto cfg = [&](Key key, int host_port, int lidar_port) {
        return livox::makeHostIpConfig(key, livox::HostIpConfig{host_ip_,
                                                                static_cast<uint16_t>(host_port),
                                                                static_cast<uint16_t>(lidar_port)});
      };
      return livox::makeSetKeyValueRequest(
          seq, {cfg(Key::kStateInfoHostIpConfig, n.host_push_port, n.sensor_push_port),
                cfg(Key::kPointDataHostIpConfig, n.host_point_port, n.sensor_point_port),
                cfg(Key::kImuDataHostIpConfig, n.host_imu_port, n.sensor_imu_port)});
    }
    case kDataType:
      return livox::makeSetKeyValueRequest(
          seq, {livox::makeUint8(Key::kPointDataType, static_cast<uint8_t>(c.point_data_type))});
    case kPattern:
      return livox::makeSetKeyValueRequest(seq, {livox::makeUint8(Key::kPatternMode, 0)});
    case kAttitude:
      return livox::makeSetKeyValueRequest(seq, {livox::makeInstallAttitude(0, 0, 0, 0, 0, 0)});
    case kImuEnable:
      return livox::makeSetKeyValueRequest(
          seq, {livox::makeUint8(Key::kImuDataEnable, sp.imu ? 1 : 0)});
    case kWorkMode:
      return livox::makeSetKeyValueRequest(
          seq, {livox::makeWorkMode(c.work_mode == "idle" ? livox::WorkMode::kIdle
                                                          : livox::WorkMode::kSampling)});
    default:
      return livox::makeQueryRequest(
          seq, {static_cast<uint16_t>(Key::kSerialNumber), static_cast<uint16_t>(Key::kFirmwareVersion),
                static_cast<uint16_t>(Key::kTimeSyncType)});
  }
}

std::string SensorConfigurator::describe(std::size_t i) const {
  const SensorControlState& s = sensors_[i];
  std::string d = "sensor " + std::to_string(i) + " (";
  d += s.ip_known ? livox::formatIpv4(s.ip) : std::string("auto: the first Mid-360 to answer");
  if (!s.serial.empty()) d += ", serial " + s.serial;
  return d + ")";
}

std::string SensorConfigurator::waitingFor() const {
  const NetworkParams& n = params_.network;
  std::string out;
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    const SensorControlState& s = sensors_[i];
    if (s.phase == Phase::kDone) continue;
    if (!out.empty()) out += "; ";
    out += describe(i) + ": ";
    if (s.phase == Phase::kDiscovering) {
      out += "no discovery answer yet (" + std::to_string(discovery_requests_) +
             " requests broadcast to " + n.discovery_address + ":" + std::to_string(n.discovery_port) +
             " from " + n.host_ip + ", answers awaited on 0.0.0.0:" + std::to_string(n.discovery_port) +
             ")";
    } else {
      std::string names, rejected;
      int attempts = 0;
      for (int k : openSteps(i)) {
        const StepState& st = step_state_[i][static_cast<std::size_t>(k)];
        names += (names.empty() ? "'" : ", '") + std::string(stepName(k)) + "'";
        attempts = std::max(attempts, st.attempts);
        if (!st.rejection.empty()) rejected += (rejected.empty() ? "" : ", ") + st.rejection;
      }
      out += "no ack to " + names + " after " + std::to_string(attempts) + " requests to " +
             livox::formatIpv4(s.ip) + ":" + std::to_string(s.command_port);
      if (!rejected.empty()) out += " (the sensor rejected: " + rejected + ")";
    }
  }
  return out;
}

void SensorConfigurator::fail(double t_s) {
  failed_ = true;
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.1f s", t_s - start_s_);
  const NetworkParams& n = params_.network;
  failure_ = "not every Mid-360 is configured after " + std::string(buf) + " (control.timeout_s): " +
             waitingFor() + ". Check: each sensor is powered and cabled; the host has an address in "
             "the sensors' subnet (network.host_ip = " + n.host_ip + "); sensors[].ip are the "
             "sensors' addresses (factory 192.168.1.1XX, XX = the serial's last two digits); no "
             "firewall drops UDP ports " + std::to_string(n.discovery_port) + "-" +
             std::to_string(n.host_imu_port + 100) + ". ucon-lidar-driver --check lists what answers. In "
             "simulation: is ucon-simulator running with the same ports?";
}

std::vector<OutgoingDatagram> SensorConfigurator::poll(double t_s) {
  std::vector<OutgoingDatagram> out;
  if (start_s_ < 0) {
    start_s_ = t_s;
    next_discovery_s_ = t_s;
    for (auto& v : step_state_) {
      for (StepState& st : v) st.next_send_s = std::min(st.next_send_s, t_s);
    }
  }
  if (failed_ || allDone()) return out;
  if (params_.control.timeout_s > 0.0 && t_s - start_s_ >= params_.control.timeout_s) {
    fail(t_s);
    return out;
  }
  const double retry = params_.control.retry_interval_s;
  const bool discovering = std::any_of(sensors_.begin(), sensors_.end(), [](const SensorControlState& s) {
    return s.phase == Phase::kDiscovering;
  });
  if (discovering && t_s >= next_discovery_s_) {
    OutgoingDatagram d;
    d.via = OutgoingDatagram::Via::kDiscovery;
    d.ip = livox::parseIpv4(params_.network.discovery_address).value_or(std::array<uint8_t, 4>{});
    d.port = static_cast<uint16_t>(params_.network.discovery_port);
    d.bytes = livox::encodeControlFrame(livox::makeDiscoveryRequest(seq_++));
    out.push_back(std::move(d));
    ++discovery_requests_;
    ++requests_sent_;
    for (auto& s : sensors_) {
      if (s.phase == Phase::kDiscovering) ++s.attempts;
    }
    next_discovery_s_ = t_s + retry;
  }
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    SensorControlState& s = sensors_[i];
    for (int k : openSteps(i)) {
      StepState& ss = step_state_[i][static_cast<std::size_t>(k)];
      if (t_s < ss.next_send_s) continue;
      const Step& st = steps_[static_cast<std::size_t>(k)];
      if (st.max_attempts > 0 && ss.attempts >= st.max_attempts) {
        warnings_.push_back(describe(i) + ": no answer to '" + st.name + "' after " +
                            std::to_string(ss.attempts) + " requests; going on without it");
        finishStep(i, k, t_s);
        continue;
      }
      // A retry goes with a new seq, like Livox's SDK; an ack to any of them counts.
      const ControlFrame req = request(i, k);
      OutgoingDatagram d;
      d.via = OutgoingDatagram::Via::kCommand;
      d.ip = s.ip;
      d.port = s.command_port;
      d.bytes = livox::encodeControlFrame(req);
      ss.seqs.push_back(req.seq);
      out.push_back(std::move(d));
      ++ss.attempts;
      ++requests_sent_;
      ss.next_send_s = t_s + retry;
    }
    const auto open = openSteps(i);
    s.attempts = open.empty() ? 0 : step_state_[i][static_cast<std::size_t>(open.front())].attempts;
  }
  return out;
}

void SensorConfigurator::finishStep(std::size_t i, int step, double t_s) {
  SensorControlState& s = sensors_[i];
  s.step_done[static_cast<std::size_t>(step)] = true;
  step_state_[i][static_cast<std::size_t>(step)].rejection.clear();
  if (step == kHostConfig) {
    for (StepState& st : step_state_[i]) st.next_send_s = t_s;  // the others right away
  }
  const auto open = openSteps(i);
  s.step = open.empty() ? stepCount() : open.front();
  if (open.empty()) {
    s.phase = Phase::kDone;
    ++s.configured_count;
  }
}

void SensorConfigurator::restart(std::size_t i, double t_s) {
  if (i >= sensors_.size()) return;
  if (params_.network.discovery) {
    sensors_[i].phase = Phase::kDiscovering;
    sensors_[i].attempts = 0;
    next_discovery_s_ = std::min(next_discovery_s_, t_s);
  } else {
    beginConfiguring(i, t_s);
  }
  // A reconfiguration is new: the timeout counts from here.
  if (start_s_ >= 0) start_s_ = t_s;
}

void SensorConfigurator::onDiscoveryDatagram(const std::array<uint8_t, 4>& src, const uint8_t* data,
                                             std::size_t size, double t_s) {
  ControlFrame f;
  if (livox::decodeControlFrame(data, size, f) != livox::ControlStatus::kOk) {
    ++ignored_;
    return;
  }
  const auto info = livox::parseDiscoveryAck(f);
  if (!info || f.sender != static_cast<uint8_t>(livox::Sender::kLidar)) {
    ++ignored_;  // our own broadcast request comes back here; so do other hosts' requests
    return;
  }
  if (info->ret_code != 0 || info->dev_type != livox::kDeviceTypeMid360) {
    ++ignored_;
    return;
  }
  // The sensor is known by the address its answer comes from (as Livox's SDK does); the IP in
  // the answer's payload is the same on a Mid-360.
  int idx = indexOf(src);
  if (idx < 0) {
    for (std::size_t i = 0; i < sensors_.size(); ++i) {
      if (!sensors_[i].ip_known) {
        sensors_[i].ip_known = true;
        sensors_[i].ip = src;
        idx = static_cast<int>(i);
        break;
      }
    }
  }
  if (idx < 0) {
    if (std::find(unlisted_seen_.begin(), unlisted_seen_.end(), src) == unlisted_seen_.end()) {
      unlisted_seen_.push_back(src);
      warnings_.push_back("a Mid-360 at " + livox::formatIpv4(src) + " (serial " + info->serial +
                          ") answered discovery but is not in sensors[]: ignored");
    }
    return;
  }
  SensorControlState& s = sensors_[static_cast<std::size_t>(idx)];
  s.serial = info->serial;
  if (s.phase != Phase::kDiscovering) return;  // a later answer to a repeated broadcast
  if (info->cmd_port != 0) s.command_port = info->cmd_port;
  beginConfiguring(static_cast<std::size_t>(idx), t_s);  // configure right away
}

void SensorConfigurator::onCommandDatagram(const std::array<uint8_t, 4>& src, const uint8_t* data,
                                           std::size_t size, double t_s) {
  ControlFrame f;
  const int idx = indexOf(src);
  if (idx < 0 || livox::decodeControlFrame(data, size, f) != livox::ControlStatus::kOk) {
    ++ignored_;
    return;
  }
  const std::size_t i = static_cast<std::size_t>(idx);
  SensorControlState& s = sensors_[i];
  // The ack of any attempt at an open step (a slow answer to an earlier one counts too).
  int step = -1;
  if (f.cmd_type == static_cast<uint8_t>(livox::CommandType::kAck)) {
    for (int k : openSteps(i)) {
      const auto& seqs = step_state_[i][static_cast<std::size_t>(k)].seqs;
      if (std::find(seqs.begin(), seqs.end(), f.seq) != seqs.end()) step = k;
    }
  }
  const uint16_t expected_cmd = static_cast<uint16_t>(step == kQueryInfo ? livox::CommandId::kQuery
                                                                         : livox::CommandId::kSetKeyValue);
  if (step < 0 || f.cmd_id != expected_cmd) {
    ++ignored_;
    return;
  }
  const Step& st = steps_[static_cast<std::size_t>(step)];
  if (step == kQueryInfo) {
    const auto ack = livox::parseQueryAck(f);
    if (!ack) {
      ++ignored_;
      return;
    }
    if (const auto* sn = livox::findKey(ack->values, Key::kSerialNumber)) {
      std::string serial(sn->value.begin(), sn->value.end());
      serial = serial.substr(0, serial.find('\0'));
      if (!serial.empty()) s.serial = serial;
    }
    if (const auto* fw = livox::findKey(ack->values, Key::kFirmwareVersion); fw && fw->value.size() == 4) {
      s.firmware = std::to_string(fw->value[0]) + "." + std::to_string(fw->value[1]) + "." +
                   std::to_string(fw->value[2]) + "." + std::to_string(fw->value[3]);
    }
    if (const auto* ts = livox::findKey(ack->values, Key::kTimeSyncType); ts && ts->value.size() == 1) {
      s.time_sync_type = ts->value[0];
    }
    finishStep(i, step, t_s);
    return;
  }
  const auto ack = livox::parseSetKeyValueAck(f);
  if (!ack) {
    ++ignored_;
    return;
  }
  if (ack->ret_code != 0) {
    s.last_rejection = "ret_code " + std::to_string(ack->ret_code) + " for key " + hex4(ack->error_key);
    step_state_[i][static_cast<std::size_t>(step)].rejection = s.last_rejection;
    if (st.optional) {
      warnings_.push_back(describe(i) + " rejected '" + st.name + "' (" + s.last_rejection +
                          "); going on without it");
      finishStep(i, step, t_s);
    } else {
      warnings_.push_back(describe(i) + " rejected '" + st.name + "' (" + s.last_rejection +
                          "); retrying every " + std::to_string(params_.control.retry_interval_s) + " s");
    }
    return;
  }
  finishStep(i, step, t_s);
}

void SensorConfigurator::onPushDatagram(const std::array<uint8_t, 4>& src, const uint8_t* data,
                                        std::size_t size) {
  ControlFrame f;
  const int idx = indexOf(src);
  if (idx < 0 || livox::decodeControlFrame(data, size, f) != livox::ControlStatus::kOk) {
    ++ignored_;
    return;
  }
  const auto kvs = livox::parsePushMessage(f);
  if (!kvs) {
    ++ignored_;
    return;
  }
  if (const auto* ts = livox::findKey(*kvs, Key::kTimeSyncType); ts && ts->value.size() == 1) {
    sensors_[static_cast<std::size_t>(idx)].time_sync_type = ts->value[0];
  }
}

}  // namespace lidar_driver
}  // namespace ucon
