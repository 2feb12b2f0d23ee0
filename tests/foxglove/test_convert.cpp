// ucon messages -> Foxglove views: point cloud layout, transforms, tracked objects with their
// covariance ellipse and the sector of paper eqs. 6-7 (closed form), trajectory line, static map.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "ucon/foxglove/convert.hpp"
#include "ucon/foxglove/foxglove_schemas.hpp"
#include "ucon/foxglove/lcm_json.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/robot_pose_t.hpp"
#include "ucon/sim_ground_truth_t.hpp"
#include "ucon/static_points_t.hpp"
#include "ucon/tracked_objects_t.hpp"
#include "ucon/trajectory_t.hpp"

namespace fg = ucon::foxglove;
using nlohmann::json;

namespace {

std::string plannerYaml() {
  std::ifstream f("deploy/config/planner.yaml");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

fg::ViewParams shippedParams() {
  std::string err;
  const auto p = fg::viewParamsFromPlannerYaml(plannerYaml(), "planner.yaml", &err);
  EXPECT_TRUE(p.has_value()) << err;
  return p.value_or(fg::ViewParams{});
}

template <class T>
std::vector<fg::FoxgloveMessage> convert(fg::FoxgloveConverter& c, const std::string& channel, const T& m,
                                         int64_t utime) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  std::vector<fg::FoxgloveMessage> out;
  EXPECT_TRUE(c.convert(channel, *fg::findLcmType(b.data(), b.size()), b.data(), b.size(), utime, &out));
  return out;
}

std::vector<uint8_t> base64Decode(const std::string& s) {
  static const std::string kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<uint8_t> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    if (c == '=') break;
    acc = (acc << 6) | static_cast<uint32_t>(kAlphabet.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<uint8_t>((acc >> bits) & 0xFF));
    }
  }
  return out;
}

float floatAt(const std::vector<uint8_t>& d, std::size_t at) {
  uint32_t v = d[at] | (d[at + 1] << 8) | (d[at + 2] << 16) | (uint32_t{d[at + 3]} << 24);
  float f;
  std::memcpy(&f, &v, 4);
  return f;
}

const json& only(const std::vector<fg::FoxgloveMessage>& out, const std::string& topic, json* storage) {
  for (const auto& m : out) {
    if (m.topic.topic == topic) {
      *storage = json::parse(m.json);
      return *storage;
    }
  }
  ADD_FAILURE() << "no message on " << topic;
  return *storage;
}

ucon::tracked_object_t track(int64_t id, double vx, double vy, double var_x, double var_y) {
  ucon::tracked_object_t o{};
  o.id = id;
  o.state = ucon::tracked_object_t::STATE_CONFIRMED;
  o.x = 2.0;
  o.y = 1.0;
  o.z = 0.85;
  o.vx = vx;
  o.vy = vy;
  o.size_x = 0.6;
  o.size_y = 0.8;  // footprint diagonal 1.0: r/2 = 0.5
  o.size_z = 1.7;
  o.cov_size = 36;
  o.cov.assign(36, 0.0);
  o.cov[0] = var_x;
  o.cov[7] = var_y;
  o.cov[14] = 0.01;
  o.cov[21] = o.cov[28] = o.cov[35] = 0.04;
  return o;
}

}  // namespace

TEST(FoxgloveView, GivenTheShippedPlannerYamlWhenReadThenTheDefaultsEqualIt) {
  const fg::ViewParams p = shippedParams();
  const fg::ViewParams d;
  EXPECT_EQ(p.min_radius, d.min_radius);
  EXPECT_EQ(p.map_resolution, d.map_resolution);
  EXPECT_EQ(p.band_z_min, d.band_z_min);
  EXPECT_EQ(p.band_z_max, d.band_z_max);
  EXPECT_EQ(p.optimizer.sector.h, 0.02);
  EXPECT_EQ(p.optimizer.sector.k, 2.0);
  EXPECT_EQ(p.optimizer.sector.kappa, 0.05);
  EXPECT_EQ(p.optimizer.safe_distance, 0.4);
}

