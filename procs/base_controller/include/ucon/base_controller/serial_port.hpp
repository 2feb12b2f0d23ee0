#pragma once
/// @file serial_port.hpp
/// A raw (8N1, no flow control, no echo) serial port for the motor board. I/O: used by the
/// process and its tests, never by the node.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace ucon {
namespace base_controller {

/// Owns one tty file descriptor. Writes never block: a frame that does not fit in the
/// kernel buffer is dropped and counted (a stale wheel command is worse than a missing one).
class SerialPort {
 public:
  /// Opens `device` at `baud` (one of 9600 ... 921600) in raw mode. nullptr and `error` on
  /// failure (no such device, permission, not a tty, unsupported baud rate).
  static std::unique_ptr<SerialPort> open(const std::string& device, int baud, std::string* error);

  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;
  ~SerialPort();

  /// Writes `n` bytes; false (and counted) if the port would block (frame dropped) or failed.
  bool write(const uint8_t* data, std::size_t n);
  /// Reads up to `n` bytes without blocking; returns the count (0 = nothing), -1 on error.
  long read(uint8_t* data, std::size_t n);

  int64_t droppedWrites() const { return dropped_; }
  int64_t writeErrors() const { return errors_; }
  const std::string& device() const { return device_; }

 private:
  SerialPort(int fd, std::string device) : fd_(fd), device_(std::move(device)) {}
  int fd_ = -1;
  std::string device_;
  int64_t dropped_ = 0;
  int64_t errors_ = 0;
};

}  // namespace base_controller
}  // namespace ucon
