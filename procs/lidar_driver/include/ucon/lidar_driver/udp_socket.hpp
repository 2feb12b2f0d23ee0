#pragma once
/// @file udp_socket.hpp
/// IPv4 UDP socket with batched receive (recvmmsg) for the driver process and its benchmark.
/// This is the process-side I/O; the node library never includes it.

#include <sys/socket.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ucon {
namespace lidar_driver {

class UdpSocket {
 public:
  /// Datagrams per recvmmsg call and bytes per datagram slot (a Mid-360 packet is <= 1380 B).
  static constexpr int kBatch = 64;
  static constexpr std::size_t kSlotBytes = 2048;

  /// Binds `ip`:`port` (non-blocking; "0.0.0.0" = any address, which also receives
  /// broadcasts). `rcvbuf_bytes` > 0 asks for that SO_RCVBUF; if the kernel grants less,
  /// `warning` says so and how to raise net.core.rmem_max. `shared` sets SO_REUSEADDR, so that
  /// a send socket on host_ip:56000 and a broadcast listener on 0.0.0.0:56000 can coexist
  /// (and two processes on one host can both hear broadcasts). Every datagram carries its
  /// kernel receive time (SO_TIMESTAMPNS). Returns nullptr and fills `error` (naming the
  /// address) on failure.
  static std::unique_ptr<UdpSocket> open(const std::string& ip, uint16_t port, int rcvbuf_bytes,
                                         std::string* error, std::string* warning,
                                         bool shared = false);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  int fd() const { return fd_; }
  /// Receive buffer the kernel granted [bytes] (as getsockopt reports it).
  int receiveBufferBytes() const { return rcvbuf_; }

  /// Receives up to kBatch waiting datagrams without blocking; returns how many (0 if none,
  /// -1 on a socket error).
  int receiveBatch();
  const uint8_t* data(int i) const { return slots_.data() + static_cast<std::size_t>(i) * kSlotBytes; }
  std::size_t size(int i) const { return sizes_[static_cast<std::size_t>(i)]; }
  /// True if datagram i was larger than a slot (cut).
  bool truncated(int i) const { return truncated_[static_cast<std::size_t>(i)]; }
  std::array<uint8_t, 4> sourceIp(int i) const;
  uint16_t sourcePort(int i) const;
  /// Kernel receive time of datagram i, CLOCK_REALTIME [ns] (0 if the kernel gave none).
  int64_t receiveTimeNs(int i) const { return stamps_[static_cast<std::size_t>(i)]; }

  /// Sends one datagram; false on error.
  bool sendTo(const std::array<uint8_t, 4>& ip, uint16_t port, const uint8_t* data, std::size_t n);

 private:
  explicit UdpSocket(int fd);
  int fd_;
  int rcvbuf_ = 0;
  std::vector<uint8_t> slots_;
  std::vector<std::size_t> sizes_;
  std::vector<bool> truncated_;
  std::vector<int64_t> stamps_;
  std::vector<uint8_t> control_;  // cmsg space per slot
  std::vector<struct sockaddr_storage> addrs_;
  std::vector<struct iovec> iovs_;
  std::vector<struct mmsghdr> msgs_;
};

/// Time of the steady clock [s] (process side: retries, idle flush, CPU measurements).
double monotonicSeconds();
/// CLOCK_REALTIME [ns] (host time of a datagram when the kernel gave no stamp).
int64_t realtimeNs();

}  // namespace lidar_driver
}  // namespace ucon