TEST(FoxgloveView, GivenABadPlannerYamlWhenReadThenTheErrorNamesTheKey) {
  std::string yaml = plannerYaml();
  const auto at = yaml.find("kappa: 0.05");
  ASSERT_NE(at, std::string::npos);
  yaml.replace(at, 11, "kappa: -1.0");
  std::string err;
  EXPECT_FALSE(fg::viewParamsFromPlannerYaml(yaml, "planner.yaml", &err).has_value());
  EXPECT_NE(err.find("kappa"), std::string::npos) << err;
  EXPECT_FALSE(fg::viewParamsFromPlannerYaml("optimizer: [", "x.yaml", &err).has_value());
  EXPECT_FALSE(err.empty());
}

TEST(FoxgloveView, GivenChannelsWhenAskedForTopicsThenEachTypeMapsToItsViews) {
  EXPECT_EQ(fg::foxgloveTopicsFor("LIDAR_POINTS", "ucon.point_cloud_t").at(0).topic, "/lidar_points");
  const auto pose = fg::foxgloveTopicsFor("ROBOT_POSE", "ucon.robot_pose_t");
  ASSERT_EQ(pose.size(), 2u);
  EXPECT_EQ(pose[0].topic, "/tf");
  EXPECT_EQ(pose[0].schema_name, "foxglove.FrameTransform");
  EXPECT_EQ(pose[1].schema_name, "foxglove.PoseInFrame");
  EXPECT_EQ(fg::foxgloveTopicsFor("PERCEPTION_STATIC", "ucon.static_points_t").at(1).schema_name, "foxglove.Grid");
  EXPECT_TRUE(fg::foxgloveTopicsFor("BASE_STATUS", "ucon.base_status_t").empty());
  for (const char* s : {"foxglove.PointCloud", "foxglove.FrameTransform", "foxglove.PoseInFrame",
                        "foxglove.SceneUpdate", "foxglove.Grid", "ucon.StatusView"}) {
    const json schema = json::parse(fg::foxgloveSchema(s));
    EXPECT_EQ(schema["title"], s);
    EXPECT_EQ(schema["type"], "object");
  }
  EXPECT_TRUE(fg::foxgloveSchema("foxglove.Nothing").empty());
}

TEST(FoxgloveView, GivenAPointCloudWhenConvertedThenThePackedLayoutHoldsEveryFinitePoint) {
  fg::FoxgloveConverter c(shippedParams());
  ucon::point_cloud_t m{};
  m.utime = 3'500'000;
  m.frame_id = "base";
  m.num_points = 3;
  m.x = {1.5f, std::nanf(""), -2.25f};
  m.y = {0.5f, 0.f, 4.f};
  m.z = {0.1f, 0.f, -0.3f};
  m.t_offset_ns = {0, 100, 19'000'000};
  m.reflectivity = {10, 20, 250};
  m.tag = {0, 1, 0x30};
  json j;
  const auto out = convert(c, "LIDAR_POINTS", m, m.utime);
  ASSERT_EQ(out.size(), 1u);
  only(out, "/lidar_points", &j);
  EXPECT_EQ(j["timestamp"]["sec"], 3);
  EXPECT_EQ(j["timestamp"]["nsec"], 500'000'000);
  EXPECT_EQ(j["frame_id"], "base");
  const int stride = j["point_stride"];
  const auto data = base64Decode(j["data"]);
  ASSERT_EQ(data.size(), 2u * stride);  // the NaN point is left out
  EXPECT_EQ(c.stats().points_skipped, 1);
  std::map<std::string, std::pair<int, int>> fields;
  for (const auto& f : j["fields"]) fields[f["name"]] = {f["offset"], f["type"]};
  EXPECT_EQ(fields["x"], std::make_pair(0, 7));
  EXPECT_EQ(fields["z"], std::make_pair(8, 7));
  EXPECT_EQ(stride, 14);
  EXPECT_EQ(fields.count("t_offset_ns"), 0u);  // in the raw message only
  EXPECT_EQ(fields["reflectivity"].second, 1);
  EXPECT_EQ(floatAt(data, stride + fields["x"].first), -2.25f);
  EXPECT_EQ(floatAt(data, stride + fields["y"].first), 4.f);
  EXPECT_EQ(floatAt(data, stride + fields["z"].first), -0.3f);
  EXPECT_EQ(data[stride + fields["reflectivity"].first], 250);
  EXPECT_EQ(data[stride + fields["tag"].first], 0x30);
}

