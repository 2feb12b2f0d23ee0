#pragma once
// Small RAII UDP socket for the simulator's main (IPv4, non-blocking receive).
#include <netinet/in.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
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

  /// Opens a socket bound to ip:port (port 0 = any; 0.0.0.0 = any address, which also hears
  /// broadcasts). `shared` sets SO_REUSEADDR (several sockets on one discovery port).
  /// Returns false and `error` on failure.
  bool open(const std::array<uint8_t, 4>& ip, uint16_t port, std::string* error, bool shared = false);
  /// Sends one datagram; false on error.
  bool sendTo(const uint8_t* data, std::size_t size, const std::array<uint8_t, 4>& ip, uint16_t port);
  bool sendTo(const uint8_t* data, std::size_t size, const sockaddr_in& to);
  /// Receives one datagram if one is waiting; returns its size, 0 if none, -1 on error.
  long receive(std::vector<uint8_t>& buf, sockaddr_in* from);
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
};

/// The sockets of the emulated Mid-360s, as the real ones use them: per sensor its discovery
/// port (also where its broadcast answers leave from), command port and the source ports of its
/// point and IMU packets, all on the sensor's address; plus one listener on 0.0.0.0:discovery
/// port, which hears the hosts' broadcast discovery requests for every sensor.
class SensorSockets {
 public:
  struct Ports {
    uint16_t discovery = 56000, command = 56100, point = 56300, imu = 56400;  // 0 = any (data)
  };
  /// Opens everything for sensors at `ips`; false with `error` naming the socket on failure.
  /// A data source port that is taken falls back to any port (`warning` says so).
  bool open(const std::vector<std::array<uint8_t, 4>>& ips, const Ports& ports, std::string* error,
            std::string* warning);
  /// Receives waiting control requests and answers them: `handle(sensor, bytes, size,
  /// &broadcast)` returns the reply; a broadcast reply goes to 255.255.255.255 at the
  /// requester's port, as a Mid-360 answers discovery. Returns the send errors.
  using Handler = std::function<std::optional<std::vector<uint8_t>>(std::size_t, const uint8_t*,
                                                                    std::size_t, bool*)>;
  int64_t serviceControl(const Handler& handle);
  /// Sends a data datagram from sensor `sensor`'s point (or IMU) source socket.
  bool send(std::size_t sensor, bool imu, const uint8_t* data, std::size_t size,
            const std::array<uint8_t, 4>& ip, uint16_t port);

 private:
  struct One {
    UdpSocket discovery, command, point, imu;
  };
  std::vector<std::unique_ptr<One>> sensors_;
  UdpSocket any_discovery_;
  std::vector<uint8_t> rx_;
};

}  // namespace simulator
}  // namespace ucon
