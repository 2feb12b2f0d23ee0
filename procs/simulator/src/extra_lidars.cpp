// The emulated Mid-360s after the first (params.extra_lidars) and the packet encoding all of
// them share. Each extra sensor scans the same world from its own mounting with its own
// pattern offset and noise seed, answers its own control requests and sends its points from
// its own address, as a second sensor on the robot's network would.
#include <cmath>

#include "ucon/simulator/simulator.hpp"

namespace ucon {
namespace simulator {

void Simulator::initExtraLidars() {
  const auto primary = livox::parseIpv4(params_.net.sensor_ip);
  const auto id = [](const std::array<uint8_t, 4>& ip) {
    return (int64_t{ip[0]} << 24) | (int64_t{ip[1]} << 16) | (int64_t{ip[2]} << 8) | int64_t{ip[3]};
  };
  // Frames assembled in-process carry the sensor origin, like the driver's.
  const Eigen::Vector3d o = options_.frames_in_base ? Eigen::Vector3d(lidar_.mount().translation()) : Eigen::Vector3d::Zero();
  cloud_.num_sensors = 1;
  cloud_.sensor_ids = {primary ? id(*primary) : 0};
  cloud_.origin_x = {static_cast<float>(o.x())};
  cloud_.origin_y = {static_cast<float>(o.y())};
  cloud_.origin_z = {static_cast<float>(o.z())};
  cloud_.num_point_sensors = 0;

  for (const ExtraLidarParams& e : params_.extra_lidars) {
    LidarParams lp = params_.lidar;
    lp.mount_xyz = e.mount_xyz;
    lp.mount_rpy_deg = e.mount_rpy_deg;
    lp.seed = e.seed;
    SensorState st = control_.state();  // the same factory settings as the first sensor
    const auto ip = livox::parseIpv4(e.sensor_ip);
    extras_.push_back(ExtraLidar{LidarEmulator(lp),
                                 ControlResponder(st, ip ? *ip : std::array<uint8_t, 4>{{127, 0, 0, 2}},
                                                  static_cast<uint16_t>(params_.net.command_port), e.serial),
                                 0, -1});
  }
}

bool Simulator::makePointDatagram(const SensorState& st, uint64_t stamp_ns, uint16_t udp_cnt,
                                  uint8_t sensor, Datagram& d) {
  livox::PacketInfo info;
  info.timestamp_ns = stamp_ns;
  info.time_interval = static_cast<uint16_t>(livox::kPointsPerPacket * spacing_ns_ / 100);
  info.udp_cnt = udp_cnt;
  info.frame_cnt = frame_cnt_;
  info.time_type = livox::TimeType::kNone;
  d.ip = st.point_host_ip;
  d.port = st.point_host_port;
  d.sensor = sensor;
  return livox::encodePointPacket(info, static_cast<livox::DataType>(st.data_type), pts_.data(),
                                  livox::kPointsPerPacket, d.bytes) == livox::EncodeStatus::kOk;
}

void Simulator::emitExtraPackets(int64_t t_ns, SimOutputs& out) {
  if (extras_.empty() || !options_.make_packets) return;
  const Eigen::Isometry3d T_wb = basePose();  // with the vibration's roll and pitch, as the main sensor
  const uint64_t stamp_ns = static_cast<uint64_t>(params_.start_utime) * 1000ULL + static_cast<uint64_t>(t_ns);
  const int64_t frame = t_ns / frame_period_ns_;
  for (std::size_t i = 0; i < extras_.size(); ++i) {
    ExtraLidar& e = extras_[i];
    if (frame != e.frame) {  // udp_cnt restarts with each sensor frame (frame_cnt_ moved on)
      e.frame = frame;
      e.udp_cnt = 0;
    }
    const SensorState& st = e.control.state();
    if (!st.sampling()) continue;
    world_.setTime(static_cast<double>(t_ns) * 1e-9);
    e.lidar.scan(world_, T_wb * e.lidar.mount(), next_point_k_, livox::kPointsPerPacket, pts_.data(), nullptr);
    Datagram d;
    if (makePointDatagram(st, stamp_ns, e.udp_cnt, static_cast<uint8_t>(i + 1), d)) {
      out.point_packets.push_back(std::move(d));
      ++counters_.packets;
      counters_.points += static_cast<int64_t>(livox::kPointsPerPacket);
    } else {
      ++counters_.encode_errors;
    }
    ++e.udp_cnt;
  }
}

}  // namespace simulator
}  // namespace ucon
