#include "ucon/perception/motion_test.hpp"

#include <algorithm>
#include <cmath>

namespace ucon {
namespace perception {

namespace {
double seconds(int64_t dt_us) { return static_cast<double>(dt_us) * 1e-6; }

FreeSpaceMemory::Params memoryParams(const SegmentationParams& s) {
  FreeSpaceMemory::Params m;
  m.horizon = s.free_memory;
  m.cell = s.free_memory_cell;
  m.min_height = s.free_memory_heights.at(0);
  m.max_height = s.free_memory_heights.at(1);
  m.range = s.free_memory_range;
  m.margin = s.free_space_margin;
  m.period = s.history_chunk;
  return m;
}
}  // namespace

MotionTest::MotionTest(const SegmentationParams& params, const AngularGrid& grid)
    : params_(params), grid_(grid), memory_(memoryParams(params)) {}

void MotionTest::selectReference(int64_t utime) {
  const SegmentationParams& s = params_;
  ref_chunks_.clear();
  for (const auto& h : history_) {
    if (!h.closed || h.index.size() == 0) continue;
    if (seconds(utime - h.last_utime) >= s.history_min_age && seconds(utime - h.first_utime) <= s.history_max_age)
      ref_chunks_.push_back(&h);
  }
  if (!ref_chunks_.empty()) {
    const double covered = seconds(ref_chunks_.back()->last_utime - ref_chunks_.front()->first_utime);
    if (covered < 0.6 * (s.history_max_age - s.history_min_age)) ref_chunks_.clear();
  }
}

int MotionTest::markMoved(const Frame& frame, const std::vector<int>& indices, const Eigen::Vector2d& center,
                          std::vector<char>* moved, MotionEvidence* evidence) const {
  MotionEvidence ev;
  const SegmentationParams& s = params_;
  const double range = (center - frame.robot_xy).norm();
  const double dist = s.motion_distance + s.motion_distance_per_m * range;
  const auto motion_d2 = static_cast<float>(dist * dist);
  int n = 0;
  for (int i : indices) {
    bool near = false;
    for (const HistoryChunk* c : ref_chunks_) {
      if (c->index.anyWithin(frame.points[i], motion_d2)) {
        near = true;
        break;
      }
    }
    if (near) {
      ++ev.near_reference;
      continue;
    }
    Verdict v = pointMoved(frame, frame.points[i]);
    if (v == Verdict::kUndecided && memory_.seenFree(frame.points[i], frame.utime)) {
      v = Verdict::kMoved;
      ++ev.remembered;
    }
    const bool m = v == Verdict::kMoved;
    ++(m ? ev.moved : v == Verdict::kSurface ? ev.surface : ev.undecided);
    n += m ? 1 : 0;
    (*moved)[i] = m ? 1 : 0;
  }
  if (evidence) *evidence = ev;
  return n;
}

MotionTest::Verdict MotionTest::pointMoved(const Frame& frame, const Eigen::Vector3f& p) const {
  // A point with no reference point nearby is new surface. It is motion, not a disocclusion,
  // when some reference chunk (seen from its own sensor origin) either
  //  - saw past it along its ray: the space it occupies now was free (an object moving in), or
  //  - saw only nearer returns along its ray, and this frame sees through the farthest of
  //    them: what stood in front of the point then has gone (an object moving away; its new
  //    surface lies behind its old one, where the reference could not look).
  // Parallax from the robot's own motion fails both: the occluder is still there.
  // A bin no reference chunk has a return in is judged by the bins around it (unseenMoved).
  // The vanishing test needs every chunk to have stopped short of the point: one ray of the
  // window passing beside a nearer edge in the same bin makes the bin ambiguous.
  // "Saw past it" also needs no return of the bin clearly in front of the point: a bin holds
  // rays on both sides of an edge (a box corner, a pillar), and a chunk's rays leave from the
  // origins of its frames, not only from its first one (a driving sensor moves centimetres per
  // chunk), so the face an edge hid shares bins with rays that passed beside the edge. Such a
  // bin is no evidence either way. (A return at the point's own range is no occluder: someone
  // walking in another's footsteps is seen where the other was.)
  const float margin = static_cast<float>(params_.free_space_margin);
  float best_seen = 0.0f, best_range = 0.0f;
  const HistoryChunk* best = nullptr;
  bool mixed = false;
  for (const HistoryChunk* c : ref_chunks_) {
    const Eigen::Vector3f ray = p - c->origin;
    const float range = ray.norm();
    if (!(range > 0.0f)) continue;
    const auto bin = static_cast<std::size_t>(grid_.bin(ray));
    const float seen = c->max_range[bin];
    if (seen == 0.0f) continue;
    if (seen > range + margin) {
      if (c->min_range[bin] >= range - margin) return Verdict::kMoved;
      mixed = true;
      continue;
    }
    if (best == nullptr || seen - range > best_seen - best_range) best = c, best_seen = seen, best_range = range;
  }
  if (mixed) return Verdict::kUndecided;
  if (best == nullptr) return unseenMoved(p) ? Verdict::kMoved : Verdict::kSurface;
  if (best_seen >= best_range - margin) return Verdict::kSurface;
  // The gap bounds how far the object moved; a larger one is more likely structure revealed
  // by a mover that passed in front of it.
  if (best_seen < best_range - static_cast<float>(params_.vanish_max_gap)) return Verdict::kUndecided;
  const Eigen::Vector3f q = best->origin + (p - best->origin) * (best_seen / best_range) - frame.sensor_origin;
  const float now = frame.nearest_fine[static_cast<std::size_t>(grid_.bin(q))];
  return std::isfinite(now) && now > q.norm() + margin ? Verdict::kMoved : Verdict::kUndecided;
}

// No reference chunk had a return in the point's own bin. The scan is sparse (a Mid-360 puts
// about one return per 1-degree bin in 0.1 s, fewer towards the edge of its field of view, and
// its pattern turns with the sensor), so that is often a gap in the sampling, not a direction
// nobody looked in: the bins around it decide. A neighbour bin with a return at or before the
// point's range (within the margin) saw a surface there or in front of it: structure sampled
// around the point (a wall seen at a grazing angle comes nearer from bin to bin), no evidence
// of motion. Neighbours that saw only beyond the point (the space was free: an object moved
// in), or nothing at all (open space: nothing to compare with), leave the point moved, as an
// unseen direction always was.
bool MotionTest::unseenMoved(const Eigen::Vector3f& p) const {
  const float margin = static_cast<float>(params_.free_space_margin);
  int around[8];
  for (const HistoryChunk* c : ref_chunks_) {
    const Eigen::Vector3f ray = p - c->origin;
    const float range = ray.norm();
    if (!(range > 0.0f)) continue;
    const int n = grid_.neighbours(grid_.bin(ray), around);
    for (int k = 0; k < n; ++k) {
      const auto b = static_cast<std::size_t>(around[k]);
      if (c->max_range[b] > 0.0f && c->min_range[b] < range + margin) return false;
    }
  }
  return true;
}

void MotionTest::push(const Frame& frame, const std::vector<char>& tracked_point) {
  const SegmentationParams& sp = params_;
  ref_chunks_.clear();  // chunks may be dropped below
  const int64_t utime = frame.utime;
  const int64_t chunk_us = static_cast<int64_t>(sp.history_chunk * 1e6);
  if (history_.empty() || history_.back().closed) {
    history_.emplace_back();
    history_.back().first_utime = utime;
  }
  HistoryChunk& c = history_.back();
  if (c.max_range.empty()) {
    c.origin = frame.sensor_origin;
    c.max_range.assign(static_cast<std::size_t>(grid_.size()), 0.0f);
    c.min_range.assign(static_cast<std::size_t>(grid_.size()), INFINITY);
  }
  // Free-space evidence of the newest frame: every return, ground included (frame.points
  // holds the last frames again, cropped).
  for (const auto& p : frame.returns) {
    const Eigen::Vector3f ray = p - c.origin;
    const auto bin = static_cast<std::size_t>(grid_.bin(ray));
    const float r = ray.norm();
    c.max_range[bin] = std::max(c.max_range[bin], r);
    c.min_range[bin] = std::min(c.min_range[bin], r);
  }
  c.last_utime = utime;
  memory_.mark(frame);
  // Reference points: what this frame did not give to a track. Someone walking where a tracked
  // person was (a follower, or the person itself turning back) would otherwise be matched
  // against that trail and look static. The free-space evidence above still includes it, so
  // structure wrongly tracked for a moment is not taken for motion.
  if (sp.history_static_only) {
    for (std::size_t i = 0; i < frame.points.size(); ++i)
      if (!tracked_point[i]) c.points.push_back(frame.points[i]);
  } else {
    c.points.insert(c.points.end(), frame.points.begin(), frame.points.end());
  }
  if (utime - c.first_utime >= chunk_us) {
    c.index.build(c.points);
    c.points.clear();
    c.points.shrink_to_fit();
    c.closed = true;
  }
  const int64_t keep_us = static_cast<int64_t>(sp.history_max_age * 1e6);
  while (!history_.empty() && utime - history_.front().first_utime > keep_us) history_.pop_front();
}

}  // namespace perception
}  // namespace ucon
