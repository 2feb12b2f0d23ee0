// The driver's UDP helper over loopback: batched receive with sizes, sources and the
// truncation flag; bind errors name the address; the receive-buffer warning.
#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <fstream>

#include "ucon/lidar_driver/udp_socket.hpp"

using ucon::lidar_driver::UdpSocket;

TEST(UdpSocket, GivenDatagramsOnLoopbackThenABatchReceiveReturnsThemWithSizesAndSource) {
  std::string err, warn;
  auto rx = UdpSocket::open("127.0.0.1", 27026, 1 << 20, &err, &warn);
  ASSERT_TRUE(rx) << err;
  auto tx = UdpSocket::open("127.0.0.1", 27027, 0, &err, &warn);
  ASSERT_TRUE(tx) << err;
  std::vector<uint8_t> buf(3000);
  for (int i = 0; i < 100; ++i) {
    buf[0] = static_cast<uint8_t>(i);
    ASSERT_TRUE(tx->sendTo({127, 0, 0, 1}, 27026, buf.data(), 100 + static_cast<std::size_t>(i)));
  }
  ASSERT_TRUE(tx->sendTo({127, 0, 0, 1}, 27026, buf.data(), 3000));  // larger than a slot
  int got = 0, batches = 0;
  bool saw_truncated = false;
  for (int tries = 0; tries < 100 && got < 101; ++tries) {
    pollfd p{rx->fd(), POLLIN, 0};
    ::poll(&p, 1, 10);
    const int n = rx->receiveBatch();
    ASSERT_GE(n, 0);
    if (n > 0) ++batches;
    for (int i = 0; i < n; ++i, ++got) {
      EXPECT_EQ(rx->sourceIp(i), (std::array<uint8_t, 4>{127, 0, 0, 1}));
      EXPECT_EQ(rx->sourcePort(i), 27027);
      if (got < 100) {
        EXPECT_EQ(rx->size(i), 100u + static_cast<std::size_t>(got));
        EXPECT_EQ(rx->data(i)[0], got);
        EXPECT_FALSE(rx->truncated(i));
      } else {
        saw_truncated = rx->truncated(i);
      }
    }
  }
  EXPECT_EQ(got, 101);
  EXPECT_GE(batches, 2);  // at most 64 per call
  EXPECT_TRUE(saw_truncated);
  EXPECT_EQ(rx->receiveBatch(), 0);  // nothing left, does not block
}

TEST(UdpSocket, GivenAnAddressInUseOrNotLocalThenOpenFailsNamingIt) {
  std::string err, warn;
  auto a = UdpSocket::open("127.0.0.1", 27028, 0, &err, &warn);
  ASSERT_TRUE(a) << err;
  auto b = UdpSocket::open("127.0.0.1", 27028, 0, &err, &warn);
  EXPECT_FALSE(b);
  EXPECT_NE(err.find("127.0.0.1:27028"), std::string::npos) << err;
  EXPECT_NE(err.find("another"), std::string::npos) << err;
  auto c = UdpSocket::open("192.0.2.1", 27029, 0, &err, &warn);  // TEST-NET-1: never local
  EXPECT_FALSE(c);
  EXPECT_NE(err.find("network.host_ip"), std::string::npos) << err;
  EXPECT_FALSE(UdpSocket::open("not-an-ip", 27029, 0, &err, &warn));
}

TEST(UdpSocket, GivenABufferAboveTheKernelLimitThenItIsGrantedWhenPrivilegedElseAWarningNamesRmemMax) {
  int rmem_max = 0;
  std::ifstream("/proc/sys/net/core/rmem_max") >> rmem_max;
  ASSERT_GT(rmem_max, 0);
  const int ask = std::min(2 * rmem_max, 1 << 29);
  std::string err, warn;
  auto s = UdpSocket::open("127.0.0.1", 27025, ask, &err, &warn);
  ASSERT_TRUE(s) << err;
  if (geteuid() == 0) {
    // CAP_NET_ADMIN: SO_RCVBUFFORCE passes the limit.
    EXPECT_GE(s->receiveBufferBytes() / 2, ask);
    EXPECT_TRUE(warn.empty()) << warn;
  } else {
    EXPECT_LT(s->receiveBufferBytes() / 2, ask);
    EXPECT_NE(warn.find("net.core.rmem_max"), std::string::npos) << warn;
  }
}
