#pragma once
/// @file captured_udp.hpp
/// The UDP datagram inside one captured link-layer frame (pcap): Ethernet (with 802.1Q tags),
/// Linux "any" captures (SLL, SLL2), raw IPv4 and BSD loopback. Pure byte parsing; the pcap
/// file itself is read by PcapReader (process side).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace ucon {
namespace lidar_driver {

/// Link-layer types (pcap LINKTYPE_* values) the extractor understands.
enum class LinkType : int {
  kNull = 0,         ///< BSD loopback: 4-byte address family
  kEthernet = 1,
  kRawIpv4 = 228,    ///< also LINKTYPE_RAW (101) and DLT_RAW (12/14)
  kLinuxSll = 113,
  kLinuxSll2 = 276,
};

/// One IPv4/UDP datagram found in a frame. `payload` points into the frame.
struct CapturedUdp {
  std::array<uint8_t, 4> src_ip{};
  std::array<uint8_t, 4> dst_ip{};
  uint16_t src_port = 0;
  uint16_t dst_port = 0;
  const uint8_t* payload = nullptr;
  std::size_t size = 0;
};

/// Why a frame gave no datagram.
enum class CaptureSkip {
  kNone,
  kNotIpv4,      ///< another protocol (ARP, IPv6, ...)
  kNotUdp,
  kFragment,     ///< an IP fragment (a Mid-360 packet fits one Ethernet frame: none expected)
  kTruncated,    ///< cut by the capture's snap length, or malformed headers
  kUnknownLink,  ///< a link type this reader does not know
};

/// The UDP datagram in `frame` (`caplen` captured bytes) of link type `linktype` (the pcap
/// header's value), or nullopt with the reason in `skip`.
std::optional<CapturedUdp> extractUdp(int linktype, const uint8_t* frame, std::size_t caplen,
                                      CaptureSkip* skip);

}  // namespace lidar_driver
}  // namespace ucon
