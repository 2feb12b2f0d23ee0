#include "ucon/simulator/simulator.hpp"

#include "ucon/world/difficulty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ucon {
namespace simulator {

namespace {

constexpr double kGravity = 9.80665;
constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d vec3(const std::vector<double>& v) {
  return v.size() == 3 ? Eigen::Vector3d(v[0], v[1], v[2]) : Eigen::Vector3d::Zero();
}

SensorState initialState(const SimulatorParams& p) {
  SensorState s;
  const auto ip = livox::parseIpv4(p.net.host_ip);
  if (ip) {
    s.point_host_ip = *ip;
    s.imu_host_ip = *ip;
  }
  s.point_host_port = static_cast<uint16_t>(p.net.host_point_port);
  s.imu_host_port = static_cast<uint16_t>(p.net.host_imu_port);
  s.data_type = static_cast<uint8_t>(p.lidar.data_type);
  return s;
}

std::array<uint8_t, 4> sensorIp(const SimulatorParams& p) {
  const auto ip = livox::parseIpv4(p.net.sensor_ip);
  return ip ? *ip : std::array<uint8_t, 4>{{127, 0, 0, 1}};
}

// Period of a rate [Hz] in whole nanoseconds, at least 1 ns (params.validate() keeps rates sane).
int64_t periodNs(double rate_hz) {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) return 1000000000;
  return std::max<int64_t>(1, static_cast<int64_t>(std::llround(1e9 / rate_hz)));
}

}  // namespace

void SimOutputs::clear() {
  point_packets.clear();
  imu_packets.clear();
  poses.clear();
  ground_truth.clear();
  frames.clear();
}

Simulator::Simulator(const SimulatorParams& params, world::Scenario scenario, SimOptions options)
    : params_(params),
      options_(options),
      world_(std::move(scenario),
             world::World::Options{1.0, 0.0, params.lidar.ground_reflectivity}),
      plant_(params.base),
      lidar_(params.lidar),
      control_(initialState(params), sensorIp(params), static_cast<uint16_t>(params.net.command_port),
               params.net.serial),
      imu_rng_(world::deriveSeed(static_cast<uint64_t>(params.lidar.seed), 0x1A0)),
      spacing_ns_(periodNs(params.lidar.point_rate)),
      imu_period_ns_(periodNs(params.imu.rate_hz)),
      pose_period_ns_(periodNs(params.pose_rate_hz)),
      frame_period_ns_(periodNs(params.frame_rate_hz)),
      gyro_bias_(vec3(params.imu.gyro_bias)),
      acc_bias_(vec3(params.imu.acc_bias)),
      imu_position_(vec3(params.imu.position)),
      imu_time_offset_ns_(static_cast<int64_t>(std::llround(params.imu.time_offset_s * 1e9))),
      min_clearance_(std::numeric_limits<double>::infinity()) {
  const auto& r = world_.scenario().robot;
  plant_.reset(r.start.x(), r.start.y(), r.start_yaw);
  pts_.resize(livox::kPointsPerPacket);
  cloud_.frame_id = options_.frames_in_base ? "base" : "lidar";
  cloud_.time_sync = point_cloud_t::TIME_NONE;
  initExtraLidars();
}

void Simulator::vibration(int64_t t_ns, double* roll, double* pitch, double* droll, double* dpitch) const {
  const double a = params_.vibration.amplitude_deg * kPi / 180.0;
  if (a <= 0.0) {
    *roll = *pitch = *droll = *dpitch = 0.0;
    return;
  }
  const double t = static_cast<double>(t_ns) * 1e-9;
  const double w1 = 2.0 * kPi * params_.vibration.frequency_hz, w2 = 1.37 * w1;
  *roll = a * std::sin(w1 * t);
  *pitch = a * std::sin(w2 * t + 1.0);
  *droll = a * w1 * std::cos(w1 * t);
  *dpitch = a * w2 * std::cos(w2 * t + 1.0);
}

