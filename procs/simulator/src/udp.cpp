#include "udp.hpp"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <tuple>

namespace ucon {
namespace simulator {

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpSocket::open(const std::array<uint8_t, 4>& ip, uint16_t port, std::string* error, bool shared) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd_ < 0) {
    if (error) *error = std::string("socket(): ") + std::strerror(errno);
    return false;
  }
  const int one = 1;
  ::setsockopt(fd_, SOL_SOCKET, SO_BROADCAST, &one, sizeof(one));
  if (shared) ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
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

bool SensorSockets::open(const std::vector<std::array<uint8_t, 4>>& ips, const Ports& ports,
                         std::string* error, std::string* warning) {
  std::string err;
  if (!any_discovery_.open({{0, 0, 0, 0}}, ports.discovery, &err, true)) {
    if (error) *error = "discovery listener: " + err;
    return false;
  }
  for (const auto& ip : ips) {
    auto s = std::make_unique<One>();
    if (!s->discovery.open(ip, ports.discovery, &err, true) || !s->command.open(ip, ports.command, &err)) {
      if (error) *error = "control socket: " + err + " (is another simulator or a sensor emulator running?)";
      return false;
    }
    for (auto [sock, port, what] : {std::make_tuple(&s->point, ports.point, "point"),
                                     std::make_tuple(&s->imu, ports.imu, "imu")}) {
      if (!sock->open(ip, port, &err)) {
        if (warning) *warning += std::string(what) + " source port: " + err + "; using any port. ";
        if (!sock->open(ip, 0, &err)) {
          if (error) *error = std::string(what) + " socket: " + err;
          return false;
        }
      }
    }
    sensors_.push_back(std::move(s));
  }
  return true;
}

int64_t SensorSockets::serviceControl(const Handler& handle) {
  int64_t errors = 0;
  const auto answer = [&](UdpSocket& sock, std::size_t first, std::size_t last) {
    sockaddr_in from{};
    for (int k = 0; k < 64; ++k) {
      const long n = sock.receive(rx_, &from);
      if (n <= 0) break;
      for (std::size_t i = first; i < last; ++i) {
        bool broadcast = false;
        const auto reply = handle(i, rx_.data(), rx_.size(), &broadcast);
        if (!reply) continue;
        // Replies leave from the sensor's own socket on the port the request came to.
        UdpSocket& out = &sock == &any_discovery_ ? sensors_[i]->discovery : sock;
        sockaddr_in to = from;
        if (broadcast) to.sin_addr.s_addr = htonl(INADDR_BROADCAST);
        if (!out.sendTo(reply->data(), reply->size(), to)) ++errors;
      }
    }
  };
  answer(any_discovery_, 0, sensors_.size());  // a broadcast request: every sensor answers
  for (std::size_t i = 0; i < sensors_.size(); ++i) {
    answer(sensors_[i]->discovery, i, i + 1);
    answer(sensors_[i]->command, i, i + 1);
  }
  return errors;
}

bool SensorSockets::send(std::size_t sensor, bool imu, const uint8_t* data, std::size_t size,
                         const std::array<uint8_t, 4>& ip, uint16_t port) {
  if (sensor >= sensors_.size()) return false;
  return (imu ? sensors_[sensor]->imu : sensors_[sensor]->point).sendTo(data, size, ip, port);
}

}  // namespace simulator
}  // namespace ucon
