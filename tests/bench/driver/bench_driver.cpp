// ucon-bench-driver: (1) packet-parser throughput on one core, per data type, and the node's
// (parse + filter + transform + frame assembly) throughput; (2) the driver's CPU share while
// receiving a paced Mid-360 stream (200 000 points/s, 96-point packets) over loopback UDP:
// a sender thread paces the packets, the measured thread runs the driver's receive loop
// (poll, recvmmsg, node, LCM encoding of every frame) and its CPU time is read with
// CLOCK_THREAD_CPUTIME_ID. Prints medians; --json writes them.
#include <CLI/CLI.hpp>
#include <poll.h>
#include <pthread.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <random>
#include <thread>
#include <vector>

#include "ucon/cpu_time.hpp"
#include "ucon/lidar_driver/lidar_driver_node.hpp"
#include "ucon/lidar_driver/udp_socket.hpp"
#include "ucon/livox/protocol.hpp"

namespace ld = ucon::lidar_driver;
namespace livox = ucon::livox;

namespace {

using ucon::threadCpuSeconds;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? NAN : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

// A Mid-360-like stream: points on a sphere-ish scene, 5 us apart, 96 per packet, sensor
// frames of 208 packets (udp_cnt restarts), starting at t0.
std::vector<std::vector<uint8_t>> makePackets(int count, livox::DataType type, uint64_t t0_ns) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> range(0.5f, 30.0f), ang(0.0f, 6.2831853f), el(-0.12f, 0.9f);
  std::vector<std::vector<uint8_t>> out(static_cast<std::size_t>(count));
  std::vector<livox::LidarPoint> pts(livox::kPointsPerPacket);
  for (int k = 0; k < count; ++k) {
    for (auto& p : pts) {
      const float r = range(rng), a = ang(rng), e = el(rng);
      p = livox::LidarPoint{r * std::cos(e) * std::cos(a), r * std::cos(e) * std::sin(a),
                            r * std::sin(e), static_cast<uint8_t>(rng() & 0xFF), 0};
    }
    livox::PacketInfo info;
    info.timestamp_ns = t0_ns + static_cast<uint64_t>(k) * 96u * 5000u;
    info.time_interval = 4800;
    info.udp_cnt = static_cast<uint16_t>(k % 208);
    info.frame_cnt = static_cast<uint8_t>(k / 208);
    info.time_type = livox::TimeType::kPtp;
    livox::encodePointPacket(info, type, pts, out[static_cast<std::size_t>(k)]);
  }
  return out;
}

// Points/s of parsePacket over `packets`, median of `reps` passes of at least `min_s` each.
double parseThroughput(const std::vector<std::vector<uint8_t>>& packets, int reps, double min_s) {
  livox::ParsedPacket pkt;
  std::vector<double> rates;
  for (int r = 0; r < reps; ++r) {
    int64_t points = 0;
    const double t0 = ld::monotonicSeconds();
    double t1 = t0;
    do {
      for (const auto& p : packets) {
        if (livox::parsePacket(p.data(), p.size(), pkt) == livox::ParseStatus::kOk) {
          points += static_cast<int64_t>(pkt.points.size());
        }
      }
      t1 = ld::monotonicSeconds();
    } while (t1 - t0 < min_s);
    rates.push_back(static_cast<double>(points) / (t1 - t0));
  }
  return median(rates);
}

// Points/s through the whole node (parse, filter, extrinsic, frames).
double nodeThroughput(const std::vector<std::vector<uint8_t>>& packets, int reps) {
  ld::DriverParams params;  // defaults: extrinsic applied, range filter on, 50 Hz
  params.sensors[0].rpy_deg = {180.0, 0.0, 0.0};
  std::vector<double> rates;
  for (int r = 0; r < reps; ++r) {
    ld::LidarDriverNode node(params);
    ld::DriverOutputs out;
    const double t0 = ld::monotonicSeconds();
    for (const auto& p : packets) node.onDatagram(p.data(), p.size(), out);
    const double t1 = ld::monotonicSeconds();
    rates.push_back(static_cast<double>(node.counters().points) / (t1 - t0));
  }
  return median(rates);
}