TEST(FoxgloveView, GivenARobotPoseWhenConvertedThenTransformWorldToBaseAndPose) {
  fg::FoxgloveConverter c(shippedParams());
  ucon::robot_pose_t p{};
  p.utime = 2'000'000;
  p.valid = 1;
  p.x = 1.0;
  p.y = 2.0;
  p.qw = 2.0;  // not normalised: the transform is
  p.qz = 2.0;
  json j;
  auto out = convert(c, "ROBOT_POSE", p, p.utime);
  only(out, "/tf", &j);
  EXPECT_EQ(j["parent_frame_id"], "world");
  EXPECT_EQ(j["child_frame_id"], "base");
  EXPECT_EQ(j["translation"]["y"], 2.0);
  EXPECT_NEAR(j["rotation"]["w"].get<double>(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(j["rotation"]["z"].get<double>(), std::sqrt(0.5), 1e-12);
  only(out, "/robot_pose", &j);
  EXPECT_EQ(j["frame_id"], "world");
  EXPECT_EQ(j["pose"]["position"]["x"], 1.0);
  // Not localised: no transform (Foxglove would otherwise move the robot there), the pose still.
  p.valid = 0;
  out = convert(c, "ROBOT_POSE", p, p.utime);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic.topic, "/robot_pose");
}

TEST(FoxgloveView, GivenTheOdometryPoseBesideRobotPoseWhenConvertedThenOnlyRobotPoseMovesTheBaseFrame) {
  fg::FoxgloveConverter c(shippedParams());
  ucon::robot_pose_t p{};
  p.utime = 2'000'000;
  p.valid = 1;
  p.x = 1.0;
  p.qw = 1.0;
  const auto out = convert(c, "ODOMETRY_POSE", p, p.utime);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].topic.topic, "/odometry_pose");
  EXPECT_EQ(out[0].topic.schema_name, "foxglove.PoseInFrame");
  const auto topics = fg::foxgloveTopicsFor("ODOMETRY_POSE", "ucon.robot_pose_t");
  ASSERT_EQ(topics.size(), 1u);
  EXPECT_EQ(topics[0].topic, "/odometry_pose");
}

TEST(FoxgloveView, GivenAMovingTrackWhenConvertedThenSectorIsEqs6And7AndEllipseIsTwoSigma) {
  const fg::ViewParams params = shippedParams();
  fg::FoxgloveConverter c(params);
  ucon::tracked_objects_t m{};
  m.utime = 10'000'000;
  m.valid = 1;
  m.frame_id = "world";
  m.num_objects = 1;
  m.objects.push_back(track(5, 1.0, 0.0, 0.04, 0.09));  // sigma_x 0.2 m, sigma_y 0.3 m
  json j;
  only(convert(c, "PERCEPTION_OBJECTS", m, m.utime), "/perception_objects", &j);
  EXPECT_EQ(j["deletions"][0]["type"], 1);  // ALL: tracks that vanished go away
  ASSERT_EQ(j["entities"].size(), 1u);
  const json& e = j["entities"][0];
  EXPECT_EQ(e["id"], "track_5");
  EXPECT_NEAR(e["cylinders"][0]["size"]["x"].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(e["texts"][0]["text"], "5");
  EXPECT_NEAR(e["arrows"][0]["shaft_length"].get<double>() + e["arrows"][0]["head_length"].get<double>(), 1.0, 1e-12);

  // Eq. 6: R = |v| h + k sqrt(v^T S v) + r/2 + s; eq. 7: theta/2 = atan(kappa sqrt(u^T S u) / (|v| h)).
  const auto& sp = params.optimizer.sector;
  const double R = 1.0 * sp.h + sp.k * 0.2 + 0.5 + params.optimizer.safe_distance;
  const double half = std::atan2(sp.kappa * 0.3, 1.0 * sp.h);
  const json& fan = e["triangles"][0];
  const json& pts = fan["points"];
  EXPECT_EQ(pts[0]["x"], 2.0);  // centre
  EXPECT_EQ(pts[0]["y"], 1.0);
  const std::size_t n = pts.size() - 1;
  ASSERT_GE(n, 3u);
  EXPECT_EQ(fan["indices"].size(), 3 * (n - 1));
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const double dx = pts[i]["x"].get<double>() - 2.0, dy = pts[i]["y"].get<double>() - 1.0;
    EXPECT_NEAR(std::hypot(dx, dy), R, 1e-9);
  }
  EXPECT_NEAR(std::atan2(pts[1]["y"].get<double>() - 1.0, pts[1]["x"].get<double>() - 2.0), -half, 1e-9);
  EXPECT_NEAR(std::atan2(pts[n]["y"].get<double>() - 1.0, pts[n]["x"].get<double>() - 2.0), half, 1e-9);

  // 2-sigma ellipse: extent 2 * 0.2 along x and 2 * 0.3 along y around the centre.
  double max_dx = 0, max_dy = 0;
  for (const auto& p : e["lines"][0]["points"]) {
    max_dx = std::max(max_dx, std::abs(p["x"].get<double>() - 2.0));
    max_dy = std::max(max_dy, std::abs(p["y"].get<double>() - 1.0));
  }
  EXPECT_NEAR(max_dx, 0.4, 1e-9);
  EXPECT_NEAR(max_dy, 0.6, 1e-9);
  EXPECT_EQ(e["lines"][0]["type"], 1);  // LINE_LOOP
}

