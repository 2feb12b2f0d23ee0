#include "ucon/viewer/viewer_data.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace ucon {
namespace viewer {

// Schema (version 1). Lengths in cm, angles in mrad, speeds in cm/s, times in ms since t0,
// all integers, so that a 5-minute run stays a few MB:
//   {"version": 1, "title", "scenario", "t0_us", "duration_ms", "rate_hz", "bounds": [x0, y0, x1, y1],
//    "robot_radius", "vmax", "sigma",
//    "static": {"res": cm, "cells": [ix, iy, first_frame, ...]},      // cell centre = (i + 0.5) res
//    "plans": [{"t", "id", "status", "pts": [x, y, x, y, ...]}],
//    "collisions": [[t, x, y], ...],
//    "frames": [{"t", "r": [x, y, yaw, speed] | null, "p": plan index | -1, "c": 0|1,
//                "o": [[id, x, y, vx, vy, ell_a, ell_b, ell_angle, sec_r, sec_heading, sec_half, state], ...],
//                "g": [[id, x, y, radius], ...]}],
//    "stats": {"frames", "tracks", "ground_truth_ids", "skipped"}}
// ell_a = 0 means no covariance; sec_r = 0 means no sector.

namespace {
using nlohmann::json;

int64_t cm(double m) { return std::llround(m * 100.0); }
int64_t mrad(double a) { return std::llround(a * 1000.0); }

template <typename T>
std::vector<const T*> sortedByTime(const std::vector<T>& v) {
  std::vector<const T*> out;
  out.reserve(v.size());
  for (const auto& e : v) out.push_back(&e);
  std::stable_sort(out.begin(), out.end(), [](const T* a, const T* b) { return a->utime < b->utime; });
  return out;
}

// Latest element at or before t (advancing cursor over a time-sorted list).
template <typename T>
const T* latestAt(const std::vector<const T*>& v, std::size_t* cursor, int64_t t) {
  while (*cursor < v.size() && v[*cursor]->utime <= t) ++*cursor;
  return *cursor == 0 ? nullptr : v[*cursor - 1];
}

json buildOnce(const plot::RunData& run, const ViewerOptions& opt, double rate_hz, ViewerStats* stats) {
  const auto [t0, t1] = run.timeRange();
  const int64_t step_us = std::max<int64_t>(1000, std::llround(1e6 / rate_hz));
  const int n_frames = static_cast<int>((t1 - t0) / step_us) + 1;
  const int64_t stale_us = std::llround(opt.stale_s * 1e6);
  const auto path = run.robotPath();
  const auto poses = sortedByTime(path);
  const auto objects = sortedByTime(run.objects);
  const auto gts = sortedByTime(run.ground_truth);
  const auto plans = sortedByTime(run.trajectories);
  const double robot_r = run.robotRadius(0.3);

  plot::Bounds b;
  double vmax = 0.1;
  for (const auto& p : path) {
    b.add(p.x, p.y);
    vmax = std::max(vmax, p.speed());
  }
  for (const auto& g : run.ground_truth)  // the simulated world: bounded and true, all shown
    for (const auto& o : g.objects) b.add(o.x, o.y);
  std::vector<Eigen::Vector2d> object_points;  // tracked objects: only those near the run
  for (const auto& f : run.objects)
    for (const auto& o : f.objects) object_points.emplace_back(o.x, o.y);

  json frames = json::array();
  json plan_list = json::array();
  std::map<const plot::TrajectorySnapshot*, int> plan_index;
  std::size_t ip = 0, io = 0, ig = 0, it = 0;
  for (int i = 0; i < n_frames; ++i) {
    const int64_t t = t0 + static_cast<int64_t>(i) * step_us;
    json f;
    f["t"] = (t - t0) / 1000;
    const auto* p = latestAt(poses, &ip, t);
    if (p && t - p->utime <= stale_us) f["r"] = {cm(p->x), cm(p->y), mrad(p->yaw), cm(p->speed())};
    else f["r"] = nullptr;
    json objs = json::array();
    if (const auto* of = latestAt(objects, &io, t); of && t - of->utime <= stale_us) {
      for (const auto& o : of->objects) {
        std::array<int64_t, 3> ell{0, 0, 0};
        if (o.has_cov) {
          if (const auto e = plot::covarianceEllipse(o.cov_xy, opt.sigma)) ell = {cm(e->a), cm(e->b), mrad(e->angle)};
        }
        std::array<int64_t, 3> sec{0, 0, 0};
        if (const auto s = plot::uncertaintySector({o.x, o.y}, {o.vx, o.vy}, o.cov_xy, o.has_cov,
                                                   std::hypot(o.size_x, o.size_y), opt.sector)) {
          sec = {cm(s->radius), mrad(s->heading), mrad(s->half_angle)};
        }
        objs.push_back({o.id, cm(o.x), cm(o.y), cm(o.vx), cm(o.vy), ell[0], ell[1], ell[2], sec[0], sec[1], sec[2],
                        o.state});
      }
    }
    f["o"] = std::move(objs);
    json gt = json::array();
    int collision = 0;
    if (const auto* g = latestAt(gts, &ig, t); g && t - g->utime <= stale_us) {
      for (const auto& o : g->objects) gt.push_back({o.id, cm(o.x), cm(o.y), cm(o.radius)});
      collision = g->collision ? 1 : 0;
    }
    f["g"] = std::move(gt);
    f["c"] = collision;
    int pidx = -1;
    if (const auto* pl = latestAt(plans, &it, t); pl && pl->points.size() >= 2) {
      auto [pos, inserted] = plan_index.try_emplace(pl, static_cast<int>(plan_list.size()));
      if (inserted) {
        json pts = json::array();
        const std::size_t n = pl->points.size();
        const std::size_t keep = std::min<std::size_t>(n, static_cast<std::size_t>(std::max(2, opt.max_plan_points)));
        for (std::size_t k = 0; k < keep; ++k) {
          const auto& q = pl->points[keep == 1 ? 0 : k * (n - 1) / (keep - 1)];
          pts.push_back(cm(q.x()));
          pts.push_back(cm(q.y()));
          b.add(q.x(), q.y());
        }
        plan_list.push_back({{"t", (pl->utime - t0) / 1000}, {"id", pl->plan_id}, {"status", pl->status}, {"pts", pts}});
      }
      pidx = pos->second;
    }
    f["p"] = pidx;
    frames.push_back(std::move(f));
  }

  json cells = json::array();
  int n_cells = 0;
  const auto& grid = run.static_grid;
  for (const auto& [key, c] : grid.cells) {
    if (c.hits < opt.min_static_hits) continue;
    const int first = static_cast<int>(std::clamp<int64_t>((c.first_utime - t0 + step_us - 1) / step_us, 0, n_frames - 1));
    cells.push_back(key.first);
    cells.push_back(key.second);
    cells.push_back(first);
    const auto ctr = grid.centre(key);
    b.add(ctr.x(), ctr.y());
    ++n_cells;
  }
  b = plot::focusBounds(b, object_points, opt.focus_margin);
  json collisions = json::array();
  for (const auto& c : run.collisions) collisions.push_back({(c.utime - t0) / 1000, cm(c.x), cm(c.y)});
  if (!b.valid) {  // nothing with a position (e.g. only rejected plans): a 10 m view of the origin
    b.add(-5.0, -5.0);
    b.add(5.0, 5.0);
  }
  b.pad(0.03, 1.0);

  std::set<int64_t> ids, gt_ids;
  for (const auto& f : run.objects)
    for (const auto& o : f.objects) ids.insert(o.id);
  for (const auto& g : run.ground_truth)
    for (const auto& o : g.objects) gt_ids.insert(o.id);
  int64_t skipped = 0;
  for (const auto& [k, n] : run.skipped) skipped += n;

  json doc;
  doc["version"] = 1;
  doc["title"] = opt.title;
  doc["scenario"] = run.scenario;
  doc["t0_us"] = t0;
  doc["duration_ms"] = (t1 - t0) / 1000;
  doc["rate_hz"] = std::round(rate_hz * 1000.0) / 1000.0;
  doc["bounds"] = {cm(b.min_x), cm(b.min_y), cm(b.max_x), cm(b.max_y)};
  doc["robot_radius"] = cm(robot_r);
  doc["vmax"] = cm(vmax);
  doc["sigma"] = opt.sigma;
  doc["static"] = {{"res", cm(grid.resolution)}, {"cells", std::move(cells)}};
  doc["plans"] = std::move(plan_list);
  doc["collisions"] = std::move(collisions);
  doc["frames"] = std::move(frames);
  doc["stats"] = {{"frames", n_frames},
                  {"tracks", ids.size()},
                  {"ground_truth_ids", gt_ids.size()},
                  {"skipped", skipped},
                  {"pose_source", run.poses.empty() ? "SIM_GROUND_TRUTH" : "ROBOT_POSE"}};
  if (stats) {
    stats->frames = n_frames;
    stats->rate_hz = rate_hz;
    stats->plans = static_cast<int>(doc["plans"].size());
    stats->static_cells = n_cells;
  }
  return doc;
}

}  // namespace

std::string buildViewerJson(const plot::RunData& run, const ViewerOptions& opt, ViewerStats* stats) {
  if (run.empty()) return {};
  const double budget = std::max(0.1, opt.max_megabytes) * 1e6;
  double rate = std::clamp(opt.rate_hz, 0.2, 100.0);
  // A frame takes at least ~40 bytes: never build more frames than the budget can hold (a
  // bogus timestamp far from the others would otherwise ask for billions of frames).
  const auto [t0, t1] = run.timeRange();
  const double duration_s = std::max(1e-3, (t1 - t0) * 1e-6);
  rate = std::max(std::min(rate, budget / 40.0 / duration_s), 1e-9);
  std::string out;
  // Lower the rate until the page fits (the frames dominate the size, roughly linear in rate).
  for (int attempt = 0; attempt < 8; ++attempt) {
    ViewerStats s;
    out = buildOnce(run, opt, rate, &s).dump(-1, ' ', true, json::error_handler_t::replace);
    s.json_bytes = out.size();
    if (stats) *stats = s;
    if (out.size() <= budget || s.frames <= 2) break;
    rate = rate * 0.9 * budget / static_cast<double>(out.size());
  }
  return out;
}

}  // namespace viewer
}  // namespace ucon