struct CpuResult {
  double cpu_percent = NAN;      // receive thread CPU / wall [% of one core]
  double process_cpu_percent = NAN;  // whole process incl. the sender thread
  int64_t sent = 0, parsed = 0, frames = 0, lost = 0;
  double frames_per_s = 0;
};

CpuResult measureCpu(uint16_t port, double seconds) {
  CpuResult res;
  std::string err, warn;
  auto rx = ld::UdpSocket::open("127.0.0.1", port, 8 << 20, &err, &warn);
  if (!rx) {
    std::fprintf(stderr, "bench: %s\n", err.c_str());
    return res;
  }
  auto tx = ld::UdpSocket::open("127.0.0.1", static_cast<uint16_t>(port + 1), 0, &err, &warn);
  if (!tx) {
    std::fprintf(stderr, "bench: %s\n", err.c_str());
    return res;
  }
  const int packets_total = static_cast<int>(seconds * 200000.0 / 96.0);
  const auto packets = makePackets(packets_total, livox::DataType::kCartesianHigh, 1'000'000'000'000ull);

  ld::DriverParams params;
  params.sensors[0].rpy_deg = {180.0, 0.0, 0.0};
  ld::LidarDriverNode node(params);
  std::atomic<bool> sender_done{false};
  std::atomic<int64_t> sent{0};

  rusage ru0;
  getrusage(RUSAGE_SELF, &ru0);
  const double wall0 = ld::monotonicSeconds();
  std::thread sender([&] {
    // Pace: packet k leaves at wall0 + k * 480 us; wake every 1 ms and send what is due.
    timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    int k = 0;
    while (k < packets_total) {
      const double due_s = ld::monotonicSeconds() - wall0;
      const int due = std::min(packets_total, static_cast<int>(due_s / 480e-6) + 1);
      for (; k < due; ++k) {
        const auto& p = packets[static_cast<std::size_t>(k)];
        if (tx->sendTo({127, 0, 0, 1}, port, p.data(), p.size())) ++sent;
      }
      next.tv_nsec += 1'000'000;
      if (next.tv_nsec >= 1'000'000'000) {
        next.tv_nsec -= 1'000'000'000;
        ++next.tv_sec;
      }
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
    }
    sender_done = true;
  });

  // The driver's loop, as in procs/lidar_driver/src/main.cpp, minus the LCM send itself:
  // every frame is encoded into the buffer LCM would send.
  const double cpu0 = threadCpuSeconds();
  ld::DriverOutputs out;
  std::vector<uint8_t> encoded;
  int64_t frames = 0;
  double last_rx = ld::monotonicSeconds();
  for (;;) {
    pollfd pfd{rx->fd(), POLLIN, 0};
    ::poll(&pfd, 1, 10);
    const double now = ld::monotonicSeconds();
    int n = 0;
    while ((n = rx->receiveBatch()) > 0) {
      last_rx = now;
      for (int i = 0; i < n; ++i) {
        node.onDatagram(rx->data(i), rx->size(i), out);
        for (const auto& c : out.clouds) {
          encoded.resize(static_cast<std::size_t>(c.getEncodedSize()));
          c.encode(encoded.data(), 0, static_cast<int>(encoded.size()));
          ++frames;
        }
      }
      if (n < ld::UdpSocket::kBatch) break;
    }
    if (sender_done && now - last_rx > 0.1) break;
  }
  const double cpu1 = threadCpuSeconds();
  const double wall1 = last_rx;  // the receive loop's working span (excludes the final idle wait)
  sender.join();
  rusage ru1;
  getrusage(RUSAGE_SELF, &ru1);
  const auto tv = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * t.tv_usec; };
  const double proc_cpu = tv(ru1.ru_utime) - tv(ru0.ru_utime) + tv(ru1.ru_stime) - tv(ru0.ru_stime);
  const double wall = wall1 - wall0;
  res.cpu_percent = 100.0 * (cpu1 - cpu0) / wall;
  res.process_cpu_percent = 100.0 * proc_cpu / (ld::monotonicSeconds() - wall0);
  res.sent = sent;
  res.parsed = node.counters().point_packets;
  res.frames = frames;
  res.lost = node.counters().lost_packets;
  res.frames_per_s = static_cast<double>(frames) / wall;
  return res;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Lidar driver benchmark: parser throughput and CPU share at the Mid-360 rate."};
  std::string json_path;
  bool quick = false;
  int port = 27050;
  app.add_option("--json", json_path, "write the results as JSON to this file");
  app.add_flag("--quick", quick, "short run (ctest)");
  app.add_option("--port", port, "loopback UDP port for the CPU measurement (uses port+1 too)")
      ->check(CLI::Range(1024, 65534));
  CLI11_PARSE(app, argc, argv);

  const int reps = quick ? 3 : 7;
  const double min_s = quick ? 0.05 : 0.3;
  const auto t1 = makePackets(2000, livox::DataType::kCartesianHigh, 1'000'000'000ull);
  const auto t2 = makePackets(2000, livox::DataType::kCartesianLow, 1'000'000'000ull);
  const auto t3 = makePackets(2000, livox::DataType::kSpherical, 1'000'000'000ull);
  const double p1 = parseThroughput(t1, reps, min_s);
  const double p2 = parseThroughput(t2, reps, min_s);
  const double p3 = parseThroughput(t3, reps, min_s);
  const double nd = nodeThroughput(t1, reps);
  const CpuResult cpu = measureCpu(static_cast<uint16_t>(port), quick ? 1.0 : 5.0);

  const double parsed_share = cpu.sent > 0 ? static_cast<double>(cpu.parsed) / static_cast<double>(cpu.sent) : 0.0;
  std::printf("lidar driver benchmark (%s)\n", quick ? "quick" : "full");
  std::printf("  parser, type 1 (cartesian high)  %8.1f M points/s  (median of %d; target >= 20)  %s\n",
              p1 / 1e6, reps, p1 >= 20e6 ? "OK" : "MISSED");
  std::printf("  parser, type 2 (cartesian low)   %8.1f M points/s\n", p2 / 1e6);
  std::printf("  parser, type 3 (spherical)       %8.1f M points/s\n", p3 / 1e6);
  std::printf("  node (parse+filter+extrinsic+frames) %6.1f M points/s\n", nd / 1e6);
  std::printf("  driver CPU at 200 000 points/s   %8.2f %% of one core (receive thread; target <= 5)  %s\n",
              cpu.cpu_percent, cpu.cpu_percent <= 5.0 ? "OK" : "MISSED");
  std::printf("  whole bench process incl. sender %8.2f %%\n", cpu.process_cpu_percent);
  std::printf("  packets sent %lld, parsed %lld (%.3f %%), lost %lld, frames %lld (%.1f /s)\n",
              static_cast<long long>(cpu.sent), static_cast<long long>(cpu.parsed), 100.0 * parsed_share,
              static_cast<long long>(cpu.lost), static_cast<long long>(cpu.frames), cpu.frames_per_s);

  if (!json_path.empty()) {
    std::ofstream j(json_path);
    char buf[1024];
    std::snprintf(buf, sizeof(buf),
                  "{\n  \"parse_points_per_s\": %.0f,\n  \"parse_points_per_s_type2\": %.0f,\n"
                  "  \"parse_points_per_s_type3\": %.0f,\n  \"node_points_per_s\": %.0f,\n"
                  "  \"driver_cpu_percent\": %.3f,\n  \"process_cpu_percent\": %.3f,\n"
                  "  \"packets_sent\": %lld,\n  \"packets_parsed\": %lld,\n  \"lost_packets\": %lld,\n"
                  "  \"frames\": %lld,\n  \"frames_per_s\": %.2f,\n  \"quick\": %s\n}\n",
                  p1, p2, p3, nd, cpu.cpu_percent, cpu.process_cpu_percent,
                  static_cast<long long>(cpu.sent), static_cast<long long>(cpu.parsed),
                  static_cast<long long>(cpu.lost), static_cast<long long>(cpu.frames),
                  cpu.frames_per_s, quick ? "true" : "false");
    j << buf;
    if (!j) {
      std::fprintf(stderr, "cannot write %s\n", json_path.c_str());
      return 1;
    }
  }
  // Functional check (timings are reported, not enforced: the machine may be shared).
  if (cpu.sent == 0 || parsed_share < 0.999) {
    std::fprintf(stderr, "FAIL: only %.3f %% of the sent packets were parsed\n", 100.0 * parsed_share);
    return 1;
  }
  return 0;
}