TEST(FoxgloveView, GivenASlowTrackWhenConvertedThenTheSectorIsADisk) {
  const fg::ViewParams params = shippedParams();
  fg::FoxgloveConverter c(params);
  ucon::tracked_objects_t m{};
  m.utime = 10'000'000;
  m.valid = 1;
  m.num_objects = 1;
  m.objects.push_back(track(9, 0.01, 0.0, 0.04, 0.09));
  json j;
  only(convert(c, "PERCEPTION_OBJECTS", m, m.utime), "/perception_objects", &j);
  const json& pts = j["entities"][0]["triangles"][0]["points"];
  const std::size_t n = pts.size() - 1;
  // A disk: the arc closes on itself; radius r/2 + s + k sqrt(tr S).
  EXPECT_NEAR(pts[1]["x"].get<double>(), pts[n]["x"].get<double>(), 1e-9);
  EXPECT_NEAR(pts[1]["y"].get<double>(), pts[n]["y"].get<double>(), 1e-9);
  const double R = 0.5 + params.optimizer.safe_distance + params.optimizer.sector.k * std::sqrt(0.04 + 0.09);
  EXPECT_NEAR(std::hypot(pts[1]["x"].get<double>() - 2.0, pts[1]["y"].get<double>() - 1.0), R, 1e-9);
}

TEST(FoxgloveView, GivenBadInputsWhenConvertedThenTheyAreSkippedAndCounted) {
  fg::FoxgloveConverter c(shippedParams());
  ucon::tracked_objects_t m{};
  m.utime = 1'000'000;
  m.valid = 1;
  m.num_objects = 3;
  auto nan_pos = track(1, 1.0, 0.0, 0.04, 0.04);
  nan_pos.x = std::nan("");
  auto bad_cov = track(2, 1.0, 0.0, -1.0, 0.04);  // not positive definite
  auto deleted = track(3, 1.0, 0.0, 0.04, 0.04);
  deleted.state = ucon::tracked_object_t::STATE_DELETED;
  m.objects = {nan_pos, bad_cov, deleted};
  json j;
  only(convert(c, "PERCEPTION_OBJECTS", m, m.utime), "/perception_objects", &j);
  ASSERT_EQ(j["entities"].size(), 1u);
  EXPECT_EQ(j["entities"][0]["id"], "track_2");
  EXPECT_TRUE(j["entities"][0]["lines"].empty());
  EXPECT_EQ(j["entities"][0]["triangles"].size(), 1u);  // sector without the uncertainty terms
  EXPECT_EQ(c.stats().objects_skipped, 1);
  EXPECT_EQ(c.stats().ellipses_skipped, 1);
}

