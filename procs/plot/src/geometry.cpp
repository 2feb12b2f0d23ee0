#include "ucon/plot/geometry.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace ucon {
namespace plot {

std::optional<Ellipse> covarianceEllipse(const Eigen::Matrix2d& cov, double n_sigma) {
  if (!cov.allFinite() || !std::isfinite(n_sigma) || n_sigma < 0.0) return std::nullopt;
  const double scale = std::max(1e-300, cov.cwiseAbs().maxCoeff());
  if (std::abs(cov(0, 1) - cov(1, 0)) > 1e-9 * scale) return std::nullopt;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  if (es.info() != Eigen::Success) return std::nullopt;
  const Eigen::Vector2d ev = es.eigenvalues();  // ascending
  if (ev(0) < -1e-9 * scale) return std::nullopt;
  Ellipse e;
  e.a = n_sigma * std::sqrt(std::max(0.0, ev(1)));
  e.b = n_sigma * std::sqrt(std::max(0.0, ev(0)));
  const Eigen::Vector2d major = es.eigenvectors().col(1);
  e.angle = std::atan2(major.y(), major.x());
  return e;
}

std::optional<Sector> uncertaintySector(const Eigen::Vector2d& position, const Eigen::Vector2d& velocity,
                                        const Eigen::Matrix2d& cov_xy, bool has_cov, double box_diagonal,
                                        const SectorParams& p) {
  if (!position.allFinite() || !velocity.allFinite() || !std::isfinite(box_diagonal)) return std::nullopt;
  const Eigen::Matrix2d S = has_cov && cov_xy.allFinite() ? cov_xy : Eigen::Matrix2d::Zero();
  auto safeSqrt = [](double x) { return std::sqrt(std::max(0.0, x)); };
  Sector s;
  s.centre = position;
  const double body = 0.5 * std::max(0.0, box_diagonal) + p.safe_distance;
  const double speed = velocity.norm();
  if (speed < p.min_speed || speed * p.h <= 0.0) {
    s.radius = body + p.k * safeSqrt(S.trace());
    s.half_angle = M_PI;
    return s;
  }
  const Eigen::Vector2d dir = velocity / speed;
  const Eigen::Vector2d perp(-dir.y(), dir.x());
  s.heading = std::atan2(dir.y(), dir.x());
  s.radius = speed * p.h + p.k * safeSqrt(dir.dot(S * dir)) + body;            // eq. (6)
  s.half_angle = std::atan2(p.kappa * safeSqrt(perp.dot(S * perp)), speed * p.h);  // eq. (7) / 2
  return s;
}

Rgb speedColour(double u) {
  // Viridis, 9 control points (matplotlib's table sampled at k/8), linear in between.
  static const std::array<Rgb, 9> kTable = {{{0.267, 0.005, 0.329},
                                              {0.279, 0.175, 0.483},
                                              {0.230, 0.322, 0.546},
                                              {0.173, 0.449, 0.558},
                                              {0.128, 0.567, 0.551},
                                              {0.158, 0.684, 0.502},
                                              {0.369, 0.789, 0.383},
                                              {0.678, 0.864, 0.190},
                                              {0.993, 0.906, 0.144}}};
  if (!std::isfinite(u)) u = 0.0;
  u = std::clamp(u, 0.0, 1.0) * 8.0;
  const int i = std::min(7, static_cast<int>(u));
  const double f = u - i;
  const Rgb& a = kTable[i];
  const Rgb& b = kTable[i + 1];
  return {a.r + (b.r - a.r) * f, a.g + (b.g - a.g) * f, a.b + (b.b - a.b) * f};
}

Rgb idColour(int64_t id) {
  static const std::array<Rgb, 10> kTable = {{{0.122, 0.467, 0.706},
                                               {1.000, 0.498, 0.055},
                                               {0.173, 0.627, 0.173},
                                               {0.839, 0.153, 0.157},
                                               {0.580, 0.404, 0.741},
                                               {0.549, 0.337, 0.294},
                                               {0.890, 0.467, 0.761},
                                               {0.498, 0.498, 0.498},
                                               {0.737, 0.741, 0.133},
                                               {0.090, 0.745, 0.812}}};
  const int64_t n = static_cast<int64_t>(kTable.size());
  return kTable[static_cast<std::size_t>(((id % n) + n) % n)];
}

std::string toHex(const Rgb& c) {
  auto byte = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  char buf[8];
  std::snprintf(buf, sizeof(buf), "#%02x%02x%02x", byte(c.r), byte(c.g), byte(c.b));
  return buf;
}

double niceLength(double max_length) {
  if (!std::isfinite(max_length) || max_length <= 0.0) return 0.0;
  const double p = std::pow(10.0, std::floor(std::log10(max_length)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * p <= max_length * (1.0 + 1e-12)) return m * p;
  }
  return p;
}

void Bounds::add(double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return;
  if (!valid) {
    min_x = max_x = x;
    min_y = max_y = y;
    valid = true;
    return;
  }
  min_x = std::min(min_x, x);
  max_x = std::max(max_x, x);
  min_y = std::min(min_y, y);
  max_y = std::max(max_y, y);
}

void Bounds::pad(double fraction, double minimum) {
  if (!valid) return;
  const double dx = std::max(minimum, fraction * width());
  const double dy = std::max(minimum, fraction * height());
  min_x -= dx;
  max_x += dx;
  min_y -= dy;
  max_y += dy;
}

Bounds focusBounds(const Bounds& robot_and_map, const std::vector<Eigen::Vector2d>& objects, double margin) {
  Bounds out = robot_and_map;
  if (!robot_and_map.valid) {
    for (const auto& p : objects) out.add(p.x(), p.y());
    return out;
  }
  Bounds window = robot_and_map;
  window.min_x -= margin;
  window.min_y -= margin;
  window.max_x += margin;
  window.max_y += margin;
  for (const auto& p : objects) {
    if (window.contains(p.x(), p.y())) out.add(p.x(), p.y());
  }
  return out;
}

}  // namespace plot
}  // namespace ucon
