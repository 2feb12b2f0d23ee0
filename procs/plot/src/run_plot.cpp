#include "ucon/plot/run_plot.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "canvas.hpp"

namespace ucon {
namespace plot {

using detail::Align;
using detail::fmt;
using detail::setColour;
using detail::text;

namespace {

// Colours of the layers (legend and drawing use the same constants).
const Rgb kStatic{0.30, 0.30, 0.30};
const Rgb kGroundTruth{0.55, 0.55, 0.55};
const Rgb kPlan{0.84, 0.16, 0.62};
const Rgb kSector{1.00, 0.50, 0.05};
const Rgb kEllipse{0.10, 0.25, 0.75};
const Rgb kArrow{0.10, 0.10, 0.10};
const Rgb kCollision{0.85, 0.05, 0.05};
const Rgb kStart{0.10, 0.65, 0.20};
const Rgb kGrid{0.90, 0.90, 0.90};
const Rgb kInk{0.10, 0.10, 0.10};

constexpr double kGapS = 1.0;  // a track/path with a pause longer than this is broken [s]

struct Xform {
  double s = 1.0, ox = 0.0, oy = 0.0, min_x = 0.0, max_y = 0.0;
  double px(double x) const { return ox + (x - min_x) * s; }
  double py(double y) const { return oy + (max_y - y) * s; }
};

template <typename T>
const T* nearestByTime(const std::vector<T>& v, int64_t t, int64_t max_gap_us) {
  const T* best = nullptr;
  int64_t best_d = max_gap_us + 1;
  for (const auto& e : v) {
    const int64_t d = std::llabs(e.utime - t);
    if (d < best_d) {
      best_d = d;
      best = &e;
    }
  }
  return best;
}

const TrajectorySnapshot* planAt(const RunData& run, int64_t t) {
  const TrajectorySnapshot* best = nullptr;
  for (const auto& tr : run.trajectories) {
    if (tr.points.size() < 2) continue;
    if (tr.utime <= t && (!best || tr.utime >= best->utime)) best = &tr;
  }
  return best;
}

double boxDiagonal(const TrackedState& o) { return std::hypot(o.size_x, o.size_y); }

// Points closer than half a pixel to the last one drawn are dropped (the last point is
// always drawn): minutes of 50 Hz tracks stay a small SVG and a fast PNG.
void polyline(cairo_t* cr, const Xform& X, const std::vector<Eigen::Vector2d>& pts) {
  double lx = 0.0, ly = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double x = X.px(pts[i].x()), y = X.py(pts[i].y());
    if (i == 0) {
      cairo_move_to(cr, x, y);
    } else if (i + 1 == pts.size() || std::abs(x - lx) + std::abs(y - ly) >= 0.5) {
      cairo_line_to(cr, x, y);
    } else {
      continue;
    }
    lx = x;
    ly = y;
  }
}

void circle(cairo_t* cr, double cx, double cy, double r) {
  cairo_new_sub_path(cr);
  cairo_arc(cr, cx, cy, r, 0, 2 * M_PI);
}

void sectorPath(cairo_t* cr, const Xform& X, const Sector& s) {
  if (s.half_angle >= M_PI - 1e-9) {
    circle(cr, X.px(s.centre.x()), X.py(s.centre.y()), s.radius * X.s);
    return;
  }
  cairo_move_to(cr, X.px(s.centre.x()), X.py(s.centre.y()));
  const int n = 24;
  for (int i = 0; i <= n; ++i) {
    const double a = s.heading - s.half_angle + 2.0 * s.half_angle * i / n;
    cairo_line_to(cr, X.px(s.centre.x() + s.radius * std::cos(a)), X.py(s.centre.y() + s.radius * std::sin(a)));
  }
  cairo_close_path(cr);
}

void ellipsePath(cairo_t* cr, const Xform& X, const Eigen::Vector2d& c, const Ellipse& e) {
  cairo_save(cr);
  cairo_translate(cr, X.px(c.x()), X.py(c.y()));
  cairo_rotate(cr, -e.angle);  // y points down on the page
  cairo_scale(cr, std::max(1e-3, e.a * X.s), std::max(1e-3, e.b * X.s));
  cairo_new_sub_path(cr);
  cairo_arc(cr, 0, 0, 1, 0, 2 * M_PI);
  cairo_restore(cr);
}

void arrow(cairo_t* cr, double x0, double y0, double x1, double y1, double head) {
  const double len = std::hypot(x1 - x0, y1 - y0);
  if (len < 1.0) return;
  cairo_move_to(cr, x0, y0);
  cairo_line_to(cr, x1, y1);
  cairo_stroke(cr);
  const double ux = (x1 - x0) / len, uy = (y1 - y0) / len;
  head = std::min(head, 0.6 * len);
  cairo_move_to(cr, x1, y1);
  cairo_line_to(cr, x1 - head * ux - 0.5 * head * uy, y1 - head * uy + 0.5 * head * ux);
  cairo_line_to(cr, x1 - head * ux + 0.5 * head * uy, y1 - head * uy - 0.5 * head * ux);
  cairo_close_path(cr);
  cairo_fill(cr);
}

void labelBox(cairo_t* cr, double x, double y, const std::string& s, double size) {
  const double w = detail::textWidth(cr, s, size, true);
  cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
  cairo_rectangle(cr, x - 3, y - size, w + 6, size + 5);
  cairo_fill(cr);
  setColour(cr, kInk);
  text(cr, x, y, s, size, Align::kLeft, true);
}

struct TimedPoint {
  int64_t utime;
  Eigen::Vector2d p;
};

// Splits a time-ordered series where it pauses for more than kGapS or jumps faster than
// kJumpSpeed (a track re-initialised elsewhere, an object respawned): those are not motion.
constexpr double kJumpSpeed = 20.0;  // [m/s]
std::vector<std::vector<Eigen::Vector2d>> splitAtGaps(const std::vector<TimedPoint>& pts) {
  std::vector<std::vector<Eigen::Vector2d>> out;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    bool split = i == 0;
    if (!split) {
      const double dt = (pts[i].utime - pts[i - 1].utime) * 1e-6;
      const double d = (pts[i].p - pts[i - 1].p).norm();
      split = dt > kGapS || d > std::max(1.0, kJumpSpeed * dt);
    }
    if (split) out.emplace_back();
    out.back().push_back(pts[i].p);
  }
  return out;
}

}  // namespace

