#pragma once
// A synthetic run written as an LCM log with LogWriterFile, for the plot and viewer tests:
// the robot drives from (0, 0) towards (8, 2) in `duration_s` seconds, three obstacles move
// (ground truth ids 1..3, tracked ids 11..13 with 6x6 covariances), a wall of static points
// at y = 5 and a box at (3, -2), a two-piece quintic plan every 0.2 s, and one collision
// episode from t = 4.0 s to 4.2 s at the robot's position.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/runtime/log_reader.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/trajectory_t.hpp"

namespace ucon_test {

struct SyntheticRun {
  double duration_s = 6.0;
  bool pose = true, ground_truth = true, objects = true, static_points = true, trajectory = true;
  int movers = 3;               // moving obstacles; the ones past the first three circle in a grid
  int64_t t0 = 1'000'000'000;  // [us]
  int64_t other_clock = 0;     // added to the utimes of perception and planner messages (not the log's receive times)

  // Counts written, for the tests' expectations.
  int poses = 0, gts = 0, object_frames = 0, statics = 0, plans = 0;
  std::vector<int64_t> offsets;  // byte offset of every event written

  static constexpr double kGoalX = 8.0, kGoalY = 2.0;

  // Robot position at time s [s] since t0: smooth start, speed peaking mid-run.
  void robotAt(double s, double* x, double* y, double* vx, double* vy) const {
    const double u = std::min(1.0, std::max(0.0, s / duration_s));
    const double f = 3 * u * u - 2 * u * u * u;           // smoothstep
    const double df = (6 * u - 6 * u * u) / duration_s;   // d f / d s
    *x = kGoalX * f;
    *y = kGoalY * f;
    *vx = kGoalX * df;
    *vy = kGoalY * df;
  }
  // Moving obstacle k (0..2) at time s.
  static void obstacleAt(int k, double s, double* x, double* y, double* vx, double* vy) {
    switch (k) {
      case 0: *x = 5.0; *y = -3.0 + 1.1 * s; *vx = 0.0; *vy = 1.1; break;
      case 1: *x = 10.0 - 1.0 * s; *y = 3.0; *vx = -1.0; *vy = 0.0; break;
      case 2:
        *x = 2.0 + 0.5 * s;
        *y = 2.5 + 0.6 * std::sin(s);
        *vx = 0.5;
        *vy = 0.6 * std::cos(s);
        break;
      default: {
        const double a = 0.3 * s + k;
        *x = -5.0 + 2.0 * (k % 10) + std::cos(a);
        *y = -8.0 - 2.0 * (k / 10) + std::sin(a);
        *vx = -0.3 * std::sin(a);
        *vy = 0.3 * std::cos(a);
      }
    }
  }

  template <typename Msg>
  bool put(ucon::runtime::LogWriterFile& w, const char* channel, const Msg& m, int64_t t) {
    std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    return w.write(channel, buf.data(), buf.size(), t);
  }

