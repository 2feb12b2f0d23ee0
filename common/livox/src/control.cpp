#include "ucon/livox/control.hpp"

#include <cstdio>

#include "le.hpp"
#include "ucon/livox/crc.hpp"

namespace ucon {
namespace livox {

const char* toString(ControlStatus status) {
  switch (status) {
    case ControlStatus::kOk: return "ok";
    case ControlStatus::kTruncated: return "truncated";
    case ControlStatus::kBadSof: return "bad_sof";
    case ControlStatus::kBadVersion: return "bad_version";
    case ControlStatus::kBadLength: return "bad_length";
    case ControlStatus::kBadHeaderCrc: return "bad_header_crc";
    case ControlStatus::kBadDataCrc: return "bad_data_crc";
    case ControlStatus::kTooLarge: return "too_large";
  }
  return "unknown";
}

std::vector<uint8_t> encodeControlFrame(const ControlFrame& f) {
  const std::size_t total = kControlHeaderSize + f.data.size();
  if (total > 0xFFFF) return {};
  std::vector<uint8_t> b(total, 0);
  b[0] = kControlSof;
  b[1] = f.version;
  le::store<uint16_t>(&b[2], static_cast<uint16_t>(total));
  le::store<uint32_t>(&b[4], f.seq);
  le::store<uint16_t>(&b[8], f.cmd_id);
  b[10] = f.cmd_type;
  b[11] = f.sender;
  // bytes 12-17 reserved (0)
  le::store<uint16_t>(&b[18], crc16CcittFalse(b.data(), 18));
  if (!f.data.empty()) std::memcpy(&b[kControlHeaderSize], f.data.data(), f.data.size());
  le::store<uint32_t>(&b[20], crc32(f.data.data(), f.data.size()));
  return b;
}

ControlStatus decodeControlFrame(const uint8_t* bytes, std::size_t size, ControlFrame& out) {
  if (bytes == nullptr || size < kControlHeaderSize) return ControlStatus::kTruncated;
  if (bytes[0] != kControlSof) return ControlStatus::kBadSof;
  if (bytes[1] != 0) return ControlStatus::kBadVersion;
  if (le::load<uint16_t>(bytes + 2) != size) return ControlStatus::kBadLength;
  if (le::load<uint16_t>(bytes + 18) != crc16CcittFalse(bytes, 18)) {
    return ControlStatus::kBadHeaderCrc;
  }
  const uint8_t* d = bytes + kControlHeaderSize;
  const std::size_t n = size - kControlHeaderSize;
  if (le::load<uint32_t>(bytes + 20) != crc32(d, n)) return ControlStatus::kBadDataCrc;
  out.version = bytes[1];
  out.seq = le::load<uint32_t>(bytes + 4);
  out.cmd_id = le::load<uint16_t>(bytes + 8);
  out.cmd_type = bytes[10];
  out.sender = bytes[11];
  out.data.assign(d, d + n);
  return ControlStatus::kOk;
}

bool operator==(const KeyValue& a, const KeyValue& b) {
  return a.key == b.key && a.value == b.value;
}

std::vector<uint8_t> encodeKeyValueList(const std::vector<KeyValue>& kvs) {
  std::vector<uint8_t> out(4, 0);
  le::store<uint16_t>(out.data(), static_cast<uint16_t>(kvs.size()));
  for (const KeyValue& kv : kvs) {
    const std::size_t at = out.size();
    out.resize(at + 4 + kv.value.size());
    le::store<uint16_t>(&out[at], kv.key);
    le::store<uint16_t>(&out[at + 2], static_cast<uint16_t>(kv.value.size()));
    if (!kv.value.empty()) std::memcpy(&out[at + 4], kv.value.data(), kv.value.size());
  }
  return out;
}

std::optional<std::vector<KeyValue>> decodeKeyValueList(const std::vector<uint8_t>& data) {
  if (data.size() < 4) return std::nullopt;
  const uint16_t count = le::load<uint16_t>(data.data());
  std::size_t at = 4;
  std::vector<KeyValue> kvs;
  kvs.reserve(count);
  for (uint16_t i = 0; i < count; ++i) {
    if (at + 4 > data.size()) return std::nullopt;
    KeyValue kv;
    kv.key = le::load<uint16_t>(&data[at]);
    const uint16_t len = le::load<uint16_t>(&data[at + 2]);
    at += 4;
    if (at + len > data.size()) return std::nullopt;
    kv.value.assign(data.begin() + static_cast<std::ptrdiff_t>(at),
                    data.begin() + static_cast<std::ptrdiff_t>(at + len));
    at += len;
    kvs.push_back(std::move(kv));
  }
  if (at != data.size()) return std::nullopt;
  return kvs;
}

KeyValue makeHostIpConfig(Key key, const HostIpConfig& cfg) {
  KeyValue kv;
  kv.key = static_cast<uint16_t>(key);
  kv.value.resize(8);
  std::memcpy(kv.value.data(), cfg.host_ip.data(), 4);
  le::store<uint16_t>(&kv.value[4], cfg.host_port);
  le::store<uint16_t>(&kv.value[6], cfg.lidar_port);
  return kv;
}

std::optional<HostIpConfig> parseHostIpConfig(const KeyValue& kv) {
  if (kv.value.size() != 8) return std::nullopt;
  HostIpConfig c;
  std::memcpy(c.host_ip.data(), kv.value.data(), 4);
  c.host_port = le::load<uint16_t>(&kv.value[4]);
  c.lidar_port = le::load<uint16_t>(&kv.value[6]);
  return c;
}

KeyValue makeWorkMode(WorkMode mode) {
  return KeyValue{static_cast<uint16_t>(Key::kWorkMode), {static_cast<uint8_t>(mode)}};
}

bool isSettableWorkMode(uint8_t mode) {
  return mode == static_cast<uint8_t>(WorkMode::kSampling) ||
         mode == static_cast<uint8_t>(WorkMode::kIdle);
}

KeyValue makeUint8(Key key, uint8_t value) { return KeyValue{static_cast<uint16_t>(key), {value}}; }

KeyValue makeInstallAttitude(float roll_deg, float pitch_deg, float yaw_deg, int32_t x_mm,
                             int32_t y_mm, int32_t z_mm) {
  KeyValue kv;
  kv.key = static_cast<uint16_t>(Key::kInstallAttitude);
  kv.value.resize(24);
  le::store(&kv.value[0], roll_deg);
  le::store(&kv.value[4], pitch_deg);
  le::store(&kv.value[8], yaw_deg);
  le::store(&kv.value[12], x_mm);
  le::store(&kv.value[16], y_mm);
  le::store(&kv.value[20], z_mm);
  return kv;
}

const KeyValue* findKey(const std::vector<KeyValue>& kvs, Key key) {
  for (const KeyValue& kv : kvs) {
    if (kv.key == static_cast<uint16_t>(key)) return &kv;
  }
  return nullptr;
}

std::optional<uint8_t> parseWorkMode(const KeyValue& kv) {
  if (kv.value.size() != 1) return std::nullopt;
  return kv.value[0];
}

namespace {
ControlFrame makeFrame(uint32_t seq, CommandId id, CommandType type, Sender sender,
                       std::vector<uint8_t> data) {
  ControlFrame f;
  f.seq = seq;
  f.cmd_id = static_cast<uint16_t>(id);
  f.cmd_type = static_cast<uint8_t>(type);
  f.sender = static_cast<uint8_t>(sender);
  f.data = std::move(data);
  return f;
}
bool is(const ControlFrame& f, CommandId id, CommandType type) {
  return f.cmd_id == static_cast<uint16_t>(id) && f.cmd_type == static_cast<uint8_t>(type);
}
}  // namespace

ControlFrame makeDiscoveryRequest(uint32_t seq) {
  return makeFrame(seq, CommandId::kDiscovery, CommandType::kRequest, Sender::kHost, {});
}

ControlFrame makeDiscoveryAck(uint32_t seq, const DiscoveryInfo& info) {
  std::vector<uint8_t> d(24, 0);
  d[0] = info.ret_code;
  d[1] = info.dev_type;
  const std::size_t n = info.serial.size() < 16 ? info.serial.size() : 16;
  std::memcpy(&d[2], info.serial.data(), n);
  std::memcpy(&d[18], info.lidar_ip.data(), 4);
  le::store<uint16_t>(&d[22], info.cmd_port);
  return makeFrame(seq, CommandId::kDiscovery, CommandType::kAck, Sender::kLidar, std::move(d));
}

ControlFrame makeSetKeyValueRequest(uint32_t seq, const std::vector<KeyValue>& kvs) {
  return makeFrame(seq, CommandId::kSetKeyValue, CommandType::kRequest, Sender::kHost,
                   encodeKeyValueList(kvs));
}

ControlFrame makeSetKeyValueAck(uint32_t seq, const SetKeyValueAck& ack) {
  std::vector<uint8_t> d(3, 0);
  d[0] = ack.ret_code;
  le::store<uint16_t>(&d[1], ack.error_key);
  return makeFrame(seq, CommandId::kSetKeyValue, CommandType::kAck, Sender::kLidar, std::move(d));
}

ControlFrame makeQueryRequest(uint32_t seq, const std::vector<uint16_t>& keys) {
  std::vector<uint8_t> d(4 + 2 * keys.size(), 0);
  le::store<uint16_t>(d.data(), static_cast<uint16_t>(keys.size()));
  for (std::size_t i = 0; i < keys.size(); ++i) le::store<uint16_t>(&d[4 + 2 * i], keys[i]);
  return makeFrame(seq, CommandId::kQuery, CommandType::kRequest, Sender::kHost, std::move(d));
}

ControlFrame makeQueryAck(uint32_t seq, const QueryAck& ack) {
  // The same list layout as a set command, with ret_code in front of it (and no reserved u16).
  const std::vector<uint8_t> list = encodeKeyValueList(ack.values);
  std::vector<uint8_t> d;
  d.reserve(list.size() + 1);
  d.push_back(ack.ret_code);
  d.insert(d.end(), list.begin(), list.begin() + 2);  // key_num
  d.insert(d.end(), list.begin() + 4, list.end());    // entries
  return makeFrame(seq, CommandId::kQuery, CommandType::kAck, Sender::kLidar, std::move(d));
}

ControlFrame makePushMessage(uint32_t seq, const std::vector<KeyValue>& kvs) {
  return makeFrame(seq, CommandId::kPush, CommandType::kRequest, Sender::kLidar,
                   encodeKeyValueList(kvs));
}

std::optional<std::vector<uint16_t>> parseQueryRequest(const ControlFrame& f) {
  if (!is(f, CommandId::kQuery, CommandType::kRequest) || f.data.size() < 4) return std::nullopt;
  const uint16_t n = le::load<uint16_t>(f.data.data());
  if (f.data.size() != 4 + 2 * static_cast<std::size_t>(n)) return std::nullopt;
  std::vector<uint16_t> keys(n);
  for (uint16_t i = 0; i < n; ++i) keys[i] = le::load<uint16_t>(&f.data[4 + 2 * i]);
  return keys;
}

std::optional<QueryAck> parseQueryAck(const ControlFrame& f) {
  if (!is(f, CommandId::kQuery, CommandType::kAck) || f.data.size() < 3) return std::nullopt;
  QueryAck a;
  a.ret_code = f.data[0];
  // Rebuild the set-command layout (count, reserved, entries) to reuse its decoder.
  std::vector<uint8_t> list(f.data.begin() + 1, f.data.begin() + 3);
  list.push_back(0);
  list.push_back(0);
  list.insert(list.end(), f.data.begin() + 3, f.data.end());
  auto kvs = decodeKeyValueList(list);
  if (!kvs) return std::nullopt;
  a.values = std::move(*kvs);
  return a;
}

std::optional<std::vector<KeyValue>> parsePushMessage(const ControlFrame& f) {
  if (f.cmd_id != static_cast<uint16_t>(CommandId::kPush) ||
      f.sender != static_cast<uint8_t>(Sender::kLidar)) {
    return std::nullopt;
  }
  return decodeKeyValueList(f.data);
}

std::optional<DiscoveryInfo> parseDiscoveryAck(const ControlFrame& f) {
  if (!is(f, CommandId::kDiscovery, CommandType::kAck) || f.data.size() != 24) return std::nullopt;
  DiscoveryInfo info;
  info.ret_code = f.data[0];
  info.dev_type = f.data[1];
  std::size_t n = 0;
  while (n < 16 && f.data[2 + n] != 0) ++n;
  info.serial.assign(reinterpret_cast<const char*>(&f.data[2]), n);
  std::memcpy(info.lidar_ip.data(), &f.data[18], 4);
  info.cmd_port = le::load<uint16_t>(&f.data[22]);
  return info;
}

std::optional<std::vector<KeyValue>> parseSetKeyValueRequest(const ControlFrame& f) {
  if (!is(f, CommandId::kSetKeyValue, CommandType::kRequest)) return std::nullopt;
  return decodeKeyValueList(f.data);
}

std::optional<SetKeyValueAck> parseSetKeyValueAck(const ControlFrame& f) {
  if (!is(f, CommandId::kSetKeyValue, CommandType::kAck) || f.data.size() < 3) return std::nullopt;
  SetKeyValueAck a;
  a.ret_code = f.data[0];
  a.error_key = le::load<uint16_t>(&f.data[1]);
  return a;
}

bool isAckOf(const ControlFrame& ack, const ControlFrame& request) {
  return ack.seq == request.seq && ack.cmd_id == request.cmd_id &&
         ack.cmd_type == static_cast<uint8_t>(CommandType::kAck) &&
         ack.sender == static_cast<uint8_t>(Sender::kLidar);
}

std::optional<std::array<uint8_t, 4>> parseIpv4(const std::string& text) {
  std::array<uint8_t, 4> ip{};
  std::size_t at = 0;
  for (int part = 0; part < 4; ++part) {
    if (at >= text.size()) return std::nullopt;
    int value = 0, digits = 0;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') {
      value = value * 10 + (text[at] - '0');
      ++at;
      if (++digits > 3 || value > 255) return std::nullopt;
    }
    if (digits == 0) return std::nullopt;
    ip[static_cast<std::size_t>(part)] = static_cast<uint8_t>(value);
    if (part < 3) {
      if (at >= text.size() || text[at] != '.') return std::nullopt;
      ++at;
    }
  }
  if (at != text.size()) return std::nullopt;
  return ip;
}

std::string formatIpv4(const std::array<uint8_t, 4>& ip) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "%u.%u.%u.%u", ip[0], ip[1], ip[2], ip[3]);
  return buf;
}

}  // namespace livox
}  // namespace ucon
