#include "ucon/foxglove/convert.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "ucon/channels.hpp"
#include "ucon/config.hpp"
#include "ucon/foxglove/foxglove_schemas.hpp"
#include "ucon/foxglove/json_writer.hpp"
#include "ucon/foxglove/lcm_json.hpp"
#include "ucon/trajectory/piecewise_polynomial.hpp"
#include "ucon/trajopt/cost_terms.hpp"

namespace ucon {
namespace foxglove {

namespace {

constexpr const char* kPointCloud = "foxglove.PointCloud";
constexpr const char* kFrameTransform = "foxglove.FrameTransform";
constexpr const char* kPoseInFrame = "foxglove.PoseInFrame";
constexpr const char* kSceneUpdate = "foxglove.SceneUpdate";
constexpr const char* kGrid = "foxglove.Grid";
constexpr const char* kStatusView = "ucon.StatusView";
constexpr const char* kWorld = "world";
constexpr double kPi = 3.14159265358979323846;

std::string lower(const std::string& s) {
  std::string out = s;
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool finite(double a, double b) { return std::isfinite(a) && std::isfinite(b); }

struct Rgba {
  double r, g, b, a;
};

// A colour per track id: hues spaced by the golden angle, so that neighbouring ids differ.
Rgba idColour(int64_t id, double alpha) {
  const double h = std::fmod(static_cast<double>(id < 0 ? -id : id) * 0.618033988749895, 1.0) * 6.0;
  const double s = 0.75, v = 0.95;
  const int i = static_cast<int>(h) % 6;
  const double f = h - std::floor(h);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (i) {
    case 0: return {v, t, p, alpha};
    case 1: return {q, v, p, alpha};
    case 2: return {p, v, t, alpha};
    case 3: return {p, q, v, alpha};
    case 4: return {t, p, v, alpha};
    default: return {v, p, q, alpha};
  }
}

// Small writers for the Foxglove building blocks.
void writeTime(JsonWriter& w, const char* key, int64_t utime) {
  const int64_t u = std::max<int64_t>(0, utime);
  w.key(key);
  w.beginObject();
  w.field("sec", u / 1000000);
  w.field("nsec", (u % 1000000) * 1000);
  w.endObject();
}

void writeVector(JsonWriter& w, const char* key, double x, double y, double z) {
  w.key(key);
  w.beginObject();
  w.field("x", x);
  w.field("y", y);
  w.field("z", z);
  w.endObject();
}

void writeQuaternion(JsonWriter& w, const char* key, double x, double y, double z, double qw) {
  w.key(key);
  w.beginObject();
  w.field("x", x);
  w.field("y", y);
  w.field("z", z);
  w.field("w", qw);
  w.endObject();
}

void writePose(JsonWriter& w, const char* key, double x, double y, double z, double yaw) {
  w.key(key);
  w.beginObject();
  writeVector(w, "position", x, y, z);
  writeQuaternion(w, "orientation", 0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw));
  w.endObject();
}

void writeColour(JsonWriter& w, const char* key, const Rgba& c) {
  w.key(key);
  w.beginObject();
  w.field("r", c.r);
  w.field("g", c.g);
  w.field("b", c.b);
  w.field("a", c.a);
  w.endObject();
}

void writeField(JsonWriter& w, const char* name, int offset, NumericType type) {
  w.beginObject();
  w.field("name", name);
  w.field("offset", offset);
  w.field("type", static_cast<int>(type));
  w.endObject();
}

void writeDeleteAll(JsonWriter& w, int64_t utime) {
  w.key("deletions");
  w.beginArray();
  w.beginObject();
  writeTime(w, "timestamp", utime);
  w.field("type", static_cast<int>(DeletionType::kAll));
  w.field("id", "");
  w.endObject();
  w.endArray();
}

// Opens a SceneEntity: everything up to its primitive arrays.
void beginEntity(JsonWriter& w, int64_t utime, const std::string& frame, const std::string& id) {
  w.beginObject();
  writeTime(w, "timestamp", utime);
  w.field("frame_id", frame);
  w.field("id", id);
  w.key("lifetime");
  w.beginObject();
  w.field("sec", 0);
  w.field("nsec", 0);
  w.endObject();
  w.field("frame_locked", false);
}

void writeCylinder(JsonWriter& w, double x, double y, double z, double diameter, double height, const Rgba& c) {
  w.beginObject();
  writePose(w, "pose", x, y, z, 0.0);
  writeVector(w, "size", diameter, diameter, height);
  w.field("bottom_scale", 1.0);
  w.field("top_scale", 1.0);
  writeColour(w, "color", c);
  w.endObject();
}

void writeArrow(JsonWriter& w, double x, double y, double z, double vx, double vy, const Rgba& c) {
  // The arrow spans one second of travel.
  const double len = std::hypot(vx, vy);
  const double head = std::min(0.3, 0.4 * len);
  w.beginObject();
  writePose(w, "pose", x, y, z, std::atan2(vy, vx));
  w.field("shaft_length", std::max(0.0, len - head));
  w.field("shaft_diameter", 0.05);
  w.field("head_length", head);
  w.field("head_diameter", 0.15);
  writeColour(w, "color", c);
  w.endObject();
}

void writeLabel(JsonWriter& w, double x, double y, double z, const std::string& label) {
  w.beginObject();
  writePose(w, "pose", x, y, z, 0.0);
  w.field("billboard", true);
  w.field("font_size", 14.0);
  w.field("scale_invariant", true);
  writeColour(w, "color", Rgba{1.0, 1.0, 1.0, 1.0});
  w.field("text", label);
  w.endObject();
}

// "points": x-y points at height z, as foxglove.Point3.
void writePoints(JsonWriter& w, const std::vector<Eigen::Vector2d>& pts, double z) {
  w.key("points");
  w.beginArray();
  for (const auto& p : pts) {
    w.beginObject();
    w.field("x", p.x());
    w.field("y", p.y());
    w.field("z", z);
    w.endObject();
  }
  w.endArray();
}

// A polyline in the x-y plane at height z.
void writeLine(JsonWriter& w, LineType type, const std::vector<Eigen::Vector2d>& pts, double z, double thickness,
               const Rgba& c) {
  w.beginObject();
  w.field("type", static_cast<int>(type));
  writePose(w, "pose", 0.0, 0.0, 0.0, 0.0);
  w.field("thickness", thickness);
  w.field("scale_invariant", false);
  writePoints(w, pts, z);
  writeColour(w, "color", c);
  w.key("colors");
  w.beginArray();
  w.endArray();
  w.key("indices");
  w.beginArray();
  w.endArray();
  w.endObject();
}

// The sector as a triangle fan around its centre: vertex 0 is the centre, then the arc from
// heading - half_angle to heading + half_angle; triangle i is (0, i + 1, i + 2).
void writeSectorFan(JsonWriter& w, const trajopt::SectorShape& s, double heading, double z, const Rgba& c) {
  const double span = 2.0 * s.half_angle;
  const int n = std::max(2, static_cast<int>(std::ceil(span / (kPi / 24.0))));
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(static_cast<std::size_t>(n) + 2);
  pts.push_back(s.centre);
  for (int i = 0; i <= n; ++i) {
    const double a = heading - s.half_angle + span * i / n;
    pts.push_back(s.centre + s.radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  w.beginObject();
  writePose(w, "pose", 0.0, 0.0, 0.0, 0.0);
  writePoints(w, pts, z);
  writeColour(w, "color", c);
  w.key("colors");
  w.beginArray();
  w.endArray();
  w.key("indices");
  w.beginArray();
  for (int i = 0; i < n; ++i) {
    w.integer(0);
    w.integer(i + 1);
    w.integer(i + 2);
  }
  w.endArray();
  w.endObject();
}

// Points on the k-sigma ellipse of a 2x2 covariance: mu + k L (cos a, sin a) with L L^T = cov
// traces it exactly. Empty when the covariance is not finite or not positive definite.
std::vector<Eigen::Vector2d> sigmaEllipse(const Eigen::Vector2d& mu, const Eigen::Matrix2d& cov, double k) {
  std::vector<Eigen::Vector2d> pts;
  if (!cov.allFinite() || !mu.allFinite()) return pts;
  const Eigen::Matrix2d sym = 0.5 * (cov + cov.transpose());
  Eigen::LLT<Eigen::Matrix2d> llt(sym);
  if (llt.info() != Eigen::Success) return pts;
  const Eigen::Matrix2d L = llt.matrixL();
  constexpr int kSegments = 36;
  pts.reserve(kSegments);
  for (int i = 0; i < kSegments; ++i) {
    const double a = 2.0 * kPi * i / kSegments;
    pts.push_back(mu + k * L * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return pts;
}

// A float32 in little-endian byte order (Foxglove's packed fields), at p; returns p + 4.
char* putFloat(char* p, float f) {
  uint32_t v;
  std::memcpy(&v, &f, 4);
  for (int i = 0; i < 4; ++i) *p++ = static_cast<char>((v >> (8 * i)) & 0xFF);
  return p;
}

const char* stateName(int8_t s) {
  switch (s) {
    case tracked_object_t::STATE_TENTATIVE: return "tentative";
    case tracked_object_t::STATE_CONFIRMED: return "confirmed";
    case tracked_object_t::STATE_COASTING: return "coasting";
    case tracked_object_t::STATE_DELETED: return "deleted";
  }
  return "unknown";
}

const char* associationName(int8_t a) {
  switch (a) {
    case tracked_object_t::ASSOC_NONE: return "none";
    case tracked_object_t::ASSOC_NEW: return "new";
    case tracked_object_t::ASSOC_OBJECT: return "object";
    case tracked_object_t::ASSOC_REASSOCIATED: return "reassociated";
  }
  return "unknown";
}

void writeMetadata(JsonWriter& w, const std::vector<std::pair<const char*, std::string>>& kv) {
  w.key("metadata");
  w.beginArray();
  for (const auto& [k, v] : kv) {
    w.beginObject();
    w.field("key", k);
    w.field("value", v);
    w.endObject();
  }
  w.endArray();
}

// Empty primitive arrays an entity does not use.
void emptyArrays(JsonWriter& w, std::initializer_list<const char*> keys) {
  for (const char* k : keys) {
    w.key(k);
    w.beginArray();
    w.endArray();
  }
}

// Packs the finite points into *out: x y z as float32 (little-endian), then one byte from
// each of `extra` (per-point byte arrays); no padding (Foxglove reads unaligned fields).
// Returns the number of non-finite points left out.
std::size_t packPoints(const std::vector<float>& x, const std::vector<float>& y, const std::vector<float>& z,
                       std::initializer_list<const std::vector<uint8_t>*> extra, std::string* out) {
  std::size_t count = std::min({x.size(), y.size(), z.size()});
  for (const auto* e : extra) count = std::min(count, e->size());
  const std::size_t stride = 12 + extra.size();
  out->resize(count * stride);
  char* p = &(*out)[0];
  std::size_t skipped = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) {
      ++skipped;
      continue;
    }
    p = putFloat(p, x[i]);
    p = putFloat(p, y[i]);
    p = putFloat(p, z[i]);
    for (const auto* e : extra) *p++ = static_cast<char>((*e)[i]);
  }
  out->resize(static_cast<std::size_t>(p - out->data()));
  return skipped;
}

// A foxglove.PointCloud of points packed by packPoints with `byte_fields` after x y z.
void writeCloud(JsonWriter& w, int64_t utime, const std::string& frame,
                std::initializer_list<const char*> byte_fields, const std::string& packed) {
  w.beginObject();
  writeTime(w, "timestamp", utime);
  w.field("frame_id", frame);
  writePose(w, "pose", 0.0, 0.0, 0.0, 0.0);
  w.field("point_stride", static_cast<int>(12 + byte_fields.size()));
  w.key("fields");
  w.beginArray();
  writeField(w, "x", 0, NumericType::kFloat32);
  writeField(w, "y", 4, NumericType::kFloat32);
  writeField(w, "z", 8, NumericType::kFloat32);
  int offset = 12;
  for (const char* f : byte_fields) writeField(w, f, offset++, NumericType::kUint8);
  w.endArray();
  w.key("data");
  w.base64(reinterpret_cast<const uint8_t*>(packed.data()), packed.size());
  w.endObject();
}

}  // namespace

std::optional<ViewParams> viewParamsFromPlannerYaml(const std::string& yaml, const std::string& source,
                                                    std::string* error) {
  ConfigError parse_error;
  auto reader = ConfigReader::parse(yaml, source, &parse_error);
  if (!reader) {
    if (error) *error = parse_error.toString();
    return std::nullopt;
  }
  ViewParams p;
  auto optimizer = reader->section("optimizer");
  p.optimizer.read(optimizer);
  // planner.yaml `prediction`: the process noise of the planner's constant-velocity prediction
  // (PredictionParams::model(); the measurement noise is perception's and does not enter it).
  auto prediction = reader->section("prediction");
  prediction.read("accel_psd_xy", p.prediction.accel_psd_xy, 1e-9, 1e3);
  prediction.read("accel_psd_z", p.prediction.accel_psd_z, 1e-9, 1e3);
  auto objects = reader->section("objects");
  objects.read("min_radius", p.min_radius, 0.0, 5.0);
  auto map = reader->section("map");
  map.read("resolution", p.map_resolution, 0.01, 10.0);
  map.read("band_z_min", p.band_z_min, -10.0, 10.0);
  map.read("band_z_max", p.band_z_max, -10.0, 10.0);
  if (!reader->ok()) {
    if (error) *error = reader->errorText();
    return std::nullopt;
  }
  std::string bad = p.optimizer.validate();
  if (bad.empty()) {
    const std::string k = p.prediction.validate();
    if (!k.empty()) bad = "prediction." + k;
  } else {
    bad = "optimizer." + bad;
  }
  if (bad.empty() && !(p.band_z_max > p.band_z_min)) bad = "map.band_z_max (must be above band_z_min)";
  if (!bad.empty()) {
    if (error) *error = source + ": bad value at " + bad;
    return std::nullopt;
  }
  return p;
}

std::vector<FoxgloveTopic> foxgloveTopicsFor(const std::string& channel, const std::string& type_name) {
  const std::string c = "/" + lower(channel);
  if (type_name == "ucon.point_cloud_t") return {{c, kPointCloud}};
  if (type_name == "ucon.static_points_t") return {{c, kPointCloud}, {"/map", kGrid}};
  // Only the pose the stack drives on moves the base frame; another pose source beside it
  // (ODOMETRY_POSE while the simulator gives ROBOT_POSE) is a pose of its own.
  if (type_name == "ucon.robot_pose_t" && channel == channels::kRobotPose)
    return {{"/tf", kFrameTransform}, {c, kPoseInFrame}};
  if (type_name == "ucon.robot_pose_t") return {{c, kPoseInFrame}};
  if (type_name == "ucon.sim_ground_truth_t")
    return {{"/tf", kFrameTransform}, {c + "/pose", kPoseInFrame}, {c + "/objects", kSceneUpdate}};
  if (type_name == "ucon.tracked_objects_t") return {{c, kSceneUpdate}};
  if (type_name == "ucon.trajectory_t") return {{c, kSceneUpdate}};
  if (type_name == "ucon.nav_goal_t") return {{c, kPoseInFrame}};
  if (type_name == "ucon.process_status_t") return {{c, kStatusView}};
  return {};
}

FoxgloveConverter::FoxgloveConverter(const ViewParams& params) : params_(params) {}

bool FoxgloveConverter::convert(const std::string& channel, const LcmTypeInfo& type, const void* data,
                                std::size_t size, int64_t utime, std::vector<FoxgloveMessage>* out) {
  const std::string name = type.name;
  const std::string c = "/" + lower(channel);
  const int n = static_cast<int>(size);
  auto emit = [&](const std::string& topic, const char* schema) -> std::string& {
    out->push_back(FoxgloveMessage{FoxgloveTopic{topic, schema}, std::string()});
    return out->back().json;
  };

  if (name == "ucon.point_cloud_t") {
    point_cloud_t m{};
    if (m.decode(data, 0, n) != n) return false;
    // Reflectivity and tag ride along; the per-point time offsets stay in LIDAR_POINTS.
    stats_.points_skipped += packPoints(m.x, m.y, m.z, {&m.reflectivity, &m.tag}, &scratch_);
    JsonWriter w(&emit(c, kPointCloud));
    writeCloud(w, utime, m.frame_id.empty() ? std::string("lidar") : m.frame_id, {"reflectivity", "tag"}, scratch_);
    return true;
  }

  if (name == "ucon.static_points_t") {
    static_points_t m{};
    if (m.decode(data, 0, n) != n) return false;
    stats_.points_skipped += packPoints(m.x, m.y, m.z, {}, &scratch_);
    JsonWriter w(&emit(c, kPointCloud));
    writeCloud(w, utime, kWorld, {}, scratch_);
    // Only points of a valid message go into the map (the planner does the same).
    if (m.valid) addMapPoints(m.x, m.y, m.z);
    if (map_dirty_ && utime >= next_map_utime_) {
      flushMap(utime, true, out);
      next_map_utime_ = utime + static_cast<int64_t>(std::llround(params_.map_period_s * 1e6));
    }
    return true;
  }

  if (name == "ucon.robot_pose_t") {
    robot_pose_t m{};
    if (m.decode(data, 0, n) != n) return false;
    double qw = m.qw, qx = m.qx, qy = m.qy, qz = m.qz;
    const double norm = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
    if (!(norm > 1e-9) || !std::isfinite(norm)) {
      // No usable quaternion: the planar heading alone.
      const double yaw = std::isfinite(m.yaw) ? m.yaw : 0.0;
      qw = std::cos(0.5 * yaw), qx = 0.0, qy = 0.0, qz = std::sin(0.5 * yaw);
    } else {
      qw /= norm, qx /= norm, qy /= norm, qz /= norm;
    }
    if (channel == channels::kRobotPose && m.valid && finite(m.x, m.y) && std::isfinite(m.z)) {
      JsonWriter t(&emit("/tf", kFrameTransform));
      t.beginObject();
      writeTime(t, "timestamp", utime);
      t.field("parent_frame_id", kWorld);
      t.field("child_frame_id", "base");
      writeVector(t, "translation", m.x, m.y, m.z);
      writeQuaternion(t, "rotation", qx, qy, qz, qw);
      t.endObject();
    }
    JsonWriter w(&emit(c, kPoseInFrame));
    w.beginObject();
    writeTime(w, "timestamp", utime);
    w.field("frame_id", kWorld);
    w.key("pose");
    w.beginObject();
    writeVector(w, "position", m.x, m.y, m.z);
    writeQuaternion(w, "orientation", qx, qy, qz, qw);
    w.endObject();
    w.endObject();
    return true;
  }

  if (name == "ucon.sim_ground_truth_t") {
    sim_ground_truth_t m{};
    if (m.decode(data, 0, n) != n) return false;
    if (finite(m.robot_x, m.robot_y) && std::isfinite(m.robot_yaw)) {
      JsonWriter t(&emit("/tf", kFrameTransform));
      t.beginObject();
      writeTime(t, "timestamp", utime);
      t.field("parent_frame_id", kWorld);
      t.field("child_frame_id", "base_truth");
      writeVector(t, "translation", m.robot_x, m.robot_y, 0.0);
      writeQuaternion(t, "rotation", 0.0, 0.0, std::sin(0.5 * m.robot_yaw), std::cos(0.5 * m.robot_yaw));
      t.endObject();
    }
    {
      JsonWriter w(&emit(c + "/pose", kPoseInFrame));
      w.beginObject();
      writeTime(w, "timestamp", utime);
      w.field("frame_id", kWorld);
      writePose(w, "pose", m.robot_x, m.robot_y, 0.0, std::isfinite(m.robot_yaw) ? m.robot_yaw : 0.0);
      w.endObject();
    }
    JsonWriter w(&emit(c + "/objects", kSceneUpdate));
    w.beginObject();
    writeDeleteAll(w, utime);
    w.key("entities");
    w.beginArray();
    for (const auto& o : m.objects) {
      if (!finite(o.x, o.y) || !(o.radius > 0.0) || !(o.height > 0.0) || !std::isfinite(o.radius) ||
          !std::isfinite(o.height)) {
        ++stats_.objects_skipped;
        continue;
      }
      beginEntity(w, utime, kWorld, "truth_" + std::to_string(o.id));
      writeMetadata(w, {{"id", std::to_string(o.id)}, {"motion", std::to_string(o.motion)}});
      const Rgba grey{0.8, 0.8, 0.8, 0.35};
      w.key("arrows");
      w.beginArray();
      if (finite(o.vx, o.vy) && std::hypot(o.vx, o.vy) > 0.05)
        writeArrow(w, o.x, o.y, o.height + 0.05, o.vx, o.vy, Rgba{0.8, 0.8, 0.8, 0.9});
      w.endArray();
      emptyArrays(w, {"cubes", "spheres"});
      w.key("cylinders");
      w.beginArray();
      writeCylinder(w, o.x, o.y, 0.5 * o.height, 2.0 * o.radius, o.height, grey);
      w.endArray();
      emptyArrays(w, {"lines", "triangles"});
      w.key("texts");
      w.beginArray();
      writeLabel(w, o.x, o.y, o.height + 0.25, "truth " + std::to_string(o.id));
      w.endArray();
      emptyArrays(w, {"models"});
      w.endObject();
    }
    if (finite(m.robot_x, m.robot_y) && m.robot_radius > 0.0 && std::isfinite(m.robot_radius)) {
      beginEntity(w, utime, kWorld, "robot_truth");
      writeMetadata(w, {{"collision", m.collision ? "true" : "false"},
                        {"collisions", std::to_string(m.num_collisions)}});
      emptyArrays(w, {"arrows", "cubes", "spheres"});
      w.key("cylinders");
      w.beginArray();
      const Rgba colour = m.collision ? Rgba{1.0, 0.1, 0.1, 0.6} : Rgba{0.2, 0.6, 1.0, 0.3};
      writeCylinder(w, m.robot_x, m.robot_y, 0.15, 2.0 * m.robot_radius, 0.3, colour);
      w.endArray();
      emptyArrays(w, {"lines", "triangles", "texts", "models"});
      w.endObject();
    }
    w.endArray();
    w.endObject();
    return true;
  }

  if (name == "ucon.tracked_objects_t") {
    tracked_objects_t m{};
    if (m.decode(data, 0, n) != n) return false;
    const std::string frame = m.frame_id.empty() ? std::string(kWorld) : m.frame_id;
    const double k = params_.sigma;
    JsonWriter w(&emit(c, kSceneUpdate));
    w.beginObject();
    writeDeleteAll(w, utime);
    w.key("entities");
    w.beginArray();
    for (const auto& o : m.objects) {
      if (o.state == tracked_object_t::STATE_DELETED) continue;
      const double diag = std::hypot(o.size_x, o.size_y);
      if (!finite(o.x, o.y) || !std::isfinite(diag) || !std::isfinite(o.size_z)) {
        ++stats_.objects_skipped;
        continue;
      }
      const double z = std::isfinite(o.z) ? o.z : 0.5 * o.size_z;
      const double height = std::max(0.05, o.size_z);
      const double alpha = !m.valid ? 0.25 : o.state == tracked_object_t::STATE_CONFIRMED ? 0.8 : 0.45;
      const Rgba colour = m.valid ? idColour(o.id, alpha) : Rgba{0.5, 0.5, 0.5, alpha};
      beginEntity(w, utime, frame, "track_" + std::to_string(o.id));
      char speed[32];
      std::snprintf(speed, sizeof(speed), "%.2f", std::hypot(o.vx, o.vy));
      writeMetadata(w, {{"id", std::to_string(o.id)},
                        {"state", stateName(o.state)},
                        {"association", associationName(o.last_association)},
                        {"speed_mps", speed},
                        {"age_frames", std::to_string(o.age_frames)},
                        {"frames_since_seen", std::to_string(o.frames_since_seen)},
                        {"valid", m.valid ? "true" : "false"}});
      w.key("arrows");
      w.beginArray();
      if (finite(o.vx, o.vy) && std::hypot(o.vx, o.vy) > 0.05)
        writeArrow(w, o.x, o.y, z + 0.5 * height + 0.05, o.vx, o.vy, Rgba{colour.r, colour.g, colour.b, 1.0});
      w.endArray();
      emptyArrays(w, {"cubes", "spheres"});
      w.key("cylinders");
      w.beginArray();
      writeCylinder(w, o.x, o.y, z, std::max(0.05, diag), height, colour);
      w.endArray();

      w.key("lines");
      w.beginArray();
      bool drew_ellipse = false;
      if (o.cov_size == 36 && o.cov.size() == 36) {
        Eigen::Matrix2d cov;
        cov << o.cov[0], o.cov[1], o.cov[6], o.cov[7];
        const auto pts = sigmaEllipse(Eigen::Vector2d(o.x, o.y), cov, k);
        if (!pts.empty()) {
          writeLine(w, LineType::kLineLoop, pts, 0.03, 0.03, Rgba{colour.r, colour.g, colour.b, 1.0});
          drew_ellipse = true;
        }
      }
      if (!drew_ellipse) ++stats_.ellipses_skipped;
      w.endArray();

      // Paper eqs. 6-7 as the planner computes them (its config, its body radius).
      w.key("triangles");
      w.beginArray();
      trajopt::PredictedObstacle ob = trajopt::obstacleFromMessage(o, m.utime);
      ob.radius = std::max(ob.radius, params_.min_radius);
      trajopt::ObstacleTrack track;
      bool covariance_ok = true;
      if (trajopt::prepareObstacle(ob, m.utime, params_.prediction, params_.optimizer, &track, &covariance_ok)) {
        const trajopt::SectorShape s = trajopt::sectorAt(track, 0.0, params_.optimizer);
        const double heading = track.disk ? 0.0 : std::atan2(track.dir.y(), track.dir.x());
        if (s.centre.allFinite() && std::isfinite(s.radius) && std::isfinite(s.half_angle) && s.radius > 0.0) {
          writeSectorFan(w, s, heading, 0.02, Rgba{colour.r, colour.g, colour.b, 0.25});
        } else {
          ++stats_.sectors_skipped;
        }
      } else {
        ++stats_.sectors_skipped;
      }
      w.endArray();
      w.key("texts");
      w.beginArray();
      writeLabel(w, o.x, o.y, z + 0.5 * height + 0.3, std::to_string(o.id));
      w.endArray();
      emptyArrays(w, {"models"});
      w.endObject();
    }
    w.endArray();
    w.endObject();
    return true;
  }

  if (name == "ucon.trajectory_t") {
    trajectory_t m{};
    if (m.decode(data, 0, n) != n) return false;
    JsonWriter w(&emit(c, kSceneUpdate));
    w.beginObject();
    writeDeleteAll(w, utime);
    w.key("entities");
    w.beginArray();
    trajectory::PiecewisePolynomial poly;
    const auto st = trajectory::PiecewisePolynomial::fromMessage(m, &poly);
    if (st == trajectory::TrajectoryStatus::kOk) {
      const double duration = poly.duration();
      const double step = params_.trajectory_step_s;
      const int count = std::min(4000, static_cast<int>(std::ceil(duration / step)) + 1);
      std::vector<Eigen::Vector2d> pts;
      pts.reserve(static_cast<std::size_t>(count));
      for (int i = 0; i < count; ++i) {
        const auto p = poly.sampleRelative(std::min(duration, i * step)).position;
        pts.emplace_back(p.x(), p.y());
      }
      Rgba colour{0.1, 0.9, 0.2, 1.0};
      if (m.status == trajectory_t::STATUS_STOP) colour = {1.0, 0.6, 0.0, 1.0};
      if (m.status == trajectory_t::STATUS_GOAL_REACHED) colour = {0.2, 0.5, 1.0, 1.0};
      if (m.status == trajectory_t::STATUS_INVALID) colour = {1.0, 0.1, 0.1, 1.0};
      beginEntity(w, utime, kWorld, "trajectory");
      char dur[32];
      std::snprintf(dur, sizeof(dur), "%.3f", duration);
      writeMetadata(w, {{"plan_id", std::to_string(m.plan_id)},
                        {"goal_id", std::to_string(m.goal_id)},
                        {"status", std::to_string(m.status)},
                        {"message", m.message},
                        {"duration_s", dur}});
      emptyArrays(w, {"arrows", "cubes", "spheres", "cylinders"});
      w.key("lines");
      w.beginArray();
      writeLine(w, LineType::kLineStrip, pts, 0.05, 0.05, colour);
      w.endArray();
      emptyArrays(w, {"triangles", "texts", "models"});
      w.endObject();
    } else {
      ++stats_.trajectories_invalid;
    }
    w.endArray();
    w.endObject();
    return true;
  }

  if (name == "ucon.nav_goal_t") {
    nav_goal_t m{};
    if (m.decode(data, 0, n) != n) return false;
    JsonWriter w(&emit(c, kPoseInFrame));
    w.beginObject();
    writeTime(w, "timestamp", utime);
    w.field("frame_id", kWorld);
    writePose(w, "pose", m.x, m.y, 0.0, std::isfinite(m.yaw) ? m.yaw : 0.0);
    w.endObject();
    return true;
  }
  if (name == "ucon.process_status_t") {
    process_status_t m{};
    if (m.decode(data, 0, n) != n) return false;
    JsonWriter w(&emit(c, kStatusView));
    w.beginObject();
    w.field("utime", m.utime);
    w.field("name", m.name);
    w.field("health", static_cast<int>(m.health));
    w.field("message", m.message);
    w.key("timings");
    w.beginArray();
    for (std::size_t i = 0; i < m.timing_names.size(); ++i) {
      w.beginObject();
      w.field("name", m.timing_names[i]);
      w.field("median_ms", i < m.timing_median_ms.size() ? m.timing_median_ms[i] : std::nan(""));
      w.field("max_ms", i < m.timing_max_ms.size() ? m.timing_max_ms[i] : std::nan(""));
      w.endObject();
    }
    w.endArray();
    auto pairs = [&](const char* key, const std::vector<std::string>& names, const auto& values) {
      w.key(key);
      w.beginArray();
      for (std::size_t i = 0; i < names.size() && i < values.size(); ++i) {
        w.beginObject();
        w.field("name", names[i]);
        w.field("value", static_cast<double>(values[i]));
        w.endObject();
      }
      w.endArray();
    };
    pairs("counters", m.counter_names, m.counter_values);
    pairs("values", m.value_names, m.values);
    w.endObject();
    return true;
  }
  return true;  // no Foxglove view for this type
}

void FoxgloveConverter::addMapPoints(const std::vector<float>& x, const std::vector<float>& y,
                                     const std::vector<float>& z) {
  const double inv = 1.0 / params_.map_resolution;
  const std::size_t count = std::min({x.size(), y.size(), z.size()});
  constexpr double kLimit = 1e6;  // cells; farther points are not map material
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) continue;
    if (z[i] < params_.band_z_min || z[i] > params_.band_z_max) continue;
    const double fx = std::floor(x[i] * inv), fy = std::floor(y[i] * inv);
    if (std::abs(fx) > kLimit || std::abs(fy) > kLimit) {
      ++stats_.map_points_clipped;
      continue;
    }
    const int32_t ix = static_cast<int32_t>(fx), iy = static_cast<int32_t>(fy);
    const uint64_t key = (uint64_t{static_cast<uint32_t>(ix)} << 32) | static_cast<uint32_t>(iy);
    ++map_hits_[key];
    last_cx_ = ix;
    last_cy_ = iy;
    map_dirty_ = true;
  }
}

void FoxgloveConverter::flushMap(int64_t utime, bool only_if_changed, std::vector<FoxgloveMessage>* out) {
  if (map_hits_.empty() || (only_if_changed && !map_dirty_)) return;
  map_dirty_ = false;
  int32_t min_x = INT32_MAX, min_y = INT32_MAX, max_x = INT32_MIN, max_y = INT32_MIN;
  auto cellOf = [](uint64_t key, int32_t* ix, int32_t* iy) {
    *ix = static_cast<int32_t>(static_cast<uint32_t>(key >> 32));
    *iy = static_cast<int32_t>(static_cast<uint32_t>(key & 0xFFFFFFFFu));
  };
  for (const auto& [key, hits] : map_hits_) {
    int32_t ix, iy;
    cellOf(key, &ix, &iy);
    min_x = std::min(min_x, ix), max_x = std::max(max_x, ix);
    min_y = std::min(min_y, iy), max_y = std::max(max_y, iy);
  }
  // A map larger than max_map_cells is cut to a square window around the latest points.
  int64_t width = int64_t{max_x} - min_x + 1, height = int64_t{max_y} - min_y + 1;
  if (width * height > params_.max_map_cells) {
    const int32_t half = static_cast<int32_t>(std::sqrt(static_cast<double>(params_.max_map_cells)) / 2);
    min_x = std::max(min_x, last_cx_ - half), max_x = std::min(max_x, last_cx_ + half - 1);
    min_y = std::max(min_y, last_cy_ - half), max_y = std::min(max_y, last_cy_ + half - 1);
    width = int64_t{max_x} - min_x + 1, height = int64_t{max_y} - min_y + 1;
  }
  scratch_.assign(static_cast<std::size_t>(width * height), '\0');
  for (const auto& [key, hits] : map_hits_) {
    int32_t ix, iy;
    cellOf(key, &ix, &iy);
    if (ix < min_x || ix > max_x || iy < min_y || iy > max_y) continue;
    scratch_[static_cast<std::size_t>((int64_t{iy} - min_y) * width + (int64_t{ix} - min_x))] =
        static_cast<char>(std::min<uint32_t>(hits, 255));
  }
  out->push_back(FoxgloveMessage{FoxgloveTopic{"/map", kGrid}, std::string()});
  JsonWriter w(&out->back().json);
  const double r = params_.map_resolution;
  w.beginObject();
  writeTime(w, "timestamp", utime);
  w.field("frame_id", kWorld);
  writePose(w, "pose", min_x * r, min_y * r, 0.0, 0.0);
  w.field("column_count", width);
  w.key("cell_size");
  w.beginObject();
  w.field("x", r);
  w.field("y", r);
  w.endObject();
  w.field("row_stride", width);
  w.field("cell_stride", 1);
  w.key("fields");
  w.beginArray();
  writeField(w, "hits", 0, NumericType::kUint8);
  w.endArray();
  w.key("data");
  w.base64(reinterpret_cast<const uint8_t*>(scratch_.data()), scratch_.size());
  w.endObject();
}

}  // namespace foxglove
}  // namespace ucon
