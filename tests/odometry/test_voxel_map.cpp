// The incremental voxel map: nearest neighbours against brute force, the spacing and
// per-voxel bounds, the LRU and distance bounds, determinism; voxel downsampling; scan-to-map
// registration on a synthetic scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "ucon/lio/registration.hpp"
#include "ucon/lio/so3.hpp"
#include "ucon/lio/voxel_map.hpp"
#include "ucon/world/rng.hpp"

using namespace ucon::lio;

namespace {

std::vector<Eigen::Vector3f> randomCloud(int n, double extent, uint64_t seed) {
  ucon::world::Rng rng(seed);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < n; ++i)
    pts.emplace_back(static_cast<float>(rng.uniform(-extent, extent)), static_cast<float>(rng.uniform(-extent, extent)),
                     static_cast<float>(rng.uniform(-extent, extent)));
  return pts;
}

// Points on the floor and four walls of a 10 x 8 x 3 m room, plus two boxes, every `step` m.
std::vector<Eigen::Vector3f> roomCloud(double step) {
  std::vector<Eigen::Vector3f> pts;
  for (double x = -5; x <= 5; x += step)
    for (double y = -4; y <= 4; y += step) pts.emplace_back(x, y, 0.0);
  for (double s = -5; s <= 5; s += step)
    for (double z = 0; z <= 3; z += step) {
      pts.emplace_back(s, -4.0, z);
      pts.emplace_back(s, 4.0, z);
    }
  for (double s = -4; s <= 4; s += step)
    for (double z = 0; z <= 3; z += step) {
      pts.emplace_back(-5.0, s, z);
      pts.emplace_back(5.0, s, z);
    }
  for (double a = 0; a <= 1; a += step)
    for (double z = 0; z <= 1; z += step) {
      pts.emplace_back(1.0 + a, 1.0, z);
      pts.emplace_back(1.0, 1.0 + a, z);
      pts.emplace_back(-2.0 + 0.7 * a, -1.5 + 0.7 * a, z);
    }
  return pts;
}

}  // namespace

TEST(VoxelMap, GivenPointsWhenQueriedThenTheNearestEqualBruteForceWithinTheSearchedVoxels) {
  VoxelMapParams p;
  p.voxel_size = 0.5;
  p.max_points_per_voxel = 64;
  p.min_point_spacing = 0.0;
  p.neighbourhood = Neighbourhood::kAll;
  VoxelMap map(p);
  const auto pts = randomCloud(3000, 3.0, 1);
  EXPECT_EQ(map.insert(pts), pts.size());
  EXPECT_EQ(map.numPoints(), pts.size());
  const auto queries = randomCloud(200, 3.0, 2);
  Neighbours nb;
  for (const auto& q : queries) {
    // Within 0.5 m (one voxel) the 3x3x3 block holds every candidate: exact kNN.
    map.nearest(q, 5, 0.5f, &nb);
    std::vector<float> d2;
    for (const auto& p3 : pts) {
      const float d = (p3 - q).squaredNorm();
      if (d < 0.25f) d2.push_back(d);
    }
    std::sort(d2.begin(), d2.end());
    ASSERT_EQ(nb.count, static_cast<int>(std::min<std::size_t>(5, d2.size())));
    for (int i = 0; i < nb.count; ++i) EXPECT_FLOAT_EQ(nb.dist2[i], d2[static_cast<std::size_t>(i)]);
  }
}

