#include "drive_eval.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>
#include <unordered_set>

#include "ucon/base_controller/binding.hpp"
#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/mot/runtime_frames.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/perception/binding.hpp"
#include "ucon/perception/outputs.hpp"
#include "ucon/replay/bound_adapter.hpp"
#include "ucon/replay/sim_recorder.hpp"
#include "ucon/runtime/log_reader.hpp"
#include "ucon/world/world.hpp"
#include "../bench_util.hpp"
#include "odometry_in_loop.hpp"

namespace ucon {
namespace bench {

namespace {

constexpr double kPi = 3.14159265358979323846;

double wrapAngle(double a) {
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}

uint64_t fnv(uint64_t h, const void* p, std::size_t n) {
  const auto* b = static_cast<const uint8_t*>(p);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  return h;
}

/// The ground truth nearest in time to `utime` at or before it (else the first after it).
const sim_ground_truth_t* groundTruthNear(const std::map<int64_t, sim_ground_truth_t>& gts, int64_t utime) {
  if (gts.empty()) return nullptr;
  auto it = gts.upper_bound(utime);
  if (it == gts.begin()) return &it->second;
  return &std::prev(it)->second;
}

/// The route: NAV_GOAL with the next route point whenever the robot is within tolerance of the
/// current one (the scenario's goals, then its start, then again), re-sent every second until
/// reached, as ucon-mission does. Time is the poses' utime.
class PatrolAdapter : public replay::NodeAdapter {
 public:
  PatrolAdapter(std::vector<Eigen::Vector2d> route, double tolerance) : route_(std::move(route)), tol_(tolerance) {}
  std::string name() const override { return "patrol"; }
  std::vector<std::string> inputChannels() const override { return {channels::kRobotPose}; }
  std::vector<std::string> outputChannels() const override { return {channels::kNavGoal}; }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return {{"goals_reached", reached_}}; }
  int64_t reached() const { return reached_; }

  replay::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                          std::vector<replay::OutputMessage>* out) override {
    if (channel != channels::kRobotPose) return replay::FeedResult::kIgnored;
    robot_pose_t p;
    if (!replay::decodeExact(data, size, &p)) return replay::FeedResult::kDecodeError;
    if (!p.valid || route_.empty()) return replay::FeedResult::kHandled;
    bool send = last_sent_ < 0 || p.utime - last_sent_ >= 1'000'000;
    if (last_sent_ >= 0 && std::hypot(p.x - route_[index_].x(), p.y - route_[index_].y()) < tol_) {
      ++reached_;
      index_ = (index_ + 1) % route_.size();
      ++goal_id_;
      send = true;
    }
    if (send) {
      nav_goal_t g{};
      g.utime = p.utime;
      g.seq = seq_++;
      g.goal_id = goal_id_;
      g.action = nav_goal_t::ACTION_GO;
      g.x = route_[index_].x();
      g.y = route_[index_].y();
      g.yaw = std::numeric_limits<double>::quiet_NaN();
      g.tolerance = 0.3;
      g.max_speed = 0.0;
      out->push_back(replay::encodeOutput(channels::kNavGoal, g));
      last_sent_ = p.utime;
    }
    return replay::FeedResult::kHandled;
  }

 private:
  std::vector<Eigen::Vector2d> route_;
  double tol_;
  std::size_t index_ = 0;
  int64_t goal_id_ = 1, seq_ = 0, last_sent_ = -1, reached_ = 0;
};

/// Perfect perception for the planner while recording: per LiDAR frame, PERCEPTION_OBJECTS
/// holds every ground-truth mover within the crop range (exact state, small covariance) and
/// PERCEPTION_STATIC the frame's returns in the perception node's crop (range, height) that
/// are not on a mover, one per voxel. The planner then drives the route it would drive with
/// flawless perception, whatever perception is being measured.
class GroundTruthPerception : public replay::NodeAdapter {
 public:
  explicit GroundTruthPerception(const perception::PerceptionParams& p) : p_(p.preprocess) {}
  std::string name() const override { return "ground_truth_perception"; }
  std::vector<std::string> inputChannels() const override {
    return {channels::kRobotPose, channels::kLidarPoints, channels::kSimGroundTruth};
  }
  std::vector<std::string> outputChannels() const override {
    return {channels::kPerceptionObjects, channels::kPerceptionStatic};
  }
  std::vector<std::pair<std::string, int64_t>> counters() const override { return {{"frames", frames_}}; }

