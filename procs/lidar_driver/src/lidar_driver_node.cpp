#include "ucon/lidar_driver/lidar_driver_node.hpp"

#include <cmath>

namespace ucon {
namespace lidar_driver {

namespace {
constexpr uint64_t kTimeResetNs = 1'000'000'000ull;  // a jump back this large restarts assembly

int8_t timeSyncOf(uint8_t time_type) {
  switch (time_type) {
    case 1: return point_cloud_t::TIME_PTP;
    case 2: return point_cloud_t::TIME_GPS;
    default: return point_cloud_t::TIME_NONE;
  }
}

// R = Rz(yaw) * Ry(pitch) * Rx(roll), row-major.
void rotationFromRpy(double roll, double pitch, double yaw, float* r) {
  const double cr = std::cos(roll), sr = std::sin(roll);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double m[9] = {cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
                       sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
                       -sp,     cp * sr,                cp * cr};
  for (int i = 0; i < 9; ++i) r[i] = static_cast<float>(m[i]);
}
}  // namespace

LidarDriverNode::LidarDriverNode(const DriverParams& params, int64_t sensor_id)
    : params_(params), sensor_id_(sensor_id) {
  frame_id_ = params_.extrinsic.apply ? "base" : "lidar";
  period_ns_ = 1'000'000'000ull / static_cast<uint64_t>(params_.frame.rate_hz);
  const double d2r = 3.14159265358979323846 / 180.0;
  if (params_.extrinsic.apply) {
    rotationFromRpy(params_.extrinsic.rpy_deg[0] * d2r, params_.extrinsic.rpy_deg[1] * d2r,
                    params_.extrinsic.rpy_deg[2] * d2r, rot_);
    for (int i = 0; i < 3; ++i) trans_[i] = static_cast<float>(params_.extrinsic.xyz[i]);
  } else {
    const float id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int i = 0; i < 9; ++i) rot_[i] = id[i];
    for (float& t : trans_) t = 0;
  }
  min_range2_ = static_cast<float>(params_.filter.min_range_m * params_.filter.min_range_m);
  max_range2_ = static_cast<float>(params_.filter.max_range_m * params_.filter.max_range_m);
  tag_mask_ = static_cast<uint8_t>(params_.filter.tag_drop_mask);
  packet_.points.reserve(livox::kPointsPerPacket);
}

livox::ParseStatus LidarDriverNode::onDatagram(const uint8_t* data, std::size_t size,
                                               DriverOutputs& out) {
  out.clear();
  ++counters_.datagrams;
  const livox::ParseStatus st = livox::parsePacket(data, size, packet_);
  if (st != livox::ParseStatus::kOk) {
    ++counters_.by_status[static_cast<std::size_t>(st)];
    if (st == livox::ParseStatus::kBadCrc) {
      ++counters_.crc_errors;
    } else {
      ++counters_.malformed;
    }
    return st;
  }
  time_sync_ = timeSyncOf(packet_.header.time_type);
  const int64_t t_us = static_cast<int64_t>(packet_.header.timestamp_ns / 1000u);
  if (t_us > now_us_) now_us_ = t_us;

  if (packet_.type == livox::DataType::kImu) {
    ++counters_.imu_packets;
    const uint64_t ts = packet_.header.timestamp_ns;
    if (ts + kTimeResetNs < last_imu_ts_ns_) imu_seq_.reset();
    auto r = imu_seq_.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
    if (r.out_of_order && ts > last_imu_ts_ns_) {
      imu_seq_.reset();
      r = imu_seq_.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
    }
    last_imu_ts_ns_ = ts;
    counters_.lost_packets += r.lost;
    if (r.out_of_order) ++counters_.out_of_order_packets;
    out.imu = makeImu(packet_);
    return st;
  }

  ++counters_.point_packets;
  const uint64_t ts = packet_.header.timestamp_ns;
  // The sensor clock went far back: a reboot or a time-sync switch; its counters restart too.
  if (ts + kTimeResetNs < last_point_ts_ns_) point_seq_.reset();
  auto r = point_seq_.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
  if (r.out_of_order && ts > last_point_ts_ns_) {
    // udp_cnt went back but time went forward: the counters restarted, the data is new.
    point_seq_.reset();
    r = point_seq_.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
  }
  counters_.lost_packets += r.lost;
  if (r.out_of_order) {
    // A duplicate or a reordered packet: its points would repeat or go back in time. Over a
    // direct link both are rare; drop the packet rather than risk duplicated points.
    ++counters_.out_of_order_packets;
    counters_.points += static_cast<int64_t>(packet_.points.size());
    counters_.points_late += static_cast<int64_t>(packet_.points.size());
    return st;
  }
  last_point_ts_ns_ = ts;
  // The gap precedes this packet: it belongs to the frame this packet's first point opens
  // or continues.
  if (r.lost > 0 && !packet_.points.empty()) {
    const int64_t k = static_cast<int64_t>(packet_.points.front().time_ns / period_ns_);
    if (cur_index_ < 0) {
      startFrame(k);
    } else if (k > cur_index_) {
      emitFrame(out);
      startFrame(k);
    }
    cur_lost_ += static_cast<int32_t>(r.lost);
  }
  handlePoints(packet_, out);
  return st;
}

void LidarDriverNode::onOversizeDatagram() {
  ++counters_.datagrams;
  ++counters_.malformed;
  ++counters_.by_status[static_cast<std::size_t>(livox::ParseStatus::kBadLength)];
}

void LidarDriverNode::startFrame(int64_t index) {
  cur_ = point_cloud_t{};
  cur_.x.reserve(reserve_hint_);
  cur_.y.reserve(reserve_hint_);
  cur_.z.reserve(reserve_hint_);
  cur_.t_offset_ns.reserve(reserve_hint_);
  cur_.reflectivity.reserve(reserve_hint_);
  cur_.tag.reserve(reserve_hint_);
  cur_index_ = index;
  cur_has_point_ = false;
  cur_base_ns_ = 0;
  cur_last_ns_ = 0;
  cur_lost_ = 0;
}

void LidarDriverNode::emitFrame(DriverOutputs& out) {
  if (cur_index_ < 0) return;
  point_cloud_t& c = cur_;
  if (!cur_has_point_) {
    // No point survived the filters: the frame still happened; stamp it with its start.
    c.utime = static_cast<int64_t>(static_cast<uint64_t>(cur_index_) * period_ns_ / 1000u);
    c.duration_us = 0;
  } else {
    c.duration_us = static_cast<int32_t>((cur_last_ns_ - cur_base_ns_) / 1000u);
  }
  if (c.utime <= 0) c.utime = 1;  // 0 means invalid on the bus
  c.seq = frame_seq_++;
  c.frame_id = frame_id_;
  c.sensor_id = sensor_id_;
  c.time_sync = time_sync_;
  c.lost_packets = cur_lost_;
  c.num_points = static_cast<int32_t>(c.x.size());
  ++counters_.frames;
  counters_.points_published += c.num_points;
  last_frame_points_ = c.num_points;
  reserve_hint_ = static_cast<std::size_t>(c.num_points) + c.num_points / 8 + 64;
  out.clouds.push_back(std::move(c));
  cur_index_ = -1;
  cur_ = point_cloud_t{};
}

void LidarDriverNode::handlePoints(const livox::ParsedPacket& pkt, DriverOutputs& out) {
  counters_.points += static_cast<int64_t>(pkt.points.size());
  const std::size_t max_points = static_cast<std::size_t>(params_.frame.max_points);
  const float* R = rot_;
  for (const livox::ParsedPoint& p : pkt.points) {
    const int64_t k = static_cast<int64_t>(p.time_ns / period_ns_);
    if (cur_index_ < 0) {
      startFrame(k);
    } else if (k > cur_index_) {
      emitFrame(out);
      startFrame(k);
    } else if (k < cur_index_) {
      const uint64_t frame_start = static_cast<uint64_t>(cur_index_) * period_ns_;
      if (frame_start - p.time_ns > kTimeResetNs) {
        // The sensor clock went back (reboot, time sync switched): start over.
        ++counters_.time_resets;
        emitFrame(out);
        startFrame(k);
      } else {
        ++counters_.points_late;
        continue;
      }
    }
    const float r2 = p.x * p.x + p.y * p.y + p.z * p.z;
    if (!(r2 >= min_range2_ && r2 <= max_range2_)) {  // also drops NaN
      ++counters_.points_range_filtered;
      continue;
    }
    if ((p.tag & tag_mask_) != 0) {
      ++counters_.points_tag_filtered;
      continue;
    }
    if (cur_.x.size() >= max_points) {
      ++counters_.points_overflow;
      continue;
    }
    if (!cur_has_point_) {
      cur_has_point_ = true;
      cur_.utime = static_cast<int64_t>(p.time_ns / 1000u);
      cur_base_ns_ = static_cast<uint64_t>(cur_.utime) * 1000u;
    } else if (p.time_ns < cur_base_ns_) {
      ++counters_.points_late;  // earlier than the frame's first point (reordered packet)
      continue;
    }
    if (p.time_ns > cur_last_ns_) cur_last_ns_ = p.time_ns;
    cur_.x.push_back(R[0] * p.x + R[1] * p.y + R[2] * p.z + trans_[0]);
    cur_.y.push_back(R[3] * p.x + R[4] * p.y + R[5] * p.z + trans_[1]);
    cur_.z.push_back(R[6] * p.x + R[7] * p.y + R[8] * p.z + trans_[2]);
    cur_.t_offset_ns.push_back(static_cast<int32_t>(p.time_ns - cur_base_ns_));
    cur_.reflectivity.push_back(static_cast<int8_t>(p.reflectivity));
    cur_.tag.push_back(static_cast<int8_t>(p.tag));
  }
}

std::optional<point_cloud_t> LidarDriverNode::flush() {
  if (cur_index_ < 0) return std::nullopt;
  DriverOutputs out;
  emitFrame(out);
  return std::move(out.clouds.front());
}

imu_t LidarDriverNode::makeImu(const livox::ParsedPacket& pkt) {
  imu_t m{};
  m.utime = static_cast<int64_t>(pkt.header.timestamp_ns / 1000u);
  if (m.utime <= 0) m.utime = 1;
  m.seq = imu_seq_no_++;
  m.frame_id = frame_id_;
  const float* R = rot_;
  const float g[3] = {pkt.imu.gyro_x, pkt.imu.gyro_y, pkt.imu.gyro_z};
  const float a[3] = {pkt.imu.acc_x, pkt.imu.acc_y, pkt.imu.acc_z};
  // Rotation only: the lever arm of a translated IMU would need angular acceleration, which
  // the sensor does not give; at the Mid-360's few-cm offsets it is negligible.
  m.gyro_x = R[0] * g[0] + R[1] * g[1] + R[2] * g[2];
  m.gyro_y = R[3] * g[0] + R[4] * g[1] + R[5] * g[2];
  m.gyro_z = R[6] * g[0] + R[7] * g[1] + R[8] * g[2];
  m.acc_x = R[0] * a[0] + R[1] * a[1] + R[2] * a[2];
  m.acc_y = R[3] * a[0] + R[4] * a[1] + R[5] * a[2];
  m.acc_z = R[6] * a[0] + R[7] * a[1] + R[8] * a[2];
  return m;
}

void LidarDriverNode::report(StatusReport& rep) const {
  const DriverCounters& c = counters_;
  rep.setCounter("datagrams", c.datagrams);
  rep.setCounter("packets", c.point_packets);
  rep.setCounter("imu_packets", c.imu_packets);
  rep.setCounter("points", c.points);
  rep.setCounter("points_published", c.points_published);
  rep.setCounter("frames", c.frames);
  rep.setCounter("crc_errors", c.crc_errors);
  rep.setCounter("malformed", c.malformed);
  rep.setCounter("lost_packets", c.lost_packets);
  rep.setCounter("out_of_order_packets", c.out_of_order_packets);
  rep.setCounter("points_range_filtered", c.points_range_filtered);
  rep.setCounter("points_tag_filtered", c.points_tag_filtered);
  rep.setCounter("points_late", c.points_late);
  rep.setCounter("points_overflow", c.points_overflow);
  rep.setCounter("time_resets", c.time_resets);
  for (std::size_t i = 1; i < c.by_status.size(); ++i) {
    if (c.by_status[i] > 0) {
      rep.setCounter(std::string("invalid_") + livox::toString(static_cast<livox::ParseStatus>(i)),
                     c.by_status[i]);
    }
  }
  rep.set("time_sync", static_cast<double>(time_sync_));
  rep.set("frame_rate_hz", static_cast<double>(params_.frame.rate_hz));
  rep.set("last_frame_points", static_cast<double>(last_frame_points_));
}

}  // namespace lidar_driver
}  // namespace ucon
