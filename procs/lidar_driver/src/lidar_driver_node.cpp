#include "ucon/lidar_driver/lidar_driver_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>

#include "ucon/livox/control.hpp"
#include "ucon/livox/point_packet.hpp"

namespace ucon {
namespace lidar_driver {

namespace {
constexpr int64_t kTimeResetNs = 1'000'000'000;   // a jump back this large restarts assembly
constexpr int64_t kOffsetWindowNs = 1'000'000'000;  // clock offset: min over this host time
constexpr int64_t kAlignThresholdNs = 10'000'000;   // clocks closer than this are one clock

int8_t timeSyncOf(uint8_t time_type) {
  switch (time_type) {
    case 1: return point_cloud_t::TIME_PTP;
    case 2: return point_cloud_t::TIME_GPS;
    default: return point_cloud_t::TIME_NONE;
  }
}

// How synchronised: NONE < PTP = GPS (for "the least synchronised sensor").
int syncRank(int8_t t) { return t == point_cloud_t::TIME_NONE ? 0 : 1; }

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

LidarDriverNode::LidarDriverNode(const DriverParams& params)
    : params_(params),
      multi_(params.sensors.size() > 1),
      merge_wait_ns_(static_cast<int64_t>(std::llround(params.frame.merge_wait_s * 1e9))) {
  const bool apply = params_.frame.apply_extrinsic;
  frame_id_ = apply ? "base" : "lidar";
  period_ns_ = 1'000'000'000 / params_.frame.rate_hz;
  const double d2r = 3.14159265358979323846 / 180.0;
  for (const SensorParams& sp : params_.sensors) {
    Sensor s;
    if (apply) {
      rotationFromRpy(sp.rpy_deg[0] * d2r, sp.rpy_deg[1] * d2r, sp.rpy_deg[2] * d2r, s.rot);
      for (int i = 0; i < 3; ++i) s.trans[i] = static_cast<float>(sp.xyz[i]);
    } else {
      const float id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      std::copy(id, id + 9, s.rot);
      std::fill(s.trans, s.trans + 3, 0.0f);
    }
    std::copy(s.trans, s.trans + 3, s.origin);
    s.imu = sp.imu;
    if (!sp.isAuto()) s.id = sensorIdOf(*livox::parseIpv4(sp.ip));
    sensors_.push_back(s);
  }
  streams_.resize(sensors_.size());
  min_range2_ = static_cast<float>(params_.filter.min_range_m * params_.filter.min_range_m);
  max_range2_ = static_cast<float>(params_.filter.max_range_m * params_.filter.max_range_m);
  const auto drops = [](uint8_t value, int level) { return level > 0 && value >= level; };
  for (int t = 0; t < 256; ++t) {
    const uint8_t tag = static_cast<uint8_t>(t);
    drop_tag_[static_cast<std::size_t>(t)] =
        drops(livox::MidTag::sticking(tag), params_.filter.drop_sticking_level) ||
        drops(livox::MidTag::rainFogDust(tag), params_.filter.drop_rain_fog_dust_level) ||
        drops(livox::MidTag::otherNoise(tag), params_.filter.drop_other_noise_level);
  }
  packet_.points.reserve(livox::kPointsPerPacket);
}

void LidarDriverNode::setSensorAddress(std::size_t i, const std::array<uint8_t, 4>& ip) {
  if (i < sensors_.size()) sensors_[i].id = sensorIdOf(ip);
}

int8_t LidarDriverNode::timeSync() const {
  int8_t worst = point_cloud_t::TIME_GPS;
  bool any = false;
  for (const SensorStream& s : streams_) {
    if (!s.have_time) continue;
    if (!any || syncRank(s.time_sync) < syncRank(worst)) worst = s.time_sync;
    any = true;
  }
  return any ? worst : point_cloud_t::TIME_NONE;
}

bool LidarDriverNode::crcAccepts(Sensor& s, livox::CrcCheck crc) {
  switch (crc) {
    case livox::CrcCheck::kAbsent:
      ++counters_.crc_absent;
      return true;
    case livox::CrcCheck::kMatch:
      s.crc_mismatches_in_row = 0;
      if (++s.crc_matches_in_row >= kCrcTrustAfter) s.crc_trusted = true;
      return true;
    case livox::CrcCheck::kMismatch:
      s.crc_matches_in_row = 0;
      if (++s.crc_mismatches_in_row >= kCrcTrustAfter) s.crc_trusted = false;
      if (s.crc_trusted) {
        ++counters_.crc_errors;
        return false;
      }
      ++counters_.crc_mismatches_kept;
      return true;
  }
  return true;
}

void LidarDriverNode::observeHostTime(std::size_t i, int64_t host_time_ns, uint64_t sensor_ts_ns) {
  if (host_time_ns <= 0) return;
  Sensor& s = sensors_[i];
  SensorStream& st = streams_[i];
  const int64_t d = host_time_ns - static_cast<int64_t>(sensor_ts_ns);
  if (!s.window_open || host_time_ns - s.window_start_ns >= kOffsetWindowNs ||
      host_time_ns < s.window_start_ns) {
    if (s.window_open) {
      // The window closed: its minimum is the estimate. A change of a second or more is a
      // clock jump (reboot, sync switched on) and is taken as it is.
      st.host_minus_sensor_ns = s.window_min_ns;
      st.offset_valid = true;
    }
    s.window_open = true;
    s.window_start_ns = host_time_ns;
    s.window_min_ns = d;
  } else {
    s.window_min_ns = std::min(s.window_min_ns, d);
  }
  if (!st.offset_valid) {  // the first packet: a provisional estimate
    st.host_minus_sensor_ns = d;
    st.offset_valid = true;
  }
  // Sensors whose clocks differ (not synchronised to one master) are brought onto sensor 0's.
  if (i > 0 && streams_[0].offset_valid) {
    const int64_t diff = st.host_minus_sensor_ns - streams_[0].host_minus_sensor_ns;
    const bool synced = st.time_sync != point_cloud_t::TIME_NONE &&
                        streams_[0].time_sync != point_cloud_t::TIME_NONE;
    st.correction_ns = (!synced && std::llabs(diff) >= kAlignThresholdNs) ? diff : 0;
  }
}

livox::ParseStatus LidarDriverNode::onDatagram(std::size_t i, const uint8_t* data, std::size_t size,
                                               int64_t host_time_ns, DriverOutputs& out) {
  out.clear();
  ++counters_.datagrams;
  if (i >= sensors_.size()) {
    ++counters_.malformed;  // the caller's routing is wrong; never index out of range
    return livox::ParseStatus::kBadValue;
  }
  const livox::ParseStatus st = livox::parsePacket(data, size, packet_);
  if (st != livox::ParseStatus::kOk) {
    ++counters_.by_status[static_cast<std::size_t>(st)];
    ++counters_.malformed;
    return st;
  }
  Sensor& s = sensors_[i];
  SensorStream& ss = streams_[i];
  if (!crcAccepts(s, packet_.crc)) {
    ++counters_.by_status[static_cast<std::size_t>(livox::ParseStatus::kBadCrc)];
    return livox::ParseStatus::kBadCrc;
  }
  ss.time_sync = timeSyncOf(packet_.header.time_type);
  ss.have_time = true;
  const uint64_t ts = packet_.header.timestamp_ns;
  // The packet leaves the sensor after its last point.
  observeHostTime(i, host_time_ns, ts + static_cast<uint64_t>(packet_.header.time_interval) * 100u);
  const int64_t corr = ss.correction_ns;
  const int64_t t_us = (static_cast<int64_t>(ts) + corr) / 1000;
  if (t_us > now_us_) now_us_ = t_us;

  if (packet_.type == livox::DataType::kImu) {
    ++ss.imu_packets;
    if (!s.imu) {
      ++counters_.imu_ignored;
      return st;
    }
    ++counters_.imu_packets;
    if (ts + kTimeResetNs < s.last_imu_ts_ns) s.imu_seq.reset();
    auto r = s.imu_seq.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
    if (r.out_of_order && ts > s.last_imu_ts_ns) {
      s.imu_seq.reset();
      r = s.imu_seq.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
    }
    s.last_imu_ts_ns = ts;
    counters_.lost_packets += r.lost;
    if (r.out_of_order) ++counters_.out_of_order_packets;
    out.imu = makeImu(s, packet_, corr);
    return st;
  }

  ++counters_.point_packets;
  ++ss.point_packets;
  counters_.points_bad_records += static_cast<int64_t>(packet_.bad_points);
  // The sensor clock went far back: a reboot or a time-sync switch; its counters restart too.
  if (ts + kTimeResetNs < s.last_point_ts_ns) s.point_seq.reset();
  auto r = s.point_seq.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
  if (r.out_of_order && ts > s.last_point_ts_ns) {
    // udp_cnt went back but time went forward: the counters restarted, the data is new.
    s.point_seq.reset();
    r = s.point_seq.observe(packet_.header.frame_cnt, packet_.header.udp_cnt);
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
  s.last_point_ts_ns = ts;
  const int64_t t0 = static_cast<int64_t>(ts) + corr;
  if (s.watermark_ns >= 0 && t0 + kTimeResetNs < s.watermark_ns) {
    // The sensor clock went back (reboot, time sync switched): start over.
    ++counters_.time_resets;
    resetAssembly(out);
  }
  // The gap precedes this packet: it belongs to the frame this packet's first point is in.
  if (r.lost > 0 && !packet_.points.empty()) {
    const int64_t k = (static_cast<int64_t>(packet_.points.front().time_ns) + corr) / period_ns_;
    if (OpenFrame* f = frameFor(k)) f->lost += static_cast<int32_t>(r.lost);
  }
  handlePoints(i, packet_, out);
  return st;
}

void LidarDriverNode::onOversizeDatagram() {
  ++counters_.datagrams;
  ++counters_.malformed;
  ++counters_.by_status[static_cast<std::size_t>(livox::ParseStatus::kBadLength)];
}

LidarDriverNode::OpenFrame* LidarDriverNode::frameFor(int64_t index) {
  if (index <= emitted_upto_) return nullptr;
  // Usually the newest open frame; several sensors may still fill an older one.
  auto it = open_.end();
  while (it != open_.begin() && std::prev(it)->index >= index) {
    --it;
    if (it->index == index) return &*it;
  }
  OpenFrame f;
  f.index = index;
  point_cloud_t& c = f.cloud;
  c.x.reserve(reserve_hint_);
  c.y.reserve(reserve_hint_);
  c.z.reserve(reserve_hint_);
  c.t_offset_ns.reserve(reserve_hint_);
  c.reflectivity.reserve(reserve_hint_);
  c.tag.reserve(reserve_hint_);
  if (multi_) c.point_sensor.reserve(reserve_hint_);
  return &*open_.insert(it, std::move(f));
}

void LidarDriverNode::handlePoints(std::size_t i, const livox::ParsedPacket& pkt, DriverOutputs& out) {
  Sensor& s = sensors_[i];
  counters_.points += static_cast<int64_t>(pkt.points.size());
  const std::size_t max_points = static_cast<std::size_t>(params_.frame.max_points);
  const int64_t corr = streams_[i].correction_ns;
  const float* R = s.rot;
  const int8_t sync = streams_[i].time_sync;
  OpenFrame* f = nullptr;
  int64_t f_start = 0, f_end = -1;  // [start, end) of f in ns
  for (const livox::ParsedPoint& p : pkt.points) {
    const int64_t t = static_cast<int64_t>(p.time_ns) + corr;
    if (t < 0) {
      ++counters_.points_late;  // before sensor 0's time origin: cannot be placed
      continue;
    }
    if (t < f_start || t >= f_end) {
      const int64_t k = t / period_ns_;
      f = frameFor(k);
      f_start = k * period_ns_;
      f_end = f_start + period_ns_;
      if (f && (f->time_sync < 0 || syncRank(sync) < syncRank(f->time_sync))) f->time_sync = sync;
    }
    if (f == nullptr) {
      ++counters_.points_late;  // its frame is published already
      continue;
    }
    const float r2 = p.x * p.x + p.y * p.y + p.z * p.z;
    if (!(r2 >= min_range2_ && r2 <= max_range2_)) {  // also drops NaN
      ++counters_.points_range_filtered;
      continue;
    }
    if (drop_tag_[p.tag]) {
      ++counters_.points_tag_filtered;
      continue;
    }
    point_cloud_t& c = f->cloud;
    if (c.x.size() >= max_points) {
      ++counters_.points_overflow;
      continue;
    }
    const int64_t off = t - f_start;
    if (!f->has_point) {
      f->has_point = true;
      f->min_off_ns = f->max_off_ns = off;
    } else {
      f->min_off_ns = std::min(f->min_off_ns, off);
      f->max_off_ns = std::max(f->max_off_ns, off);
    }
    c.x.push_back(R[0] * p.x + R[1] * p.y + R[2] * p.z + s.trans[0]);
    c.y.push_back(R[3] * p.x + R[4] * p.y + R[5] * p.z + s.trans[1]);
    c.z.push_back(R[6] * p.x + R[7] * p.y + R[8] * p.z + s.trans[2]);
    c.t_offset_ns.push_back(static_cast<int32_t>(off));
    c.reflectivity.push_back(p.reflectivity);
    c.tag.push_back(p.tag);
    if (multi_) c.point_sensor.push_back(static_cast<uint8_t>(i));
  }
  if (!pkt.points.empty()) {
    const int64_t last = static_cast<int64_t>(pkt.points.back().time_ns) + corr;
    s.watermark_ns = std::max(s.watermark_ns, last);
  }
  emitReady(out);
}

void LidarDriverNode::emitReady(DriverOutputs& out) {
  // The time every sensor still sending has reached; one lagging by more than merge_wait
  // behind the newest is not waited for.
  int64_t newest = -1;
  for (const Sensor& s : sensors_) newest = std::max(newest, s.watermark_ns);
  if (newest < 0) return;
  int64_t ready = newest;
  for (const Sensor& s : sensors_) {
    if (s.watermark_ns >= 0 && s.watermark_ns >= newest - merge_wait_ns_) {
      ready = std::min(ready, s.watermark_ns);
    }
  }
  while (!open_.empty() && (open_.front().index + 1) * period_ns_ <= ready) emitFront(out);
}

void LidarDriverNode::emitFront(DriverOutputs& out) {
  OpenFrame& f = open_.front();
  point_cloud_t& c = f.cloud;
  const int64_t base_ns = f.index * period_ns_;
  if (!f.has_point) {
    // No point survived the filters: the frame still happened; stamp it with its start.
    c.utime = base_ns / 1000;
    c.duration_us = 0;
  } else {
    // utime is the first point's time (whole us); offsets count from there.
    c.utime = (base_ns + f.min_off_ns) / 1000;
    const int32_t shift = static_cast<int32_t>(c.utime * 1000 - base_ns);
    if (shift != 0) {
      for (int32_t& o : c.t_offset_ns) o -= shift;
    }
    c.duration_us = static_cast<int32_t>((f.max_off_ns - f.min_off_ns) / 1000);
  }
  if (c.utime <= 0) c.utime = 1;  // 0 means invalid on the bus
  c.seq = frame_seq_++;
  c.frame_id = frame_id_;
  c.sensor_id = multi_ ? 0 : sensors_[0].id;
  c.time_sync = f.time_sync >= 0 ? f.time_sync : timeSync();
  c.lost_packets = f.lost;
  c.num_points = static_cast<int32_t>(c.x.size());
  c.num_sensors = static_cast<int8_t>(sensors_.size());
  c.sensor_ids.clear();
  c.origin_x.clear();
  c.origin_y.clear();
  c.origin_z.clear();
  for (const Sensor& s : sensors_) {
    c.sensor_ids.push_back(s.id);
    c.origin_x.push_back(s.origin[0]);
    c.origin_y.push_back(s.origin[1]);
    c.origin_z.push_back(s.origin[2]);
  }
  c.num_point_sensors = multi_ ? c.num_points : 0;
  if (!multi_) c.point_sensor.clear();
  ++counters_.frames;
  counters_.points_published += c.num_points;
  last_frame_points_ = c.num_points;
  reserve_hint_ = static_cast<std::size_t>(c.num_points) + c.num_points / 8 + 64;
  emitted_upto_ = f.index;
  out.clouds.push_back(std::move(c));
  open_.pop_front();
}

void LidarDriverNode::resetAssembly(DriverOutputs& out) {
  while (!open_.empty()) emitFront(out);
  emitted_upto_ = INT64_MIN;
  for (Sensor& s : sensors_) s.watermark_ns = -1;
}

std::vector<point_cloud_t> LidarDriverNode::flushAll() {
  DriverOutputs out;
  while (!open_.empty()) emitFront(out);
  return std::move(out.clouds);
}

std::optional<point_cloud_t> LidarDriverNode::flush() {
  auto all = flushAll();
  if (all.empty()) return std::nullopt;
  return std::move(all.front());
}

imu_t LidarDriverNode::makeImu(const Sensor& s, const livox::ParsedPacket& pkt, int64_t correction_ns) {
  imu_t m{};
  m.utime = (static_cast<int64_t>(pkt.header.timestamp_ns) + correction_ns) / 1000;
  if (m.utime <= 0) m.utime = 1;
  m.seq = imu_seq_no_++;
  m.frame_id = frame_id_;
  const float* R = s.rot;
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
  rep.setCounter("imu_ignored", c.imu_ignored);
  rep.setCounter("points", c.points);
  rep.setCounter("points_published", c.points_published);
  rep.setCounter("frames", c.frames);
  rep.setCounter("crc_errors", c.crc_errors);
  rep.setCounter("crc_mismatches_kept", c.crc_mismatches_kept);
  rep.setCounter("crc_absent", c.crc_absent);
  rep.setCounter("malformed", c.malformed);
  rep.setCounter("lost_packets", c.lost_packets);
  rep.setCounter("out_of_order_packets", c.out_of_order_packets);
  rep.setCounter("points_range_filtered", c.points_range_filtered);
  rep.setCounter("points_tag_filtered", c.points_tag_filtered);
  rep.setCounter("points_bad_records", c.points_bad_records);
  rep.setCounter("points_late", c.points_late);
  rep.setCounter("points_overflow", c.points_overflow);
  rep.setCounter("time_resets", c.time_resets);
  for (std::size_t i = 1; i < c.by_status.size(); ++i) {
    if (c.by_status[i] > 0) {
      rep.setCounter(std::string("invalid_") + livox::toString(static_cast<livox::ParseStatus>(i)),
                     c.by_status[i]);
    }
  }
  for (std::size_t i = 0; i < streams_.size(); ++i) {
    const SensorStream& s = streams_[i];
    const std::string sfx = i == 0 ? "" : "_s" + std::to_string(i);
    if (i > 0) {
      rep.setCounter("packets" + sfx, s.point_packets);
      rep.setCounter("imu_packets" + sfx, s.imu_packets);
    } else if (multi_) {
      rep.setCounter("packets_s0", s.point_packets);
    }
    rep.set("time_sync" + sfx, static_cast<double>(s.time_sync));
    rep.set("host_minus_sensor_ms" + sfx,
            s.offset_valid ? static_cast<double>(s.host_minus_sensor_ns) * 1e-6
                           : std::numeric_limits<double>::quiet_NaN());
    if (i > 0) rep.set("clock_correction_ms" + sfx, static_cast<double>(s.correction_ns) * 1e-6);
  }
  rep.set("frame_rate_hz", static_cast<double>(params_.frame.rate_hz));
  rep.set("last_frame_points", static_cast<double>(last_frame_points_));
}

}  // namespace lidar_driver
}  // namespace ucon
