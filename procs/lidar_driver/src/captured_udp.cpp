#include "ucon/lidar_driver/captured_udp.hpp"

#include <cstring>

namespace ucon {
namespace lidar_driver {

namespace {
uint16_t be16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }

constexpr uint16_t kEtherIpv4 = 0x0800;
constexpr uint16_t kEtherVlan = 0x8100;
constexpr uint16_t kEtherQinQ = 0x88A8;

std::optional<CapturedUdp> fromIpv4(const uint8_t* ip, std::size_t len, CaptureSkip* skip) {
  const auto no = [&](CaptureSkip why) -> std::optional<CapturedUdp> {
    if (skip) *skip = why;
    return std::nullopt;
  };
  if (len < 20) return no(CaptureSkip::kTruncated);
  if ((ip[0] >> 4) != 4) return no(CaptureSkip::kNotIpv4);
  const std::size_t ihl = static_cast<std::size_t>(ip[0] & 0x0F) * 4;
  const std::size_t total = be16(ip + 2);
  if (ihl < 20 || total < ihl || len < ihl) return no(CaptureSkip::kTruncated);
  if (ip[9] != 17) return no(CaptureSkip::kNotUdp);
  const uint16_t frag = be16(ip + 6);
  if ((frag & 0x2000) != 0 || (frag & 0x1FFF) != 0) return no(CaptureSkip::kFragment);
  if (len < total || total < ihl + 8) return no(CaptureSkip::kTruncated);
  const uint8_t* udp = ip + ihl;
  const std::size_t ulen = be16(udp + 4);
  if (ulen < 8 || ihl + ulen > total) return no(CaptureSkip::kTruncated);
  CapturedUdp d;
  std::memcpy(d.src_ip.data(), ip + 12, 4);
  std::memcpy(d.dst_ip.data(), ip + 16, 4);
  d.src_port = be16(udp);
  d.dst_port = be16(udp + 2);
  d.payload = udp + 8;
  d.size = ulen - 8;
  if (skip) *skip = CaptureSkip::kNone;
  return d;
}
}  // namespace

std::optional<CapturedUdp> extractUdp(int linktype, const uint8_t* frame, std::size_t caplen,
                                      CaptureSkip* skip) {
  const auto no = [&](CaptureSkip why) -> std::optional<CapturedUdp> {
    if (skip) *skip = why;
    return std::nullopt;
  };
  if (frame == nullptr) return no(CaptureSkip::kTruncated);
  switch (linktype) {
    case static_cast<int>(LinkType::kEthernet): {
      std::size_t at = 12;
      if (caplen < at + 2) return no(CaptureSkip::kTruncated);
      uint16_t type = be16(frame + at);
      while (type == kEtherVlan || type == kEtherQinQ) {  // 802.1Q / 802.1ad tags
        at += 4;
        if (caplen < at + 2) return no(CaptureSkip::kTruncated);
        type = be16(frame + at);
      }
      if (type != kEtherIpv4) return no(CaptureSkip::kNotIpv4);
      return fromIpv4(frame + at + 2, caplen - at - 2, skip);
    }
    case static_cast<int>(LinkType::kLinuxSll):  // 16-byte header, protocol at 14
      if (caplen < 16) return no(CaptureSkip::kTruncated);
      if (be16(frame + 14) != kEtherIpv4) return no(CaptureSkip::kNotIpv4);
      return fromIpv4(frame + 16, caplen - 16, skip);
    case static_cast<int>(LinkType::kLinuxSll2):  // 20-byte header, protocol at 0
      if (caplen < 20) return no(CaptureSkip::kTruncated);
      if (be16(frame) != kEtherIpv4) return no(CaptureSkip::kNotIpv4);
      return fromIpv4(frame + 20, caplen - 20, skip);
    case static_cast<int>(LinkType::kNull): {  // address family in host byte order
      if (caplen < 4) return no(CaptureSkip::kTruncated);
      uint32_t family = 0;
      std::memcpy(&family, frame, 4);
      if (family != 2 && family != 0x02000000u) return no(CaptureSkip::kNotIpv4);
      return fromIpv4(frame + 4, caplen - 4, skip);
    }
    case static_cast<int>(LinkType::kRawIpv4):
    case 101:  // LINKTYPE_RAW
    case 12:   // DLT_RAW on most systems
    case 14:   // DLT_RAW on OpenBSD
      return fromIpv4(frame, caplen, skip);
    default:
      return no(CaptureSkip::kUnknownLink);
  }
}

}  // namespace lidar_driver
}  // namespace ucon