Eigen::Isometry3d Simulator::basePose() const {
  const auto& s = plant_.state();
  double roll, pitch, dr, dp;
  vibration(now_ns_, &roll, &pitch, &dr, &dp);
  Eigen::Isometry3d T_wb = Eigen::Isometry3d::Identity();
  T_wb.linear() = Eigen::AngleAxisd(s.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  if (roll != 0.0 || pitch != 0.0)
    T_wb.linear() = T_wb.linear() * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                    Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T_wb.translation() = Eigen::Vector3d(s.x, s.y, 0.0);
  return T_wb;
}

Eigen::Isometry3d Simulator::sensorPose() const { return basePose() * lidar_.mount(); }

void Simulator::stepPlantTo(int64_t t_ns) {
  if (cmd_active_ && t_ns - last_cmd_ns_ > static_cast<int64_t>(params_.cmd_timeout_s * 1e9)) {
    // Watchdog: the base controller went quiet; brake (with the motor lag) like the motor board.
    plant_.setCommand(mecanum::WheelSpeeds{}, false);
    cmd_active_ = false;
    ++counters_.cmd_timeouts;
  }
  if (t_ns > plant_ns_) {
    plant_.step(static_cast<double>(t_ns - plant_ns_) * 1e-9);
    plant_ns_ = t_ns;
  }
}

void Simulator::advanceTo(int64_t utime, SimOutputs& out) {
  const int64_t target_ns = (utime - params_.start_utime) * 1000;
  if (target_ns < now_ns_) return;
  while (true) {
    const int64_t t_packet = static_cast<int64_t>(next_point_k_) * spacing_ns_;
    const int64_t t = std::min(std::min(next_pose_ns_, next_gt_ns_), std::min(next_imu_ns_, t_packet));
    if (t > target_ns) break;
    stepPlantTo(t);
    now_ns_ = t;
    // Fixed order at equal times: pose, ground truth, IMU, points.
    if (next_pose_ns_ == t) {
      emitPose(t, out);
      next_pose_ns_ += pose_period_ns_;
    } else if (next_gt_ns_ == t) {
      emitGroundTruth(t, out);
      next_gt_ns_ += frame_period_ns_;
    } else if (next_imu_ns_ == t) {
      emitImu(t, out);
      next_imu_ns_ += imu_period_ns_;
    } else {
      emitPacket(t, out);
      emitExtraPackets(t, out);
      next_point_k_ += livox::kPointsPerPacket;
    }
  }
  stepPlantTo(target_ns);
  now_ns_ = std::max(now_ns_, target_ns);
}

bool Simulator::onWheelCmd(const wheel_cmd_t& cmd) {
  const mecanum::WheelSpeeds w{cmd.w_fl, cmd.w_fr, cmd.w_rl, cmd.w_rr};
  last_cmd_ns_ = now_ns_;
  cmd_active_ = true;
  if (!w.allFinite()) {
    ++counters_.bad_wheel_cmds;
    plant_.setCommand(mecanum::WheelSpeeds{}, false);
    return false;
  }
  ++counters_.wheel_cmds;
  plant_.setCommand(w, cmd.enable);
  return true;
}

void Simulator::startFrame(int64_t frame_index, SimOutputs& out) {
  if (cur_frame_ >= 0) {
    ++frame_cnt_;
    if (options_.make_frames && cloud_.num_points > 0) {
      cloud_.seq = cloud_seq_++;
      out.frames.push_back(cloud_);
      ++counters_.frames;
    }
  }
  cur_frame_ = frame_index;
  udp_cnt_ = 0;
  cloud_.utime = 0;
  cloud_.num_points = 0;
  cloud_.x.clear();
  cloud_.y.clear();
  cloud_.z.clear();
  cloud_.t_offset_ns.clear();
  cloud_.reflectivity.clear();
  cloud_.tag.clear();
  cloud_.duration_us = 0;
}

void Simulator::emitPacket(int64_t t_ns, SimOutputs& out) {
  const int64_t frame = t_ns / frame_period_ns_;
  if (frame != cur_frame_) startFrame(frame, out);
  const SensorState& st = control_.state();
  if (!st.sampling()) return;  // standby: the sensor sends nothing
  world_.setTime(static_cast<double>(t_ns) * 1e-9);
  const std::size_t n = livox::kPointsPerPacket;
  lidar_.scan(world_, sensorPose(), next_point_k_, n, pts_.data(), &scan_stats_);
  const uint64_t stamp_ns = static_cast<uint64_t>(params_.start_utime) * 1000ULL + static_cast<uint64_t>(t_ns);
  if (options_.make_packets) {
    Datagram d;
    if (makePointDatagram(st, stamp_ns, udp_cnt_, 0, d)) {
      out.point_packets.push_back(std::move(d));
      ++counters_.packets;
      counters_.points += static_cast<int64_t>(n);
    } else {
      ++counters_.encode_errors;
    }
  }
  if (options_.make_frames) {
    if (cloud_.num_points == 0 && cloud_.utime == 0) cloud_.utime = static_cast<int64_t>(stamp_ns / 1000);
    const int64_t base_ns = cloud_.utime * 1000;
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = pts_[i];
      if (p.x == 0.0f && p.y == 0.0f && p.z == 0.0f) continue;
      const int64_t tp = static_cast<int64_t>(stamp_ns) + static_cast<int64_t>(i) * spacing_ns_;
      if (options_.frames_in_base) {
        const Eigen::Vector3d b = lidar_.mount() * Eigen::Vector3d(p.x, p.y, p.z);
        cloud_.x.push_back(static_cast<float>(b.x()));
        cloud_.y.push_back(static_cast<float>(b.y()));
        cloud_.z.push_back(static_cast<float>(b.z()));
      } else {
        cloud_.x.push_back(p.x);
        cloud_.y.push_back(p.y);
        cloud_.z.push_back(p.z);
      }
      cloud_.t_offset_ns.push_back(static_cast<int32_t>(tp - base_ns));
      cloud_.reflectivity.push_back(p.reflectivity);
      cloud_.tag.push_back(p.tag);
      cloud_.duration_us = static_cast<int32_t>((tp - base_ns) / 1000);
    }
    cloud_.num_points = static_cast<int32_t>(cloud_.x.size());
  }
  for (std::size_t i = 0; i < n; ++i)
    if (pts_[i].x != 0.0f || pts_[i].y != 0.0f || pts_[i].z != 0.0f) ++counters_.returns;
  ++udp_cnt_;
}

