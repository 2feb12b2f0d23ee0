#include "ucon/planner/guide_path.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "ucon/config.hpp"

namespace ucon::planner {

void FrontEndParams::read(ConfigReader& r) {
  r.read("inflation", inflation, 0.0, 5.0);
  r.read("hard_clearance", hard_clearance, 0.0, 5.0);
  r.read("soft_cost", soft_cost, 0.0, 100.0);
  if (hard_clearance > inflation) r.fail("hard_clearance", "must be <= inflation");
  r.read("window_radius", window_radius, 0.5, 50.0);
  r.read("max_expansions", max_expansions, 1, 10000000);
  r.read("piece_length", piece_length, 0.1, 20.0);
  r.read("max_pieces", max_pieces, 1, 64);
  r.read("guess_speed_ratio", guess_speed_ratio, 0.1, 1.0);
  r.read("guess_accel_ratio", guess_accel_ratio, 0.1, 1.0);
}

const char* toString(GuideStatus s) {
  switch (s) {
    case GuideStatus::kOk: return "ok";
    case GuideStatus::kGoalInCollision: return "goal inside an obstacle; heading to the nearest reachable safe point";
    case GuideStatus::kGoalUnreachable: return "goal unreachable; heading to the nearest reachable point";
    case GuideStatus::kStartOutsideMap: return "robot outside the local map";
    case GuideStatus::kNoMap: return "no map yet";
    case GuideStatus::kBadInput: return "non-finite start or goal";
  }
  return "unknown";
}

bool segmentClear(const EsdfMap& map, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                  double clearance) {
  const double len = (b - a).norm();
  const double step = 0.25 * map.slice().resolution;
  const int n = std::max(1, int(std::ceil(len / step)));
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (double(i) / n);
    if (map.distance(p.x(), p.y(), nullptr) < clearance) return false;
  }
  return true;
}

