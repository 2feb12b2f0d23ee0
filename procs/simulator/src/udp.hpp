#pragma once
// Small RAII UDP socket for the simulator's main (IPv4, non-blocking receive).
#include <netinet/in.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ucon {
namespace simulator {

class UdpSocket {
 public:
  UdpSocket() = default;
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  /// Opens a socket bound to ip:port (port 0 = any). Returns false and `error` on failure.
  bool open(const std::array<uint8_t, 4>& ip, uint16_t port, std::string* error);
  /// Sends one datagram; false on error.
  bool sendTo(const uint8_t* data, std::size_t size, const std::array<uint8_t, 4>& ip, uint16_t port);
  bool sendTo(const uint8_t* data, std::size_t size, const sockaddr_in& to);
  /// Receives one datagram if one is waiting; returns its size, 0 if none, -1 on error.
  long receive(std::vector<uint8_t>& buf, sockaddr_in* from);
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
};

}  // namespace simulator
}  // namespace ucon