// The store grows by chunks of slots: thousands of voxels, half of them dropped and their
// slots reused by new ones, and every stored point must still be found where it was put.
TEST(VoxelMap, GivenThousandsOfVoxelsDroppedAndReusedThenEveryPointIsFoundWhereItWasPut) {
  VoxelMapParams p;
  p.voxel_size = 1.0;
  p.max_points_per_voxel = 4;
  p.min_point_spacing = 0.0;
  p.radius = 30.0;
  VoxelMap map(p);
  // A 60 x 50 grid of voxels (3 000, more than ten chunks), two points in each.
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 50; ++j) {
      pts.emplace_back(static_cast<float>(i) + 0.25f, static_cast<float>(j) + 0.25f, 0.5f);
      pts.emplace_back(static_cast<float>(i) + 0.75f, static_cast<float>(j) + 0.5f, 0.25f);
    }
  ASSERT_EQ(map.insert(pts), pts.size());
  ASSERT_EQ(map.numVoxels(), 3000u);
  // Keep what lies within 30 m of (0, 0): about a quarter circle; the rest frees its slots.
  const std::size_t dropped = map.removeFar(Eigen::Vector3d(0.0, 0.0, 0.0));
  ASSERT_GT(dropped, 1000u);
  std::vector<Eigen::Vector3f> kept;
  for (const auto& q : pts)
    if (Eigen::Vector2f(std::floor(q.x()) + 0.5f, std::floor(q.y()) + 0.5f).norm() <= 30.0f) kept.push_back(q);
  // New voxels elsewhere take the freed slots (and new chunks once those run out).
  std::vector<Eigen::Vector3f> fresh;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 40; ++j) fresh.emplace_back(-static_cast<float>(i) - 0.5f, static_cast<float>(j) + 0.5f, 3.5f);
  ASSERT_EQ(map.insert(fresh), fresh.size());
  kept.insert(kept.end(), fresh.begin(), fresh.end());
  EXPECT_EQ(map.numPoints(), kept.size());
  EXPECT_EQ(map.numVoxels(), 3000u - dropped + fresh.size());
  Neighbours nb;
  for (const auto& q : kept) {
    ASSERT_EQ(map.nearest(q, 1, 0.01f, &nb), 1) << q.transpose();
    EXPECT_EQ(nb.points[0], q);
  }
  auto sorted = [](std::vector<Eigen::Vector3f> v) {
    std::sort(v.begin(), v.end(), [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
      return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
    });
    return v;
  };
  EXPECT_EQ(sorted(map.points()), sorted(kept));
}

TEST(VoxelMap, GivenSpacingAndCapacityThenCloseAndSurplusPointsAreDropped) {
  VoxelMapParams p;
  p.voxel_size = 1.0;
  p.max_points_per_voxel = 3;
  p.min_point_spacing = 0.1;
  VoxelMap map(p);
  EXPECT_TRUE(map.insert(Eigen::Vector3f(0.5f, 0.5f, 0.5f)));
  EXPECT_FALSE(map.insert(Eigen::Vector3f(0.55f, 0.5f, 0.5f)));  // 5 cm from a kept point
  EXPECT_TRUE(map.insert(Eigen::Vector3f(0.7f, 0.5f, 0.5f)));
  EXPECT_TRUE(map.insert(Eigen::Vector3f(0.9f, 0.5f, 0.5f)));
  EXPECT_FALSE(map.insert(Eigen::Vector3f(0.1f, 0.1f, 0.1f)));   // voxel full
  EXPECT_FALSE(map.insert(Eigen::Vector3f(NAN, 0.0f, 0.0f)));
  EXPECT_EQ(map.numPoints(), 3u);
  EXPECT_EQ(map.numVoxels(), 1u);
}

TEST(VoxelMap, GivenBoundsThenTheLeastRecentVoxelsAndTheFarOnesGo) {
  VoxelMapParams p;
  p.voxel_size = 1.0;
  p.max_voxels = 10;
  p.radius = 5.0;
  VoxelMap map(p);
  for (int i = 0; i < 20; ++i) map.insert(Eigen::Vector3f(static_cast<float>(i) + 0.5f, 0.5f, 0.5f));
  EXPECT_EQ(map.numVoxels(), 10u);
  Neighbours nb;
  EXPECT_EQ(map.nearest(Eigen::Vector3f(0.5f, 0.5f, 0.5f), 1, 0.5f, &nb), 0);   // evicted (oldest)
  EXPECT_EQ(map.nearest(Eigen::Vector3f(19.5f, 0.5f, 0.5f), 1, 0.5f, &nb), 1);  // newest kept
  // Voxels 10..19 remain; within 5 m of x = 17: centres 12.5 .. 19.5 (8 voxels).
  EXPECT_EQ(map.removeFar(Eigen::Vector3d(17.0, 0.5, 0.5)), 2u);
  EXPECT_EQ(map.numVoxels(), 8u);
  // Freed slots are reused.
  map.insert(Eigen::Vector3f(30.5f, 0.5f, 0.5f));
  EXPECT_EQ(map.numVoxels(), 9u);
  EXPECT_EQ(map.points().front(), Eigen::Vector3f(30.5f, 0.5f, 0.5f));
}

