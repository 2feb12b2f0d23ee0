#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

#include "ucon/base_controller/motor_backend.hpp"
#include "ucon/base_controller/serial_frame.hpp"
#include "ucon/base_controller/serial_port.hpp"

using namespace ucon::base_controller;

TEST(SerialFrame, GivenTheCheckStringThenCrc16IsTheCcittFalseCheckValue) {
  const char* s = "123456789";
  EXPECT_EQ(crc16CcittFalse(reinterpret_cast<const uint8_t*>(s), 9), 0x29B1);
}

TEST(SerialFrame, GivenSpeedsThenEncodedLayoutIsAsDocumented) {
  const auto f = encodeWheelFrame(0x1234, true, {1.0, -1.0, 327.67, -0.004});
  EXPECT_EQ(f[0], 0xAA);
  EXPECT_EQ(f[1], 0x55);
  EXPECT_EQ(f[2], 1);
  EXPECT_EQ(f[3], 1);
  EXPECT_EQ(f[4], 0x34);  // little-endian sequence number
  EXPECT_EQ(f[5], 0x12);
  EXPECT_EQ(f[6], 100);   // 1.0 rad/s = 100 counts = 0x0064
  EXPECT_EQ(f[7], 0);
  EXPECT_EQ(f[8], 0x9C);  // -100 = 0xFF9C
  EXPECT_EQ(f[9], 0xFF);
  EXPECT_EQ(f[10], 0xFF);  // 32767 = 0x7FFF
  EXPECT_EQ(f[11], 0x7F);
  EXPECT_EQ(f[12], 0);     // -0.4 counts rounds to 0
  EXPECT_EQ(f[13], 0);
  const uint16_t crc = crc16CcittFalse(f.data(), 14);
  EXPECT_EQ(f[14], crc & 0xFF);
  EXPECT_EQ(f[15], crc >> 8);
}

TEST(SerialFrame, GivenAFrameWhenDecodedThenRoundTripsAndClampsOutOfRange) {
  int clamped = -1;
  const auto f = encodeWheelFrame(65535, false, {12.34, -0.01, 400.0, -400.0}, &clamped);
  EXPECT_EQ(clamped, 2);
  WheelFrame d;
  ASSERT_EQ(decodeWheelFrame(f.data(), f.size(), &d), FrameStatus::kOk);
  EXPECT_EQ(d.seq, 65535);
  EXPECT_FALSE(d.enable);
  EXPECT_NEAR(d.speeds()[0], 12.34, 1e-9);
  EXPECT_NEAR(d.speeds()[1], -0.01, 1e-9);
  EXPECT_NEAR(d.speeds()[2], 327.67, 1e-9);
  EXPECT_NEAR(d.speeds()[3], -327.67, 1e-9);
}

TEST(SerialFrame, GivenNaNSpeedThenFrameIsDisabledAndZero) {
  const auto f = encodeWheelFrame(1, true, {1.0, std::nan(""), 0, 0});
  WheelFrame d;
  ASSERT_EQ(decodeWheelFrame(f.data(), f.size(), &d), FrameStatus::kOk);
  EXPECT_FALSE(d.enable);
  EXPECT_EQ(d.raw[0], 0);
}

TEST(SerialFrame, GivenCorruptFramesThenEachErrorIsNamed) {
  auto f = encodeWheelFrame(7, true, {1, 2, 3, 4});
  EXPECT_EQ(decodeWheelFrame(f.data(), 15, nullptr), FrameStatus::kTooShort);
  auto g = f;
  g[8] ^= 0x01;
  EXPECT_EQ(decodeWheelFrame(g.data(), g.size(), nullptr), FrameStatus::kBadCrc);
  g = f;
  g[0] = 0xAB;
  EXPECT_EQ(decodeWheelFrame(g.data(), g.size(), nullptr), FrameStatus::kBadSync);
  g = f;
  g[2] = 2;  // a future version with a valid CRC
  const uint16_t crc = crc16CcittFalse(g.data(), 14);
  g[14] = crc & 0xFF;
  g[15] = crc >> 8;
  EXPECT_EQ(decodeWheelFrame(g.data(), g.size(), nullptr), FrameStatus::kBadVersion);
  EXPECT_STREQ(toString(FrameStatus::kBadCrc), "bad crc");
}