void Simulator::emitImu(int64_t t_ns, SimOutputs& out) {
  const auto& s = plant_.state();
  const Eigen::Isometry3d T_wb = basePose();
  const Eigen::Isometry3d T_ws = T_wb * lidar_.mount();
  const Eigen::Matrix3d R_ws = T_ws.linear();
  // World angular velocity: yaw rate plus the vibration's Euler rates, w = E(rpy) d(rpy)/dt.
  double roll, pitch, droll, dpitch;
  vibration(t_ns, &roll, &pitch, &droll, &dpitch);
  const double cy = std::cos(s.yaw), sy = std::sin(s.yaw), cp = std::cos(pitch), sp = std::sin(pitch);
  const Eigen::Vector3d omega(cy * cp * droll - sy * dpitch, sy * cp * droll + cy * dpitch, -sp * droll + s.body.wz);
  // Velocity of the IMU point: v_base + w x r (r = base origin -> IMU, world frame).
  const Eigen::Vector3d p_imu = T_ws * imu_position_;
  const Eigen::Vector3d r = p_imu - T_wb.translation();
  const Eigen::Vector3d v = Eigen::Vector3d(s.vx_world, s.vy_world, 0.0) + omega.cross(r);
  const double dt = static_cast<double>(imu_period_ns_) * 1e-9;
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  if (have_prev_imu_) a = (v - prev_sensor_vel_) / dt;
  prev_sensor_vel_ = v;
  have_prev_imu_ = true;
  // Specific force: acceleration minus gravity (gravity is -g along world z).
  const Eigen::Vector3d f = R_ws.transpose() * (a + Eigen::Vector3d(0.0, 0.0, kGravity));
  const Eigen::Vector3d w = R_ws.transpose() * omega;
  // Bias random walk, then white noise (12 draws per sample, always, so the noise sequence
  // does not depend on the motion).
  const double sq = std::sqrt(dt);
  for (int i = 0; i < 3; ++i) gyro_bias_[i] += params_.imu.gyro_bias_walk * sq * imu_rng_.normal();
  for (int i = 0; i < 3; ++i) acc_bias_[i] += params_.imu.acc_bias_walk * sq * imu_rng_.normal();
  livox::ImuSample sample;
  const double gs = params_.imu.gyro_noise_sigma, as = params_.imu.acc_noise_sigma;
  sample.gyro_x = static_cast<float>(w.x() + gyro_bias_.x() + gs * imu_rng_.normal());
  sample.gyro_y = static_cast<float>(w.y() + gyro_bias_.y() + gs * imu_rng_.normal());
  sample.gyro_z = static_cast<float>(w.z() + gyro_bias_.z() + gs * imu_rng_.normal());
  sample.acc_x = static_cast<float>(f.x() + acc_bias_.x() + as * imu_rng_.normal());
  sample.acc_y = static_cast<float>(f.y() + acc_bias_.y() + as * imu_rng_.normal());
  sample.acc_z = static_cast<float>(f.z() + acc_bias_.z() + as * imu_rng_.normal());
  const SensorState& st = control_.state();
  if (!options_.make_packets || !st.sampling() || !st.imu_enabled) return;
  livox::PacketInfo info;
  info.timestamp_ns = static_cast<uint64_t>(
      std::max<int64_t>(1, params_.start_utime * 1000 + t_ns + imu_time_offset_ns_));
  info.udp_cnt = imu_cnt_++;
  info.frame_cnt = frame_cnt_;
  info.time_type = livox::TimeType::kNone;
  Datagram d;
  d.ip = st.imu_host_ip;
  d.port = st.imu_host_port;
  if (livox::encodeImuPacket(info, sample, d.bytes) == livox::EncodeStatus::kOk) {
    out.imu_packets.push_back(std::move(d));
    ++counters_.imu_packets;
  } else {
    ++counters_.encode_errors;
  }
}

