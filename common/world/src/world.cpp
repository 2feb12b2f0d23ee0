#include "ucon/world/world.hpp"

#include <algorithm>
#include <cmath>

#include "ucon/world/rng.hpp"

namespace ucon {
namespace world {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = 1e-12;

// Interval of the ray parameter over which z(t) = oz + dz t lies in [0, h].
bool zInterval(double oz, double dz, double h, double* t0, double* t1) {
  if (std::fabs(dz) < kEps) {
    if (oz < 0.0 || oz > h) return false;
    *t0 = -kInf;
    *t1 = kInf;
    return true;
  }
  const double a = -oz / dz, b = (h - oz) / dz;
  *t0 = std::min(a, b);
  *t1 = std::max(a, b);
  return true;
}

// Ray against a vertical cylinder standing on the ground. On a hit at t >= 0 sets *t and the
// outward normal *n.
bool rayCylinder(const Vec3& o, const Vec3& d, const Vec2& c, double r, double h, double* t,
                 Vec3* n) {
  double tz0, tz1;
  if (!zInterval(o.z(), d.z(), h, &tz0, &tz1)) return false;
  const double fx = o.x() - c.x(), fy = o.y() - c.y();
  const double a = d.x() * d.x() + d.y() * d.y();
  double ts0, ts1;
  if (a < kEps) {
    if (fx * fx + fy * fy > r * r) return false;
    ts0 = -kInf;
    ts1 = kInf;
  } else {
    const double b = fx * d.x() + fy * d.y();
    const double cc = fx * fx + fy * fy - r * r;
    const double disc = b * b - a * cc;
    if (disc < 0.0) return false;
    const double sq = std::sqrt(disc);
    ts0 = (-b - sq) / a;
    ts1 = (-b + sq) / a;
  }
  const double tin = std::max(ts0, tz0), tout = std::min(ts1, tz1);
  if (tin > tout || tout < 0.0) return false;
  const double th = std::max(tin, 0.0);
  *t = th;
  if (ts0 >= tz0) {
    const double px = fx + d.x() * th, py = fy + d.y() * th;
    const double len = std::sqrt(px * px + py * py);
    *n = len > kEps ? Vec3(px / len, py / len, 0.0) : Vec3(-d.x(), -d.y(), 0.0);
  } else {
    *n = Vec3(0.0, 0.0, d.z() < 0.0 ? 1.0 : -1.0);
  }
  return true;
}

// Ray against a vertical box (footprint centre c, half extents hs, rotation cos/sin), same
// contract as rayCylinder.
bool rayBox(const Vec3& o, const Vec3& d, const Vec2& c, const Vec2& hs, double cy, double sy,
            double h, double* t, Vec3* n) {
  double tz0, tz1;
  if (!zInterval(o.z(), d.z(), h, &tz0, &tz1)) return false;
  const double rx = o.x() - c.x(), ry = o.y() - c.y();
  const double lox = cy * rx + sy * ry, loy = -sy * rx + cy * ry;
  const double ldx = cy * d.x() + sy * d.y(), ldy = -sy * d.x() + cy * d.y();
  double tx0, tx1, ty0, ty1;
  if (std::fabs(ldx) < kEps) {
    if (std::fabs(lox) > hs.x()) return false;
    tx0 = -kInf;
    tx1 = kInf;
  } else {
    const double a = (-hs.x() - lox) / ldx, b = (hs.x() - lox) / ldx;
    tx0 = std::min(a, b);
    tx1 = std::max(a, b);
  }
  if (std::fabs(ldy) < kEps) {
    if (std::fabs(loy) > hs.y()) return false;
    ty0 = -kInf;
    ty1 = kInf;
  } else {
    const double a = (-hs.y() - loy) / ldy, b = (hs.y() - loy) / ldy;
    ty0 = std::min(a, b);
    ty1 = std::max(a, b);
  }
  const double ts0 = std::max(tx0, ty0), ts1 = std::min(tx1, ty1);
  const double tin = std::max(ts0, tz0), tout = std::min(ts1, tz1);
  if (tin > tout || tout < 0.0) return false;
  *t = std::max(tin, 0.0);
  if (ts0 >= tz0) {
    // Side face: the slab that was entered last.
    double lnx = 0.0, lny = 0.0;
    if (tx0 >= ty0)
      lnx = ldx > 0.0 ? -1.0 : 1.0;
    else
      lny = ldy > 0.0 ? -1.0 : 1.0;
    *n = Vec3(cy * lnx - sy * lny, sy * lnx + cy * lny, 0.0);
  } else {
    *n = Vec3(0.0, 0.0, d.z() < 0.0 ? 1.0 : -1.0);
  }
  return true;
}

// Distance from a point to a solid prism given the signed footprint distance s2 and height h.
double prismDistance(double s2, double z, double h) {
  if (s2 > 0.0) {
    const double dz = z > h ? z - h : (z < 0.0 ? -z : 0.0);
    return std::sqrt(s2 * s2 + dz * dz);
  }
  if (z > h) return z - h;
  if (z < 0.0) return -z;
  return std::min(-s2, h - z);
}

double boxSignedDistance(const Vec2& p, const Vec2& c, const Vec2& hs, double cy, double sy) {
  const double rx = p.x() - c.x(), ry = p.y() - c.y();
  const double qx = std::fabs(cy * rx + sy * ry) - hs.x();
  const double qy = std::fabs(-sy * rx + cy * ry) - hs.y();
  const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0);
  return std::sqrt(ox * ox + oy * oy) + std::min(std::max(qx, qy), 0.0);
}

}  // namespace