TEST(FoxgloveView, GivenATrajectoryWhenConvertedThenALineStripAlongIt) {
  fg::FoxgloveConverter c(shippedParams());
  ucon::trajectory_t t{};
  t.utime = 5'000'000;
  t.plan_id = 3;
  t.start_utime = 5'000'000;
  t.dim = 2;
  t.order1 = 6;
  t.num_pieces = 1;
  t.durations = {2.0};
  t.num_coeffs = 12;
  t.coeffs.assign(12, 0.0);
  t.coeffs[1] = 1.0;  // x = t
  t.coeffs[6] = 3.0;  // y = 3
  json j;
  only(convert(c, "PLANNER_TRAJECTORY", t, t.utime), "/planner_trajectory", &j);
  const json& line = j["entities"][0]["lines"][0];
  EXPECT_EQ(line["type"], 0);  // LINE_STRIP
  ASSERT_EQ(line["points"].size(), 41u);  // every 0.05 s over 2 s
  EXPECT_NEAR(line["points"][40]["x"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(line["points"][40]["y"].get<double>(), 3.0, 1e-12);
  t.num_pieces = 0;
  t.durations.clear();
  t.num_coeffs = 0;
  t.coeffs.clear();
  only(convert(c, "PLANNER_TRAJECTORY", t, t.utime), "/planner_trajectory", &j);
  EXPECT_TRUE(j["entities"].empty());
  EXPECT_EQ(j["deletions"].size(), 1u);
  EXPECT_EQ(c.stats().trajectories_invalid, 1);
}

TEST(FoxgloveView, GivenStaticPointsWhenConvertedThenTheMapGridCountsThoseInTheBand) {
  const fg::ViewParams params = shippedParams();
  fg::FoxgloveConverter c(params);
  ucon::static_points_t s{};
  s.utime = 1'000'000;
  s.valid = 1;
  s.num_points = 4;
  s.x = {0.05f, 0.06f, 0.35f, 0.05f};
  s.y = {0.05f, 0.07f, 0.15f, 0.05f};
  s.z = {0.3f, 0.3f, 0.3f, 2.0f};  // the last is above the band
  json j;
  auto out = convert(c, "PERCEPTION_STATIC", s, s.utime);
  only(out, "/perception_static", &j);
  EXPECT_EQ(base64Decode(j["data"]).size(), 4u * 12u);
  only(out, "/map", &j);
  EXPECT_EQ(j["column_count"], 4);  // cells x 0..3
  EXPECT_NEAR(j["cell_size"]["x"].get<double>(), params.map_resolution, 1e-12);
  const auto cells = base64Decode(j["data"]);
  ASSERT_EQ(cells.size(), 4u * 2u);  // 4 columns, rows y 0..1
  EXPECT_EQ(cells[0], 2);            // (0, 0): two points
  EXPECT_EQ(cells[4 + 3], 1);        // (3, 1)
  // Half a second later: no new map yet (period 1 s of message time), flushMap gives it now.
  s.utime = 1'500'000;
  out = convert(c, "PERCEPTION_STATIC", s, s.utime);
  EXPECT_EQ(out.size(), 1u);
  out.clear();
  c.flushMap(s.utime, true, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(base64Decode(json::parse(out[0].json)["data"])[0], 4);
  out.clear();
  c.flushMap(s.utime, true, &out);  // nothing changed since
  EXPECT_TRUE(out.empty());
}

TEST(FoxgloveView, GivenGroundTruthWhenConvertedThenTruthFrameObstaclesAndRobot) {
  fg::FoxgloveConverter c(shippedParams());
  ucon::sim_ground_truth_t g{};
  g.utime = 1'000'000;
  g.robot_x = 1.0;
  g.robot_yaw = 0.5;
  g.robot_radius = 0.3;
  g.collision = 1;
  g.num_objects = 1;
  ucon::sim_object_t o{};
  o.id = 4;
  o.x = 3.0;
  o.radius = 0.25;
  o.height = 1.8;
  o.vx = 1.0;
  g.objects.push_back(o);
  json j;
  auto out = convert(c, "SIM_GROUND_TRUTH", g, g.utime);
  only(out, "/tf", &j);
  EXPECT_EQ(j["child_frame_id"], "base_truth");
  only(out, "/sim_ground_truth/objects", &j);
  ASSERT_EQ(j["entities"].size(), 2u);
  EXPECT_EQ(j["entities"][0]["id"], "truth_4");
  EXPECT_NEAR(j["entities"][0]["cylinders"][0]["size"]["x"].get<double>(), 0.5, 1e-12);
  EXPECT_EQ(j["entities"][1]["id"], "robot_truth");
  EXPECT_EQ(j["entities"][1]["cylinders"][0]["color"]["r"], 1.0);  // red during a collision
}