GuidePath findGuidePath(const EsdfMap& map, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                        const FrontEndParams& params) {
  GuidePath out;
  if (!start.allFinite() || !goal.allFinite()) {
    out.status = GuideStatus::kBadInput;
    return out;
  }
  if (!map.ready()) {
    out.status = GuideStatus::kNoMap;
    return out;
  }
  const SliceGeometry& s = map.slice();
  auto cellOf = [&](const Eigen::Vector2d& p, int* ix, int* iy) {
    *ix = int(std::floor((p.x() - s.origin.x()) / s.resolution));
    *iy = int(std::floor((p.y() - s.origin.y()) / s.resolution));
  };
  int sx, sy;
  cellOf(start, &sx, &sy);
  if (!s.contains(sx, sy)) {
    out.status = GuideStatus::kStartOutsideMap;
    return out;
  }
  const double goal_dist = (goal - start).norm();
  const bool goal_in_window = goal_dist <= params.window_radius;
  int gx = -1, gy = -1;
  if (goal_in_window) cellOf(goal, &gx, &gy);
  const bool goal_blocked = goal_in_window && (!s.contains(gx, gy) || map.cellDistance(gx, gy) < params.hard_clearance);

  const int nx = s.nx;
  const std::size_t n = std::size_t(nx) * s.ny;
  const float inf = std::numeric_limits<float>::infinity();
  // The search grids are the slice's size (~60 000 cells, half a megabyte together): kept per
  // thread and refilled, not allocated (and page-faulted in) again for every plan.
  static thread_local std::vector<float> g;
  static thread_local std::vector<int> parent;
  static thread_local std::vector<uint8_t> closed;
  g.assign(n, inf);
  parent.assign(n, -1);
  closed.assign(n, 0);
  using Entry = std::pair<double, int>;  // f, index
  // The open list: a min-heap (std::priority_queue's operations on a kept vector, so that it
  // does not grow from nothing every plan).
  static thread_local std::vector<Entry> open_heap;
  open_heap.clear();
  struct Open {
    std::vector<Entry>& c;
    bool empty() const { return c.empty(); }
    const Entry& top() const { return c.front(); }
    void push(const Entry& e) {
      c.push_back(e);
      std::push_heap(c.begin(), c.end(), std::greater<Entry>());
    }
    void pop() {
      std::pop_heap(c.begin(), c.end(), std::greater<Entry>());
      c.pop_back();
    }
  } open{open_heap};
  auto h = [&](int ix, int iy) { return (s.cellCenter(ix, iy) - goal).norm(); };
  const int start_idx = sy * nx + sx;
  g[start_idx] = 0.0f;
  open.push({h(sx, sy), start_idx});
  const double r2 = params.window_radius * params.window_radius;
  int best = start_idx;  // closed cell nearest to the goal (fallback)
  double best_h = h(sx, sy);
  int end = -1;
  static const int dx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static const int dy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  static const double dc[8] = {1, 1, 1, 1, M_SQRT2, M_SQRT2, M_SQRT2, M_SQRT2};
  while (!open.empty()) {
    const auto [f, idx] = open.top();
    open.pop();
    if (closed[idx]) continue;
    closed[idx] = 1;
    ++out.expansions;
    const int ix = idx % nx, iy = idx / nx;
    const double hi = h(ix, iy);
    if (hi < best_h) {
      best_h = hi;
      best = idx;
    }
    if (goal_in_window) {
      if (ix == gx && iy == gy) {
        end = idx;
        break;
      }
    } else if ((s.cellCenter(ix, iy) - start).squaredNorm() >= r2) {
      end = idx;
      break;
    }
    if (out.expansions >= params.max_expansions) break;
    const double d_here = map.cellDistance(ix, iy);
    for (int k = 0; k < 8; ++k) {
      const int jx = ix + dx[k], jy = iy + dy[k];
      if (!s.contains(jx, jy)) continue;
      const int j = jy * nx + jx;
      if (closed[j]) continue;
      const double dj = map.cellDistance(jx, jy);
      const double hard = params.hard_clearance;
      if (dj < hard && !(dj >= d_here && d_here < hard)) continue;
      if (k >= 4) {  // no corner cutting through blocked cells
        if (map.cellDistance(ix + dx[k], iy) < std::min(hard, d_here) ||
            map.cellDistance(ix, iy + dy[k]) < std::min(hard, d_here)) {
          continue;
        }
      }
      double step = dc[k] * s.resolution;
      if (dj < params.inflation) {
        const double span = std::max(1e-6, params.inflation - hard);
        step *= 1.0 + params.soft_cost * std::min(1.0, (params.inflation - dj) / span);
      }
      const float gj = float(g[idx] + step);
      if (gj < g[j]) {
        g[j] = gj;
        parent[j] = idx;
        open.push({gj + h(jx, jy), j});
      }
    }
  }
  if (end < 0) {
    end = best;
    out.status = goal_blocked ? GuideStatus::kGoalInCollision : GuideStatus::kGoalUnreachable;
  } else {
    out.status = GuideStatus::kOk;
    out.reaches_goal = goal_in_window;
  }
  // Walk back.
  std::vector<Eigen::Vector2d> cells;
  for (int i = end; i >= 0; i = parent[i]) cells.push_back(s.cellCenter(i % nx, i / nx));
  std::reverse(cells.begin(), cells.end());
  cells.front() = start;
  if (out.reaches_goal) cells.back() = goal;
  // Line-of-sight shortcut (greedy, farthest visible point) that never goes closer to an
  // obstacle than the A* cells it replaces (clearance capped at the inflation).
  std::vector<double> clear(cells.size());
  for (std::size_t k = 0; k < cells.size(); ++k) {
    clear[k] = std::min(params.inflation, map.distance(cells[k].x(), cells[k].y(), nullptr));
  }
  out.points.push_back(cells.front());
  std::size_t i = 0;
  std::vector<double> worst(cells.size());
  while (i + 1 < cells.size()) {
    worst[i] = clear[i];
    for (std::size_t j = i + 1; j < cells.size(); ++j) worst[j] = std::min(worst[j - 1], clear[j]);
    std::size_t j = cells.size() - 1;
    while (j > i + 1 && !segmentClear(map, cells[i], cells[j], worst[j] - 1e-3)) --j;
    out.points.push_back(cells[j]);
    i = j;
  }
  if (out.points.size() == 1) out.points.push_back(out.points.front());
  return out;
}

