#include "ucon/lidar_driver/udp_socket.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

namespace ucon {
namespace lidar_driver {

namespace {
constexpr std::size_t kControlBytes = CMSG_SPACE(sizeof(timespec));
}  // namespace

int64_t realtimeNs() {
  timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

double monotonicSeconds() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

UdpSocket::UdpSocket(int fd)
    : fd_(fd),
      slots_(static_cast<std::size_t>(kBatch) * kSlotBytes),
      sizes_(kBatch),
      truncated_(kBatch),
      stamps_(kBatch, 0),
      control_(static_cast<std::size_t>(kBatch) * kControlBytes),
      addrs_(kBatch),
      iovs_(kBatch),
      msgs_(kBatch) {
  for (int i = 0; i < kBatch; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    iovs_[k].iov_base = slots_.data() + k * kSlotBytes;
    iovs_[k].iov_len = kSlotBytes;
  }
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<UdpSocket> UdpSocket::open(const std::string& ip, uint16_t port, int rcvbuf_bytes,
                                           std::string* error, std::string* warning, bool shared) {
  const std::string where = ip + ":" + std::to_string(port);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (inet_pton(AF_INET, ip.c_str(), &addr.sin_addr) != 1) {
    if (error) *error = "'" + ip + "' is not an IPv4 address";
    return nullptr;
  }
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    if (error) *error = std::string("socket(): ") + std::strerror(errno);
    return nullptr;
  }
  std::unique_ptr<UdpSocket> s(new UdpSocket(fd));
  const int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_BROADCAST, &one, sizeof(one));  // discovery broadcasts
  setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof(one));
  if (shared) setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  if (rcvbuf_bytes > 0) {
    // SO_RCVBUFFORCE passes net.core.rmem_max with CAP_NET_ADMIN; else the plain option.
    if (setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf_bytes, sizeof(rcvbuf_bytes)) != 0) {
      setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf_bytes, sizeof(rcvbuf_bytes));
    }
  }
  socklen_t len = sizeof(s->rcvbuf_);
  getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &s->rcvbuf_, &len);
  // Linux reports twice the usable size it granted.
  if (rcvbuf_bytes > 0 && s->rcvbuf_ / 2 < rcvbuf_bytes && warning) {
    *warning = "UDP receive buffer on " + where + " is " + std::to_string(s->rcvbuf_ / 2) +
               " bytes, asked for " + std::to_string(rcvbuf_bytes) +
               ": bursts may be dropped. Raise the kernel limit: sudo sysctl -w net.core.rmem_max=" +
               std::to_string(rcvbuf_bytes);
  }
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    if (error) {
      *error = "cannot bind UDP " + where + ": " + std::strerror(errno) +
               (errno == EADDRNOTAVAIL
                    ? " (no interface has this address: check network.host_ip)"
                    : errno == EADDRINUSE ? " (another driver or program uses this port)" : "");
    }
    return nullptr;
  }
  return s;
}

int UdpSocket::receiveBatch() {
  for (int i = 0; i < kBatch; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    msgs_[k].msg_hdr = msghdr{};
    msgs_[k].msg_hdr.msg_iov = &iovs_[k];
    msgs_[k].msg_hdr.msg_iovlen = 1;
    msgs_[k].msg_hdr.msg_name = &addrs_[k];
    msgs_[k].msg_hdr.msg_namelen = sizeof(sockaddr_storage);
    msgs_[k].msg_hdr.msg_control = control_.data() + k * kControlBytes;
    msgs_[k].msg_hdr.msg_controllen = kControlBytes;
    msgs_[k].msg_len = 0;
  }
  const int n = ::recvmmsg(fd_, msgs_.data(), kBatch, MSG_DONTWAIT, nullptr);
  if (n < 0) {
    return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? 0 : -1;
  }
  for (int i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    sizes_[k] = msgs_[k].msg_len;
    truncated_[k] = (msgs_[k].msg_hdr.msg_flags & MSG_TRUNC) != 0;
    stamps_[k] = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msgs_[k].msg_hdr); c != nullptr;
         c = CMSG_NXTHDR(&msgs_[k].msg_hdr, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts;
        std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
        stamps_[k] = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
      }
    }
  }
  return n;
}

std::array<uint8_t, 4> UdpSocket::sourceIp(int i) const {
  std::array<uint8_t, 4> ip{};
  const auto* a = reinterpret_cast<const sockaddr_in*>(&addrs_[static_cast<std::size_t>(i)]);
  if (a->sin_family == AF_INET) std::memcpy(ip.data(), &a->sin_addr.s_addr, 4);
  return ip;
}

uint16_t UdpSocket::sourcePort(int i) const {
  const auto* a = reinterpret_cast<const sockaddr_in*>(&addrs_[static_cast<std::size_t>(i)]);
  return a->sin_family == AF_INET ? ntohs(a->sin_port) : 0;
}

bool UdpSocket::sendTo(const std::array<uint8_t, 4>& ip, uint16_t port, const uint8_t* data,
                       std::size_t n) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  std::memcpy(&addr.sin_addr.s_addr, ip.data(), 4);
  ssize_t r;
  do {  // a signal (the SIGTERM handler is installed without SA_RESTART) must not lose a command
    r = ::sendto(fd_, data, n, 0, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr));
  } while (r < 0 && errno == EINTR);
  return r == static_cast<ssize_t>(n);
}

}  // namespace lidar_driver
}  // namespace ucon
