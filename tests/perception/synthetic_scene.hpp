#pragma once
// Synthetic LiDAR frames for perception tests: moving upright cylinders (people) and static
// walls/pillars sampled on their surfaces, robot at the world origin (identity pose), frame
// "base". Deterministic (fixed-seed jitter).
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "ucon/point_cloud_t.hpp"
#include "ucon/robot_pose_t.hpp"

namespace scene {

struct Person {
  double x0, y0, vx, vy;     // position at t = 0 [m], velocity [m/s]
  double radius = 0.25;      // [m]
  double x(double t) const { return x0 + vx * t; }
  double y(double t) const { return y0 + vy * t; }
};

struct Wall {  // vertical segment from (x0,y0) to (x1,y1), sampled every ds along, dz up
  double x0, y0, x1, y1;
  double ds = 0.15, dz = 0.3;
};

inline constexpr int64_t kT0 = 1'000'000'000;  // first frame time [us]
inline constexpr int64_t kDt = 20'000;         // 50 Hz

inline int64_t frameTime(int k) { return kT0 + k * kDt; }

inline ucon::robot_pose_t pose(int64_t utime) {
  ucon::robot_pose_t p{};
  p.utime = utime;
  p.valid = true;
  p.qw = 1.0;
  p.cov_size = 0;
  return p;
}

// Fills the per-point fields and the count of a cloud whose x, y, z are set.
inline void finishCloud(ucon::point_cloud_t& c) {
  c.num_points = static_cast<int32_t>(c.x.size());
  c.t_offset_ns.assign(c.x.size(), 0);
  c.reflectivity.assign(c.x.size(), 100);
  c.tag.assign(c.x.size(), 0);
  c.duration_us = 20000;
}

class Generator {
 public:
  explicit Generator(uint32_t seed = 7) : rng_(seed) {}

  // Frame k: people in `people` (hidden ones skipped by the caller), walls.
  ucon::point_cloud_t frame(int k, const std::vector<Person>& people, const std::vector<Wall>& walls) {
    const double t = static_cast<double>(k) * 1e-6 * kDt;
    ucon::point_cloud_t c{};
    c.utime = frameTime(k);
    c.seq = k;
    c.frame_id = "base";
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    auto add = [&](double x, double y, double z) {
      c.x.push_back(static_cast<float>(x + jitter(rng_)));
      c.y.push_back(static_cast<float>(y + jitter(rng_)));
      c.z.push_back(static_cast<float>(z));
    };
    for (const auto& p : people) {
      for (int a = 0; a < 16; ++a) {
        const double ang = a * 2.0 * M_PI / 16.0;
        for (double z = 0.3; z <= 1.65; z += 0.2)
          add(p.x(t) + p.radius * std::cos(ang), p.y(t) + p.radius * std::sin(ang), z);
      }
    }
    for (const auto& w : walls) {
      const double len = std::hypot(w.x1 - w.x0, w.y1 - w.y0);
      const int n = static_cast<int>(len / w.ds) + 1;
      for (int i = 0; i <= n; ++i) {
        const double s = static_cast<double>(i) / n;
        for (double z = 0.3; z <= 1.65; z += w.dz) add(w.x0 + s * (w.x1 - w.x0), w.y0 + s * (w.y1 - w.y0), z);
      }
    }
    // Ground points (cropped by the height band).
    for (int i = 0; i < 50; ++i) add(1.0 + 0.1 * i, -2.0, 0.0);
    finishCloud(c);
    return c;
  }

 private:
  std::mt19937 rng_;
};

}  // namespace scene