  replay::FeedResult feed(const std::string& channel, const uint8_t* data, std::size_t size,
                          std::vector<replay::OutputMessage>* out) override {
    if (channel == channels::kRobotPose) {
      robot_pose_t m;
      if (!replay::decodeExact(data, size, &m)) return replay::FeedResult::kDecodeError;
      poses_.add(m);
      return replay::FeedResult::kHandled;
    }
    if (channel == channels::kSimGroundTruth) {
      sim_ground_truth_t m;
      if (!replay::decodeExact(data, size, &m)) return replay::FeedResult::kDecodeError;
      gts_[m.utime] = m;
      while (gts_.size() > 100) gts_.erase(gts_.begin());
      return replay::FeedResult::kHandled;
    }
    if (channel != channels::kLidarPoints) return replay::FeedResult::kIgnored;
    point_cloud_t c;
    if (!replay::decodeExact(data, size, &c)) return replay::FeedResult::kDecodeError;
    const sim_ground_truth_t* gt = groundTruthNear(gts_, c.utime);
    const auto pose = poses_.at(c.utime);
    if (gt == nullptr || !pose) return replay::FeedResult::kHandled;  // nothing to say yet
    ++frames_;
    const double dt = 1e-6 * static_cast<double>(c.utime - gt->utime);
    std::vector<tracked_object_t> objs;
    for (const auto& o : gt->objects) {
      perception::ObjectEstimate e;
      e.id = o.id;
      e.x << o.x + o.vx * dt, o.y + o.vy * dt, 0.5 * o.height, o.vx, o.vy, 0.0;
      if (std::hypot(e.x(0) - pose->x, e.x(1) - pose->y) > p_.max_range) continue;
      e.P.diagonal() << 0.01, 0.01, 0.01, 0.01, 0.01, 0.01;
      e.size << 2 * o.radius, 2 * o.radius, o.height;
      e.num_points = 1;
      objs.push_back(perception::toMessage(e));
    }
    out->push_back(replay::encodeOutput(channels::kPerceptionObjects,
                                        perception::objectsMessage(c.utime, seq_, c.seq, std::move(objs))));
    std::vector<Eigen::Vector3f> pts;
    std::unordered_set<int64_t> voxels;
    const double v = p_.voxel_size;
    for (int i = 0; i < c.num_points; ++i) {
      const double hr = std::hypot(c.x[i], c.y[i]);
      if (hr < p_.min_range || hr > p_.max_range) continue;
      const int64_t t = c.utime + c.t_offset_ns[i] / 1000;
      const auto q = poses_.at(t);
      const double cy = std::cos(q->yaw), sy = std::sin(q->yaw);
      const double wx = q->x + cy * c.x[i] - sy * c.y[i], wy = q->y + sy * c.x[i] + cy * c.y[i], wz = c.z[i];
      if (wz < p_.min_height || wz > p_.max_height) continue;
      const double tdt = 1e-6 * static_cast<double>(t - gt->utime);
      bool on_mover = false;
      for (const auto& o : gt->objects)
        on_mover = on_mover || std::hypot(wx - (o.x + o.vx * tdt), wy - (o.y + o.vy * tdt)) <= o.radius + 0.15;
      if (on_mover) continue;
      const auto key = [&](double a) { return static_cast<int64_t>(std::floor(a / v)) & 0x1fffff; };
      if (!voxels.insert((key(wx) << 42) | (key(wy) << 21) | key(wz)).second) continue;
      pts.emplace_back(static_cast<float>(wx), static_cast<float>(wy), static_cast<float>(wz));
    }
    const double cy = std::cos(pose->yaw), sy = std::sin(pose->yaw);
    const auto& so = p_.sensor_origin;
    const Eigen::Vector3d origin(pose->x + cy * so[0] - sy * so[1], pose->y + sy * so[0] + cy * so[1], so[2]);
    out->push_back(replay::encodeOutput(
        channels::kPerceptionStatic,
        perception::staticMessage(c.utime, seq_, origin, p_.max_range, pts, std::vector<char>(pts.size(), 0))));
    ++seq_;
    poses_.dropBefore(c.utime - 1'000'000);
    return replay::FeedResult::kHandled;
  }