InitialGuess makeInitialGuess(const std::vector<Eigen::Vector2d>& path, double max_length, double v0,
                              double v_max, double a_max, const FrontEndParams& params) {
  InitialGuess g;
  // Truncate the polyline.
  std::vector<Eigen::Vector2d> pts;
  double total = 0.0;
  if (!path.empty()) pts.push_back(path.front());
  for (std::size_t i = 1; i < path.size() && total < max_length; ++i) {
    const double seg = (path[i] - path[i - 1]).norm();
    if (total + seg > max_length) {
      pts.push_back(path[i - 1] + (path[i] - path[i - 1]) * ((max_length - total) / seg));
      total = max_length;
    } else {
      pts.push_back(path[i]);
      total += seg;
    }
  }
  g.length = total;
  if (pts.empty()) pts.push_back(Eigen::Vector2d::Zero());
  g.end = pts.back();
  const int pieces = std::clamp(int(std::ceil(total / params.piece_length)), 1, params.max_pieces);
  // Arc-length positions of the piece boundaries and the polyline point at each.
  auto pointAt = [&](double sq) {
    double acc = 0.0;
    for (std::size_t i = 1; i < pts.size(); ++i) {
      const double seg = (pts[i] - pts[i - 1]).norm();
      if (acc + seg >= sq && seg > 0.0) return Eigen::Vector2d(pts[i - 1] + (pts[i] - pts[i - 1]) * ((sq - acc) / seg));
      acc += seg;
    }
    return pts.back();
  };
  // Trapezoidal speed profile from v0 to rest over the whole length (closed form s(t)), then
  // each piece boundary gets the time at which s(t) reaches it (bisection).
  v_max = std::max(v_max, 1e-3);
  a_max = std::max(a_max, 1e-3);
  v0 = std::clamp(v0, 0.0, v_max);
  // Peak speed: accelerate from v0 and decelerate to 0 within `total`.
  double vp = std::sqrt(std::max(0.0, (2.0 * a_max * total + v0 * v0) / 2.0));
  vp = std::min(vp, v_max);
  if (v0 * v0 / (2.0 * a_max) > total) vp = v0;  // cannot stop in time: decelerate only
  const double t1 = std::max(0.0, (vp - v0) / a_max);
  const double s1 = (v0 + vp) * 0.5 * t1;
  const double t3 = vp / a_max;
  const double s3 = vp * 0.5 * t3;
  const double t2 = vp > 0.0 ? std::max(0.0, (total - s1 - s3) / vp) : 0.0;
  const double t_end = t1 + t2 + t3;
  auto sOf = [&](double t) {
    if (t <= t1) return v0 * t + 0.5 * a_max * t * t;
    if (t <= t1 + t2) return s1 + vp * (t - t1);
    const double u = std::min(t - t1 - t2, t3);
    return s1 + vp * t2 + vp * u - 0.5 * a_max * u * u;
  };
  auto timeAt = [&](double sq) {
    double lo = 0.0, hi = t_end;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      (sOf(mid) < sq ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  double t_prev = 0.0;
  for (int k = 0; k < pieces; ++k) {
    const double s_next = total * (k + 1) / pieces;
    const double t_next = (k + 1 == pieces) ? t_end : timeAt(s_next);
    g.durations.push_back(std::max(t_next - t_prev, 0.05));
    t_prev = t_next;
    if (k + 1 < pieces) g.waypoints.push_back(pointAt(s_next));
  }
  return g;
}

}  // namespace ucon::planner