  // Writes the log; false on an I/O error.
  bool write(const std::string& path) {
    ucon::runtime::LogWriterFile w;
    std::string err;
    if (!w.open(path, &err)) return false;
    poses = gts = object_frames = statics = plans = 0;
    offsets.clear();
    namespace ch = ucon::channels;
    const int64_t step = 20'000;  // 50 Hz base tick [us]
    const int ticks = static_cast<int>(std::lround(duration_s * 1e6 / step));
    int64_t offset = 0;
    auto track = [&](bool ok, std::size_t size, const char* channel) {
      offsets.push_back(offset);
      offset += 4 + 8 + 8 + 4 + 4 + static_cast<int64_t>(std::string(channel).size()) + static_cast<int64_t>(size);
      return ok;
    };
    int collisions = 0;
    for (int i = 0; i <= ticks; ++i) {
      const double s = i * step * 1e-6;
      const int64_t t = t0 + static_cast<int64_t>(i) * step;
      double x, y, vx, vy;
      robotAt(s, &x, &y, &vx, &vy);
      if (pose) {
        ucon::robot_pose_t m{};
        m.utime = t;
        m.seq = i;
        m.valid = true;
        m.x = x;
        m.y = y;
        m.qw = 1.0;
        m.yaw = std::atan2(vy, vx);
        m.vx = vx;
        m.vy = vy;
        m.ax = m.ay = NAN;
        m.cov_size = 0;
        if (!track(put(w, ch::kRobotPose, m, t), m.getEncodedSize(), ch::kRobotPose)) return false;
        ++poses;
      }
      if (ground_truth && i % 2 == 0) {
        ucon::sim_ground_truth_t g{};
        g.utime = t;
        g.seq = gts;
        g.scenario = "synthetic";
        g.robot_x = x;
        g.robot_y = y;
        g.robot_yaw = std::atan2(vy, vx);
        g.robot_vx = vx;
        g.robot_vy = vy;
        g.robot_radius = 0.3;
        g.collision = s >= 4.0 - 1e-9 && s <= 4.2 + 1e-9;
        if (g.collision && std::abs(s - 4.0) < 1e-9) ++collisions;
        g.num_collisions = collisions;
        g.min_clearance = collisions ? 0.0 : 0.25;
        for (int k = 0; k < movers; ++k) {
          ucon::sim_object_t o{};
          o.id = k + 1;
          obstacleAt(k, s, &o.x, &o.y, &o.vx, &o.vy);
          o.radius = 0.3;
          o.height = 1.7;
          o.motion = k == 2 ? ucon::sim_object_t::MOTION_SINUSOIDAL : ucon::sim_object_t::MOTION_CONSTANT_VELOCITY;
          g.objects.push_back(o);
        }
        g.num_objects = movers;
        if (!track(put(w, ch::kSimGroundTruth, g, t), g.getEncodedSize(), ch::kSimGroundTruth)) return false;
        ++gts;
      }
      if (objects && i % 2 == 1) {
        ucon::tracked_objects_t f{};
        f.utime = t + other_clock;
        f.seq = object_frames;
        f.valid = true;
        f.frame_seq = i;
        f.frame_id = "world";
        for (int k = 0; k < movers; ++k) {
          ucon::tracked_object_t o{};
          o.id = 11 + k;
          o.state = ucon::tracked_object_t::STATE_CONFIRMED;
          o.last_association = ucon::tracked_object_t::ASSOC_OBJECT;
          obstacleAt(k, s, &o.x, &o.y, &o.vx, &o.vy);
          o.z = 0.85;
          o.cov_size = 36;
          o.cov.assign(36, 0.0);
          for (int d = 0; d < 6; ++d) o.cov[d * 6 + d] = d < 3 ? 0.01 : 0.04;
          // Anisotropic x-y block: sigma_x = 0.1 + 0.05 k, sigma_y = 0.2, correlation 0.5.
          const double sx = 0.1 + 0.05 * (k % 3), sy = 0.2;
          o.cov[0] = sx * sx;
          o.cov[7] = sy * sy;
          o.cov[1] = o.cov[6] = 0.5 * sx * sy;
          o.cov[2] = o.cov[12] = 0.0;  // x-z stays zero: a reader taking [2] as x-y would see it
          o.size_x = 0.6;
          o.size_y = 0.6;
          o.size_z = 1.7;
          o.num_points = 40;
          o.age_frames = object_frames;
          f.objects.push_back(o);
        }
        f.num_objects = movers;
        if (!track(put(w, ch::kPerceptionObjects, f, t), f.getEncodedSize(), ch::kPerceptionObjects)) return false;
        ++object_frames;
      }
      if (static_points && i % 10 == 0) {
        ucon::static_points_t m{};
        m.utime = t + other_clock;
        m.seq = statics;
        m.valid = true;
        m.origin_x = x;
        m.origin_y = y;
        m.origin_z = 0.5;
        m.max_range = 30.0f;
        for (double wx = -1.0; wx <= 11.0; wx += 0.1) {  // wall at y = 5
          m.x.push_back(static_cast<float>(wx));
          m.y.push_back(5.02f);
          m.z.push_back(0.6f);
        }
        for (double a = 0.0; a < 2 * M_PI; a += 0.2) {  // round pillar at (3, -2)
          m.x.push_back(static_cast<float>(3.0 + 0.4 * std::cos(a)));
          m.y.push_back(static_cast<float>(-2.0 + 0.4 * std::sin(a)));
          m.z.push_back(1.0f);
        }
        m.x.push_back(1.0f);  // a floor point, below static_min_z: ignored
        m.y.push_back(1.0f);
        m.z.push_back(0.0f);
        m.num_points = static_cast<int32_t>(m.x.size());
        if (!track(put(w, ch::kPerceptionStatic, m, t), m.getEncodedSize(), ch::kPerceptionStatic)) return false;
        ++statics;
      }
      if (trajectory && i % 10 == 5) {
        // Two quintic pieces of 1 s: straight towards the goal at the current speed, then a
        // piece that moves in y only: p_y(t) = y1 + 0.5 t^2 (x constant).
        ucon::trajectory_t m{};
        m.utime = t + other_clock;
        m.seq = plans;
        m.plan_id = plans + 1;
        m.goal_id = 1;
        m.status = ucon::trajectory_t::STATUS_OK;
        m.start_utime = t + other_clock;
        m.dim = 2;
        m.order1 = 6;
        m.num_pieces = 2;
        m.durations = {1.0, 1.0};
        const double ux = kGoalX - x, uy = kGoalY - y;
        const double n = std::max(1e-6, std::hypot(ux, uy));
        const double v = std::max(0.2, std::hypot(vx, vy));
        const double x1 = x + v * ux / n, y1 = y + v * uy / n;
        m.coeffs = {x, v * ux / n, 0, 0, 0, 0,   y, v * uy / n, 0, 0, 0, 0,
                    x1, 0, 0, 0, 0, 0,           y1, 0, 0.5, 0, 0, 0};
        m.num_coeffs = static_cast<int32_t>(m.coeffs.size());
        m.yaw = NAN;
        if (!track(put(w, ch::kPlannerTrajectory, m, t), m.getEncodedSize(), ch::kPlannerTrajectory)) return false;
        ++plans;
      }
    }
    w.close();
    return true;
  }
};

}  // namespace ucon_test