 private:
  perception::PreprocessParams p_;
  PoseTrack poses_;
  std::map<int64_t, sim_ground_truth_t> gts_;
  int64_t seq_ = 0, frames_ = 0;
};

int speedBin(double v) { return v < 0.1 ? 0 : (v < 0.75 ? 1 : 2); }
int yawBin(double w) { return w < 0.2 ? 0 : (w < 0.6 ? 1 : 2); }

}  // namespace

// ---- PoseTrack ----

bool PoseTrack::add(const robot_pose_t& p) {
  if (!p.valid || p.utime <= 0) return false;
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.yaw)) return false;
  if (!poses_.empty() && p.utime <= poses_.back().first) return false;
  PlanarPose q;
  q.x = p.x, q.y = p.y, q.yaw = p.yaw;
  q.vx = std::isfinite(p.vx) ? p.vx : 0.0;
  q.vy = std::isfinite(p.vy) ? p.vy : 0.0;
  q.wz = std::isfinite(p.wz) ? p.wz : 0.0;
  poses_.emplace_back(p.utime, q);
  return true;
}

std::optional<PlanarPose> PoseTrack::at(int64_t utime) const {
  if (poses_.empty()) return std::nullopt;
  if (utime <= poses_.front().first) return poses_.front().second;
  if (utime >= poses_.back().first) {
    PlanarPose q = poses_.back().second;
    const double dt = 1e-6 * static_cast<double>(utime - poses_.back().first);
    q.x += q.vx * dt;
    q.y += q.vy * dt;
    q.yaw = wrapAngle(q.yaw + q.wz * dt);
    return q;
  }
  const auto hi = std::upper_bound(poses_.begin(), poses_.end(), utime,
                                   [](int64_t t, const auto& e) { return t < e.first; });
  const auto lo = std::prev(hi);
  const double s = static_cast<double>(utime - lo->first) / static_cast<double>(hi->first - lo->first);
  const PlanarPose& a = lo->second;
  const PlanarPose& b = hi->second;
  PlanarPose q;
  q.x = a.x + s * (b.x - a.x);
  q.y = a.y + s * (b.y - a.y);
  q.yaw = wrapAngle(a.yaw + s * wrapAngle(b.yaw - a.yaw));
  q.vx = a.vx + s * (b.vx - a.vx);
  q.vy = a.vy + s * (b.vy - a.vy);
  q.wz = a.wz + s * (b.wz - a.wz);
  return q;
}

void PoseTrack::dropBefore(int64_t utime) {
  while (poses_.size() > 1 && poses_[1].first <= utime) poses_.pop_front();
}

// ---- visibility ----

std::map<int64_t, int> returnsOnMovers(const point_cloud_t& cloud, const PoseTrack& poses,
                                       const sim_ground_truth_t& gt, double margin, double min_z) {
  std::map<int64_t, int> hits;
  if (poses.empty() || gt.objects.empty()) return hits;
  const int n = std::min<int>(cloud.num_points, static_cast<int>(std::min({cloud.x.size(), cloud.y.size(),
                                                                             cloud.z.size()})));
  const bool timed = static_cast<int>(cloud.t_offset_ns.size()) >= n;
  for (int i = 0; i < n; ++i) {
    if (!(cloud.z[i] >= min_z)) continue;
    const int64_t t = cloud.utime + (timed ? cloud.t_offset_ns[i] / 1000 : 0);
    const auto q = poses.at(t);
    const double c = std::cos(q->yaw), s = std::sin(q->yaw);
    const double wx = q->x + c * cloud.x[i] - s * cloud.y[i];
    const double wy = q->y + s * cloud.x[i] + c * cloud.y[i];
    const double dt = 1e-6 * static_cast<double>(t - gt.utime);
    for (const auto& o : gt.objects) {
      if (cloud.z[i] > o.height + margin) continue;
      if (std::hypot(wx - (o.x + o.vx * dt), wy - (o.y + o.vy * dt)) <= o.radius + margin) ++hits[o.id];
    }
  }
  return hits;
}

// ---- recording ----