namespace {
// A scan from a sensor at the origin, 0.4 m above a floor (z = -0.4), of a wall at x = 6
// (|y| < 4, z up to 2 m) and of the floor between: points in the sensor frame, one per 0.5 deg
// of azimuth and elevation where a ray meets the wall or the floor within 8 m.
std::vector<Eigen::Vector3f> roomScan() {
  std::vector<Eigen::Vector3f> out;
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  for (double az = -60.0; az <= 60.0; az += 0.5)
    for (double el = -30.0; el <= 50.0; el += 0.5) {
      const Eigen::Vector3d dir(std::cos(el * kDeg) * std::cos(az * kDeg), std::cos(el * kDeg) * std::sin(az * kDeg),
                                std::sin(el * kDeg));
      double t = 6.0 / dir.x();  // the wall
      if (dir.z() < 0.0) t = std::min(t, -0.4 / dir.z());  // the floor
      const Eigen::Vector3d p = t * dir;
      if (t > 8.0 || std::fabs(p.y()) > 4.0 || p.z() > 2.0) continue;
      out.push_back(p.cast<float>());
    }
  return out;
}
}  // namespace

TEST(VoxelMap, GivenAScanThatSeesThroughAVoxelThenItIsCarvedAfterTheMissesUnlessTouched) {
  VoxelMapParams prm;  // the shipped carve parameters are the defaults
  prm.carve_misses = 3;
  VoxelMap map(prm);
  const std::vector<Eigen::Vector3f> scan = roomScan();
  map.insert(scan);  // the wall and the floor (sensor at the world origin, no rotation)
  const std::size_t room_voxels = map.numVoxels();
  // A person's trace between the sensor and the wall, and a box behind the wall.
  const Eigen::Vector3f ghost(3.0f, 0.2f, 0.6f), hidden(7.0f, 0.2f, 0.6f);
  ASSERT_TRUE(map.insert(ghost));
  ASSERT_TRUE(map.insert(hidden));
  Neighbours nb;
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  // Two carves see through the trace; a point falling into its voxel resets the count.
  EXPECT_EQ(map.carve(Eigen::Vector3d::Zero(), R, scan), 0u);
  EXPECT_EQ(map.carve(Eigen::Vector3d::Zero(), R, scan), 0u);
  map.insert(Eigen::Vector3f(3.05f, 0.25f, 0.65f));
  EXPECT_EQ(map.carve(Eigen::Vector3d::Zero(), R, scan), 0u);
  EXPECT_EQ(map.carve(Eigen::Vector3d::Zero(), R, scan), 0u);
  EXPECT_EQ(map.nearest(ghost, 1, 0.1f, &nb), 1);
  // The third miss in a row drops it; the wall, the floor and what the wall hides stay.
  EXPECT_EQ(map.carve(Eigen::Vector3d::Zero(), R, scan), 1u);
  EXPECT_EQ(map.nearest(ghost, 1, 0.3f, &nb), 0);
  EXPECT_EQ(map.nearest(hidden, 1, 0.01f, &nb), 1);
  EXPECT_EQ(map.numVoxels(), room_voxels + 1);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(map.carve(Eigen::Vector3d::Zero(), R, scan), 0u) << k;
  EXPECT_EQ(map.numVoxels(), room_voxels + 1);
}

TEST(VoxelMap, GivenTheSensorMovedAndTurnedThenCarvingUsesItsPose) {
  // The same room seen from a sensor at (1, 2, 0) turned 90 deg: the scan, in the sensor frame,
  // is the room rotated; the trace is still carved and nothing of the room goes.
  VoxelMapParams prm;
  prm.carve_misses = 1;
  VoxelMap map(prm);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 2.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d origin(1.0, 2.0, 0.0);
  const std::vector<Eigen::Vector3f> scan = roomScan();  // sensor frame
  for (const auto& p : scan) map.insert((R * p.cast<double>() + origin).cast<float>());
  const std::size_t room_voxels = map.numVoxels();
  const Eigen::Vector3f ghost = (R * Eigen::Vector3d(3.0, 0.2, 0.6) + origin).cast<float>();
  ASSERT_TRUE(map.insert(ghost));
  EXPECT_EQ(map.carve(origin, R, scan), 1u);
  EXPECT_EQ(map.numVoxels(), room_voxels);
  EXPECT_EQ(map.carve(origin, R, scan), 0u);  // nothing else is seen through
}