void Simulator::checkCollision(int64_t t_ns) {
  world_.setTime(static_cast<double>(t_ns) * 1e-9);
  const auto& s = plant_.state();
  const world::Contact c = world_.diskContact(Eigen::Vector2d(s.x, s.y), world_.scenario().robot.radius);
  min_clearance_ = std::min(min_clearance_, c.clearance);
  if (c.collision() && !in_collision_) ++counters_.collision_episodes;
  in_collision_ = c.collision();
}

void Simulator::emitPose(int64_t t_ns, SimOutputs& out) {
  checkCollision(t_ns);
  const auto& s = plant_.state();
  robot_pose_t m{};
  m.utime = params_.start_utime + t_ns / 1000;
  m.seq = pose_seq_++;
  m.valid = true;
  m.x = s.x;
  m.y = s.y;
  m.z = 0.0;
  m.qw = std::cos(0.5 * s.yaw);
  m.qx = 0.0;
  m.qy = 0.0;
  m.qz = std::sin(0.5 * s.yaw);
  m.yaw = s.yaw;
  m.vx = s.vx_world;
  m.vy = s.vy_world;
  m.vz = 0.0;
  m.wx = 0.0;
  m.wy = 0.0;
  m.wz = s.body.wz;
  const double dt = static_cast<double>(pose_period_ns_) * 1e-9;
  m.ax = pose_seq_ > 1 ? (s.vx_world - prev_pose_vx_) / dt : 0.0;
  m.ay = pose_seq_ > 1 ? (s.vy_world - prev_pose_vy_) / dt : 0.0;
  prev_pose_vx_ = s.vx_world;
  prev_pose_vy_ = s.vy_world;
  m.cov_size = 0;
  if (params_.pose_source == "none") return;  // the odometry publishes the pose
  out.poses.push_back(std::move(m));
  ++counters_.poses;
}

void Simulator::emitGroundTruth(int64_t t_ns, SimOutputs& out) {
  checkCollision(t_ns);
  const auto& s = plant_.state();
  sim_ground_truth_t g{};
  g.utime = params_.start_utime + t_ns / 1000;
  g.seq = gt_seq_++;
  g.scenario = world_.scenario().name;
  g.robot_x = s.x;
  g.robot_y = s.y;
  g.robot_yaw = s.yaw;
  g.robot_vx = s.vx_world;
  g.robot_vy = s.vy_world;
  g.robot_radius = world_.scenario().robot.radius;
  g.collision = in_collision_;
  g.num_collisions = static_cast<int32_t>(counters_.collision_episodes);
  g.min_clearance = std::isfinite(min_clearance_) ? min_clearance_ : 1e9;
  const auto& movers = world_.movers();
  g.num_objects = static_cast<int32_t>(movers.size());
  g.objects.resize(movers.size());
  // Visibility costs 35 rays per mover: computed for every mover in scenes of up to
  // kMaxVisibilityMovers (the perception scenarios); in denser scenes (the planning benchmarks)
  // for the movers within kVisibilityRange of the sensor, those the robot may meet within a few
  // seconds, and NaN (unknown) beyond.
  constexpr std::size_t kMaxVisibilityMovers = 20;
  constexpr double kVisibilityRange = 12.0;  // [m], as far as the planner takes objects
  const bool all_visibility = movers.size() <= kMaxVisibilityMovers;
  const Eigen::Vector3d sensor = sensorPose().translation();
  for (std::size_t i = 0; i < movers.size(); ++i) {
    sim_object_t& o = g.objects[i];
    o.id = movers[i].id;
    o.x = movers[i].position.x();
    o.y = movers[i].position.y();
    o.vx = movers[i].velocity.x();
    o.vy = movers[i].velocity.y();
    o.radius = movers[i].radius;
    o.height = movers[i].height;
    o.motion = static_cast<int8_t>(movers[i].motion);
    const double range2 = (movers[i].position.head<2>() - sensor.head<2>()).squaredNorm();
    const bool with_visibility = all_visibility || range2 <= kVisibilityRange * kVisibilityRange;
    o.visible = with_visibility ? world::moverVisibility(world_, i, sensor)
                                : std::numeric_limits<double>::quiet_NaN();
  }
  out.ground_truth.push_back(std::move(g));
  ++counters_.ground_truth;
}

}  // namespace simulator
}  // namespace ucon