double foldIntoInterval(double u, double lo, double hi, double* sign) {
  const double len = hi - lo;
  if (!(len > 0.0)) {
    *sign = 0.0;
    return 0.5 * (lo + hi);
  }
  double m = std::fmod(u - lo, 2.0 * len);
  if (m < 0.0) m += 2.0 * len;
  if (m <= len) {
    *sign = 1.0;
    return lo + m;
  }
  *sign = -1.0;
  return lo + 2.0 * len - m;
}

World::World(Scenario scenario) : World(std::move(scenario), Options{}) {}

World::World(Scenario scenario, const Options& options)
    : scenario_(std::move(scenario)), options_(options) {
  if (!(options_.cell_size > 0.0)) options_.cell_size = 1.0;
  for (const auto& s : scenario_.statics) {
    cos_yaw_.push_back(std::cos(s.yaw));
    sin_yaw_.push_back(std::sin(s.yaw));
    max_height_ = std::max(max_height_, s.height);
  }
  for (const auto& m : scenario_.movers) max_height_ = std::max(max_height_, m.height);
  buildTimelines();
  buildStaticGrid();
  setTime(0.0);
}

void World::buildTimelines() {
  timelines_.assign(scenario_.movers.size(), {});
  double horizon = options_.timeline_horizon_s;
  if (!(horizon > 0.0)) horizon = std::max(scenario_.duration_s, 3600.0);
  for (std::size_t i = 0; i < scenario_.movers.size(); ++i) {
    const MovingObstacle& m = scenario_.movers[i];
    const MotionParams& p = m.motion;
    if (p.kind != MotionKind::kPedestrian) continue;
    auto& tl = timelines_[i];
    if (p.waypoints.size() < 2) {
      // Invalid (validate() rejects it): stand still rather than misbehave.
      tl.push_back({0.0, p.waypoints.empty() ? p.position : p.waypoints[0], Vec2::Zero()});
      continue;
    }
    // Guards so that even an unvalidated scenario always makes progress.
    const double v_lo = std::max(1e-3, p.speed_min), v_hi = std::max(v_lo, p.speed_max);
    const double c_lo = std::max(1e-2, p.speed_change_min_s), c_hi = std::max(c_lo, p.speed_change_max_s);
    const double pz_lo = std::max(0.0, p.pause_min_s), pz_hi = std::max(pz_lo, p.pause_max_s);
    Rng rng(deriveSeed(scenario_.seed, static_cast<uint64_t>(m.id)));
    const std::size_t nw = p.waypoints.size();
    Vec2 pos = p.waypoints[0];
    std::size_t cur = 0;
    int dir = 1;  // ping-pong direction
    auto nextIndex = [&]() -> std::size_t {
      switch (p.mode) {
        case PathMode::kLoop:
          return (cur + 1) % nw;
        case PathMode::kPingPong: {
          if (cur + 1 >= nw && dir > 0) dir = -1;
          if (cur == 0 && dir < 0) dir = 1;
          return static_cast<std::size_t>(static_cast<long>(cur) + dir);
        }
        case PathMode::kRandom: {
          const std::size_t k = static_cast<std::size_t>(rng.below(nw - 1));
          return k >= cur ? k + 1 : k;
        }
      }
      return 0;
    };
    auto aim = [&](std::size_t k) {
      Vec2 w = p.waypoints[k];
      if (p.jitter > 0.0) {
        w.x() += rng.uniform(-p.jitter, p.jitter);
        w.y() += rng.uniform(-p.jitter, p.jitter);
      }
      return w;
    };
    double t = 0.0;
    double speed = rng.uniform(v_lo, v_hi);
    double next_change = rng.uniform(c_lo, c_hi);
    cur = nextIndex();
    Vec2 target = aim(cur);
    int stuck = 0;  // iterations without time passing (all waypoints equal, no pauses)
    while (t < horizon && stuck < 4 * static_cast<int>(nw) + 8) {
      const double t_before = t;
      if (t >= next_change) {
        speed = rng.uniform(v_lo, v_hi);
        next_change = t + rng.uniform(c_lo, c_hi);
      }
      const Vec2 delta = target - pos;
      const double dist = delta.norm();
      if (!std::isfinite(dist)) break;  // non-finite waypoint: stop here
      if (dist > 1e-9) {
        const Vec2 v = delta * (speed / dist);
        const double t_arrive = t + dist / speed;
        if (t_arrive <= next_change) {
          tl.push_back({t, pos, v});
          t = t_arrive;
          pos = target;
        } else {
          tl.push_back({t, pos, v});
          pos = pos + v * (next_change - t);
          t = next_change;
          continue;
        }
      }
      // Reached the target: maybe pause, then aim at the next waypoint.
      if (rng.uniform01() < p.pause_probability) {
        const double d = rng.uniform(pz_lo, pz_hi);
        if (d > 0.0) {
          tl.push_back({t, pos, Vec2::Zero()});
          t += d;
        }
      }
      cur = nextIndex();
      target = aim(cur);
      stuck = t > t_before ? 0 : stuck + 1;
    }
    tl.push_back({t, pos, Vec2::Zero()});  // stands still after the horizon
  }
}