TEST(WheelFrameParser, GivenGarbageSplitFramesAndACorruptOneThenResynchronises) {
  std::vector<uint8_t> stream = {0x00, 0xAA, 0x13, 0x55, 0xAA};  // noise, a false sync start
  const auto a = encodeWheelFrame(1, true, {1, 0, 0, 0});
  auto bad = encodeWheelFrame(2, true, {2, 0, 0, 0});
  bad[10] ^= 0xFF;
  const auto c = encodeWheelFrame(3, true, {3, 0, 0, 0});
  stream.insert(stream.end(), a.begin(), a.end());
  stream.insert(stream.end(), bad.begin(), bad.end());
  stream.insert(stream.end(), c.begin(), c.end());
  WheelFrameParser parser;
  std::vector<WheelFrame> got;
  for (std::size_t i = 0; i < stream.size(); i += 7) {  // arbitrary chunking
    const std::size_t n = std::min<std::size_t>(7, stream.size() - i);
    const auto frames = parser.feed(stream.data() + i, n);
    got.insert(got.end(), frames.begin(), frames.end());
  }
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].seq, 1);
  EXPECT_EQ(got[1].seq, 3);
  EXPECT_NEAR(got[1].speeds()[0], 3.0, 1e-12);
  EXPECT_GE(parser.crcErrors(), 1);
}

namespace {
/// A pseudo-terminal pair: the master side plays the motor board.
struct Pty {
  int master = -1;
  std::string slave;
  Pty() {
    master = posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return;
    const char* name = ptsname(master);
    if (name) slave = name;
    termios t{};
    tcgetattr(master, &t);
    cfmakeraw(&t);
    tcsetattr(master, TCSANOW, &t);
  }
  ~Pty() {
    if (master >= 0) close(master);
  }
  // Appends what the board side can read within `timeout_ms` (0: what is there now).
  void readAvailable(std::vector<uint8_t>* out, int timeout_ms) {
    pollfd p{master, POLLIN, 0};
    while (poll(&p, 1, timeout_ms) > 0 && (p.revents & POLLIN)) {
      uint8_t buf[4096];
      const ssize_t n = read(master, buf, sizeof(buf));
      if (n <= 0) break;
      out->insert(out->end(), buf, buf + n);
      timeout_ms = 0;
    }
  }
  std::vector<uint8_t> readFor(int ms, std::size_t want) {
    std::vector<uint8_t> out;
    for (int waited = 0; waited < ms && out.size() < want; waited += 10) readAvailable(&out, 10);
    return out;
  }
};
}  // namespace

TEST(SerialMotorBackend, GivenAPtyWhenCommandsSentThenTheBoardSideDecodesThemInMotorOrder) {
  Pty pty;
  ASSERT_FALSE(pty.slave.empty()) << "posix_openpt failed";
  std::string err;
  auto port = SerialPort::open(pty.slave, 115200, &err);
  ASSERT_TRUE(port) << err;
  ucon::mecanum::MecanumParams geo;
  geo.motor_order = {1, 0, 3, 2};
  geo.motor_sign = {1, -1, 1, -1};
  SerialMotorBackend backend(std::move(port), geo);
  ucon::wheel_cmd_t cmd{};
  cmd.enable = true;
  cmd.w_fl = 1.5;
  cmd.w_fr = -2.25;
  cmd.w_rl = 10.0;
  cmd.w_rr = 0.0;
  ASSERT_TRUE(backend.send(cmd));
  cmd.enable = false;
  ASSERT_TRUE(backend.send(cmd));

  const std::vector<uint8_t> bytes = pty.readFor(2000, 2 * kWheelFrameSize);
  WheelFrameParser parser;
  const auto frames = parser.feed(bytes.data(), bytes.size());
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].seq, 0);
  EXPECT_EQ(frames[1].seq, 1);
  EXPECT_TRUE(frames[0].enable);
  EXPECT_FALSE(frames[1].enable);
  const auto s = frames[0].speeds();  // channel i = sign[i] * wheel[order[i]]
  EXPECT_NEAR(s[0], -2.25, 1e-9);     // FR
  EXPECT_NEAR(s[1], -1.5, 1e-9);      // -FL
  EXPECT_NEAR(s[2], 0.0, 1e-9);       // RR
  EXPECT_NEAR(s[3], -10.0, 1e-9);     // -RL
  EXPECT_EQ(parser.crcErrors(), 0);
  for (const auto& [name, value] : backend.counters()) {
    if (name == "motor_cmds_sent") {
      EXPECT_EQ(value, 2);
    }
  }
}