std::optional<Recording> recordDrive(const DriveConfig& config, const world::Scenario& scenario,
                                     const std::string& scene, int64_t seed, std::string* error) {
  auto fail = [&](const std::string& e) -> std::optional<Recording> {
    if (error) *error = e;
    return std::nullopt;
  };
  std::string err;
  auto planner = replay::makeAdapter("planner", config.planner_yaml, "planner.yaml", &err);
  if (!planner) return fail(err);
  std::vector<ConfigError> errors;
  auto bc = loadParams<base_controller::BaseControllerParams>(config.base_controller_yaml, "base_controller.yaml",
                                                               &errors);
  if (!bc) {
    std::string e = "base_controller.yaml:";
    for (const auto& ce : errors) e += " " + ce.toString();
    return fail(e);
  }
  if (!config.heading_mode.empty()) bc->heading.mode = config.heading_mode;
  if (const std::string bad = bc->validate(); !bad.empty()) return fail("base_controller.yaml: " + bad);
  // Built as replay::makeAdapter builds it, with the heading mode of the drive.
  auto controller = std::make_unique<replay::BoundAdapter<base_controller::BoundBaseController>>(
      base_controller::binding(*bc), std::make_unique<base_controller::BoundBaseController>(*bc),
      [](const base_controller::BoundBaseController& n, const replay::FeedCounts&) { return n.node.counters(); });
  std::vector<Eigen::Vector2d> route;
  if (!config.parked) {
    route = scenario.robot.goals;
    route.push_back(scenario.robot.start);
  }
  PatrolAdapter patrol(route, config.goal_tolerance);
  GroundTruthPerception oracle(config.perception);

  replay::RecorderConfig cfg;
  cfg.sim = config.sim;
  std::unique_ptr<replay::NodeAdapter> odometry;
  if (!config.odometry_yaml.empty() &&
      !(odometry = odometryInLoopFromText(config.odometry_yaml, "odometry.yaml", scenario, &cfg.sim, &err)))
    return fail(err);
  cfg.driver = config.driver;
  cfg.scenario = scenario;
  cfg.duration_s = config.duration_s;
  cfg.send_goal = false;      // the patrol sends the goals
  cfg.scripted_plan = false;  // the planner plans

  Recording rec;
  rec.scene = scene;
  rec.seed = seed;
  rec.scenario = scenario;
  runtime::LogWriterFile log;
  bool log_ok = true;
  if (!config.save_log.empty() && !log.open(config.save_log, &err)) return fail(err);
  DriveStats& st = rec.stats;
  double last_x = NAN, last_y = NAN;
  int64_t gt_frames = 0, moving_frames = 0;
  sim_ground_truth_t last_gt{};
  bool have_gt = false;
  const auto sink = [&](const std::string& ch, int64_t utime, const std::vector<uint8_t>& data) {
    if (!config.save_log.empty()) log_ok = log.write(ch, data.data(), data.size(), utime) && log_ok;
    const bool keep = ch == channels::kLidarPoints || ch == channels::kRobotPose || ch == channels::kSimGroundTruth;
    if (!keep) return;
    st.digest = fnv(st.digest, ch.data(), ch.size());
    st.digest = fnv(st.digest, data.data(), data.size());
    rec.events.push_back({ch, data});
    if (ch == channels::kRobotPose) {
      robot_pose_t p{};
      if (replay::decodeExact(data.data(), data.size(), &p) && std::isfinite(p.wz))
        st.max_yaw_rate = std::max(st.max_yaw_rate, std::abs(p.wz));
      // The pose's distance from the simulator's at the same instant (its latest ground truth,
      // at most 10 ms old, carried forward with its velocity).
      const double dt = 1e-6 * static_cast<double>(p.utime - last_gt.utime);
      if (have_gt && p.valid && dt >= 0.0 && dt <= 0.01 && std::isfinite(p.x) && std::isfinite(p.y))
        st.pose_error_max = std::max(st.pose_error_max, std::hypot(p.x - (last_gt.robot_x + last_gt.robot_vx * dt),
                                                                   p.y - (last_gt.robot_y + last_gt.robot_vy * dt)));
    } else if (ch == channels::kSimGroundTruth) {
      sim_ground_truth_t g;
      if (!replay::decodeExact(data.data(), data.size(), &g)) return;
      last_gt = g;
      have_gt = true;
      if (std::isfinite(last_x)) st.path_m += std::hypot(g.robot_x - last_x, g.robot_y - last_y);
      last_x = g.robot_x, last_y = g.robot_y;
      const double v = std::hypot(g.robot_vx, g.robot_vy);
      st.max_speed = std::max(st.max_speed, v);
      ++gt_frames;
      moving_frames += v > 0.1;
    }
  };
  std::vector<replay::NodeAdapter*> nodes{&patrol, &oracle, planner.get(), controller.get()};
  if (odometry) nodes.push_back(odometry.get());
  const replay::RecordSummary s =
      replay::recordSimulatedRun(cfg, nodes, sink);
  if (!config.save_log.empty()) {
    log.close();
    if (!log_ok) return fail(config.save_log + ": write failed (disk full?)");
  }
  st.sim_s = s.sim_time_s;
  st.mean_speed = st.sim_s > 0 ? st.path_m / st.sim_s : 0.0;
  st.moving_share = gt_frames ? static_cast<double>(moving_frames) / static_cast<double>(gt_frames) : 0.0;
  st.collisions = s.collision_episodes;
  st.goals_reached = patrol.reached();
  return rec;
}