void World::buildStaticGrid() {
  const Bounds& b = scenario_.bounds;
  double x0 = b.xmin, y0 = b.ymin, x1 = b.xmax, y1 = b.ymax;
  for (std::size_t i = 0; i < scenario_.statics.size(); ++i) {
    const auto& s = scenario_.statics[i];
    const double ext = s.kind == ShapeKind::kCylinder ? s.radius : s.half_size.norm();
    x0 = std::min(x0, s.center.x() - ext);
    x1 = std::max(x1, s.center.x() + ext);
    y0 = std::min(y0, s.center.y() - ext);
    y1 = std::max(y1, s.center.y() + ext);
  }
  double pad = 0.0;
  for (const auto& m : scenario_.movers) pad = std::max(pad, m.radius + m.motion.jitter);
  cell_ = options_.cell_size;
  // Keep the grid at most ~4 million cells however large the world is.
  const double area = (x1 - x0 + 2.0 * pad + 2.0 * cell_) * (y1 - y0 + 2.0 * pad + 2.0 * cell_);
  if (area / (cell_ * cell_) > 4.0e6) cell_ = std::sqrt(area / 4.0e6);
  inv_cell_ = 1.0 / cell_;
  gx0_ = x0 - pad - cell_;
  gy0_ = y0 - pad - cell_;
  nx_ = std::max(1, static_cast<int>(std::ceil((x1 + pad + cell_ - gx0_) * inv_cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((y1 + pad + cell_ - gy0_) * inv_cell_)));
  const int ncell = nx_ * ny_;
  static_start_.assign(ncell + 1, 0);
  auto forCells = [&](std::size_t i, auto&& fn) {
    const auto& s = scenario_.statics[i];
    const double ext = s.kind == ShapeKind::kCylinder ? s.radius : s.half_size.norm();
    int cx0, cy0, cx1, cy1;
    cellRange(s.center.x() - ext, s.center.y() - ext, s.center.x() + ext, s.center.y() + ext, &cx0,
              &cy0, &cx1, &cy1);
    for (int cy = cy0; cy <= cy1; ++cy)
      for (int cx = cx0; cx <= cx1; ++cx) fn(cellIndex(cx, cy));
  };
  for (std::size_t i = 0; i < scenario_.statics.size(); ++i)
    forCells(i, [&](int c) { ++static_start_[c + 1]; });
  for (int c = 0; c < ncell; ++c) static_start_[c + 1] += static_start_[c];
  static_items_.assign(static_start_[ncell], 0);
  std::vector<int> fill(static_start_.begin(), static_start_.end() - 1);
  for (std::size_t i = 0; i < scenario_.statics.size(); ++i)
    forCells(i, [&](int c) { static_items_[fill[c]++] = static_cast<int>(i); });
  mover_start_.assign(ncell + 1, 0);
  mover_fill_.assign(ncell, 0);
}

void World::cellRange(double x0, double y0, double x1, double y1, int* cx0, int* cy0, int* cx1,
                      int* cy1) const {
  // Clamped to the grid; NaN maps to cell 0 (no undefined float->int conversion).
  auto cell = [](double v, int n) {
    if (!(v >= 0.0)) return 0;
    if (v >= static_cast<double>(n - 1)) return n - 1;
    return static_cast<int>(v);
  };
  *cx0 = cell((x0 - gx0_) * inv_cell_, nx_);
  *cy0 = cell((y0 - gy0_) * inv_cell_, ny_);
  *cx1 = cell((x1 - gx0_) * inv_cell_, nx_);
  *cy1 = cell((y1 - gy0_) * inv_cell_, ny_);
}

std::size_t World::segmentAfter(const std::vector<TimelineSegment>& tl, double t, std::size_t* hint) {
  // The index of the first piece starting after t (std::upper_bound on t0). Time mostly
  // moves forward in small steps, so the last answer or the next one is checked first.
  const auto answers = [&](std::size_t h) {
    return h <= tl.size() && (h == 0 || tl[h - 1].t0 <= t) && (h == tl.size() || t < tl[h].t0);
  };
  if (hint) {
    if (answers(*hint)) return *hint;
    if (answers(*hint + 1)) return ++*hint;
  }
  const auto it = std::upper_bound(tl.begin(), tl.end(), t,
                                   [](double tv, const TimelineSegment& sg) { return tv < sg.t0; });
  const std::size_t idx = std::size_t(it - tl.begin());
  if (hint) *hint = idx;
  return idx;
}

ObstacleState World::moverState(std::size_t i, double t) const { return moverState(i, t, nullptr); }

ObstacleState World::moverState(std::size_t i, double t, std::size_t* segment_hint) const {
  const MovingObstacle& m = scenario_.movers[i];
  const MotionParams& p = m.motion;
  ObstacleState s;
  s.id = m.id;
  s.radius = m.radius;
  s.height = m.height;
  s.motion = p.kind;
  if (!(t > 0.0)) t = 0.0;
  Vec2 u, v;  // unfolded position and velocity
  switch (p.kind) {
    case MotionKind::kConstantVelocity:
      u = p.position + p.velocity * t;
      v = p.velocity;
      break;
    case MotionKind::kConstantAcceleration: {
      const double aa = p.acceleration.squaredNorm();
      double t_cap = kInf;
      if (aa > 0.0) {
        const double va = p.velocity.dot(p.acceleration);
        const double c = p.velocity.squaredNorm() - p.speed_cap * p.speed_cap;
        t_cap = (-va + std::sqrt(std::max(0.0, va * va - aa * c))) / aa;
      }
      const double tc = std::min(t, t_cap);
      u = p.position + p.velocity * tc + 0.5 * p.acceleration * (tc * tc);
      v = p.velocity + p.acceleration * tc;
      if (t > tc) u += v * (t - tc);
      break;
    }
    case MotionKind::kSinusoidal:
      for (int k = 0; k < 2; ++k) {
        const double w = p.omega[k], ph = p.phase[k];
        u[k] = p.position[k] + p.offset[k] * t +
               p.amplitude[k] / w * (std::cos(ph) - std::cos(w * t + ph));
        v[k] = p.amplitude[k] * std::sin(w * t + ph) + p.offset[k];
      }
      break;
    case MotionKind::kPedestrian: {
      const auto& tl = timelines_[i];
      const std::size_t idx = segmentAfter(tl, t, segment_hint);
      const TimelineSegment& sg = idx == 0 ? tl.front() : tl[idx - 1];
      s.position = sg.p0 + sg.v * (t - sg.t0);
      s.velocity = sg.v;
      if (idx == tl.size()) s.velocity.setZero();
      return s;
    }
  }
  const Bounds& b = scenario_.bounds;
  double sx, sy;
  s.position.x() = foldIntoInterval(u.x(), b.xmin + m.radius, b.xmax - m.radius, &sx);
  s.position.y() = foldIntoInterval(u.y(), b.ymin + m.radius, b.ymax - m.radius, &sy);
  s.velocity = Vec2(sx * v.x(), sy * v.y());
  return s;
}

void World::moverStates(double t, std::vector<ObstacleState>& out) const {
  out.resize(scenario_.movers.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = moverState(i, t);
}

void World::setTime(double t) {
  time_ = t;
  const std::size_t n = scenario_.movers.size();
  states_.resize(n);
  segment_hints_.resize(n, 0);
  for (std::size_t i = 0; i < n; ++i) states_[i] = moverState(i, t, &segment_hints_[i]);
  // The movers' cell ranges; the grid is rebuilt only when one of them changed (a mover
  // moves about a millimetre between two packets and crosses a cell border rarely).
  bool same = mover_ranges_.size() == n;
  mover_ranges_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ObstacleState& s = states_[i];
    std::array<int, 4> r;
    cellRange(s.position.x() - s.radius, s.position.y() - s.radius, s.position.x() + s.radius,
              s.position.y() + s.radius, &r[0], &r[1], &r[2], &r[3]);
    same = same && r == mover_ranges_[i];
    mover_ranges_[i] = r;
  }
  if (same) return;
  const int ncell = nx_ * ny_;
  std::fill(mover_start_.begin(), mover_start_.end(), 0);
  // Two passes over the movers' cell ranges: count, then fill (CSR layout).
  auto forCells = [&](std::size_t i, auto&& fn) {
    const std::array<int, 4>& r = mover_ranges_[i];
    for (int cy = r[1]; cy <= r[3]; ++cy)
      for (int cx = r[0]; cx <= r[2]; ++cx) fn(cellIndex(cx, cy));
  };
  for (std::size_t i = 0; i < n; ++i) forCells(i, [&](int c) { ++mover_start_[c + 1]; });
  for (int c = 0; c < ncell; ++c) mover_start_[c + 1] += mover_start_[c];
  mover_items_.resize(mover_start_[ncell]);
  std::copy(mover_start_.begin(), mover_start_.end() - 1, mover_fill_.begin());
  for (std::size_t i = 0; i < n; ++i) forCells(i, [&](int c) { mover_items_[mover_fill_[c]++] = static_cast<int>(i); });
}

bool World::rayStatic(std::size_t i, const Vec3& o, const Vec3& d, double* t, Vec3* n) const {
  const StaticObstacle& s = scenario_.statics[i];
  if (s.kind == ShapeKind::kCylinder) return rayCylinder(o, d, s.center, s.radius, s.height, t, n);
  return rayBox(o, d, s.center, s.half_size, cos_yaw_[i], sin_yaw_[i], s.height, t, n);
}

bool World::rayMover(std::size_t i, const Vec3& o, const Vec3& d, double* t, Vec3* n) const {
  const ObstacleState& s = states_[i];
  return rayCylinder(o, d, s.position, s.radius, s.height, t, n);
}

RayHit World::castRay(const Vec3& o, const Vec3& d, double max_range) const {
  RayHit best;
  best.range = max_range;
  if (!(max_range > 0.0) || !o.allFinite() || !d.allFinite()) {
    best.range = kInf;
    return best;
  }
  if (d.z() < -kEps) {
    const double tg = -o.z() / d.z();
    if (tg >= 0.0 && tg < best.range) {
      best.kind = HitKind::kGround;
      best.range = tg;
      best.normal = Vec3::UnitZ();
      best.reflectivity = options_.ground_reflectivity;
    }
  }
  // Obstacles occupy 0 <= z <= max_height_: only that slice of the ray needs the grid.
  double t_start = 0.0, t_end = best.range;
  if (d.z() > kEps) {
    t_end = std::min(t_end, (max_height_ - o.z()) / d.z());
  } else if (d.z() < -kEps && o.z() > max_height_) {
    t_start = (max_height_ - o.z()) / d.z();
  } else if (std::fabs(d.z()) <= kEps && (o.z() > max_height_ || o.z() < 0.0)) {
    t_end = -1.0;
  }
  // Clip to the grid box.
  const double gx1 = gx0_ + nx_ * cell_, gy1 = gy0_ + ny_ * cell_;
  const double dx = d.x(), dy = d.y();
  for (int k = 0; k < 2 && t_start <= t_end; ++k) {
    const double oc = k == 0 ? o.x() : o.y(), dc = k == 0 ? dx : dy;
    const double lo = k == 0 ? gx0_ : gy0_, hi = k == 0 ? gx1 : gy1;
    if (std::fabs(dc) < kEps) {
      if (oc < lo || oc > hi) t_end = -1.0;
    } else {
      double a = (lo - oc) / dc, b = (hi - oc) / dc;
      if (a > b) std::swap(a, b);
      t_start = std::max(t_start, a);
      t_end = std::min(t_end, b);
    }
  }
  if (t_start > t_end) {
    if (best.kind == HitKind::kNone) best.range = kInf;
    return best;
  }
  const double px = o.x() + dx * t_start, py = o.y() + dy * t_start;
  int cx = std::min(nx_ - 1, std::max(0, static_cast<int>(std::floor((px - gx0_) * inv_cell_))));
  int cy = std::min(ny_ - 1, std::max(0, static_cast<int>(std::floor((py - gy0_) * inv_cell_))));
  const int step_x = dx > 0.0 ? 1 : -1, step_y = dy > 0.0 ? 1 : -1;
  double tmax_x = kInf, tmax_y = kInf, tdel_x = kInf, tdel_y = kInf;
  if (std::fabs(dx) >= kEps) {
    tmax_x = (gx0_ + (cx + (dx > 0.0 ? 1 : 0)) * cell_ - o.x()) / dx;
    tdel_x = cell_ / std::fabs(dx);
  }
  if (std::fabs(dy) >= kEps) {
    tmax_y = (gy0_ + (cy + (dy > 0.0 ? 1 : 0)) * cell_ - o.y()) / dy;
    tdel_y = cell_ / std::fabs(dy);
  }
  double t;
  Vec3 n;
  // Obstacles larger than a cell are listed in several cells: each is intersected once per
  // ray (the first kTested of them are remembered; the rest are just tested again).
  constexpr int kTested = 32;
  int tested[kTested];
  int num_tested = 0;
  const auto testedBefore = [&](int code) {
    for (int j = 0; j < num_tested; ++j)
      if (tested[j] == code) return true;
    if (num_tested < kTested) tested[num_tested++] = code;
    return false;
  };
  while (true) {
    const int c = cellIndex(cx, cy);
    for (int k = static_start_[c]; k < static_start_[c + 1]; ++k) {
      const int i = static_items_[k];
      if (testedBefore(i)) continue;
      if (rayStatic(i, o, d, &t, &n) && t < best.range) {
        best.kind = HitKind::kStatic;
        best.range = t;
        best.index = i;
        best.normal = n;
        best.reflectivity = scenario_.statics[i].reflectivity;
      }
    }
    for (int k = mover_start_[c]; k < mover_start_[c + 1]; ++k) {
      const int i = mover_items_[k];
      if (testedBefore(~i)) continue;  // movers as ~index: apart from the statics
      if (rayMover(i, o, d, &t, &n) && t < best.range) {
        best.kind = HitKind::kMoving;
        best.range = t;
        best.index = i;
        best.normal = n;
        best.reflectivity = scenario_.movers[i].reflectivity;
      }
    }
    const double t_exit = std::min(tmax_x, tmax_y);
    if (best.range <= t_exit || t_exit > t_end) break;
    if (tmax_x < tmax_y) {
      cx += step_x;
      if (cx < 0 || cx >= nx_) break;
      tmax_x += tdel_x;
    } else {
      cy += step_y;
      if (cy < 0 || cy >= ny_) break;
      tmax_y += tdel_y;
    }
  }
  if (best.kind == HitKind::kNone) best.range = kInf;
  return best;
}

double World::staticFootprintDistance(std::size_t i, const Vec2& p) const {
  const StaticObstacle& s = scenario_.statics[i];
  if (s.kind == ShapeKind::kCylinder) return (p - s.center).norm() - s.radius;
  return boxSignedDistance(p, s.center, s.half_size, cos_yaw_[i], sin_yaw_[i]);
}

bool World::segmentHitsStatic(std::size_t i, const Vec2& a, const Vec2& b) const {
  // A horizontal ray at mid-height of the obstacle, limited to the segment length.
  const StaticObstacle& s = scenario_.statics[i];
  const Vec2 ab = b - a;
  const double len = ab.norm();
  if (len < kEps) return staticFootprintDistance(i, a) <= 0.0;
  const Vec3 o(a.x(), a.y(), 0.5 * s.height);
  const Vec3 d(ab.x() / len, ab.y() / len, 0.0);
  double t;
  Vec3 n;
  return rayStatic(i, o, d, &t, &n) && t <= len;
}

Contact World::staticContact(const Vec2& center, double radius) const {
  Contact best;
  if (!center.allFinite() || !std::isfinite(radius)) {
    best.clearance = std::numeric_limits<double>::quiet_NaN();
    return best;
  }
  for (std::size_t i = 0; i < scenario_.statics.size(); ++i) {
    const double g = staticFootprintDistance(i, center) - radius;
    if (g < best.clearance) {
      best.clearance = g;
      best.kind = HitKind::kStatic;
      best.index = static_cast<int>(i);
    }
  }
  return best;
}

Contact World::diskContact(const Vec2& center, double radius) const {
  Contact best = staticContact(center, radius);
  if (std::isnan(best.clearance)) return best;
  for (std::size_t i = 0; i < states_.size(); ++i) {
    const double g = (center - states_[i].position).norm() - states_[i].radius - radius;
    if (g < best.clearance) {
      best.clearance = g;
      best.kind = HitKind::kMoving;
      best.index = static_cast<int>(i);
    }
  }
  return best;
}

double World::surfaceDistance(const Vec3& p, double cap) const {
  if (!p.allFinite() || !std::isfinite(cap)) return std::numeric_limits<double>::quiet_NaN();
  double best = std::min(cap, std::fabs(p.z()));
  int cx0, cy0, cx1, cy1;
  cellRange(p.x() - cap, p.y() - cap, p.x() + cap, p.y() + cap, &cx0, &cy0, &cx1, &cy1);
  const Vec2 q(p.x(), p.y());
  for (int cy = cy0; cy <= cy1; ++cy) {
    for (int cx = cx0; cx <= cx1; ++cx) {
      const int c = cellIndex(cx, cy);
      for (int k = static_start_[c]; k < static_start_[c + 1]; ++k) {
        const int i = static_items_[k];
        best = std::min(best, prismDistance(staticFootprintDistance(i, q), p.z(),
                                            scenario_.statics[i].height));
      }
      for (int k = mover_start_[c]; k < mover_start_[c + 1]; ++k) {
        const ObstacleState& s = states_[mover_items_[k]];
        best = std::min(best, prismDistance((q - s.position).norm() - s.radius, p.z(), s.height));
      }
    }
  }
  return best;
}

}  // namespace world
}  // namespace ucon
