#include "ucon/plot/run_data.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "ucon/channels.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/runtime/log_reader.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/trajectory_t.hpp"

namespace ucon {
namespace plot {

namespace {
namespace ch = ucon::channels;

// lcm-gen's decode also value-initialises arrays of the message's own count before it knows
// the bytes are there: a corrupt count of 2^31 would allocate and zero gigabytes. These checks
// read the counts at their documented positions (lcmtypes/*.lcm) and reject a count that
// cannot fit in the bytes that follow (every element takes at least `min_bytes`).
class Cursor {
 public:
  Cursor(const uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  bool skip(std::size_t k) {
    if (n_ - pos_ < k) return ok_ = false;
    pos_ += k;
    return ok_;
  }
  int64_t i32() {
    if (!ok_ || n_ - pos_ < 4) {
      ok_ = false;
      return -1;
    }
    const uint32_t v = (uint32_t{d_[pos_]} << 24) | (uint32_t{d_[pos_ + 1]} << 16) | (uint32_t{d_[pos_ + 2]} << 8) |
                       uint32_t{d_[pos_ + 3]};
    pos_ += 4;
    return static_cast<int32_t>(v);
  }
  bool string() {
    const int64_t len = i32();
    return ok_ && len >= 0 && skip(static_cast<std::size_t>(len));
  }
  // A count followed by count elements of at least min_bytes each.
  bool count(int64_t min_bytes, int64_t* out = nullptr) {
    const int64_t c = i32();
    if (!ok_ || c < 0 || c * min_bytes > static_cast<int64_t>(n_ - pos_)) return ok_ = false;
    if (out) *out = c;
    return true;
  }
  bool ok() const { return ok_; }

 private:
  const uint8_t* d_;
  std::size_t n_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

bool plausibleCounts(const ucon::static_points_t*, const uint8_t* d, std::size_t n) {
  Cursor c(d, n);
  return c.skip(8 + 8 + 8 + 1 + 24 + 4) && c.count(12);
}
bool plausibleCounts(const ucon::trajectory_t*, const uint8_t* d, std::size_t n) {
  Cursor c(d, n);
  int64_t pieces = 0;
  return c.skip(8 + 4 * 8 + 1) && c.string() && c.skip(8 + 1 + 1) && c.count(8, &pieces) &&
         c.skip(static_cast<std::size_t>(pieces) * 8) && c.count(8);
}
bool plausibleCounts(const ucon::tracked_objects_t*, const uint8_t* d, std::size_t n) {
  Cursor c(d, n);
  return c.skip(8 + 8 + 8 + 1 + 8) && c.string() && c.count(103);  // tracked_object_t >= 103 bytes
}
bool plausibleCounts(const ucon::sim_ground_truth_t*, const uint8_t* d, std::size_t n) {
  Cursor c(d, n);
  return c.skip(8 + 8 + 8) && c.string() && c.skip(6 * 8 + 1 + 4 + 8) && c.count(57);  // sim_object_t: 57 bytes
}
bool plausibleCounts(const ucon::robot_pose_t*, const uint8_t*, std::size_t) { return true; }  // int8 count

// lcm-gen's decode resizes arrays from the counts in the message before checking the buffer,
// so a corrupt count can throw (length_error, bad_alloc): treat that as undecodable.
template <typename Msg>
bool decodeMessage(const uint8_t* data, std::size_t size, Msg* msg) {
  if (size > static_cast<std::size_t>(INT32_MAX) || !plausibleCounts(msg, data, size)) return false;
  try {
    return msg->decode(data, 0, static_cast<int>(size)) >= 0;
  } catch (const std::exception&) {
    return false;
  }
}

bool finite(std::initializer_list<double> xs) {
  for (double x : xs) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}
}  // namespace

double PoseSample::speed() const { return std::hypot(vx, vy); }

Eigen::Vector2d StaticGrid::centre(const std::pair<int32_t, int32_t>& key) const {
  return {(key.first + 0.5) * resolution, (key.second + 0.5) * resolution};
}

bool RunData::empty() const {
  return poses.empty() && ground_truth.empty() && objects.empty() && trajectories.empty() &&
         static_messages == 0;
}

std::vector<PoseSample> RunData::robotPath() const {
  if (!poses.empty()) return poses;
  std::vector<PoseSample> out;
  out.reserve(ground_truth.size());
  for (const auto& g : ground_truth) out.push_back(g.robot);
  return out;
}

std::pair<int64_t, int64_t> RunData::timeRange() const {
  int64_t lo = INT64_MAX, hi = INT64_MIN;
  auto add = [&](int64_t t) {
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  };
  for (const auto& p : poses) add(p.utime);
  for (const auto& g : ground_truth) add(g.utime);
  for (const auto& o : objects) add(o.utime);
  for (const auto& t : trajectories) add(t.utime);
  for (const auto& [k, c] : static_grid.cells) add(c.first_utime);
  if (lo > hi) return {0, 0};
  return {lo, hi};
}

double RunData::robotRadius(double fallback) const {
  for (const auto& g : ground_truth) {
    if (g.robot_radius > 0.0) return g.robot_radius;
  }
  return fallback;
}

std::string channelsRead() {
  return std::string(ch::kRobotPose) + ", " + ch::kSimGroundTruth + ", " + ch::kPerceptionObjects + ", " +
         ch::kPerceptionStatic + ", " + ch::kPlannerTrajectory;
}

RunDataBuilder::RunDataBuilder(const ExtractionParams& params) : params_(params) {
  data_.static_grid.resolution = params_.static_resolution > 0.0 ? params_.static_resolution : 0.1;
}

void RunDataBuilder::skip(const std::string& channel, const std::string& reason) {
  ++data_.skipped[channel + ": " + reason];
}

void RunDataBuilder::noteClock(const char* channel, int64_t utime) {
  if (current_timestamp_ == kNoTimestamp) return;
  auto& v = clock_offsets_[channel];
  if (v.size() < 4096) v.push_back(utime - current_timestamp_);  // the start of the run is enough
}

void RunDataBuilder::alignClocks() {
  std::map<std::string, int64_t> median;
  for (auto& [ch, v] : clock_offsets_) {
    if (v.empty()) continue;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    median[ch] = v[v.size() / 2];
  }
  std::string ref;
  for (const char* c : {ch::kRobotPose, ch::kSimGroundTruth, ch::kPerceptionObjects, ch::kPlannerTrajectory,
                        ch::kPerceptionStatic}) {
    if (median.count(c)) {
      ref = c;
      break;
    }
  }
  if (ref.empty()) return;
  const int64_t tol = static_cast<int64_t>(params_.clock_tolerance_s * 1e6);
  for (const auto& [c, m] : median) {
    const int64_t shift = median[ref] - m;  // added to this channel's utimes
    if (c == ref || std::llabs(shift) <= tol) continue;
    data_.notes.push_back(c + " is stamped on another clock than " + ref + " (" +
                          std::to_string(static_cast<double>(-shift) * 1e-6) + " s apart): its times were moved onto " +
                          ref + "'s clock using the log's receive times");
    if (c == ch::kRobotPose) {
      for (auto& p : data_.poses) p.utime += shift;
    } else if (c == ch::kSimGroundTruth) {
      for (auto& g : data_.ground_truth) {
        g.utime += shift;
        g.robot.utime += shift;
      }
      for (auto& e : data_.collisions) e.utime += shift;
    } else if (c == ch::kPerceptionObjects) {
      for (auto& f : data_.objects) f.utime += shift;
    } else if (c == ch::kPlannerTrajectory) {
      for (auto& t : data_.trajectories) t.utime += shift;
    } else if (c == ch::kPerceptionStatic) {
      for (auto& [k, cell] : data_.static_grid.cells) cell.first_utime += shift;
    }
  }
}

RunData RunDataBuilder::take() {
  alignClocks();
  clock_offsets_.clear();
  return std::move(data_);
}

void RunDataBuilder::add(const std::string& channel, const uint8_t* data, std::size_t size, int64_t log_timestamp) {
  current_timestamp_ = log_timestamp;
  if (channel == ch::kRobotPose) {
    addPose(data, size);
  } else if (channel == ch::kSimGroundTruth) {
    addGroundTruth(data, size);
  } else if (channel == ch::kPerceptionObjects) {
    addObjects(data, size);
  } else if (channel == ch::kPerceptionStatic) {
    addStatic(data, size);
  } else if (channel == ch::kPlannerTrajectory) {
    addTrajectory(data, size);
  }
}

void RunDataBuilder::addPose(const uint8_t* data, std::size_t size) {
  ucon::robot_pose_t m;
  if (!decodeMessage(data, size, &m)) return skip(ch::kRobotPose, "undecodable");
  if (!m.valid || m.utime <= 0) return skip(ch::kRobotPose, "invalid");
  if (!finite({m.x, m.y, m.yaw, m.vx, m.vy}) || std::abs(m.x) > params_.max_coordinate ||
      std::abs(m.y) > params_.max_coordinate) {
    return skip(ch::kRobotPose, "non-finite");
  }
  data_.poses.push_back({m.utime, m.x, m.y, m.yaw, m.vx, m.vy});
  noteClock(ch::kRobotPose, m.utime);
  ++data_.used[ch::kRobotPose];
}

void RunDataBuilder::addGroundTruth(const uint8_t* data, std::size_t size) {
  ucon::sim_ground_truth_t m;
  if (!decodeMessage(data, size, &m)) return skip(ch::kSimGroundTruth, "undecodable");
  if (m.utime <= 0) return skip(ch::kSimGroundTruth, "invalid");
  if (!finite({m.robot_x, m.robot_y, m.robot_yaw, m.robot_vx, m.robot_vy}) ||
      std::abs(m.robot_x) > params_.max_coordinate || std::abs(m.robot_y) > params_.max_coordinate) {
    return skip(ch::kSimGroundTruth, "non-finite");
  }
  GroundTruthFrame g;
  g.utime = m.utime;
  g.robot = {m.utime, m.robot_x, m.robot_y, m.robot_yaw, m.robot_vx, m.robot_vy};
  g.robot_radius = std::isfinite(m.robot_radius) && m.robot_radius > 0.0 ? m.robot_radius : 0.0;
  g.collision = m.collision;
  g.num_collisions = m.num_collisions;
  g.min_clearance = m.min_clearance;
  int64_t bad = 0;
  for (const auto& o : m.objects) {
    if (!finite({o.x, o.y, o.vx, o.vy, o.radius}) || std::abs(o.x) > params_.max_coordinate ||
        std::abs(o.y) > params_.max_coordinate || o.radius < 0.0) {
      ++bad;
      continue;
    }
    g.objects.push_back({o.id, o.x, o.y, o.vx, o.vy, o.radius});
  }
  if (bad > 0) data_.skipped[std::string(ch::kSimGroundTruth) + ": non-finite object"] += bad;
  if (m.collision && !last_collision_) data_.collisions.push_back({m.utime, m.robot_x, m.robot_y});
  last_collision_ = m.collision;
  if (data_.scenario.empty()) data_.scenario = m.scenario;
  data_.ground_truth.push_back(std::move(g));
  noteClock(ch::kSimGroundTruth, m.utime);
  ++data_.used[ch::kSimGroundTruth];
}

void RunDataBuilder::addObjects(const uint8_t* data, std::size_t size) {
  ucon::tracked_objects_t m;
  if (!decodeMessage(data, size, &m)) return skip(ch::kPerceptionObjects, "undecodable");
  if (!m.valid || m.utime <= 0) return skip(ch::kPerceptionObjects, "invalid");
  ObjectsFrame f;
  f.utime = m.utime;
  int64_t bad = 0, bad_cov = 0;
  for (const auto& o : m.objects) {
    if (o.state == ucon::tracked_object_t::STATE_DELETED) continue;
    if (!finite({o.x, o.y, o.vx, o.vy, o.size_x, o.size_y, o.yaw}) || std::abs(o.x) > params_.max_coordinate ||
        std::abs(o.y) > params_.max_coordinate) {
      ++bad;
      continue;
    }
    TrackedState s;
    s.id = o.id;
    s.state = o.state;
    s.x = o.x;
    s.y = o.y;
    s.vx = o.vx;
    s.vy = o.vy;
    s.size_x = std::max(0.0, o.size_x);
    s.size_y = std::max(0.0, o.size_y);
    s.yaw = o.yaw;
    if (o.cov_size == 36 && o.cov.size() == 36) {
      Eigen::Matrix2d c;
      c << o.cov[0], o.cov[1], o.cov[6], o.cov[7];  // rows/cols x, y of the 6x6 row-major matrix
      const bool psd = c.allFinite() && c(0, 0) >= 0.0 && c(1, 1) >= 0.0 &&
                       c(0, 0) * c(1, 1) - c(0, 1) * c(1, 0) >= -1e-12 &&
                       std::abs(c(0, 1) - c(1, 0)) <= 1e-9 * std::max(1e-12, c.cwiseAbs().maxCoeff());
      if (psd) {
        s.has_cov = true;
        s.cov_xy = 0.5 * (c + c.transpose());
      } else {
        ++bad_cov;
      }
    } else if (o.cov_size != 0) {
      ++bad_cov;
    }
    f.objects.push_back(s);
  }
  if (bad > 0) data_.skipped[std::string(ch::kPerceptionObjects) + ": non-finite object"] += bad;
  if (bad_cov > 0) data_.skipped[std::string(ch::kPerceptionObjects) + ": bad covariance (drawn without)"] += bad_cov;
  data_.objects.push_back(std::move(f));
  noteClock(ch::kPerceptionObjects, m.utime);
  ++data_.used[ch::kPerceptionObjects];
}

void RunDataBuilder::addStatic(const uint8_t* data, std::size_t size) {
  ucon::static_points_t m;
  if (!decodeMessage(data, size, &m)) return skip(ch::kPerceptionStatic, "undecodable");
  if (!m.valid || m.utime <= 0) return skip(ch::kPerceptionStatic, "invalid");
  const std::size_t n = std::min({m.x.size(), m.y.size(), m.z.size()});
  auto& grid = data_.static_grid;
  const double res = grid.resolution;
  int64_t bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = m.x[i], y = m.y[i], z = m.z[i];
    if (!finite({x, y, z}) || std::abs(x) > params_.max_coordinate || std::abs(y) > params_.max_coordinate) {
      ++bad;
      continue;
    }
    if (z < params_.static_min_z || z > params_.static_max_z) continue;
    const std::pair<int32_t, int32_t> key{static_cast<int32_t>(std::floor(x / res)),
                                          static_cast<int32_t>(std::floor(y / res))};
    auto [it, inserted] = grid.cells.try_emplace(key);
    if (inserted) it->second.first_utime = m.utime;
    ++it->second.hits;
  }
  if (bad > 0) data_.skipped[std::string(ch::kPerceptionStatic) + ": non-finite point"] += bad;
  ++data_.static_messages;
  noteClock(ch::kPerceptionStatic, m.utime);
  ++data_.used[ch::kPerceptionStatic];
}

void RunDataBuilder::addTrajectory(const uint8_t* data, std::size_t size) {
  ucon::trajectory_t m;
  if (!decodeMessage(data, size, &m)) return skip(ch::kPlannerTrajectory, "undecodable");
  if (m.utime <= 0) return skip(ch::kPlannerTrajectory, "invalid");
  TrajectorySnapshot s;
  s.utime = m.utime;
  s.plan_id = m.plan_id;
  s.status = m.status;
  if (m.status != ucon::trajectory_t::STATUS_INVALID && m.num_pieces > 0) {
    ucon::trajectory::PiecewisePolynomial poly;
    const auto st = ucon::trajectory::PiecewisePolynomial::fromMessage(m, &poly);
    if (st != ucon::trajectory::TrajectoryStatus::kOk) {
      return skip(ch::kPlannerTrajectory, std::string("bad trajectory (") + ucon::trajectory::toString(st) + ")");
    }
    const double step = params_.trajectory_step_s > 0.0 ? params_.trajectory_step_s : 0.1;
    const int n = static_cast<int>(std::min(10000.0, std::ceil(poly.duration() / step)));
    s.points.reserve(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
      const Eigen::Vector3d p = poly.sampleRelative(std::min(poly.duration(), i * step)).position;
      if (!p.allFinite()) continue;
      s.points.emplace_back(p.x(), p.y());
    }
  }
  data_.trajectories.push_back(std::move(s));
  noteClock(ch::kPlannerTrajectory, m.utime);
  ++data_.used[ch::kPlannerTrajectory];
}

const char* toString(LoadStatus s) {
  switch (s) {
    case LoadStatus::kOk: return "ok";
    case LoadStatus::kOpenFailed: return "cannot open the log";
    case LoadStatus::kCorrupt: return "the log is damaged";
    case LoadStatus::kNoChannels: return "the log has none of the channels drawn";
  }
  return "?";
}

LoadStatus loadRunLog(const std::string& path, const ExtractionParams& params, RunData* out,
                      std::string* error) {
  ucon::runtime::LogReader reader;
  if (!reader.open(path)) {
    if (error) *error = reader.error();
    return LoadStatus::kOpenFailed;
  }
  RunDataBuilder builder(params);
  ucon::runtime::LogEvent e;
  ucon::runtime::LogReadStatus s;
  while ((s = reader.next(&e)) == ucon::runtime::LogReadStatus::kOk) {
    builder.countEvent();
    builder.add(e.channel, e.data.data(), e.data.size(), e.timestamp);
  }
  *out = builder.take();
  if (s != ucon::runtime::LogReadStatus::kEnd) {
    if (error) *error = reader.error();
    return LoadStatus::kCorrupt;
  }
  if (out->empty()) {
    if (error) {
      *error = path + ": none of the channels " + channelsRead() + " in " + std::to_string(out->events) +
               " events";
      if (!out->skipped.empty()) {
        *error += " (skipped:";
        for (const auto& [k, n] : out->skipped) *error += " " + k + " x" + std::to_string(n) + ";";
        *error += ")";
      }
    }
    return LoadStatus::kNoChannels;
  }
  return LoadStatus::kOk;
}

}  // namespace plot
}  // namespace ucon
