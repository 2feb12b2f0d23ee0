#pragma once
/// @file lidar_driver_node.hpp
/// The lidar driver's logic: Mid-360 datagrams in, LIDAR_POINTS frames and LIDAR_IMU samples
/// out. No sockets and no wall clock: time comes from the packets' sensor timestamps.

#include <array>
#include <cstddef>
#include <cstdint>
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

/// Totals since start (published on LIDAR_STATUS).
struct DriverCounters {
  int64_t datagrams = 0;          ///< every datagram given to the node
  int64_t point_packets = 0;      ///< valid point packets
  int64_t imu_packets = 0;        ///< valid IMU packets
  int64_t points = 0;             ///< points decoded from valid packets
  int64_t points_published = 0;   ///< points in published frames
  int64_t points_range_filtered = 0;  ///< outside [min_range_m, max_range_m]
  int64_t points_tag_filtered = 0;    ///< (tag & tag_drop_mask) != 0
  int64_t points_late = 0;        ///< before the frame being assembled, or in an out-of-order
                                  ///< packet: dropped
  int64_t points_overflow = 0;    ///< beyond frame.max_points: dropped
  int64_t frames = 0;             ///< published frames
  int64_t crc_errors = 0;         ///< packets with a bad crc32: dropped
  int64_t malformed = 0;          ///< other invalid packets (length, version, type, NaN, ...)
  int64_t lost_packets = 0;       ///< udp_cnt gaps, point and IMU streams
  int64_t out_of_order_packets = 0;  ///< udp_cnt went backwards (duplicate, reordered): dropped
  int64_t time_resets = 0;        ///< sensor time jumped back by more than 1 s
  /// Invalid packets by reason, indexed by livox::ParseStatus.
  std::array<int64_t, 8> by_status{};
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

/// Frame assembly: a point belongs to frame k = floor(t / T) of its sensor time t
/// (T = 1 / frame.rate_hz); a frame is published when the first point of a later frame
/// arrives (or on flush()). Frames are cut on these fixed boundaries, not on packet or
/// sensor frame_cnt boundaries, so a 50 Hz stream gives exactly 50 frames per sensor second.
class LidarDriverNode {
 public:
  /// `sensor_id` goes into every cloud (the sensor's IPv4 as an integer; 0 = unknown).
  explicit LidarDriverNode(const DriverParams& params, int64_t sensor_id = 0);

  /// Handles one UDP datagram. Complete frames and the IMU sample are written to `out`
  /// (cleared first). Invalid packets are counted and dropped; the status is returned.
  livox::ParseStatus onDatagram(const uint8_t* data, std::size_t size, DriverOutputs& out);

  /// A datagram too large for the receive buffer (cut by the kernel): counted as malformed.
  void onOversizeDatagram();

  /// Publishes the frame being assembled, if any (end of stream, or no packet for a while).
  std::optional<point_cloud_t> flush();

  const DriverCounters& counters() const { return counters_; }
  /// Latest sensor time seen [us]; 0 before the first valid packet.
  int64_t now() const { return now_us_; }
  /// point_cloud_t::TIME_* of the latest packet.
  int8_t timeSync() const { return time_sync_; }
  /// Writes counters and gauges into `report` (names as in DriverCounters).
  void report(StatusReport& report) const;

  /// "base" when the extrinsic is applied, else "lidar".
  const std::string& frameId() const { return frame_id_; }

 private:
  void handlePoints(const livox::ParsedPacket& pkt, DriverOutputs& out);
  void startFrame(int64_t index);
  void emitFrame(DriverOutputs& out);
  imu_t makeImu(const livox::ParsedPacket& pkt);

  DriverParams params_;
  int64_t sensor_id_;
  std::string frame_id_;
  uint64_t period_ns_;
  float rot_[9];    // row-major R
  float trans_[3];  // [m]
  float min_range2_, max_range2_;
  uint8_t tag_mask_;

  livox::ParsedPacket packet_;  // reused parse buffer
  SequenceTracker point_seq_, imu_seq_;
  uint64_t last_point_ts_ns_ = 0;  // timestamp of the latest accepted point packet
  uint64_t last_imu_ts_ns_ = 0;
  DriverCounters counters_;

  // Frame being assembled.
  point_cloud_t cur_;
  int64_t cur_index_ = -1;      // frame index k; -1 = none open
  bool cur_has_point_ = false;  // a point was appended (utime set)
  uint64_t cur_base_ns_ = 0;    // utime * 1000
  uint64_t cur_last_ns_ = 0;
  int32_t cur_lost_ = 0;
  std::size_t reserve_hint_ = 4096;

  int64_t frame_seq_ = 0;
  int64_t imu_seq_no_ = 0;
  int64_t now_us_ = 0;
  int8_t time_sync_ = point_cloud_t::TIME_NONE;
  int64_t last_frame_points_ = 0;
};

}  // namespace lidar_driver
}  // namespace ucon
