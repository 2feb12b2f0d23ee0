#include "ucon/perception/outputs.hpp"

#include <algorithm>
#include <utility>

namespace ucon {
namespace perception {

tracked_object_t toMessage(const ObjectEstimate& e) {
  tracked_object_t t{};
  t.id = e.id;
  t.state = e.state;
  t.last_association = e.last_association;
  t.x = e.x(0);
  t.y = e.x(1);
  t.z = e.x(2);
  t.vx = e.x(3);
  t.vy = e.x(4);
  t.vz = e.x(5);
  t.cov_size = 36;
  t.cov.resize(36);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) t.cov[static_cast<std::size_t>(r * 6 + c)] = e.P(r, c);
  t.size_x = std::max(e.size.x(), 0.01);
  t.size_y = std::max(e.size.y(), 0.01);
  t.size_z = std::max(e.size.z(), 0.01);
  t.yaw = 0.0;
  t.num_points = e.num_points;
  t.age_frames = e.age_frames;
  t.frames_since_seen = e.frames_since_seen;
  return t;
}

tracked_objects_t objectsMessage(int64_t utime, int64_t seq, int64_t frame_seq, std::vector<tracked_object_t> objects) {
  tracked_objects_t o{};
  o.utime = utime;
  o.seq = seq;
  o.valid = true;
  o.frame_seq = frame_seq;
  o.frame_id = "world";
  o.objects = std::move(objects);
  o.num_objects = static_cast<int32_t>(o.objects.size());
  return o;
}

tracked_objects_t invalidObjects(int64_t utime, int64_t seq, int64_t frame_seq) {
  tracked_objects_t o = objectsMessage(utime, seq, frame_seq, {});
  o.valid = false;
  return o;
}

static_points_t staticMessage(int64_t utime, int64_t seq, const Eigen::Vector3d& origin, double max_range,
                              const std::vector<Eigen::Vector3f>& points, const std::vector<char>& dynamic) {
  static_points_t s{};
  s.utime = utime;
  s.seq = seq;
  s.valid = true;
  s.origin_x = origin.x();
  s.origin_y = origin.y();
  s.origin_z = origin.z();
  s.max_range = static_cast<float>(max_range);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (dynamic[i]) continue;
    s.x.push_back(points[i].x());
    s.y.push_back(points[i].y());
    s.z.push_back(points[i].z());
  }
  s.num_points = static_cast<int32_t>(s.x.size());
  return s;
}

static_points_t invalidStatic(int64_t utime, int64_t seq, double max_range) {
  static_points_t s{};
  s.utime = utime;
  s.seq = seq;
  s.valid = false;
  s.max_range = static_cast<float>(max_range);
  s.num_points = 0;
  return s;
}

bool covarianceOf(const tracked_object_t& o, kalman::Cov6* P) {
  if (o.cov_size != 36 || o.cov.size() != 36) return false;
  for (int i = 0; i < 36; ++i) (*P)(i / 6, i % 6) = o.cov[static_cast<std::size_t>(i)];
  return true;
}

}  // namespace perception
}  // namespace ucon
