#include "ucon/world/difficulty.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace ucon {
namespace world {

namespace {

// Distance from point p to segment a-b, and the segment parameter of the closest point.
double pointSegment(const Vec2& p, const Vec2& a, const Vec2& b, double* u) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  double s = l2 > 0.0 ? (p - a).dot(ab) / l2 : 0.0;
  s = std::min(1.0, std::max(0.0, s));
  *u = s;
  return (a + s * ab - p).norm();
}

}  // namespace

std::string DifficultyCounts::toString() const {
  std::ostringstream os;
  os << "close passes " << close_passes << ", static passes " << static_passes << ", occlusions "
     << occlusions << " (" << occlusions_by_mover << " by movers, " << occlusions_by_static
     << " by static) in " << duration_s << " s";
  return os.str();
}

DifficultyCounts computeDifficulty(const World& world, const Vec3& sensor, double duration_s,
                                   const DifficultyParams& P) {
  DifficultyCounts out;
  out.duration_s = duration_s;
  out.min_mover_distance = std::numeric_limits<double>::infinity();
  const std::size_t n = world.numMovers();
  const std::size_t ns = world.scenario().statics.size();
  std::vector<char> pair_close(n * n, 0), static_close(n * ns, 0);
  std::vector<double> occluded_since(n, -1.0);
  std::vector<int> occluder_kind(n, 0);  // 1 mover, 2 static
  std::vector<char> occlusion_counted(n, 0);
  std::vector<ObstacleState> st;
  const Vec2 s2(sensor.x(), sensor.y());
  const long steps = static_cast<long>(std::floor(duration_s / P.dt + 1e-9));
  for (long k = 0; k <= steps; ++k) {
    const double t = static_cast<double>(k) * P.dt;
    world.moverStates(t, st);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        const double d = (st[i].position - st[j].position).norm();
        out.min_mover_distance = std::min(out.min_mover_distance, d);
        char& c = pair_close[i * n + j];
        if (!c && d < P.close_pass_m) {
          c = 1;
          ++out.close_passes;
        } else if (c && d > P.close_release_m) {
          c = 0;
        }
      }
      for (std::size_t q = 0; q < ns; ++q) {
        const double gap = world.staticFootprintDistance(q, st[i].position) - st[i].radius;
        char& c = static_close[i * ns + q];
        if (!c && gap < P.static_pass_m) {
          c = 1;
          ++out.static_passes;
        } else if (c && gap > P.static_release_m) {
          c = 0;
        }
      }
      // Occlusion of mover i's centre.
      const Vec2 target = st[i].position;
      const double range = (target - s2).norm();
      int by = 0;
      if (range <= P.max_range_m && range > st[i].radius) {
        for (std::size_t j = 0; j < n && !by; ++j) {
          if (j == i) continue;
          double u;
          // Only occluders in front of the target count (closer to the sensor than it).
          if (pointSegment(st[j].position, s2, target, &u) < st[j].radius &&
              (st[j].position - s2).norm() < range)
            by = 1;
        }
        for (std::size_t q = 0; q < ns && !by; ++q) {
          if (world.scenario().statics[q].height < sensor.z()) continue;
          if (world.segmentHitsStatic(q, s2, target)) by = 2;
        }
      }
      if (by) {
        if (occluded_since[i] < 0.0) {
          occluded_since[i] = t;
          occluder_kind[i] = by;
          occlusion_counted[i] = 0;
        }
        if (!occlusion_counted[i] && t - occluded_since[i] >= P.min_occlusion_s - 1e-9) {
          occlusion_counted[i] = 1;
          ++out.occlusions;
          if (occluder_kind[i] == 1)
            ++out.occlusions_by_mover;
          else
            ++out.occlusions_by_static;
        }
      } else {
        occluded_since[i] = -1.0;
      }
    }
  }
  if (n < 2) out.min_mover_distance = 0.0;
  return out;
}

double moverVisibility(const World& world, std::size_t i, const Vec3& sensor, int columns, int rows,
                       double max_range) {
  if (i >= world.numMovers() || columns < 1 || rows < 1 || !sensor.allFinite()) return 0.0;
  const ObstacleState& m = world.movers()[i];
  const Vec2 s2(sensor.x(), sensor.y());
  const Vec2 to = m.position - s2;
  const double dist = to.norm();
  if (dist <= m.radius) return 0.0;  // the sensor is inside it
  // Points on the chord facing the sensor, slightly inside the body so a ray aimed at them must
  // cross the surface first.
  const Vec2 u = to / dist;
  const Vec2 lateral(-u.y(), u.x());
  int seen = 0, total = 0;
  for (int c = 0; c < columns; ++c) {
    const double a = columns == 1 ? 0.0 : -0.9 + 1.8 * c / (columns - 1);  // across 90 % of the width
    for (int r = 0; r < rows; ++r) {
      const double z = m.height * (rows == 1 ? 0.5 : 0.05 + 0.9 * r / (rows - 1));
      const Vec2 p = m.position + lateral * (a * m.radius) - u * (0.2 * m.radius);
      const Vec3 target(p.x(), p.y(), z);
      const Vec3 d = target - sensor;
      const double len = d.norm();
      ++total;
      if (len > max_range) continue;
      const RayHit h = world.castRay(sensor, d / len, max_range);
      if (h.kind == HitKind::kMoving && h.index == static_cast<int>(i)) ++seen;
    }
  }
  return total > 0 ? static_cast<double>(seen) / total : 0.0;
}

}  // namespace world
}  // namespace ucon
