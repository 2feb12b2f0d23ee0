#include "ucon/mot/clear_mot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ucon {
namespace mot {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double ratio(int64_t num, int64_t den) {
  return den > 0 ? static_cast<double>(num) / static_cast<double>(den) : kNaN;
}

}  // namespace

double boxIou(const Box& a, const Box& b) {
  if (!(a.w > 0.0 && a.h > 0.0 && b.w > 0.0 && b.h > 0.0)) return 0.0;
  const double ix = std::min(a.x + a.w, b.x + b.w) - std::max(a.x, b.x);
  const double iy = std::min(a.y + a.h, b.y + b.h) - std::max(a.y, b.y);
  if (!(ix > 0.0 && iy > 0.0)) return 0.0;
  const double inter = ix * iy;
  const double uni = a.w * a.h + b.w * b.h - inter;
  return uni > 0.0 ? inter / uni : 0.0;
}

CostMatrix xyDistances(const std::vector<PointXY>& objects, const std::vector<PointXY>& hypotheses,
                       double threshold) {
  CostMatrix d(static_cast<int>(objects.size()), static_cast<int>(hypotheses.size()), kInf);
  for (int i = 0; i < d.rows; ++i) {
    for (int j = 0; j < d.cols; ++j) {
      const double dist = std::hypot(objects[i].x - hypotheses[j].x, objects[i].y - hypotheses[j].y);
      // As py-motmetrics: pairs farther than the threshold are forbidden, equal is allowed.
      if (std::isfinite(dist) && dist <= threshold) d(i, j) = dist;
    }
  }
  return d;
}

CostMatrix iouDistances(const std::vector<Box>& objects, const std::vector<Box>& hypotheses,
                        double min_iou) {
  CostMatrix d(static_cast<int>(objects.size()), static_cast<int>(hypotheses.size()), kInf);
  for (int i = 0; i < d.rows; ++i) {
    for (int j = 0; j < d.cols; ++j) {
      const double iou = boxIou(objects[i], hypotheses[j]);
      if (std::isfinite(iou) && iou >= min_iou && iou > 0.0) d(i, j) = 1.0 - iou;
    }
  }
  return d;
}

FrameEvents ClearMotAccumulator::update(const std::vector<int64_t>& object_ids,
                                        const std::vector<int64_t>& hypothesis_ids,
                                        const CostMatrix& dist,
                                        const std::vector<char>* ignored) {
  FrameEvents ev;
  const int n_obj = static_cast<int>(object_ids.size());
  const int n_hyp = static_cast<int>(hypothesis_ids.size());
  auto cost = [&](int i, int j) {
    if (dist.rows != n_obj || dist.cols != n_hyp) return kInf;  // malformed: nothing allowed
    const double v = dist(i, j);
    return std::isfinite(v) ? v : kInf;
  };

  auto is_ignored = [&](int i) {
    return ignored && ignored->size() == static_cast<std::size_t>(n_obj) && (*ignored)[i] != 0;
  };
  ++totals_.num_frames;

  std::vector<int> obj_match(static_cast<std::size_t>(n_obj), -1);
  std::vector<int> hyp_match(static_cast<std::size_t>(n_hyp), -1);

  // 1. Keep the pair an object had at its previous occurrence if it is still allowed.
  for (int i = 0; i < n_obj; ++i) {
    auto it = objects_.find(object_ids[i]);
    if (it == objects_.end() || !it->second.matched_at_last_occurrence) continue;
    for (int j = 0; j < n_hyp; ++j) {
      if (hyp_match[j] >= 0 || hypothesis_ids[j] != it->second.last_hypothesis) continue;
      if (std::isfinite(cost(i, j))) {
        obj_match[i] = j;
        hyp_match[j] = i;
      }
      break;
    }
  }

  // 2. Minimum-cost assignment over the objects and hypotheses still free.
  std::vector<int> free_obj, free_hyp;
  for (int i = 0; i < n_obj; ++i)
    if (obj_match[i] < 0) free_obj.push_back(i);
  for (int j = 0; j < n_hyp; ++j)
    if (hyp_match[j] < 0) free_hyp.push_back(j);
  if (!free_obj.empty() && !free_hyp.empty()) {
    CostMatrix sub(static_cast<int>(free_obj.size()), static_cast<int>(free_hyp.size()), kInf);
    for (int a = 0; a < sub.rows; ++a)
      for (int b = 0; b < sub.cols; ++b) sub(a, b) = cost(free_obj[a], free_hyp[b]);
    const std::vector<int> assign = solveAssignment(sub);
    for (int a = 0; a < sub.rows; ++a) {
      if (assign[a] < 0) continue;
      obj_match[free_obj[a]] = free_hyp[assign[a]];
      hyp_match[free_hyp[assign[a]]] = free_obj[a];
    }
  }

  // 3. Events and per-object history. Ignored objects and what they matched are dropped.
  for (int i = 0; i < n_obj; ++i) {
    if (is_ignored(i)) {
      ++totals_.num_ignored;
      ev.ignored.emplace_back(object_ids[i], obj_match[i] >= 0 ? hypothesis_ids[obj_match[i]] : 0);
      if (obj_match[i] >= 0) hyp_match[obj_match[i]] = -2;  // absorbed: not a false positive
      continue;
    }
    ++totals_.num_objects;
    ObjectHistory& h = objects_[object_ids[i]];
    ++h.frames_present;
    if (obj_match[i] >= 0) {
      const int j = obj_match[i];
      const int64_t hid = hypothesis_ids[j];
      ev.matches.emplace_back(object_ids[i], hid);
      ++totals_.num_matches;
      totals_.total_distance += cost(i, j);
      if (h.has_match && h.last_hypothesis != hid) {
        ev.switches.emplace_back(object_ids[i], hid);
        ++totals_.num_switches;
      }
      if (h.in_gap) ++h.fragmentations;
      h.in_gap = false;
      h.has_match = true;
      h.last_hypothesis = hid;
      h.matched_at_last_occurrence = true;
      ++h.frames_matched;
    } else {
      ev.misses.push_back(object_ids[i]);
      ++totals_.num_misses;
      h.matched_at_last_occurrence = false;
      if (h.has_match) h.in_gap = true;
    }
  }
  for (int j = 0; j < n_hyp; ++j) {
    if (hyp_match[j] == -2) continue;
    ++totals_.num_predictions;
    if (hyp_match[j] >= 0) continue;
    ev.false_positives.push_back(hypothesis_ids[j]);
    ++totals_.num_false_positives;
  }
  return ev;
}

