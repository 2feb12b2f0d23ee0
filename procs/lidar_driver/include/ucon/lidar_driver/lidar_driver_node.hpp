#pragma once
/// @file lidar_driver_node.hpp
/// The lidar driver's logic: Mid-360 datagrams of one or several sensors in, LIDAR_POINTS
/// frames and LIDAR_IMU samples out. No sockets and no wall clock: time comes from the
/// packets' sensor timestamps; the host receive time given with a datagram is only used to
/// estimate each sensor's clock offset.

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "ucon/imu_t.hpp"
#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/lidar_driver/sequence_tracker.hpp"
#include "ucon/livox/packet_parser.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/status_report.hpp"

namespace ucon {
namespace lidar_driver {

/// Totals since start, all sensors together (published on LIDAR_STATUS).
struct DriverCounters {
  int64_t datagrams = 0;          ///< every datagram given to the node
  int64_t point_packets = 0;      ///< valid point packets
  int64_t imu_packets = 0;        ///< valid IMU packets of the IMU sensor
  int64_t imu_ignored = 0;        ///< valid IMU packets of the other sensors: not published
  int64_t points = 0;             ///< points decoded from valid packets
  int64_t points_published = 0;   ///< points in published frames
  int64_t points_range_filtered = 0;  ///< outside [min_range_m, max_range_m]
  int64_t points_tag_filtered = 0;    ///< a tag confidence at or above its drop level
  int64_t points_bad_records = 0;     ///< records that are no measurement (spherical angle out
                                      ///< of range): only they are dropped, not their packet
  int64_t points_late = 0;        ///< in a frame already published, or in an out-of-order
                                  ///< packet: dropped
  int64_t points_overflow = 0;    ///< beyond frame.max_points: dropped
  int64_t frames = 0;             ///< published frames
  int64_t crc_errors = 0;         ///< packets dropped for a crc32 mismatch (see CrcPolicy)
  int64_t crc_mismatches_kept = 0;  ///< crc32 mismatches kept (the field was not trusted yet)
  int64_t crc_absent = 0;         ///< packets whose crc32 field is 0 (kept)
  int64_t malformed = 0;          ///< other invalid packets (length, version, type, NaN, ...)
  int64_t lost_packets = 0;       ///< udp_cnt gaps, point and IMU streams
  int64_t out_of_order_packets = 0;  ///< udp_cnt went backwards (duplicate, reordered): dropped
  int64_t time_resets = 0;        ///< a sensor's time jumped back by more than 1 s
  /// Invalid packets by reason, indexed by livox::ParseStatus.
  std::array<int64_t, 8> by_status{};
};

/// What the node knows about one sensor's stream.
struct SensorStream {
  int64_t point_packets = 0;
  int64_t imu_packets = 0;
  int8_t time_sync = point_cloud_t::TIME_NONE;  ///< TIME_* of its latest packet
  bool have_time = false;       ///< a valid packet arrived
  /// Host clock minus sensor clock [ns] (the smallest host receive time minus sensor send
  /// time over the last second: clock offset plus the smallest transport delay).
  bool offset_valid = false;
  int64_t host_minus_sensor_ns = 0;
  int64_t correction_ns = 0;    ///< added to this sensor's times to bring them onto sensor 0's
                                ///< clock (0 unless the clocks differ by 10 ms or more)
};

/// What one datagram produced.
struct DriverOutputs {
  std::vector<point_cloud_t> clouds;  ///< frames completed by this datagram (usually 0 or 1)
  std::optional<imu_t> imu;           ///< the IMU sample it carried
  void clear() {
    clouds.clear();
    imu.reset();
  }
};

/// The crc32 field of a point packet. Livox's SDK and ROS driver never check it, so a sensor
/// that leaves it 0 or fills it some other way must not lose data; but where a sensor fills it
/// as the protocol says, it protects against corrupt packets. So, per sensor: a 0 field is
/// never checked; a packet whose non-zero field mismatches is dropped only once the field has
/// matched on kCrcTrustAfter packets in a row (it is then known to be filled correctly);
/// before that it is kept and counted. kCrcTrustAfter mismatches in a row withdraw the trust
/// (the sensor changed how it fills the field).
constexpr int kCrcTrustAfter = 8;

/// Frame assembly: a point belongs to frame k = floor(t / T) of its time t (T = 1 /
/// frame.rate_hz; several sensors: t on sensor 0's clock). Frame k is published once every
/// sensor still sending has passed (k + 1) T (a sensor lagging the others by more than
/// frame.merge_wait_s is not waited for), or on flush(). Frames are cut on these fixed
/// boundaries, not on packets or the sensors' frame_cnt, so a 50 Hz stream gives exactly 50
/// frames per sensor second. Several sensors' points go into one frame per period, in the body
/// frame, each with the index of its sensor (point_cloud_t::point_sensor).
class LidarDriverNode {
 public:
  explicit LidarDriverNode(const DriverParams& params);