namespace {
std::atomic<int> g_usr1_count{0};
void onUsr1(int) { g_usr1_count.fetch_add(1, std::memory_order_relaxed); }
}  // namespace

// The processes install their SIGTERM/SIGINT handlers without SA_RESTART (so that a wait ends at
// once); a signal arriving while a frame is being written must not lose that frame.
TEST(SerialPort, GivenSignalsArrivingDuringWritesThenNoFrameIsLost) {
  Pty pty;
  ASSERT_FALSE(pty.slave.empty()) << "posix_openpt failed";
  std::string err;
  auto port = SerialPort::open(pty.slave, 115200, &err);
  ASSERT_TRUE(port) << err;
  struct sigaction sa {}, old {};
  sa.sa_handler = onUsr1;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART, as in the processes
  ASSERT_EQ(sigaction(SIGUSR1, &sa, &old), 0);

  constexpr int kMinFrames = 500, kMaxFrames = 60000, kMinSignals = 200;
  std::atomic<bool> done{false};
  const pthread_t writer = pthread_self();
  std::thread pester([&] {
    while (!done.load()) {
      pthread_kill(writer, SIGUSR1);
      std::this_thread::sleep_for(std::chrono::microseconds(5));
    }
  });
  std::vector<uint8_t> bytes;
  int failed = 0, written = 0;
  // Write until enough signals have arrived (the seq wraps at 65536, so stay below).
  for (int i = 0; i < kMaxFrames && (i < kMinFrames || g_usr1_count.load() < kMinSignals); ++i, ++written) {
    const auto f = encodeWheelFrame(static_cast<uint16_t>(i), true, {1.0, 2.0, 3.0, 4.0});
    if (!port->write(f.data(), f.size())) ++failed;
    if (i % 64 == 0) pty.readAvailable(&bytes, 0);
  }
  done = true;
  pester.join();
  sigaction(SIGUSR1, &old, nullptr);
  const std::vector<uint8_t> rest = pty.readFor(2000, written * kWheelFrameSize - bytes.size());
  bytes.insert(bytes.end(), rest.begin(), rest.end());

  EXPECT_GE(g_usr1_count.load(), kMinSignals) << "the test did not interrupt the writer";
  EXPECT_EQ(failed, 0);
  EXPECT_EQ(port->droppedWrites(), 0);
  EXPECT_EQ(port->writeErrors(), 0);
  WheelFrameParser parser;
  const auto frames = parser.feed(bytes.data(), bytes.size());
  ASSERT_EQ(frames.size(), static_cast<std::size_t>(written));
  for (int i = 0; i < written; ++i) ASSERT_EQ(frames[static_cast<std::size_t>(i)].seq, static_cast<uint16_t>(i));
  EXPECT_EQ(parser.crcErrors(), 0);
}

TEST(SerialPort, GivenBadDeviceOrBaudThenClearError) {
  std::string err;
  EXPECT_FALSE(SerialPort::open("/nonexistent/tty", 115200, &err));
  EXPECT_NE(err.find("/nonexistent/tty"), std::string::npos);
  EXPECT_FALSE(SerialPort::open("/dev/null", 12345, &err));
  EXPECT_NE(err.find("baud"), std::string::npos);
  EXPECT_FALSE(SerialPort::open("/dev/null", 115200, &err));  // not a tty
  EXPECT_NE(err.find("tty"), std::string::npos) << err;
}