RunSummary summarise(const RunData& run, int min_static_hits) {
  RunSummary s;
  const auto [t0, t1] = run.timeRange();
  s.duration_s = (t1 - t0) * 1e-6;
  const auto path = run.robotPath();
  for (std::size_t i = 0; i < path.size(); ++i) {
    s.max_speed = std::max(s.max_speed, path[i].speed());
    if (i > 0) s.distance_m += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  }
  if (path.size() > 1 && path.back().utime > path.front().utime) {
    s.mean_speed = s.distance_m / ((path.back().utime - path.front().utime) * 1e-6);
  }
  s.collisions = static_cast<int>(run.collisions.size());
  if (!run.ground_truth.empty()) {
    s.collisions = std::max(s.collisions, run.ground_truth.back().num_collisions);
    s.min_clearance = run.ground_truth.back().min_clearance;
  }
  std::set<int64_t> ids, gt_ids;
  for (const auto& f : run.objects)
    for (const auto& o : f.objects) ids.insert(o.id);
  for (const auto& g : run.ground_truth)
    for (const auto& o : g.objects) gt_ids.insert(o.id);
  s.track_ids = static_cast<int>(ids.size());
  s.ground_truth_ids = static_cast<int>(gt_ids.size());
  for (const auto& [k, c] : run.static_grid.cells) s.static_cells += c.hits >= min_static_hits ? 1 : 0;
  return s;
}

