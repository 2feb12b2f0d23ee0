#include "observation.hpp"

#include <cmath>

namespace ucon::bench {

const char* toString(ObserveMode m) { return m == ObserveMode::kLineOfSight ? "los" : "all"; }

bool parseObserveMode(const std::string& s, ObserveMode* out) {
  if (s == "all") {
    *out = ObserveMode::kAll;
  } else if (s == "los") {
    *out = ObserveMode::kLineOfSight;
  } else {
    return false;
  }
  return true;
}

bool lineOfSight(const world::World& w, const Eigen::Vector2d& sensor, double sensor_height, std::size_t i,
                 double range) {
  const world::ObstacleState& o = w.movers()[i];
  const Eigen::Vector2d d = o.position - sensor;
  const double dist = d.norm();
  if (!(dist <= range)) return false;
  if (dist <= o.radius) return true;  // the sensor is inside the body
  const Eigen::Vector2d across = Eigen::Vector2d(-d.y(), d.x()) / dist;
  const world::Vec3 origin(sensor.x(), sensor.y(), sensor_height);
  for (const double side : {0.0, 0.8, -0.8}) {
    const Eigen::Vector2d target = o.position + side * o.radius * across;
    const Eigen::Vector2d ray = target - sensor;
    const double len = ray.norm();
    const world::Vec3 dir(ray.x() / len, ray.y() / len, 0.0);
    const world::RayHit hit = w.castRay(origin, dir, len + o.radius);
    if (hit.kind == world::HitKind::kMoving && hit.index == int(i)) return true;
  }
  return false;
}

Observer::Observer(const world::World& w, const ObserveConfig& cfg, uint64_t seed)
    : w_(w), cfg_(cfg), noise_(world::deriveSeed(seed, 0x5eed)) {
  Track t;
  t.kf = kalman::ConstantVelocityKalman(cfg_.kalman);
  tracks_.assign(w.numMovers(), t);
}

int Observer::moverOfTrack(int64_t id) const {
  for (std::size_t i = 0; i < tracks_.size(); ++i)
    if (tracks_[i].live && tracks_[i].id == id) return int(i);
  return -1;
}

std::optional<double> Observer::trackAge(std::size_t i) const {
  if (i >= tracks_.size() || !tracks_[i].live) return std::nullopt;
  return w_.time() - tracks_[i].created_s;
}

std::vector<perception::ObjectEstimate> Observer::frame(double dt, const Eigen::Vector2d& sensor) {
  const double t = w_.time();
  std::vector<perception::ObjectEstimate> out;
  out.reserve(tracks_.size());
  for (std::size_t i = 0; i < w_.numMovers(); ++i) {
    const world::ObstacleState& o = w_.movers()[i];
    // Two draws per mover and frame whether it is seen or not: the noise of a mover does not
    // depend on what the robot saw of the others.
    const Eigen::Vector3d z(o.position.x() + cfg_.noise_std * noise_.normal(),
                            o.position.y() + cfg_.noise_std * noise_.normal(), 0.5 * o.height);
    Track& tr = tracks_[i];
    const bool seen = cfg_.mode == ObserveMode::kAll || lineOfSight(w_, sensor, cfg_.sensor_height, i, cfg_.range);
    if (seen) {
      ++measurements_;
      if (tr.live) {
        tr.kf.predict(dt);
        tr.kf.updatePosition(z);
      } else {
        tr.kf = kalman::ConstantVelocityKalman(cfg_.kalman);
        tr.kf.init(z, Eigen::Vector3d::Zero());
        tr.live = true;
        tr.id = cfg_.mode == ObserveMode::kAll ? o.id : next_id_++;
        tr.created_s = t;
        tr.frames = 0;
        ++started_;
      }
      tr.last_seen_s = t;
    } else if (tr.live) {
      ++coasting_;
      tr.kf.predict(dt);
      if (cfg_.coast_velocity_decay > 0.0) {
        kalman::State6 x = tr.kf.state();
        x.tail<3>() *= std::exp(-dt / cfg_.coast_velocity_decay);
        tr.kf.initState(x, tr.kf.covariance());
      }
      if (t - tr.last_seen_s > cfg_.max_coast) tr.live = false;
    }
    if (!tr.live) continue;
    ++tr.frames;
    perception::ObjectEstimate e;  // measured at object level; coasting while unseen
    e.id = tr.id;
    e.state = seen ? tracked_object_t::STATE_CONFIRMED : tracked_object_t::STATE_COASTING;
    e.last_association = seen ? tracked_object_t::ASSOC_OBJECT : tracked_object_t::ASSOC_NONE;
    e.x = tr.kf.state();
    e.P = tr.kf.covariance();
    e.size << 2.0 * o.radius, 2.0 * o.radius, o.height;
    e.num_points = seen ? 50 : 0;
    e.age_frames = tr.frames;
    e.frames_since_seen = seen ? 0 : int32_t(std::lround((t - tr.last_seen_s) * 50.0));
    out.push_back(e);
  }
  return out;
}

}  // namespace ucon::bench