TEST(VoxelMap, GivenTheSameInsertionsThenTheSameAnswers) {
  VoxelMapParams p;
  const auto pts = randomCloud(5000, 4.0, 3);
  VoxelMap a(p), b(p);
  a.insert(pts);
  b.insert(pts);
  a.removeFar(Eigen::Vector3d(1, 1, 1));
  b.removeFar(Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(a.points(), b.points());
  Neighbours na, nb;
  for (const auto& q : randomCloud(100, 4.0, 4)) {
    a.nearest(q, 5, 1.0f, &na);
    b.nearest(q, 5, 1.0f, &nb);
    ASSERT_EQ(na.count, nb.count);
    for (int i = 0; i < na.count; ++i) EXPECT_EQ(na.points[i], nb.points[i]);
  }
}

TEST(VoxelDownsample, GivenACloudThenOnePointPerCellInInputOrder) {
  const std::vector<Eigen::Vector3f> pts = {{0.1f, 0.1f, 0.1f}, {0.2f, 0.1f, 0.1f}, {1.1f, 0.1f, 0.1f},
                                            {0.15f, 0.1f, 0.1f}, {-0.1f, 0.1f, 0.1f}};
  const auto idx = voxelDownsampleIndices(pts, 0.5);
  EXPECT_EQ(idx, (std::vector<int>{0, 2, 4}));
  EXPECT_EQ(voxelDownsample(pts, 0.0).size(), pts.size());
}

// Against a plain reference (std::floor, std::set) on a cloud with negative coordinates, points
// exactly on cell faces, duplicates and non-finite points: the same points, in input order.
TEST(VoxelDownsample, GivenALargeCloudThenTheSameIndicesAsAPlainReference) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-30.0f, 30.0f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 20000; ++i) pts.emplace_back(u(rng), u(rng), 0.1f * u(rng));
  for (int i = -8; i <= 8; ++i) pts.emplace_back(0.3f * static_cast<float>(i), -0.3f * static_cast<float>(i), -0.6f);
  pts.emplace_back(std::nanf(""), 0.0f, 0.0f);
  pts.push_back(pts[5]);
  for (const double voxel : {0.3, 0.5, 1.0}) {
    std::set<std::tuple<int64_t, int64_t, int64_t>> seen;
    std::vector<int> ref;
    const float inv = static_cast<float>(1.0 / voxel);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3f& p = pts[i];
      if (!p.allFinite()) continue;
      const auto key = std::make_tuple(static_cast<int64_t>(std::floor(p.x() * inv)),
                                       static_cast<int64_t>(std::floor(p.y() * inv)),
                                       static_cast<int64_t>(std::floor(p.z() * inv)));
      if (seen.insert(key).second) ref.push_back(static_cast<int>(i));
    }
    EXPECT_EQ(voxelDownsampleIndices(pts, voxel), ref) << voxel;
  }
}

TEST(Registration, GivenARoomScanOffsetBy30cmAnd5DegThenItIsAlignedToTheMillimetre) {
  VoxelMapParams mp;
  mp.voxel_size = 0.5;
  VoxelMap map(mp);
  map.insert(roomCloud(0.05));
  Eigen::Isometry3d T_true = Eigen::Isometry3d::Identity();
  T_true.linear() = expSO3(Eigen::Vector3d(0.01, -0.02, 5.0 * M_PI / 180.0));
  T_true.translation() = Eigen::Vector3d(0.3, -0.2, 0.05);
  // The scan: room points seen from T_true (in the scan frame), downsampled.
  std::vector<Eigen::Vector3f> scan;
  for (const auto& p : voxelDownsample(roomCloud(0.07), 0.25))
    scan.push_back((T_true.inverse() * p.cast<double>()).cast<float>());
  RegistrationParams rp;
  rp.max_iterations = 30;
  const auto r = registerPointToPlane(map, scan, Eigen::Isometry3d::Identity(), rp);
  EXPECT_NEAR((r.T.translation() - T_true.translation()).norm(), 0.0, 2e-3);
  EXPECT_NEAR(logSO3(r.T.linear().transpose() * T_true.linear()).norm(), 0.0, 1e-3);
  EXPECT_GT(r.correspondences, static_cast<int>(scan.size()) / 2);
}