std::vector<int64_t> snapshotTimes(const RunData& run, int n) {
  std::vector<int64_t> out;
  if (n <= 0 || run.empty()) return out;
  std::vector<int64_t> plans;
  for (const auto& t : run.trajectories) {
    if (t.points.size() >= 2) plans.push_back(t.utime);
  }
  std::sort(plans.begin(), plans.end());
  if (!plans.empty()) {
    const int k = std::min<int>(n, static_cast<int>(plans.size()));
    for (int i = 0; i < k; ++i) {
      // Centres of k equal slices: avoids the very first plan (often a start-up transient).
      const std::size_t idx = static_cast<std::size_t>((i + 0.5) * plans.size() / k);
      out.push_back(plans[std::min(idx, plans.size() - 1)]);
    }
  } else {
    const auto [t0, t1] = run.timeRange();
    for (int i = 0; i < n; ++i) out.push_back(t0 + static_cast<int64_t>((i + 0.5) * (t1 - t0) / n));
  }
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

const char* toString(PlotStatus s) {
  switch (s) {
    case PlotStatus::kOk: return "ok";
    case PlotStatus::kBadOptions: return "bad options";
    case PlotStatus::kNothingToDraw: return "nothing to draw";
    case PlotStatus::kWriteFailed: return "cannot write the picture";
  }
  return "?";
}

PlotStatus renderRunPlot(const RunData& run, const RunPlotOptions& opt, const std::string& path,
                         std::string* error) {
  if (opt.snapshots < 0 || opt.snapshots > 20 || !(opt.sigma > 0.0 && opt.sigma <= 10.0)) {
    if (error) *error = "snapshots must be in [0, 20] and sigma in (0, 10]";
    return PlotStatus::kBadOptions;
  }
  const auto robot_path = run.robotPath();
  const RunSummary summary = summarise(run, opt.min_static_hits);
  const auto snaps = snapshotTimes(run, opt.snapshots);
  const auto [t0, t1] = run.timeRange();
  const double robot_r = run.robotRadius(0.3);

  // Tracks per id (std::map: deterministic drawing order).
  std::map<int64_t, std::vector<TimedPoint>> tracks, gt_tracks;
  std::map<int64_t, double> gt_radius;
  for (const auto& f : run.objects)
    for (const auto& o : f.objects) tracks[o.id].push_back({f.utime, {o.x, o.y}});
  for (const auto& g : run.ground_truth)
    for (const auto& o : g.objects) {
      gt_tracks[o.id].push_back({g.utime, {o.x, o.y}});
      gt_radius[o.id] = o.radius;
    }

  // World bounds over everything drawn.
  Bounds b;
  for (const auto& p : robot_path) b.add(p.x, p.y);
  for (const auto& [key, c] : run.static_grid.cells) {
    if (c.hits < opt.min_static_hits) continue;
    const auto ctr = run.static_grid.centre(key);
    b.add(ctr.x(), ctr.y());
  }
  for (int64_t t : snaps) {
    if (const auto* tr = planAt(run, t))
      for (const auto& p : tr->points) b.add(p.x(), p.y());
  }
  // The simulator's world is bounded and true: all of it is shown. Tracked objects only near
  // the run (one spurious far-away track must not shrink the picture).
  for (const auto& [id, tr] : gt_tracks)
    for (const auto& p : tr) b.add(p.p.x(), p.p.y());
  std::vector<Eigen::Vector2d> object_points;
  for (const auto& [id, tr] : tracks)
    for (const auto& p : tr) object_points.push_back(p.p);
  b = focusBounds(b, object_points, opt.focus_margin);
  if (!b.valid) {
    if (error) *error = "the run has no position to draw";
    return PlotStatus::kNothingToDraw;
  }
  b.pad(0.04, 1.0);

  detail::Canvas canvas;
  if (!canvas.open(path, opt.width, opt.height, error)) return PlotStatus::kBadOptions;
  cairo_t* cr = canvas.cr();
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);

  const double W = opt.width, H = opt.height;
  const double panel_w = std::min(340.0, 0.3 * W);
  const double ax0 = 64, ay0 = 70, aw = W - ax0 - panel_w - 24, ah = H - ay0 - 48;
  Xform X;
  X.s = std::min(aw / b.width(), ah / b.height());
  X.min_x = b.min_x;
  X.max_y = b.max_y;
  X.ox = ax0 + (aw - b.width() * X.s) / 2.0;
  X.oy = ay0 + (ah - b.height() * X.s) / 2.0;
  const double fx0 = X.px(b.min_x), fx1 = X.px(b.max_x), fy0 = X.py(b.max_y), fy1 = X.py(b.min_y);

  // Title.
  setColour(cr, kInk);
  std::string title = opt.title.empty() ? "run" : opt.title;
  if (!run.scenario.empty()) title += "  —  scenario " + run.scenario;
  text(cr, ax0, 30, title, 20, Align::kLeft, true);
  text(cr, ax0, 54,
       fmt("%.1f s, path %.1f m, mean speed %.2f m/s, collisions %d%s", summary.duration_s, summary.distance_m,
           summary.mean_speed, summary.collisions,
           summary.min_clearance >= 0 && summary.min_clearance < 1e8
               ? fmt(", min clearance %.2f m", summary.min_clearance).c_str()
               : ""),
       14);

  // Frame, grid and axis labels.
  const double grid = niceLength(std::max(b.width(), b.height()) / 8.0);
  cairo_set_line_width(cr, 1.0);
  setColour(cr, kGrid);
  for (double x = std::ceil(b.min_x / grid) * grid; x <= b.max_x; x += grid) {
    cairo_move_to(cr, X.px(x), fy0);
    cairo_line_to(cr, X.px(x), fy1);
  }
  for (double y = std::ceil(b.min_y / grid) * grid; y <= b.max_y; y += grid) {
    cairo_move_to(cr, fx0, X.py(y));
    cairo_line_to(cr, fx1, X.py(y));
  }
  cairo_stroke(cr);
  setColour(cr, {0.35, 0.35, 0.35});
  for (double x = std::ceil(b.min_x / grid) * grid; x <= b.max_x; x += grid)
    text(cr, X.px(x), fy1 + 18, fmt("%g", std::abs(x) < 1e-9 ? 0.0 : x), 12, Align::kCentre);
  for (double y = std::ceil(b.min_y / grid) * grid; y <= b.max_y; y += grid)
    text(cr, fx0 - 6, X.py(y) + 4, fmt("%g", std::abs(y) < 1e-9 ? 0.0 : y), 12, Align::kRight);
  text(cr, fx1, fy1 + 36, "x [m]", 13, Align::kRight);
  cairo_save(cr);  // y label along the axis, clear of the title
  cairo_translate(cr, std::max(16.0, fx0 - 46.0), (fy0 + fy1) / 2);
  cairo_rotate(cr, -M_PI / 2);
  text(cr, 0, 0, "y [m]", 13, Align::kCentre);
  cairo_restore(cr);
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_rectangle(cr, fx0, fy0, fx1 - fx0, fy1 - fy0);
  cairo_stroke(cr);
  cairo_save(cr);
  cairo_rectangle(cr, fx0, fy0, fx1 - fx0, fy1 - fy0);
  cairo_clip(cr);

  // Static points.
  const double cell_px = std::max(1.5, run.static_grid.resolution * X.s);
  setColour(cr, kStatic);
  for (const auto& [key, c] : run.static_grid.cells) {
    if (c.hits < opt.min_static_hits) continue;
    const auto ctr = run.static_grid.centre(key);
    cairo_rectangle(cr, X.px(ctr.x()) - cell_px / 2, X.py(ctr.y()) - cell_px / 2, cell_px, cell_px);
  }
  cairo_fill(cr);

  // Ground-truth tracks of the moving obstacles, with their footprint at the end.
  cairo_set_line_width(cr, 1.2);
  for (const auto& [id, tr] : gt_tracks) {
    setColour(cr, kGroundTruth, 0.8);
    for (const auto& seg : splitAtGaps(tr)) polyline(cr, X, seg);
    cairo_stroke(cr);
    const auto& last = tr.back().p;
    setColour(cr, kGroundTruth, 0.25);
    circle(cr, X.px(last.x()), X.py(last.y()), std::max(2.0, gt_radius[id] * X.s));
    cairo_fill_preserve(cr);
    setColour(cr, kGroundTruth, 0.9);
    cairo_stroke(cr);
  }

  // Tracked objects: one colour per id, id at the end of the track.
  const bool many = tracks.size() > 60;
  cairo_set_line_width(cr, 1.8);
  for (const auto& [id, tr] : tracks) {
    setColour(cr, idColour(id), 0.9);
    for (const auto& seg : splitAtGaps(tr)) {
      if (seg.size() == 1) circle(cr, X.px(seg[0].x()), X.py(seg[0].y()), 1.5);
      else polyline(cr, X, seg);
    }
    cairo_stroke(cr);
  }
  for (const auto& [id, tr] : tracks) {
    if (tr.size() < (many ? 20u : 3u)) continue;
    const auto& last = tr.back().p;
    setColour(cr, idColour(id));
    text(cr, X.px(last.x()) + 4, X.py(last.y()) - 4, fmt("#%lld", static_cast<long long>(id)), 12, Align::kLeft,
         true);
  }

  // Snapshots: true obstacles (dashed outline), objects' sectors, covariance ellipses and
  // velocities; the plans and the robot come after the path.
  for (std::size_t k = 0; k < snaps.size(); ++k) {
    const int64_t t = snaps[k];
    if (const auto* g = nearestByTime(run.ground_truth, t, 300000)) {
      static const double kDash[] = {4.0, 3.0};
      cairo_set_dash(cr, kDash, 2, 0.0);
      cairo_set_line_width(cr, 1.3);
      setColour(cr, kGroundTruth, 0.95);
      for (const auto& o : g->objects) {
        circle(cr, X.px(o.x), X.py(o.y), std::max(2.0, o.radius * X.s));
        cairo_stroke(cr);
      }
      cairo_set_dash(cr, nullptr, 0, 0.0);
    }
    if (const auto* frame = nearestByTime(run.objects, t, 300000)) {
      for (const auto& o : frame->objects) {
        const Eigen::Vector2d pos(o.x, o.y), vel(o.vx, o.vy);
        if (const auto s = uncertaintySector(pos, vel, o.cov_xy, o.has_cov, boxDiagonal(o), opt.sector)) {
          sectorPath(cr, X, *s);
          setColour(cr, kSector, 0.16);
          cairo_fill_preserve(cr);
          setColour(cr, kSector, 0.75);
          cairo_set_line_width(cr, 1.0);
          cairo_stroke(cr);
        }
        if (o.has_cov) {
          if (const auto e = covarianceEllipse(o.cov_xy, opt.sigma)) {
            ellipsePath(cr, X, pos, *e);
            setColour(cr, kEllipse, 0.9);
            cairo_set_line_width(cr, 1.4);
            cairo_stroke(cr);
          }
        }
        setColour(cr, kArrow);
        cairo_set_line_width(cr, 1.4);
        arrow(cr, X.px(o.x), X.py(o.y), X.px(o.x + o.vx), X.py(o.y + o.vy), 8);
        circle(cr, X.px(o.x), X.py(o.y), 2.5);
        cairo_fill(cr);
      }
    }
  }

  // Robot path coloured by speed.
  const double vmax = std::max(0.1, summary.max_speed);
  // Consecutive segments of the same colour (64 levels) form one stroke: a 100 Hz pose over
  // minutes stays a few hundred strokes, and the SVG small.
  cairo_set_line_width(cr, 3.5);
  int open_bin = -1;
  for (std::size_t i = 1; i < robot_path.size(); ++i) {
    const auto& a = robot_path[i - 1];
    const auto& c = robot_path[i];
    if (c.utime - a.utime > static_cast<int64_t>(kGapS * 1e6)) {
      if (open_bin >= 0) cairo_stroke(cr);
      open_bin = -1;
      continue;
    }
    const double u = std::clamp(0.5 * (a.speed() + c.speed()) / vmax, 0.0, 1.0);
    const int bin = static_cast<int>(std::lround(u * 63.0));
    if (bin != open_bin) {
      if (open_bin >= 0) cairo_stroke(cr);
      setColour(cr, speedColour(bin / 63.0));
      cairo_move_to(cr, X.px(a.x), X.py(a.y));
      open_bin = bin;
    }
    double lx, ly;
    cairo_get_current_point(cr, &lx, &ly);
    const bool last = i + 1 == robot_path.size();
    if (last || std::abs(X.px(c.x) - lx) + std::abs(X.py(c.y) - ly) >= 0.5) cairo_line_to(cr, X.px(c.x), X.py(c.y));
  }
  if (open_bin >= 0) cairo_stroke(cr);
  if (!robot_path.empty()) {
    const auto& s0 = robot_path.front();
    const auto& s1 = robot_path.back();
    setColour(cr, kStart);
    circle(cr, X.px(s0.x), X.py(s0.y), 7);
    cairo_fill(cr);
    setColour(cr, kInk);
    cairo_rectangle(cr, X.px(s1.x) - 6, X.py(s1.y) - 6, 12, 12);
    cairo_fill(cr);
  }

  // Planned trajectories over the path (they start where the robot was), then the robot at
  // each snapshot, numbered.
  for (int64_t t : snaps) {
    if (const auto* plan = planAt(run, t)) {
      // Dashed: the plan runs over the path it became, whose speed colours stay visible.
      static const double kDash[] = {9.0, 6.0};
      setColour(cr, kPlan, 0.95);
      cairo_set_line_width(cr, 2.2);
      cairo_set_dash(cr, kDash, 2, 0.0);
      polyline(cr, X, plan->points);
      cairo_stroke(cr);
      cairo_set_dash(cr, nullptr, 0, 0.0);
      circle(cr, X.px(plan->points.back().x()), X.py(plan->points.back().y()), 3.5);
      cairo_fill(cr);
    }
  }
  for (std::size_t k = 0; k < snaps.size(); ++k) {
    const int64_t t = snaps[k];
    const PoseSample* p = nearestByTime(robot_path, t, 500000);
    if (!p) continue;
    cairo_set_source_rgba(cr, 1, 1, 1, 0.55);
    circle(cr, X.px(p->x), X.py(p->y), std::max(4.0, robot_r * X.s));
    cairo_fill_preserve(cr);
    setColour(cr, kInk);
    cairo_set_line_width(cr, 2.0);
    cairo_stroke(cr);
    cairo_move_to(cr, X.px(p->x), X.py(p->y));
    cairo_line_to(cr, X.px(p->x + robot_r * std::cos(p->yaw)), X.py(p->y + robot_r * std::sin(p->yaw)));
    cairo_stroke(cr);
    // Short label, alternately above and below (snapshots can be close); times in the Run block.
    const double rr = std::max(4.0, robot_r * X.s);
    labelBox(cr, X.px(p->x) - 8, k % 2 == 0 ? X.py(p->y) - rr - 6 : X.py(p->y) + rr + 16, fmt("S%zu", k + 1), 12);
  }

  if (!robot_path.empty()) {
    labelBox(cr, X.px(robot_path.front().x) + 10, X.py(robot_path.front().y) + 22, "start", 12);
    labelBox(cr, X.px(robot_path.back().x) + 10, X.py(robot_path.back().y) + 22, "end", 12);
  }

  // Collisions.
  for (const auto& c : run.collisions) {
    const double x = X.px(c.x), y = X.py(c.y);
    setColour(cr, kCollision);
    cairo_set_line_width(cr, 3.0);
    circle(cr, x, y, 11);
    cairo_stroke(cr);
    cairo_move_to(cr, x - 7, y - 7);
    cairo_line_to(cr, x + 7, y + 7);
    cairo_move_to(cr, x + 7, y - 7);
    cairo_line_to(cr, x - 7, y + 7);
    cairo_stroke(cr);
  }
  cairo_restore(cr);  // clip

  // Scale bar, bottom left inside the frame.
  {
    const double len = niceLength(b.width() / 5.0);
    const double bx = fx0 + 16, by = fy1 - 18, bw = len * X.s;
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_rectangle(cr, bx - 8, by - 26, bw + 16, 36);
    cairo_fill(cr);
    setColour(cr, kInk);
    cairo_rectangle(cr, bx, by - 3, bw, 6);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_rectangle(cr, bx + bw / 2, by - 2, bw / 2 - 1, 4);
    cairo_fill(cr);
    setColour(cr, kInk);
    text(cr, bx + bw / 2, by - 9, fmt("%g m", len), 13, Align::kCentre, true);
  }

  // Legend panel.
  const double lx = W - panel_w, lw = panel_w - 16;
  double y = ay0 + 4;
  setColour(cr, {0.97, 0.97, 0.97});
  cairo_rectangle(cr, lx - 4, ay0 - 8, lw + 8, H - ay0 - 16);
  cairo_fill(cr);
  setColour(cr, kInk);
  text(cr, lx + 6, y + 10, "Legend", 16, Align::kLeft, true);
  y += 30;
  auto entry = [&](const std::string& label, const std::function<void(double, double)>& glyph) {
    glyph(lx + 10, y);
    setColour(cr, kInk);
    text(cr, lx + 52, y + 5, label, 13);
    y += 24;
  };
  auto line = [&](const Rgb& c, double width, double alpha) {
    return [&cr, c, width, alpha](double x, double yy) {
      setColour(cr, c, alpha);
      cairo_set_line_width(cr, width);
      cairo_move_to(cr, x, yy);
      cairo_line_to(cr, x + 34, yy);
      cairo_stroke(cr);
    };
  };
  if (!robot_path.empty()) {
    // Speed colour bar.
    setColour(cr, kInk);
    text(cr, lx + 10, y + 5, fmt("robot path, speed [m/s] (%s)", run.poses.empty() ? "ground truth" : "ROBOT_POSE"),
         13);
    y += 14;
    const double cbw = lw - 30;
    for (int i = 0; i < 100; ++i) {
      setColour(cr, speedColour(i / 99.0));
      cairo_rectangle(cr, lx + 10 + cbw * i / 100.0, y, cbw / 100.0 + 0.6, 12);
      cairo_fill(cr);
    }
    setColour(cr, kInk);
    for (int i = 0; i <= 4; ++i)
      text(cr, lx + 10 + cbw * i / 4.0, y + 27, fmt("%.2g", vmax * i / 4.0), 11, Align::kCentre);
    y += 44;
    entry("start", [&](double x, double yy) {
      setColour(cr, kStart);
      circle(cr, x + 17, yy, 6);
      cairo_fill(cr);
    });
    entry("end", [&](double x, double yy) {
      setColour(cr, kInk);
      cairo_rectangle(cr, x + 12, yy - 5, 10, 10);
      cairo_fill(cr);
    });
  }
  if (!snaps.empty()) {
    entry("robot at snapshot S1..", [&](double x, double yy) {
      setColour(cr, kInk);
      cairo_set_line_width(cr, 2.0);
      circle(cr, x + 17, yy, 8);
      cairo_stroke(cr);
    });
  }
  if (!run.trajectories.empty()) {
    entry("planned trajectory (at snapshot)", [&](double x, double yy) {
      static const double kDash[] = {9.0, 6.0};
      cairo_set_dash(cr, kDash, 2, 0.0);
      line(kPlan, 2.2, 0.95)(x, yy);
      cairo_set_dash(cr, nullptr, 0, 0.0);
    });
  }
  if (!tracks.empty()) {
    entry("tracked object #id (PERCEPTION)", [&](double x, double yy) {
      for (int i = 0; i < 3; ++i) {
        setColour(cr, idColour(i + 1));
        cairo_set_line_width(cr, 1.8);
        cairo_move_to(cr, x + i * 12, yy + 4);
        cairo_line_to(cr, x + i * 12 + 9, yy - 4);
        cairo_stroke(cr);
      }
    });
    entry("uncertainty sector (eq. 6-7)", [&](double x, double yy) {
      Sector s;
      s.centre = {0, 0};
      s.radius = 1.0;
      s.half_angle = 0.45;
      Xform g;
      g.s = 30;
      g.ox = x + 2;
      g.oy = yy;
      sectorPath(cr, g, s);
      setColour(cr, kSector, 0.25);
      cairo_fill_preserve(cr);
      setColour(cr, kSector, 0.8);
      cairo_set_line_width(cr, 1.0);
      cairo_stroke(cr);
    });
    entry(fmt("%g-sigma position covariance", opt.sigma), [&](double x, double yy) {
      Xform g;
      g.s = 1;
      g.ox = x + 17;
      g.oy = yy;
      ellipsePath(cr, g, {0, 0}, Ellipse{15, 7, 0.3});
      setColour(cr, kEllipse, 0.9);
      cairo_set_line_width(cr, 1.4);
      cairo_stroke(cr);
    });
    entry("velocity (1 s of motion)", [&](double x, double yy) {
      setColour(cr, kArrow);
      cairo_set_line_width(cr, 1.4);
      arrow(cr, x, yy, x + 34, yy, 8);
    });
  }
  if (!gt_tracks.empty()) {
    entry("moving obstacle, ground truth (end)", [&](double x, double yy) {
      line(kGroundTruth, 1.2, 0.8)(x, yy);
      setColour(cr, kGroundTruth, 0.35);
      circle(cr, x + 34, yy, 6);
      cairo_fill(cr);
    });
    if (!snaps.empty()) {
      entry("obstacle at snapshot, ground truth", [&](double x, double yy) {
        static const double kDash[] = {4.0, 3.0};
        cairo_set_dash(cr, kDash, 2, 0.0);
        setColour(cr, kGroundTruth, 0.95);
        cairo_set_line_width(cr, 1.3);
        circle(cr, x + 17, yy, 7);
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0.0);
      });
    }
  }
  if (summary.static_cells > 0) {
    entry("static points (PERCEPTION_STATIC)", [&](double x, double yy) {
      setColour(cr, kStatic);
      for (int i = 0; i < 5; ++i) cairo_rectangle(cr, x + 4 + i * 6, yy - 2 + (i % 2) * 3, 4, 4);
      cairo_fill(cr);
    });
  }
  if (!run.ground_truth.empty()) {
    entry("collision", [&](double x, double yy) {
      setColour(cr, kCollision);
      cairo_set_line_width(cr, 2.5);
      circle(cr, x + 17, yy, 7);
      cairo_stroke(cr);
    });
  }

  // The run in figures.
  y += 10;
  setColour(cr, kInk);
  text(cr, lx + 6, y, "Run", 16, Align::kLeft, true);
  y += 22;
  auto line_text = [&](const std::string& s) {
    text(cr, lx + 10, y, s, 12);
    y += 18;
  };
  line_text(fmt("time %.1f s (t=0 at first message)", summary.duration_s));
  if (!snaps.empty()) {
    std::string st = "snapshots:";
    for (std::size_t k = 0; k < snaps.size(); ++k) st += fmt(" S%zu %.1f s%s", k + 1, (snaps[k] - t0) * 1e-6, k + 1 < snaps.size() ? "," : "");
    line_text(st);
  }
  line_text(fmt("path %.1f m, speed mean %.2f / max %.2f m/s", summary.distance_m, summary.mean_speed,
                summary.max_speed));
  if (!run.ground_truth.empty()) {
    line_text(fmt("collisions %d, min clearance %s", summary.collisions,
                  summary.min_clearance >= 0 && summary.min_clearance < 1e8
                      ? fmt("%.2f m", summary.min_clearance).c_str()
                      : "n/a"));
    line_text(fmt("moving obstacles (ground truth) %d", summary.ground_truth_ids));
  }
  line_text(fmt("tracked ids %d, static cells %d (%.2g m)", summary.track_ids, summary.static_cells,
                run.static_grid.resolution));
  for (const auto& [ch, n] : run.used) line_text(fmt("%s: %lld msgs", ch.c_str(), static_cast<long long>(n)));
  int64_t skipped = 0;
  for (const auto& [k, n] : run.skipped) skipped += n;
  if (!run.notes.empty()) {
    setColour(cr, kCollision);
    line_text(fmt("%zu channel(s) on another clock, re-based", run.notes.size()));
  }
  if (skipped > 0) {
    setColour(cr, kCollision);
    line_text(fmt("skipped (bad/invalid): %lld", static_cast<long long>(skipped)));
  }
  (void)t1;

  if (!canvas.finish(error)) return PlotStatus::kWriteFailed;
  return PlotStatus::kOk;
}

}  // namespace plot
}  // namespace ucon
