#include "probes.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "ucon/channels.hpp"
#include "ucon/perception/outputs.hpp"

namespace ucon::bench::nav {

rp::FeedResult TimedAdapter::feed(const std::string& channel, const uint8_t* data, std::size_t size,
                                  std::vector<rp::OutputMessage>* out) {
  const std::size_t before = out->size();
  const auto t0 = Clock::now();
  const rp::FeedResult r = inner_->feed(channel, data, size, out);
  const double ms = msSince(t0);
  times_->total_ms += ms;
  times_->by_input_ms[channel] += ms;
  bool unit = on_input_ && channel == unit_;
  for (std::size_t i = before; !on_input_ && i < out->size(); ++i) unit = unit || (*out)[i].channel == unit_;
  if (unit) times_->samples_ms.push_back(ms);
  return r;
}

// ---- Ground-truth movers as perception's track messages (--oracle-objects) ----

namespace {
/// A confirmed track, measured at object level, at the mover's exact state with a small fixed
/// covariance (0.05 m, 0.1 m/s).
perception::ObjectEstimate exactEstimate(int64_t id, double x, double y, double vx, double vy, double radius,
                                         double height) {
  perception::ObjectEstimate e;
  e.id = id;
  e.x << x, y, 0.5 * height, vx, vy, 0.0;
  e.P.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 0.1 * 0.1, 0.1 * 0.1, 0.1 * 0.1;
  e.size << 2.0 * radius, 2.0 * radius, height;
  e.num_points = 10;
  e.age_frames = 100;
  return e;
}
}  // namespace

tracked_objects_t oracleObjects(const sim_ground_truth_t& g, double range, int64_t seq) {
  std::vector<tracked_object_t> objects;
  for (const auto& s : g.objects) {
    if (std::hypot(s.x - g.robot_x, s.y - g.robot_y) > range) continue;
    objects.push_back(perception::toMessage(exactEstimate(s.id, s.x, s.y, s.vx, s.vy, s.radius, s.height)));
  }
  return perception::objectsMessage(g.utime, seq, -1, std::move(objects));
}

tracked_objects_t LineOfSightOracle::objects(const sim_ground_truth_t& g, int64_t seq) {
  std::vector<tracked_object_t> objects;
  const auto delay_us = static_cast<int64_t>(std::llround(delay_ * 1e6));
  for (const auto& s : g.objects) {
    if (std::hypot(s.x - g.robot_x, s.y - g.robot_y) > range_) continue;
    const auto it = last_seen_.find(s.id);
    if (s.visible >= kHiddenVisibility) {  // in view (NaN: not computed, so not in view)
      Seen& l = last_seen_[s.id];
      // A break in view (a ground-truth step hidden) starts the delay again, unless the mover's
      // track is still coasting (its track takes it back at once).
      if (it == last_seen_.end() || l.utime != prev_utime_) {
        const bool coasting = it != last_seen_.end() && l.published && 1e-6 * double(g.utime - l.utime) <= max_coast_;
        l.in_view_since = g.utime;
        l.published = coasting;
      }
      l.utime = g.utime;
      l.x = s.x, l.y = s.y, l.vx = s.vx, l.vy = s.vy, l.radius = s.radius, l.height = s.height;
      l.published = l.published || g.utime - l.in_view_since >= delay_us;
      if (!l.published) continue;
      objects.push_back(perception::toMessage(exactEstimate(s.id, s.x, s.y, s.vx, s.vy, s.radius, s.height)));
      continue;
    }
    if (it == last_seen_.end() || !it->second.published) continue;
    const Seen& l = it->second;
    const double hidden_s = 1e-6 * static_cast<double>(g.utime - l.utime);
    if (hidden_s > max_coast_) continue;
    const double std_xy = 0.05 + kCoastStdPerS * hidden_s;
    perception::ObjectEstimate e =
        exactEstimate(s.id, l.x + l.vx * hidden_s, l.y + l.vy * hidden_s, l.vx, l.vy, l.radius, l.height);
    e.state = tracked_object_t::STATE_COASTING;
    e.P(0, 0) = e.P(1, 1) = std_xy * std_xy;
    e.frames_since_seen = static_cast<int32_t>(hidden_s * 50.0);
    objects.push_back(perception::toMessage(e));
  }
  prev_utime_ = g.utime;
  return perception::objectsMessage(g.utime, seq, -1, std::move(objects));
}

// ---- The perception probe ----

std::vector<std::string> PerceptionProbe::inputChannels() const {
  auto v = inner_->inputChannels();
  v.push_back(channels::kSimGroundTruth);
  return v;
}

rp::FeedResult PerceptionProbe::feed(const std::string& channel, const uint8_t* data, std::size_t size,
                                     std::vector<rp::OutputMessage>* out) {
  if (channel != channels::kSimGroundTruth) {
    const std::size_t before = out->size();
    const rp::FeedResult r = inner_->feed(channel, data, size, out);
    probeOutputs(out, before);
    return r;
  }
  sim_ground_truth_t& g = last_gt_;
  if (!rp::decodeExact(data, size, &g)) return rp::FeedResult::kDecodeError;
  if (!oracle_.objects) return rp::FeedResult::kHandled;
  out->push_back(rp::encodeOutput(channels::kPerceptionObjects, oracle_.line_of_sight
                                                                   ? line_of_sight_.objects(g, seq_++)
                                                                   : oracleObjects(g, range_, seq_++)));
  return rp::FeedResult::kHandled;
}

void PerceptionProbe::probeOutputs(std::vector<rp::OutputMessage>* out, std::size_t before) {
  if (oracle_.objects)
    out->erase(std::remove_if(out->begin() + static_cast<std::ptrdiff_t>(before), out->end(),
                              [](const rp::OutputMessage& m) { return m.channel == channels::kPerceptionObjects; }),
               out->end());
  for (std::size_t i = before; i < out->size(); ++i) {
    auto& m = (*out)[i];
    if (oracle_.velocity && m.channel == channels::kPerceptionObjects) {
      tracked_objects_t o;
      if (!rp::decodeExact(m.data.data(), m.data.size(), &o)) continue;
      for (auto& t : o.objects) {
        const sim_object_t* best = nullptr;
        double best_d = 0.8;
        for (const auto& g : last_gt_.objects) {
          const double d = std::hypot(g.x - t.x, g.y - t.y);
          if (d < best_d) best_d = d, best = &g;
        }
        if (best != nullptr) t.vx = best->vx, t.vy = best->vy;
      }
      m = rp::encodeOutput(channels::kPerceptionObjects, o);
      continue;
    }
    if (m.channel != channels::kPerceptionStatic || last_gt_.objects.empty()) continue;
    static_points_t s;
    if (!rp::decodeExact(m.data.data(), m.data.size(), &s)) continue;
    countLeak(s);
    if (oracle_.static_map) {
      static_points_t c = s;
      c.x.clear(), c.y.clear(), c.z.clear();
      for (int k = 0; k < s.num_points; ++k) {
        bool near = false;
        for (const auto& g : last_gt_.objects) near = near || std::hypot(s.x[k] - g.x, s.y[k] - g.y) < g.radius + 0.25;
        if (near) continue;
        c.x.push_back(s.x[k]), c.y.push_back(s.y[k]), c.z.push_back(s.z[k]);
      }
      c.num_points = static_cast<int32_t>(c.x.size());
      m = rp::encodeOutput(channels::kPerceptionStatic, c);
    }
  }
}

void PerceptionProbe::countLeak(const static_points_t& s) {
  // Leak: static points on a mover's body (within 0.1 m of its surface), movers within 15 m of
  // the robot. Each such point paints a ghost obstacle into the planner's map. Squared
  // distances, movers first cut to the cloud's bounding box: this probe runs on perception's
  // thread and must not slow the pipeline down.
  float x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (int k = 0; k < s.num_points; ++k) {
    x0 = std::min(x0, s.x[k]), x1 = std::max(x1, s.x[k]);
    y0 = std::min(y0, s.y[k]), y1 = std::max(y1, s.y[k]);
  }
  struct Disc {
    float x, y, r2;
  };
  std::vector<Disc> near_movers;
  for (const auto& g : last_gt_.objects) {
    const float reach = static_cast<float>(g.radius + 0.1);
    if (std::hypot(g.x - last_gt_.robot_x, g.y - last_gt_.robot_y) >= 15.0 || g.x + reach < x0 || g.x - reach > x1 ||
        g.y + reach < y0 || g.y - reach > y1)
      continue;
    near_movers.push_back({static_cast<float>(g.x), static_cast<float>(g.y), reach * reach});
  }
  for (int k = 0; k < s.num_points && !near_movers.empty(); ++k)
    for (const auto& g : near_movers) {
      const float dx = s.x[k] - g.x, dy = s.y[k] - g.y;
      if (dx * dx + dy * dy < g.r2) {
        ++leaked_points_;
        break;
      }
    }
  static_points_ += s.num_points;
}

}  // namespace ucon::bench::nav
