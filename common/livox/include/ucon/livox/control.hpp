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

/// Parameter keys of set/query key-value commands.
enum class Key : uint16_t {
  kPointDataType = 0x0000,          ///< uint8 DataType
  kLidarIpConfig = 0x0004,          ///< ip, netmask, gateway (4 B each)
  kStateInfoHostIpConfig = 0x0005,  ///< HostIpConfig for push messages
  kPointDataHostIpConfig = 0x0006,  ///< HostIpConfig: where point packets go
  kImuDataHostIpConfig = 0x0007,    ///< HostIpConfig: where IMU packets go
  kInstallAttitude = 0x0012,        ///< roll, pitch, yaw [deg] float, x, y, z [mm] int32
  kWorkMode = 0x001A,               ///< uint8 WorkMode
  kImuDataEnable = 0x001C,          ///< uint8 0/1
};

/// Values of Key::kWorkMode.
enum class WorkMode : uint8_t {
  kNormal = 0x01,  ///< sampling
  kWakeUp = 0x02,
  kSleep = 0x03,
};

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

/// Requests (sender host) and acks (sender lidar) with the same seq as their request.
ControlFrame makeDiscoveryRequest(uint32_t seq);
ControlFrame makeDiscoveryAck(uint32_t seq, const DiscoveryInfo& info);
ControlFrame makeSetKeyValueRequest(uint32_t seq, const std::vector<KeyValue>& kvs);
ControlFrame makeSetKeyValueAck(uint32_t seq, const SetKeyValueAck& ack);

/// nullopt unless `f` is a discovery ack with a 24-byte payload.
std::optional<DiscoveryInfo> parseDiscoveryAck(const ControlFrame& f);
/// nullopt unless `f` is a set key-value request with a well-formed key-value list.
std::optional<std::vector<KeyValue>> parseSetKeyValueRequest(const ControlFrame& f);
/// nullopt unless `f` is a set key-value ack with at least 3 data bytes.
std::optional<SetKeyValueAck> parseSetKeyValueAck(const ControlFrame& f);

/// True if `ack` is the acknowledgement of `request` (same seq and cmd_id, ack from lidar).
bool isAckOf(const ControlFrame& ack, const ControlFrame& request);

/// "a.b.c.d" -> bytes; nullopt if malformed.
std::optional<std::array<uint8_t, 4>> parseIpv4(const std::string& text);
std::string formatIpv4(const std::array<uint8_t, 4>& ip);

}  // namespace livox
}  // namespace ucon