  /// Sensor `i`'s address (the cloud's sensor id); listed sensors get theirs at construction,
  /// an "auto" sensor when it is found.
  void setSensorAddress(std::size_t i, const std::array<uint8_t, 4>& ip);

  /// Handles one UDP datagram of sensor `sensor` (index into params.sensors), received at host
  /// time `host_time_ns` (CLOCK_REALTIME [ns]; 0 = unknown). Complete frames and the IMU sample
  /// are written to `out` (cleared first). Invalid packets are counted and dropped; the status
  /// is returned (kBadCrc when the crc policy dropped it).
  livox::ParseStatus onDatagram(std::size_t sensor, const uint8_t* data, std::size_t size,
                                int64_t host_time_ns, DriverOutputs& out);
  /// One-sensor form (sensor 0, host time unknown).
  livox::ParseStatus onDatagram(const uint8_t* data, std::size_t size, DriverOutputs& out) {
    return onDatagram(0, data, size, 0, out);
  }

  /// A datagram too large for the receive buffer (cut by the kernel): counted as malformed.
  void onOversizeDatagram();

  /// Publishes every frame being assembled (end of stream, or no packet for a while).
  std::vector<point_cloud_t> flushAll();
  /// The first of flushAll() (one-sensor use, tests).
  std::optional<point_cloud_t> flush();

  const DriverCounters& counters() const { return counters_; }
  const SensorStream& stream(std::size_t i) const { return streams_[i]; }
  std::size_t sensorCount() const { return sensors_.size(); }
  /// Latest time seen [us] (sensor 0's clock); 0 before the first valid packet.
  int64_t now() const { return now_us_; }
  /// point_cloud_t::TIME_* of the least synchronised sensor.
  int8_t timeSync() const;
  /// Writes counters and gauges into `report` (names as in DriverCounters; per sensor
  /// "time_sync", "host_minus_sensor_ms", suffixed "_s<i>" for sensors after the first).
  void report(StatusReport& report) const;

  /// "base" when the extrinsic is applied, else "lidar".
  const std::string& frameId() const { return frame_id_; }

 private:
  struct Sensor {
    float rot[9];    // row-major R
    float trans[3];  // [m]
    float origin[3];  // [m] in the published frame
    int64_t id = 0;
    bool imu = false;
    SequenceTracker point_seq, imu_seq;
    uint64_t last_point_ts_ns = 0;
    uint64_t last_imu_ts_ns = 0;
    int crc_matches_in_row = 0;
    int crc_mismatches_in_row = 0;
    bool crc_trusted = false;
    int64_t watermark_ns = -1;   // latest point time, common clock; -1 = none yet
    int64_t window_start_ns = 0;  // host time the offset window opened
    int64_t window_min_ns = 0;    // smallest host - sensor in the window
    bool window_open = false;
  };
  struct OpenFrame {
    int64_t index = 0;
    point_cloud_t cloud;
    int64_t min_off_ns = 0, max_off_ns = 0;  // point times relative to index * T
    bool has_point = false;
    int32_t lost = 0;
    int8_t time_sync = -1;  // TIME_* of its least synchronised point; -1 none yet
  };

  bool crcAccepts(Sensor& s, livox::CrcCheck crc);
  void observeHostTime(std::size_t i, int64_t host_time_ns, uint64_t sensor_ts_ns);
  void handlePoints(std::size_t i, const livox::ParsedPacket& pkt, DriverOutputs& out);
  OpenFrame* frameFor(int64_t index);
  void emitReady(DriverOutputs& out);
  void emitFront(DriverOutputs& out);
  void resetAssembly(DriverOutputs& out);
  imu_t makeImu(const Sensor& s, const livox::ParsedPacket& pkt, int64_t correction_ns);

  DriverParams params_;
  std::string frame_id_;
  int64_t period_ns_;
  float min_range2_, max_range2_;
  std::array<bool, 256> drop_tag_{};
  bool multi_;
  int64_t merge_wait_ns_;

  livox::ParsedPacket packet_;  // reused parse buffer
  std::vector<Sensor> sensors_;
  std::vector<SensorStream> streams_;
  DriverCounters counters_;

  std::deque<OpenFrame> open_;       // frames being assembled, by index
  int64_t emitted_upto_ = INT64_MIN;  // index of the last published frame
  std::size_t reserve_hint_ = 4096;

  int64_t frame_seq_ = 0;
  int64_t imu_seq_no_ = 0;
  int64_t now_us_ = 0;
  int64_t last_frame_points_ = 0;
};

}  // namespace lidar_driver
}  // namespace ucon
