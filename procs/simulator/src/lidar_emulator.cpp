#include "ucon/simulator/lidar_emulator.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace simulator {

namespace {

constexpr double kPi = 3.14159265358979323846;
// R2 sequence constants as 64-bit fixed-point fractions: round(2^64 / g), round(2^64 / g^2).
constexpr uint64_t kA1 = 0xC13FA9A902A6328FULL;
constexpr uint64_t kA2 = 0x91E10DA5C79E7B1DULL;
constexpr uint64_t kHalf = 0x8000000000000000ULL;

double frac64(uint64_t x) { return static_cast<double>(x >> 11) * 0x1.0p-53; }

}  // namespace

LidarEmulator::LidarEmulator(const LidarParams& params)
    : p_(params), rng_(world::deriveSeed(static_cast<uint64_t>(params.seed), 0x11DA7)) {
  const double d2r = kPi / 180.0;
  const auto& r = p_.mount_rpy_deg;
  const auto& t = p_.mount_xyz;
  T_bs_ = Eigen::Isometry3d::Identity();
  T_bs_.linear() = (Eigen::AngleAxisd(r.size() > 2 ? r[2] * d2r : 0.0, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(r.size() > 1 ? r[1] * d2r : 0.0, Eigen::Vector3d::UnitY()) *
                    Eigen::AngleAxisd(r.size() > 0 ? r[0] * d2r : 0.0, Eigen::Vector3d::UnitX()))
                       .toRotationMatrix();
  if (t.size() == 3) T_bs_.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  sin_el_min_ = std::sin(p_.elevation_min_deg * d2r);
  sin_el_span_ = std::sin(p_.elevation_max_deg * d2r) - sin_el_min_;
}

Eigen::Vector3d LidarEmulator::direction(uint64_t k) const {
  const double u1 = frac64(kHalf + k * kA1);
  const double u2 = frac64(kHalf + k * kA2);
  const double az = 2.0 * kPi * u1;
  const double sz = sin_el_min_ + sin_el_span_ * u2;
  const double cz = std::sqrt(std::max(0.0, 1.0 - sz * sz));
  return Eigen::Vector3d(cz * std::cos(az), cz * std::sin(az), sz);
}

void LidarEmulator::scan(const world::World& world, const Eigen::Isometry3d& T_ws, uint64_t k0,
                         std::size_t n, livox::LidarPoint* out, ScanStats* stats) {
  const Eigen::Matrix3d R = T_ws.linear();
  const Eigen::Vector3d o = T_ws.translation();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d ds = direction(k0 + i);
    const Eigen::Vector3d dw = R * ds;
    const world::RayHit hit = world.castRay(o, dw, p_.max_range);
    // Noise is drawn for every ray, hit or not, so the noise sequence does not depend on the
    // scene (and a point's noise only on its index).
    const double noise = p_.range_noise_sigma > 0.0 ? p_.range_noise_sigma * rng_.normal() : 0.0;
    livox::LidarPoint& pt = out[i];
    pt = livox::LidarPoint{};
    if (stats) ++stats->rays;
    if (hit.kind == world::HitKind::kNone) continue;
    const double range = hit.range + noise;
    if (!(range >= p_.min_range) || range > p_.max_range) continue;
    const Eigen::Vector3d p = ds * range;
    pt.x = static_cast<float>(p.x());
    pt.y = static_cast<float>(p.y());
    pt.z = static_cast<float>(p.z());
    // Lambertian-like: reflectivity falls with the incidence angle, never below 20 % of the
    // surface's value; the ground uses the configured floor reflectivity.
    const double base = hit.kind == world::HitKind::kGround ? p_.ground_reflectivity : hit.reflectivity;
    const double cosi = std::fabs(hit.normal.dot(dw));
    const double refl = base * (0.2 + 0.8 * cosi);
    pt.reflectivity = static_cast<uint8_t>(std::min(255.0, std::max(1.0, std::round(refl))));
    pt.tag = 0;
    if (stats) {
      ++stats->returns;
      if (hit.kind == world::HitKind::kGround)
        ++stats->ground_returns;
      else
        ++stats->obstacle_returns;
    }
  }
}

}  // namespace simulator
}  // namespace ucon
