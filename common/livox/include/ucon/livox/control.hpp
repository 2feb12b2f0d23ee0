#pragma once
/// @file control.hpp
/// Livox SDK2 control frames (discovery, set key-values, their acks) as values and bytes.
///
/// Frame layout (24-byte header, little-endian): 0xAA, version 0, uint16 length (whole frame),
/// uint32 seq, uint16 cmd_id, uint8 cmd_type (0 request, 1 ack), uint8 sender (0 host,
/// 1 lidar), 6 reserved, uint16 crc16 (CRC-16/CCITT-FALSE over bytes 0-17), uint32 crc32
/// (CRC-32 over the data), data.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ucon {
namespace livox {

constexpr uint8_t kControlSof = 0xAA;
constexpr std::size_t kControlHeaderSize = 24;

/// Command ids.
enum class CommandId : uint16_t {
  kDiscovery = 0x0000,
  kSetKeyValue = 0x0100,
  kQuery = 0x0101,
  kPush = 0x0102,
  kReboot = 0x0200,
};
enum class CommandType : uint8_t { kRequest = 0, kAck = 1 };
enum class Sender : uint8_t { kHost = 0, kLidar = 1 };

/// Parameter keys of set/query key-value commands (Mid-360 protocol; keys >= 0x8000 are
/// read-only state that a query or a push message carries).
enum class Key : uint16_t {
  kPointDataType = 0x0000,          ///< uint8 DataType: 1 Cartesian mm, 2 Cartesian cm, 3 spherical
  kPatternMode = 0x0001,            ///< uint8 scan pattern: 0 non-repetitive (Mid-360 default)
  kLidarIpConfig = 0x0004,          ///< ip, netmask, gateway (4 B each)
  kStateInfoHostIpConfig = 0x0005,  ///< HostIpConfig for push messages
  kPointDataHostIpConfig = 0x0006,  ///< HostIpConfig: where point packets go
  kImuDataHostIpConfig = 0x0007,    ///< HostIpConfig: where IMU packets go
  kInstallAttitude = 0x0012,        ///< roll, pitch, yaw [deg] float, x, y, z [mm] int32
  kWorkMode = 0x001A,               ///< uint8 WorkMode
  kImuDataEnable = 0x001C,          ///< uint8 0/1
  kSerialNumber = 0x8000,           ///< 16 characters (query / push)
  kFirmwareVersion = 0x8002,        ///< 4 bytes: application firmware a.b.c.d (query / push)
  kCurrentWorkState = 0x8006,       ///< uint8 WorkMode the sensor is in (query / push)
  kTimeSyncType = 0x800C,           ///< uint8 0 none, 1 PTP, 2 GPS... (query / push)
};

/// Target values of Key::kWorkMode that a user sets on a Mid-360. (The sensor reports other
/// states it enters by itself, e.g. 0x04 error, 0x05 self check, 0x06 motor start-up,
/// 0x08 upgrade; 0x03 is not a Mid-360 state.)
enum class WorkMode : uint8_t {
  kSampling = 0x01,  ///< sends point and IMU packets
  kIdle = 0x02,      ///< stays on, sends no data
};
/// True for the work modes a Mid-360 accepts as a target (0x01, 0x02).
bool isSettableWorkMode(uint8_t mode);

constexpr uint8_t kDeviceTypeMid360 = 9;  ///< dev_type in a discovery ack

/// One control frame. encodeControlFrame fills length and both CRCs.
struct ControlFrame {
  uint8_t version = 0;
  uint32_t seq = 0;
  uint16_t cmd_id = 0;    ///< CommandId
  uint8_t cmd_type = 0;   ///< CommandType
  uint8_t sender = 0;     ///< Sender
  std::vector<uint8_t> data;
};

/// Outcome of decoding a control frame.
enum class ControlStatus {
  kOk,
  kTruncated,      ///< fewer than 24 bytes
  kBadSof,         ///< first byte is not 0xAA
  kBadVersion,     ///< version is not 0
  kBadLength,      ///< length field != datagram size
  kBadHeaderCrc,   ///< crc16 over bytes 0-17 does not match
  kBadDataCrc,     ///< crc32 over the data does not match
  kTooLarge,       ///< data would not fit a 16-bit length (encoder)
};
/// Short snake_case name, e.g. "bad_header_crc".
const char* toString(ControlStatus status);

/// Bytes of `frame` (length and CRCs computed). Data longer than 65535 - 24 bytes cannot be
/// framed: the result is then empty.
std::vector<uint8_t> encodeControlFrame(const ControlFrame& frame);
/// Decodes one datagram into `out`.
ControlStatus decodeControlFrame(const uint8_t* bytes, std::size_t size, ControlFrame& out);
inline ControlStatus decodeControlFrame(const std::vector<uint8_t>& bytes, ControlFrame& out) {
  return decodeControlFrame(bytes.data(), bytes.size(), out);
}

/// One key-value of a set/query command.
struct KeyValue {
  uint16_t key = 0;  ///< Key
  std::vector<uint8_t> value;
};
bool operator==(const KeyValue& a, const KeyValue& b);

/// Key-value list as carried in the data of a set command: uint16 key_num, uint16 reserved,
/// then per entry uint16 key, uint16 length, value bytes.
std::vector<uint8_t> encodeKeyValueList(const std::vector<KeyValue>& kvs);
/// nullopt if the list is truncated or its count does not match its bytes.
std::optional<std::vector<KeyValue>> decodeKeyValueList(const std::vector<uint8_t>& data);

/// Where the sensor sends one kind of data (value of keys 0x0005-0x0007).
struct HostIpConfig {
  std::array<uint8_t, 4> host_ip{};  ///< e.g. {127,0,0,1}
  uint16_t host_port = 0;            ///< destination port on the host
  uint16_t lidar_port = 0;           ///< source port on the sensor
};
KeyValue makeHostIpConfig(Key key, const HostIpConfig& cfg);
/// nullopt if the value is not 8 bytes.
std::optional<HostIpConfig> parseHostIpConfig(const KeyValue& kv);
KeyValue makeWorkMode(WorkMode mode);
/// A one-byte value for `key` (data type, pattern mode, IMU enable).
KeyValue makeUint8(Key key, uint8_t value);
/// Install attitude (key 0x0012): roll, pitch, yaw [deg], x, y, z [mm]. The sensor applies it
/// to its points before sending them.
KeyValue makeInstallAttitude(float roll_deg, float pitch_deg, float yaw_deg, int32_t x_mm,
                             int32_t y_mm, int32_t z_mm);
/// The work-mode byte; nullopt if the value is not 1 byte.
std::optional<uint8_t> parseWorkMode(const KeyValue& kv);

/// What a sensor says about itself in a discovery ack (24 data bytes).
struct DiscoveryInfo {
  uint8_t ret_code = 0;                    ///< 0 = success
  uint8_t dev_type = kDeviceTypeMid360;
  std::string serial;                      ///< up to 16 characters
  std::array<uint8_t, 4> lidar_ip{};
  uint16_t cmd_port = 56100;               ///< the sensor's control port
};

/// Ack of a set key-value command.
struct SetKeyValueAck {
  uint8_t ret_code = 0;    ///< 0 = success
  uint16_t error_key = 0;  ///< the key that failed when ret_code != 0
};

/// Ack of a query command: the values of the keys asked for.
struct QueryAck {
  uint8_t ret_code = 0;  ///< 0 = success
  std::vector<KeyValue> values;
};

/// Requests (sender host) and acks (sender lidar) with the same seq as their request.
ControlFrame makeDiscoveryRequest(uint32_t seq);
ControlFrame makeDiscoveryAck(uint32_t seq, const DiscoveryInfo& info);
ControlFrame makeSetKeyValueRequest(uint32_t seq, const std::vector<KeyValue>& kvs);
ControlFrame makeSetKeyValueAck(uint32_t seq, const SetKeyValueAck& ack);
/// Query (0x0101): data is uint16 key_num, uint16 reserved, then one uint16 key each.
ControlFrame makeQueryRequest(uint32_t seq, const std::vector<uint16_t>& keys);
/// Query ack: uint8 ret_code, uint16 key_num, then key (u16), length (u16), value per key.
ControlFrame makeQueryAck(uint32_t seq, const QueryAck& ack);
/// Push message (0x0102, sent by the sensor to the state-info host, cmd_type 0): a key-value
/// list as in a set command.
ControlFrame makePushMessage(uint32_t seq, const std::vector<KeyValue>& kvs);

/// nullopt unless `f` is a discovery ack with a 24-byte payload.
std::optional<DiscoveryInfo> parseDiscoveryAck(const ControlFrame& f);
/// nullopt unless `f` is a set key-value request with a well-formed key-value list.
std::optional<std::vector<KeyValue>> parseSetKeyValueRequest(const ControlFrame& f);
/// nullopt unless `f` is a set key-value ack with at least 3 data bytes.
std::optional<SetKeyValueAck> parseSetKeyValueAck(const ControlFrame& f);
/// nullopt unless `f` is a query request with a consistent key list.
std::optional<std::vector<uint16_t>> parseQueryRequest(const ControlFrame& f);
/// nullopt unless `f` is a query ack whose key-value list is consistent.
std::optional<QueryAck> parseQueryAck(const ControlFrame& f);
/// nullopt unless `f` is a push message from the sensor with a consistent key-value list.
std::optional<std::vector<KeyValue>> parsePushMessage(const ControlFrame& f);
/// The value of `key` in `kvs`, or nullptr.
const KeyValue* findKey(const std::vector<KeyValue>& kvs, Key key);

/// True if `ack` is the acknowledgement of `request` (same seq and cmd_id, ack from lidar).
bool isAckOf(const ControlFrame& ack, const ControlFrame& request);

/// "a.b.c.d" -> bytes; nullopt if malformed.
std::optional<std::array<uint8_t, 4>> parseIpv4(const std::string& text);
std::string formatIpv4(const std::array<uint8_t, 4>& ip);

}  // namespace livox
}  // namespace ucon
