// Finding the UDP datagram in a captured frame: Ethernet (VLAN-tagged too), Linux "any"
// captures, raw IPv4; fragments, other protocols and cut frames are skipped with their reason.
#include <gtest/gtest.h>

#include <vector>

#include "ucon/lidar_driver/captured_udp.hpp"

using namespace ucon::lidar_driver;

namespace {
// IPv4 (20 B, no options) + UDP header + payload, big-endian fields.
std::vector<uint8_t> ipUdp(const std::vector<uint8_t>& payload, uint8_t proto = 17, uint16_t frag = 0) {
  const std::size_t total = 20 + 8 + payload.size();
  std::vector<uint8_t> b = {0x45, 0, static_cast<uint8_t>(total >> 8), static_cast<uint8_t>(total & 0xFF),
                            0, 1, static_cast<uint8_t>(frag >> 8), static_cast<uint8_t>(frag & 0xFF),
                            64, proto, 0, 0, 192, 168, 1, 100, 255, 255, 255, 255};
  const std::size_t ulen = 8 + payload.size();
  const uint8_t udp[8] = {0xDA, 0xC0, 0xDA, 0xC0, static_cast<uint8_t>(ulen >> 8), static_cast<uint8_t>(ulen & 0xFF), 0, 0};
  b.insert(b.end(), udp, udp + 8);  // 56000 -> 56000
  b.insert(b.end(), payload.begin(), payload.end());
  return b;
}
std::vector<uint8_t> ethernet(const std::vector<uint8_t>& ip, bool vlan = false) {
  std::vector<uint8_t> f(12, 0xAB);
  if (vlan) f.insert(f.end(), {0x81, 0x00, 0x00, 0x05});
  f.insert(f.end(), {0x08, 0x00});
  f.insert(f.end(), ip.begin(), ip.end());
  return f;
}
}  // namespace

TEST(CapturedUdp, GivenEachLinkTypeThenTheDatagramAndItsAddressesAreFound) {
  const std::vector<uint8_t> payload = {0xAA, 1, 2, 3, 4};
  const auto ip = ipUdp(payload);
  std::vector<uint8_t> sll(14, 0);
  sll.insert(sll.end(), {0x08, 0x00});
  sll.insert(sll.end(), ip.begin(), ip.end());
  std::vector<uint8_t> sll2 = {0x08, 0x00};
  sll2.resize(20, 0);
  sll2.insert(sll2.end(), ip.begin(), ip.end());
  std::vector<uint8_t> null = {2, 0, 0, 0};
  null.insert(null.end(), ip.begin(), ip.end());
  const std::vector<std::pair<int, std::vector<uint8_t>>> frames = {
      {1, ethernet(ip)}, {1, ethernet(ip, true)}, {113, sll}, {276, sll2}, {101, ip}, {228, ip}, {0, null}};
  for (const auto& [link, frame] : frames) {
    CaptureSkip why = CaptureSkip::kTruncated;
    const auto d = extractUdp(link, frame.data(), frame.size(), &why);
    ASSERT_TRUE(d) << "link " << link;
    EXPECT_EQ(why, CaptureSkip::kNone);
    EXPECT_EQ(d->src_ip, (std::array<uint8_t, 4>{192, 168, 1, 100}));
    EXPECT_EQ(d->dst_ip, (std::array<uint8_t, 4>{255, 255, 255, 255}));
    EXPECT_EQ(d->src_port, 56000);
    EXPECT_EQ(d->dst_port, 56000);
    ASSERT_EQ(d->size, payload.size());
    EXPECT_EQ(std::vector<uint8_t>(d->payload, d->payload + d->size), payload);
  }
}

TEST(CapturedUdp, GivenFramesWithoutAWholeDatagramThenTheyAreSkippedWithTheReason) {
  const auto ip = ipUdp({1, 2, 3});
  CaptureSkip why;
  EXPECT_FALSE(extractUdp(1, ethernet(ipUdp({1}, 6)).data(), ethernet(ipUdp({1}, 6)).size(), &why));
  EXPECT_EQ(why, CaptureSkip::kNotUdp);
  const auto frag = ethernet(ipUdp({1, 2}, 17, 0x2000));  // more fragments follow
  EXPECT_FALSE(extractUdp(1, frag.data(), frag.size(), &why));
  EXPECT_EQ(why, CaptureSkip::kFragment);
  auto cut = ethernet(ip);
  cut.resize(cut.size() - 2);  // snap length shorter than the datagram
  EXPECT_FALSE(extractUdp(1, cut.data(), cut.size(), &why));
  EXPECT_EQ(why, CaptureSkip::kTruncated);
  auto arp = ethernet(ip);
  arp[12] = 0x08;
  arp[13] = 0x06;
  EXPECT_FALSE(extractUdp(1, arp.data(), arp.size(), &why));
  EXPECT_EQ(why, CaptureSkip::kNotIpv4);
  EXPECT_FALSE(extractUdp(147, ip.data(), ip.size(), &why));
  EXPECT_EQ(why, CaptureSkip::kUnknownLink);
  EXPECT_FALSE(extractUdp(1, nullptr, 10, &why));
  for (std::size_t n = 0; n < 30; ++n) EXPECT_FALSE(extractUdp(101, ip.data(), n, nullptr)) << n;
}