FrameEvents ClearMotAccumulator::updateXY(const std::vector<PointXY>& objects,
                                          const std::vector<PointXY>& hypotheses, double threshold,
                                          const std::vector<char>* ignored) {
  std::vector<int64_t> oids, hids;
  for (const auto& o : objects) oids.push_back(o.id);
  for (const auto& h : hypotheses) hids.push_back(h.id);
  return update(oids, hids, xyDistances(objects, hypotheses, threshold), ignored);
}

FrameEvents ClearMotAccumulator::updateBoxes(const std::vector<Box>& objects,
                                             const std::vector<Box>& hypotheses, double min_iou) {
  std::vector<int64_t> oids, hids;
  for (const auto& o : objects) oids.push_back(o.id);
  for (const auto& h : hypotheses) hids.push_back(h.id);
  return update(oids, hids, iouDistances(objects, hypotheses, min_iou));
}

ClearMotSummary ClearMotAccumulator::summary() const {
  ClearMotSummary s = totals_;
  s.num_unique_objects = static_cast<int64_t>(objects_.size());
  s.num_fragmentations = 0;
  s.mostly_tracked = s.partially_tracked = s.mostly_lost = 0;
  for (const auto& kv : objects_) {
    const ObjectHistory& h = kv.second;
    s.num_fragmentations += h.fragmentations;
    const double r = ratio(h.frames_matched, h.frames_present);
    if (r >= 0.8) {
      ++s.mostly_tracked;
    } else if (r < 0.2) {
      ++s.mostly_lost;
    } else {
      ++s.partially_tracked;
    }
  }
  s.mota = s.num_objects > 0
               ? 1.0 - static_cast<double>(s.num_misses + s.num_false_positives + s.num_switches) /
                           static_cast<double>(s.num_objects)
               : kNaN;
  s.motp = s.num_matches > 0 ? s.total_distance / static_cast<double>(s.num_matches) : kNaN;
  s.fn_rate = ratio(s.num_misses, s.num_objects);
  s.fp_rate = ratio(s.num_false_positives, s.num_objects);
  s.mismatch_rate = ratio(s.num_switches, s.num_objects);
  s.recall = ratio(s.num_matches, s.num_objects);
  s.precision = ratio(s.num_matches, s.num_predictions);
  return s;
}

}  // namespace mot
}  // namespace ucon
