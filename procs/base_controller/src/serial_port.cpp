#include "ucon/base_controller/serial_port.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

namespace ucon {
namespace base_controller {

namespace {
bool baudConstant(int baud, speed_t* out) {
  switch (baud) {
    case 9600: *out = B9600; return true;
    case 19200: *out = B19200; return true;
    case 38400: *out = B38400; return true;
    case 57600: *out = B57600; return true;
    case 115200: *out = B115200; return true;
    case 230400: *out = B230400; return true;
    case 460800: *out = B460800; return true;
    case 921600: *out = B921600; return true;
    default: return false;
  }
}
}  // namespace

std::unique_ptr<SerialPort> SerialPort::open(const std::string& device, int baud, std::string* error) {
  speed_t speed;
  if (!baudConstant(baud, &speed)) {
    if (error) *error = "unsupported baud rate " + std::to_string(baud);
    return nullptr;
  }
  const int fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (error) *error = "cannot open " + device + ": " + std::strerror(errno);
    return nullptr;
  }
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) {
    if (error) *error = device + " is not a tty: " + std::strerror(errno);
    ::close(fd);
    return nullptr;
  }
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS | PARENB);
  tio.c_cflag = (tio.c_cflag & ~static_cast<tcflag_t>(CSIZE)) | CS8;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) {
    if (error) *error = "cannot configure " + device + ": " + std::strerror(errno);
    ::close(fd);
    return nullptr;
  }
  return std::unique_ptr<SerialPort>(new SerialPort(fd, device));
}

SerialPort::~SerialPort() {
  if (fd_ >= 0) ::close(fd_);
}

bool SerialPort::write(const uint8_t* data, std::size_t n) {
  // A signal arriving during the call (SIGTERM at shutdown: the handlers are installed without
  // SA_RESTART so that waits end) interrupts it before anything is written: try again, or the
  // frame is lost. A full kernel buffer (EAGAIN) with nothing written drops the frame. After a
  // partial write the rest is still offered (the board would see a torn frame); if the kernel
  // takes no more, that counts as an error and the board resynchronises on the next sync word.
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd_, data + done, n - done);
    if (w > 0) {
      done += static_cast<std::size_t>(w);
      continue;
    }
    if (w < 0 && errno == EINTR) continue;
    if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK) && done == 0) {
      ++dropped_;
    } else {
      ++errors_;
    }
    return false;
  }
  return true;
}

long SerialPort::read(uint8_t* data, std::size_t n) {
  ssize_t r;
  do {
    r = ::read(fd_, data, n);
  } while (r < 0 && errno == EINTR);
  if (r < 0) return (errno == EAGAIN || errno == EWOULDBLOCK) ? 0 : -1;
  return static_cast<long>(r);
}

}  // namespace base_controller
}  // namespace ucon