// ---- scoring ----

std::optional<perception::PerceptionParams> methodParams(const std::string& method,
                                                         const perception::PerceptionParams& shipped) {
  perception::PerceptionParams p = shipped;
  if (method == "ucon") return p;
  if (method == "fapp") {
    p.association = "fapp";
    return p;
  }
  if (method == "ucon-noreassoc") {
    p.association = "ucon";
    p.reassociation.enabled = false;
    return p;
  }
  return std::nullopt;
}

std::unique_ptr<replay::NodeAdapter> makePerceptionReplay(const perception::PerceptionParams& params) {
  return std::make_unique<replay::BoundAdapter<perception::PerceptionNode>>(
      perception::binding(), std::make_unique<perception::PerceptionNode>(params),
      [](const perception::PerceptionNode&, const replay::FeedCounts& c) -> std::vector<std::pair<std::string, int64_t>> {
        return {{"frames_in", c.inputs(channels::kLidarPoints)},
                {"objects_out", c.outputs(channels::kPerceptionObjects)}};
      });
}

const char* missCauseName(MissCause cause) {
  switch (cause) {
    case kMissTrackTaken: return "track_taken";
    case kMissNoCluster: return "no_cluster";
    case kMissNotObject: return "not_object";
    case kMissHidden: return "motion_hidden";
    case kMissOnReference: return "motion_on_reference";
    case kMissMotionOther: return "motion_other";
    case kMissTentative: return "tentative";
    case kMissNoTrack: return "no_track";
    case kMissCauses: break;
  }
  return "?";
}

int missRangeBand(double range_m) { return range_m < 6.0 ? 0 : range_m < 9.0 ? 1 : range_m < 12.0 ? 2 : 3; }

MissCause classifyMiss(const Eigen::Vector2d& xy, const std::vector<perception::Detection>& detections,
                       const tracked_objects_t& objects, double threshold_m) {
  bool tentative = false;
  for (const auto& o : objects.objects) {
    if (!std::isfinite(o.x) || !std::isfinite(o.y) || std::hypot(o.x - xy.x(), o.y - xy.y()) >= threshold_m) continue;
    if (o.state == tracked_object_t::STATE_CONFIRMED || o.state == tracked_object_t::STATE_COASTING)
      return kMissTrackTaken;
    tentative = tentative || o.state == tracked_object_t::STATE_TENTATIVE;
  }
  const perception::Detection* best = nullptr;
  double best_d = kMissClusterDistance;
  for (const auto& d : detections) {
    const Eigen::Vector2d off = ((xy - d.box.center).cwiseAbs() - 0.5 * d.box.size).cwiseMax(0.0);
    if (off.norm() <= best_d) best_d = off.norm(), best = &d;
  }
  if (best == nullptr) return kMissNoCluster;
  if (!best->size_ok) return kMissNotObject;
  if (!best->dynamic()) {
    const perception::MotionEvidence& e = best->evidence;
    const int tested = e.near_reference + e.moved + e.surface + e.undecided;
    if (tested > 0 && 2 * e.undecided >= tested) return kMissHidden;
    if (tested > 0 && 2 * e.near_reference >= tested) return kMissOnReference;
    return kMissMotionOther;
  }
  return tentative ? kMissTentative : kMissNoTrack;
}

