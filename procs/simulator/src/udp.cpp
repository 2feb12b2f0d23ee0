#include "udp.hpp"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

namespace ucon {
namespace simulator {

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpSocket::open(const std::array<uint8_t, 4>& ip, uint16_t port, std::string* error) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd_ < 0) {
    if (error) *error = std::string("socket(): ") + std::strerror(errno);
    return false;
  }
  const int buf = 4 * 1024 * 1024;
  ::setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &buf, sizeof(buf));
  ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &buf, sizeof(buf));
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL, 0) | O_NONBLOCK);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  std::memcpy(&a.sin_addr.s_addr, ip.data(), 4);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    if (error) {
      *error = "bind " + std::to_string(ip[0]) + "." + std::to_string(ip[1]) + "." +
               std::to_string(ip[2]) + "." + std::to_string(ip[3]) + ":" + std::to_string(port) +
               ": " + std::strerror(errno);
    }
    ::close(fd_);
    fd_ = -1;
    return false;
  }
  return true;
}

bool UdpSocket::sendTo(const uint8_t* data, std::size_t size, const sockaddr_in& to) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    const ssize_t n = ::sendto(fd_, data, size, 0, reinterpret_cast<const sockaddr*>(&to), sizeof(to));
    if (n == static_cast<ssize_t>(size)) return true;
    if (n < 0 && errno == EINTR) continue;  // a signal (SIGTERM handler without SA_RESTART)
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS)) {
      ::usleep(50);  // send buffer full: wait for the kernel instead of dropping
      continue;
    }
    return false;
  }
  return false;
}

bool UdpSocket::sendTo(const uint8_t* data, std::size_t size, const std::array<uint8_t, 4>& ip,
                       uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  std::memcpy(&a.sin_addr.s_addr, ip.data(), 4);
  return sendTo(data, size, a);
}

long UdpSocket::receive(std::vector<uint8_t>& buf, sockaddr_in* from) {
  buf.resize(65536);
  socklen_t len = sizeof(sockaddr_in);
  const ssize_t n = ::recvfrom(fd_, buf.data(), buf.size(), 0, reinterpret_cast<sockaddr*>(from), &len);
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return 0;
    return -1;
  }
  buf.resize(static_cast<std::size_t>(n));
  return static_cast<long>(n);
}

}  // namespace simulator
}  // namespace ucon