std::vector<MethodScore> scoreRecording(const Recording& rec, const std::vector<std::string>& methods,
                                        const std::vector<perception::PerceptionParams>& params,
                                        const ScoreOptions& options) {
  if (methods.size() != params.size()) throw std::invalid_argument("scoreRecording: one parameter set per method");
  struct Run {
    MethodScore score;
    std::unique_ptr<replay::NodeAdapter> node;
    mot::ClearMotAccumulator all, visible;
    std::vector<double> latency, verr;
    std::set<int64_t> ids;
    int accumulate = 1;
    const perception::PerceptionNode* node_view = nullptr;  ///< the replayed node (its last frame's clusters)
    std::set<int64_t> static_fp_ids;
    std::vector<double> static_fp_age, static_fp_speed;
    int64_t static_fp_coasting = 0;
    int64_t coast_us = 0;                   ///< the method's max_coast
    /// A mover's last output with enough returns: its time and true position and velocity.
    struct LastView {
      int64_t utime = 0;
      double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0;
    };
    std::map<int64_t, LastView> last_seen;  ///< by mover id
  };
  std::vector<Run> runs(methods.size());
  for (std::size_t k = 0; k < methods.size(); ++k) {
    runs[k].score.method = methods[k];
    runs[k].node = makePerceptionReplay(params[k]);
    if (const auto* b = dynamic_cast<const replay::BoundAdapter<perception::PerceptionNode>*>(runs[k].node.get()))
      runs[k].node_view = &b->node();
    runs[k].accumulate = params[k].preprocess.accumulate_frames;
    runs[k].coast_us = static_cast<int64_t>(std::llround(1e6 * params[k].tracks.max_coast));
  }
  std::optional<world::World> world;
  if (!rec.scenario.statics.empty() && !world::validate(rec.scenario)) world.emplace(rec.scenario);
  mot::RuntimeEvalOptions eval;
  eval.threshold_m = options.threshold_m;
  eval.max_range_m = options.max_range_m;

  PoseTrack poses;
  std::map<int64_t, sim_ground_truth_t> gts;                      // by utime
  std::map<int64_t, std::map<int64_t, int>> frame_returns;        // cloud seq -> mover id -> returns
  // Scores what a node published: every PERCEPTION_OBJECTS, whichever input caused it (a
  // tick after a pose can publish an invalid message), as ucon-mot --log scores a replay.
  // `frame`: the outputs of a LIDAR_POINTS feed (the node's last detections are that frame's).
  const auto score = [&](Run& r, const std::vector<replay::OutputMessage>& produced, bool frame) {
    for (const auto& o : produced) {
      if (o.channel != channels::kPerceptionObjects) continue;
      r.score.output_digest = fnv(r.score.output_digest, o.data.data(), o.data.size());
      tracked_objects_t objs;
      if (!replay::decodeExact(o.data.data(), o.data.size(), &objs)) continue;
      ++r.score.frames;
      if (!objs.valid) ++r.score.invalid_frames;
      const sim_ground_truth_t* g = groundTruthNear(gts, objs.utime);
      if (g == nullptr) continue;
      const auto gt_now = mot::groundTruthAt(*g, objs.utime, eval);
      const auto hyps = mot::hypothesesOf(objs, eval);
      for (const auto& h : hyps) r.ids.insert(h.id);
      // Returns on each mover in the frames the node merged for this output.
      std::map<int64_t, int> seen;
      for (int64_t s = objs.frame_seq - r.accumulate + 1; s <= objs.frame_seq; ++s)
        if (auto f = frame_returns.find(s); f != frame_returns.end())
          for (const auto& [id, k] : f->second) seen[id] += k;
      std::vector<char> hidden(gt_now.size(), 0);
      for (std::size_t i = 0; i < gt_now.size(); ++i) {
        const int k = seen[gt_now[i].id];
        hidden[i] = k < options.min_visible_points;
        auto& sh = r.score.sensor;
        ++sh.objects;
        const auto last = r.last_seen.find(gt_now[i].id);
        if (!hidden[i]) {
          ++sh.visible, ++sh.held, ++sh.seen, ++sh.predictable;
          sh.well_seen += k >= kWellSeenPoints;
          Run::LastView& v = r.last_seen[gt_now[i].id];
          v = {objs.utime, gt_now[i].x, gt_now[i].y, 0.0, 0.0};
          for (const auto& o : g->objects)
            if (o.id == gt_now[i].id && std::isfinite(o.vx) && std::isfinite(o.vy)) v.vx = o.vx, v.vy = o.vy;
        } else if (last != r.last_seen.end()) {
          const Run::LastView& v = last->second;
          ++sh.seen;
          sh.held += objs.utime - v.utime <= r.coast_us;
          const double dt = 1e-6 * static_cast<double>(objs.utime - v.utime);
          const double at_rest = std::hypot(gt_now[i].x - v.x, gt_now[i].y - v.y);
          const double walked_on = std::hypot(gt_now[i].x - v.x - v.vx * dt, gt_now[i].y - v.y - v.vy * dt);
          sh.predictable += std::min(at_rest, walked_on) <= eval.threshold_m;
        }
      }
      const auto fa = r.all.updateXY(gt_now, hyps, eval.threshold_m);
      const auto fe = r.visible.updateXY(gt_now, hyps, eval.threshold_m, &hidden);
      const double t_s = 1e-6 * static_cast<double>(objs.utime);
      if (options.trace)
        for (const auto& [gid, tid] : fa.switches)
          for (const auto& q : gt_now)
            if (q.id == gid)
              std::fprintf(options.trace, "%s %s idsw %.2f gt %lld -> track %lld at %.2f %.2f range %.2f\n",
                           options.trace_label.c_str(), r.score.method.c_str(), t_s, static_cast<long long>(gid),
                           static_cast<long long>(tid), q.x, q.y, std::hypot(q.x - g->robot_x, q.y - g->robot_y));
      const auto rp = poses.at(objs.utime);
      if (rp) {
        const int sb = speedBin(std::hypot(rp->vx, rp->vy)), yb = yawBin(std::abs(rp->wz));
        ++r.score.fp_frames[sb][yb];
        r.score.fp_count[sb][yb] += static_cast<int64_t>(fe.false_positives.size());
      }
      if (frame && objs.valid && r.node_view != nullptr) {
        for (int64_t gid : fe.misses)
          for (const auto& q : gt_now)
            if (q.id == gid) {
              const MissCause c = classifyMiss(Eigen::Vector2d(q.x, q.y), r.node_view->lastDetections(), objs,
                                               eval.threshold_m);
              const double range = std::hypot(q.x - g->robot_x, q.y - g->robot_y);
              ++r.score.miss_causes[c][missRangeBand(range)];
              if (options.trace)
                std::fprintf(options.trace, "%s %s fn %.2f gt %lld at %.2f %.2f range %.2f %s\n",
                             options.trace_label.c_str(), r.score.method.c_str(), t_s, static_cast<long long>(gid),
                             q.x, q.y, range, missCauseName(c));
            }
      }
      for (int64_t fid : fe.false_positives) {
        const tracked_object_t* t = nullptr;
        for (const auto& q : objs.objects)
          if (q.id == fid) t = &q;
        if (t == nullptr) continue;
        int nearest = -1;
        double nd = options.static_fp_distance;
        for (std::size_t i = 0; world && i < rec.scenario.statics.size(); ++i) {
          const double dd = world->staticFootprintDistance(i, world::Vec2(t->x, t->y));
          if (dd <= nd) nd = dd, nearest = static_cast<int>(i);
        }
        bool near_mover = false;
        for (const auto& q : g->objects) near_mover = near_mover || std::hypot(q.x - t->x, q.y - t->y) < 1.5;
        if (options.trace)
          std::fprintf(options.trace, "%s %s fp %.2f track %lld at %.2f %.2f v %.2f age %d state %d %s\n",
                       options.trace_label.c_str(), r.score.method.c_str(), t_s, static_cast<long long>(t->id), t->x,
                       t->y, std::hypot(t->vx, t->vy), t->age_frames, static_cast<int>(t->state),
                       nearest >= 0 ? "on_static" : near_mover ? "near_mover" : "elsewhere");
        if (nearest >= 0) {
          ++r.score.fp_on_static;
          ++r.score.fp_per_static[nearest];
          r.static_fp_ids.insert(t->id);
          r.static_fp_age.push_back(t->age_frames);
          r.static_fp_speed.push_back(std::hypot(t->vx, t->vy));
          r.static_fp_coasting += t->frames_since_seen > 0;
        } else if (near_mover) {
          ++r.score.fp_near_mover;
        } else {
          ++r.score.fp_elsewhere;
        }
      }
      for (const auto& [gid, tid] : fe.matches) {
        const sim_object_t* go = nullptr;
        for (const auto& q : g->objects)
          if (q.id == gid) go = &q;
        if (go == nullptr || std::hypot(go->x - g->robot_x, go->y - g->robot_y) > options.velocity_range_m) continue;
        for (const auto& t : objs.objects) {
          if (t.id != tid) continue;
          const double e = std::hypot(t.vx - go->vx, t.vy - go->vy);
          r.verr.push_back(e);
          if (options.trace && e > 0.5)
            std::fprintf(options.trace,
                         "%s %s dv %.2f gt %lld track %lld err %.2f v %.2f %.2f true %.2f %.2f age %d assoc %d\n",
                         options.trace_label.c_str(), r.score.method.c_str(), t_s, static_cast<long long>(gid),
                         static_cast<long long>(tid), e, t.vx, t.vy, go->vx, go->vy, t.age_frames,
                         static_cast<int>(t.last_association));
        }
      }
    }
  };
  std::vector<replay::OutputMessage> outs;
  for (const RecordedEvent& ev : rec.events) {
    const uint8_t* d = ev.data.data();
    const std::size_t n = ev.data.size();
    if (ev.channel == channels::kSimGroundTruth) {
      sim_ground_truth_t g;
      if (!replay::decodeExact(d, n, &g)) throw std::runtime_error("undecodable SIM_GROUND_TRUTH in the recording");
      gts[g.utime] = std::move(g);
      while (gts.size() > 200) gts.erase(gts.begin());
      continue;
    }
    if (ev.channel == channels::kRobotPose) {
      robot_pose_t p;
      if (!replay::decodeExact(d, n, &p)) throw std::runtime_error("undecodable ROBOT_POSE in the recording");
      poses.add(p);
      for (auto& r : runs) {
        outs.clear();
        r.node->feed(ev.channel, d, n, &outs);
        score(r, outs, false);
      }
      continue;
    }
    if (ev.channel != channels::kLidarPoints) continue;
    point_cloud_t cloud;
    if (!replay::decodeExact(d, n, &cloud)) throw std::runtime_error("undecodable LIDAR_POINTS in the recording");
    if (const sim_ground_truth_t* g = groundTruthNear(gts, cloud.utime))
      frame_returns[cloud.seq] = returnsOnMovers(cloud, poses, *g);
    while (frame_returns.size() > 16) frame_returns.erase(frame_returns.begin());
    poses.dropBefore(cloud.utime - 2'000'000);

    for (auto& r : runs) {
      outs.clear();
      const auto t0 = std::chrono::steady_clock::now();
      r.node->feed(ev.channel, d, n, &outs);
      r.latency.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      score(r, outs, true);
    }
  }
  std::vector<MethodScore> out;
  for (auto& r : runs) {
    r.score.all = r.all.summary();
    r.score.visible = r.visible.summary();
    r.score.latency_median_ms = percentile(r.latency, 0.5);
    r.score.latency_p99_ms = percentile(r.latency, 0.99);
    r.score.track_ids = static_cast<int64_t>(r.ids.size());
    r.score.fp_static_tracks = static_cast<int64_t>(r.static_fp_ids.size());
    if (!r.static_fp_age.empty()) {
      r.score.fp_static_age_median = percentile(r.static_fp_age, 0.5);
      r.score.fp_static_speed_median = percentile(r.static_fp_speed, 0.5);
      r.score.fp_static_coasting_share =
          static_cast<double>(r.static_fp_coasting) / static_cast<double>(r.static_fp_age.size());
    }
    if (!r.verr.empty()) {
      r.score.velocity_error_median = percentile(r.verr, 0.5);
      r.score.velocity_error_p90 = percentile(r.verr, 0.9);
      r.score.velocity_error_over =
          static_cast<double>(std::count_if(r.verr.begin(), r.verr.end(), [](double e) { return e > 0.5; })) /
          static_cast<double>(r.verr.size());
    }
    out.push_back(std::move(r.score));
  }
  return out;
}

}  // namespace bench
}  // namespace ucon
