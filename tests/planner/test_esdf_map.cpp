// The planner's map: ESDF slice against brute force on random maps, incremental update equal
// to a fresh build, ray insertion clears free space, interpolation and its gradient.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "ucon/planner/esdf_map.hpp"
#include "ucon/static_points_t.hpp"

using ucon::planner::EsdfMap;
using ucon::planner::MapParams;

namespace {

MapParams smallParams() {
  MapParams p;
  p.resolution = 0.1;
  p.band_z_min = 0.1;
  p.band_z_max = 0.4;
  p.box_half_size = 4.0;
  p.recenter_distance = 1.0;
  p.max_distance = 1.5;
  return p;
}

/// A scan of n returns around `origin`: per return, the azimuth from `ang`, the range from
/// `dist` (times `shrink`) and the height from `height`, drawn in that order.
std::vector<Eigen::Vector3f> ringScan(const Eigen::Vector3d& origin, int n, float shrink, std::mt19937& rng,
                                      std::uniform_real_distribution<double>& ang,
                                      std::uniform_real_distribution<double>& dist,
                                      std::uniform_real_distribution<double>& height) {
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < n; ++i) {
    const double a = ang(rng), r = dist(rng);
    pts.emplace_back(float(origin.x() + shrink * r * std::cos(a)), float(origin.y() + shrink * r * std::sin(a)),
                     float(height(rng)));
  }
  return pts;
}

using Cell = std::pair<int, int>;  // integer cell indices in x, y (world / resolution, floored)

Eigen::Vector2d centreOf(const Cell& c, double res) {
  return Eigen::Vector2d((c.first + 0.5) * res, (c.second + 0.5) * res);
}

void occupy(EsdfMap& m, const Cell& c, bool occ) {
  const double res = m.params().resolution;
  const Eigen::Vector2d xy = centreOf(c, res);
  m.setCell(Eigen::Vector3d(xy.x(), xy.y(), 0.25), occ);
}

std::set<Cell> randomCells(std::mt19937& rng, int n, int lo, int hi) {
  std::uniform_int_distribution<int> u(lo, hi);
  std::set<Cell> cells;
  while (int(cells.size()) < n) cells.insert({u(rng), u(rng)});
  return cells;
}

/// Brute-force expected slice value at a free cell centre q: distance to the nearest occupied
/// cell centre minus half a cell, capped.
double bruteForce(const std::set<Cell>& occ, const Eigen::Vector2d& q, double res, double cap) {
  double best = 1e9;
  for (const auto& c : occ) best = std::min(best, (centreOf(c, res) - q).norm());
  return std::min(cap, best - 0.5 * res);
}

}  // namespace

TEST(EsdfMap, GivenRandomOccupiedCellsWhenUpdatedThenSliceDistancesMatchBruteForce) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 rng(seed);
    EsdfMap map(smallParams());
    const auto occ = randomCells(rng, 40, -30, 29);
    for (const auto& c : occ) occupy(map, c, true);
    map.update(Eigen::Vector2d(0.0, 0.0));
    const auto& s = map.slice();
    ASSERT_GT(s.nx, 70);
    ASSERT_GT(s.ny, 70);
    double max_err = 0.0;
    int free_cells = 0, occupied_cells = 0;
    for (int iy = 0; iy < s.ny; ++iy) {
      for (int ix = 0; ix < s.nx; ++ix) {
        const Eigen::Vector2d q = s.cellCenter(ix, iy);
        const Cell c{int(std::floor(q.x() / 0.1 + 1e-6)), int(std::floor(q.y() / 0.1 + 1e-6))};
        const double got = map.cellDistance(ix, iy);
        if (occ.count(c)) {
          EXPECT_LT(got, 0.0) << "occupied cell reads as free at " << q.transpose();
          ++occupied_cells;
          continue;
        }
        ++free_cells;
        // Obstacles outside the box are not seen by the ESDF: only compare where the brute
        // force's nearest obstacle is inside the box.
        const double want = bruteForce(occ, q, 0.1, map.params().max_distance);
        max_err = std::max(max_err, std::abs(got - want));
      }
    }
    EXPECT_EQ(occupied_cells, int(occ.size()));
    EXPECT_GT(free_cells, 1000);
    EXPECT_LT(max_err, 1e-4) << "seed " << seed;
  }
}

TEST(EsdfMap, GivenInsertionsAndClearingsWhenUpdatedIncrementallyThenSliceEqualsAFreshBuild) {
  std::mt19937 rng(7);
  const MapParams p = smallParams();
  EsdfMap incremental(p);
  auto first = randomCells(rng, 60, -35, 34);
  for (const auto& c : first) occupy(incremental, c, true);
  incremental.update(Eigen::Vector2d(0.2, -0.1));
  // Clear half of them, add new ones, update incrementally (box does not move).
  std::set<Cell> final_cells;
  int k = 0;
  for (const auto& c : first) {
    if (k++ % 2 == 0) {
      occupy(incremental, c, false);
    } else {
      final_cells.insert(c);
    }
  }
  for (const auto& c : randomCells(rng, 30, -35, 34)) {
    occupy(incremental, c, true);
    final_cells.insert(c);
  }
  const bool rebuilt = incremental.update(Eigen::Vector2d(0.3, 0.0));
  EXPECT_FALSE(rebuilt);
  EXPECT_EQ(incremental.incrementalUpdates(), 1);

  EsdfMap fresh(p);
  for (const auto& c : final_cells) occupy(fresh, c, true);
  fresh.update(Eigen::Vector2d(0.2, -0.1));
  const auto& a = incremental.slice();
  const auto& b = fresh.slice();
  ASSERT_EQ(a.nx, b.nx);
  ASSERT_EQ(a.ny, b.ny);
  ASSERT_NEAR(a.origin.x(), b.origin.x(), 1e-9);
  ASSERT_NEAR(a.origin.y(), b.origin.y(), 1e-9);
  int differing = 0;
  for (int iy = 0; iy < a.ny; ++iy)
    for (int ix = 0; ix < a.nx; ++ix)
      if (std::abs(incremental.cellDistance(ix, iy) - fresh.cellDistance(ix, iy)) > 1e-4) ++differing;
  EXPECT_EQ(differing, 0);
}

TEST(EsdfMap, GivenManyIncrementalUpdatesThenTheSliceKeptNearChangesEqualsAFullRecomputation) {
  // The slice is recomputed only within max_distance (+ margin) of projection cells that
  // changed; every other cell must already hold what a full pass over the distance transform
  // gives, bit for bit, also inside obstacles and near the box edge. Scans, single-cell writes,
  // cleared discs and blocks of obstacles, with the robot moving inside the box.
  MapParams p = smallParams();
  p.recenter_distance = 3.0;
  EsdfMap m(p);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), height(0.12, 0.45), dist(0.5, 3.9);
  std::uniform_int_distribution<int> cell(-42, 41);
  int incremental = 0, occupied_max = 0;
  for (int step = 0; step < 60; ++step) {
    const Eigen::Vector3d origin(0.03 * (step % 7), -0.02 * (step % 5), 0.25);
    const float shrink = step % 10 < 5 ? 1.0f : 0.7f;
    const std::vector<Eigen::Vector3f> pts = ringScan(origin, 200, shrink, rng, ang, dist, height);
    ASSERT_EQ(m.insert(origin, pts, 4.5), ucon::planner::InsertStatus::kOk);
    if (step % 3 == 0)
      for (int k = 0; k < 15; ++k) occupy(m, {cell(rng), cell(rng)}, k % 3 != 0);
    if (step % 5 == 2) m.addBox(-3.9, 2.5, -2.8, 3.9);   // a block at the box edge, then cleared
    if (step % 5 == 4) m.addCylinder(-3.3, 3.2, 0.7, false);
    if (step % 7 == 3) m.addCylinder(0.5, 0.5, 0.6, false);
    const bool rebuilt = m.update(Eigen::Vector2d(0.01 * step, -0.005 * step));
    incremental += rebuilt ? 0 : 1;
    ASSERT_EQ(m.sliceMismatches(), 0u) << "step " << step;
    int occupied = 0;
    for (int iy = 0; iy < m.slice().ny; ++iy)
      for (int ix = 0; ix < m.slice().nx; ++ix) occupied += m.cellDistance(ix, iy) <= 0.0 ? 1 : 0;
    occupied_max = std::max(occupied_max, occupied);
  }
  EXPECT_GT(incremental, 50);     // the incremental path ran
  EXPECT_GT(occupied_max, 100);   // with real obstacles in the slice
}

TEST(EsdfMap, GivenTheRobotMovesFarWhenUpdatedThenTheBoxIsRebuiltAroundIt) {
  EsdfMap map(smallParams());
  occupy(map, {60, 0}, true);  // at x = 6.05, outside the first box
  map.update(Eigen::Vector2d(0, 0));
  EXPECT_NEAR(map.distance(5.0, 0.05, nullptr), map.params().max_distance, 1e-9);  // outside
  EXPECT_TRUE(map.update(Eigen::Vector2d(5.0, 0.0)));
  EXPECT_EQ(map.rebuilds(), 2);
  EXPECT_NEAR(map.distance(5.05, 0.05, nullptr), 1.0 - 0.05, 1e-4);
}

TEST(EsdfMap, GivenRaysThroughAnOldObstacleWhenInsertedRepeatedlyThenItIsClearedAndEndpointsOccupied) {
  MapParams p = smallParams();
  EsdfMap map(p);
  const Eigen::Vector3d origin(0.0, 0.0, 0.25);
  // A wall of points at x = 2.
  std::vector<Eigen::Vector3f> wall;
  for (double y = -0.5; y <= 0.5; y += 0.05) wall.emplace_back(2.05f, float(y), 0.25f);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(map.insert(origin, wall, 10.0), ucon::planner::InsertStatus::kOk);
  EXPECT_TRUE(map.isOccupied(Eigen::Vector3d(2.05, 0.0, 0.25)));
  EXPECT_FALSE(map.isOccupied(Eigen::Vector3d(1.0, 0.0, 0.25)));
  map.update(Eigen::Vector2d(0, 0));
  EXPECT_LT(map.distance(2.05, 0.05, nullptr), 0.0);
  EXPECT_NEAR(map.distance(1.05, 0.05, nullptr), 0.95, 1e-3);
  // The wall moves back to x = 3: rays now pass through x = 2 and clear it.
  std::vector<Eigen::Vector3f> far_wall;  // wider, so its rays sweep the whole old wall
  for (double y = -0.8; y <= 0.8; y += 0.05) far_wall.emplace_back(3.05f, float(y), 0.25f);
  for (int i = 0; i < 10; ++i) map.insert(origin, far_wall, 10.0);
  EXPECT_FALSE(map.isOccupied(Eigen::Vector3d(2.05, 0.0, 0.25)));
  EXPECT_TRUE(map.isOccupied(Eigen::Vector3d(3.05, 0.0, 0.25)));
  map.update(Eigen::Vector2d(0, 0));
  EXPECT_NEAR(map.distance(2.05, 0.05, nullptr), 0.95, 1e-3);
  // Points beyond the maximum range only clear; nothing becomes occupied there.
  std::vector<Eigen::Vector3f> beyond{Eigen::Vector3f(0.05f, 3.05f, 0.25f)};
  map.insert(origin, beyond, 2.0);
  EXPECT_FALSE(map.isOccupied(Eigen::Vector3d(0.05, 3.05, 0.25)));
}

TEST(EsdfMap, GivenRandomScansWhenInsertedBandOnlyThenTheSliceEqualsAFullInsertion) {
  // band_only traces each ray only while it is in the height band: the band's cells, and so
  // the slice, must come out exactly as with OctoMap's full insertion, including free space
  // cleared by rays to returns far above the band and returns beyond the maximum range.
  MapParams full = smallParams();
  full.band_only = false;
  MapParams band = full;
  band.band_only = true;
  EsdfMap a(full), b(band);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), elev(-0.3, 0.9), dist(0.5, 6.0);
  for (int scan = 0; scan < 12; ++scan) {
    // The last scans come from above the band (every ray enters it from outside).
    const Eigen::Vector3d origin(0.3 * scan / 12.0, -0.2 + 0.03 * scan, scan < 10 ? 0.25 : 1.0);
    std::vector<Eigen::Vector3f> pts;
    for (int i = 0; i < 400; ++i) {
      const double az = ang(rng), el = elev(rng), r = dist(rng);
      pts.emplace_back(float(origin.x() + r * std::cos(el) * std::cos(az)),
                       float(origin.y() + r * std::cos(el) * std::sin(az)), float(origin.z() + r * std::sin(el)));
    }
    // Scans alternate between two "worlds" so that cells get both hits and misses.
    if (scan % 2) for (auto& q : pts) q.head<2>() *= 0.7f;
    ASSERT_EQ(a.insert(origin, pts, 4.0), ucon::planner::InsertStatus::kOk);
    ASSERT_EQ(b.insert(origin, pts, 4.0), ucon::planner::InsertStatus::kOk);
  }
  a.update(Eigen::Vector2d(0, 0));
  b.update(Eigen::Vector2d(0, 0));
  const auto& sa = a.slice();
  const auto& sb = b.slice();
  ASSERT_EQ(sa.nx, sb.nx);
  ASSERT_EQ(sa.ny, sb.ny);
  int occupied = 0, free_near = 0;
  for (int iy = 0; iy < sa.ny; ++iy)
    for (int ix = 0; ix < sa.nx; ++ix) {
      ASSERT_EQ(a.cellDistance(ix, iy), b.cellDistance(ix, iy)) << "cell " << ix << "," << iy;
      occupied += a.cellDistance(ix, iy) <= 0.0;
      free_near += a.cellDistance(ix, iy) > 0.0 && a.cellDistance(ix, iy) < 1.0;
    }
  EXPECT_GT(occupied, 50);   // the comparison covers real obstacles ...
  EXPECT_GT(free_near, 50);  // ... and distances
}

TEST(EsdfMap, GivenLongSequencesOfScansAndCellWritesThenEveryBandCellEqualsAFullInsertion) {
  // The band-only insertion skips hits and misses on leaves already at a clamping bound (a
  // cache of such leaves); full insertion does not. Many scans drive leaves to both bounds
  // and back, and direct cell writes in between must keep the cache honest. Every return lies
  // inside the band's slab and range, so both insertions trace the very same rays (clipped
  // rays may differ in a last cell by float rounding) and must agree leaf for leaf.
  MapParams full = smallParams();
  full.band_only = false;
  MapParams band = full;
  band.band_only = true;
  EsdfMap a(full), b(band);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), height(0.02, 0.5), dist(0.5, 3.0);
  std::uniform_int_distribution<int> cell(-30, 30);
  const auto compare = [&](int scan, int* occupied_out) {
    int occupied = 0;
    for (int ix = -35; ix <= 35; ++ix)
      for (int iy = -35; iy <= 35; ++iy)
        for (double z : {0.15, 0.25, 0.35}) {
          const Eigen::Vector3d q((ix + 0.5) * 0.1, (iy + 0.5) * 0.1, z);
          ASSERT_EQ(a.isOccupied(q), b.isOccupied(q)) << "scan " << scan << " at " << q.transpose();
          occupied += a.isOccupied(q);
        }
    *occupied_out = occupied;
  };
  int occupied_seen = 0;
  for (int scan = 0; scan < 40; ++scan) {
    const Eigen::Vector3d origin(0.02 * (scan % 5), -0.03 * (scan % 3), 0.25);
    // Three "worlds" in turn: cells are hit several times, then seen through, then hit again.
    const float shrink = scan % 12 < 6 ? 1.0f : (scan % 12 < 9 ? 0.6f : 1.3f);
    const std::vector<Eigen::Vector3f> pts = ringScan(origin, 300, shrink, rng, ang, dist, height);
    ASSERT_EQ(a.insert(origin, pts, 4.0), ucon::planner::InsertStatus::kOk);
    ASSERT_EQ(b.insert(origin, pts, 4.0), ucon::planner::InsertStatus::kOk);
    if (scan % 4 == 1) {  // direct writes: single cells and a cleared disc
      for (int k = 0; k < 20; ++k) {
        const Eigen::Vector3d q((cell(rng) + 0.5) * 0.1, (cell(rng) + 0.5) * 0.1, 0.25);
        const bool occ = k % 2 == 0;
        a.setCell(q, occ);
        b.setCell(q, occ);
      }
      a.addCylinder(0.8, -0.4, 0.5, false);
      b.addCylinder(0.8, -0.4, 0.5, false);
    }
    if (scan % 7 == 3) {  // pruning deletes leaves the band-only map holds the addresses of
      a.pruneTree();
      b.pruneTree();
    }
    int occ = 0;
    compare(scan, &occ);
    if (HasFatalFailure()) return;
    occupied_seen = std::max(occupied_seen, occ);
  }
  EXPECT_GT(occupied_seen, 200);  // the comparison covered real obstacles
  a.update(Eigen::Vector2d(0, 0));
  b.update(Eigen::Vector2d(0, 0));
  for (int iy = 0; iy < a.slice().ny; ++iy)
    for (int ix = 0; ix < a.slice().nx; ++ix) ASSERT_EQ(a.cellDistance(ix, iy), b.cellDistance(ix, iy));
}

TEST(EsdfMap, GivenRandomRaysThenTheInsertionTraversesExactlyTheCellsOfOctomapsComputeRayKeys) {
  // The band-only insertion walks each ray with its own copy of OctoMap's DDA (no key list
  // stored); it must list the very same cells, including rays along axes, through cell
  // corners and edges, and of zero length.
  EsdfMap m(smallParams());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> coord(-12.0f, 12.0f), z(-0.5f, 2.0f);
  std::uniform_int_distribution<int> grid(-120, 120), kind(0, 5);
  std::size_t total = 0;
  for (int i = 0; i < 20000; ++i) {
    Eigen::Vector3f o(coord(rng) * 0.1f, coord(rng) * 0.1f, 0.3f + 0.1f * z(rng));
    Eigen::Vector3f e(coord(rng), coord(rng), z(rng));
    switch (kind(rng)) {
      case 0: e.y() = o.y(); break;                                   // along x
      case 1: e.x() = o.x(), e.z() = o.z(); break;                    // along y
      case 2: e = Eigen::Vector3f(grid(rng), grid(rng), 3) * 0.1f; break;  // to a cell corner
      case 3: o = Eigen::Vector3f(0.05f, 0.05f, 0.25f); break;        // from a cell centre
      case 4: e = o; break;                                           // zero length
      default: break;
    }
    std::size_t cells = 0;
    ASSERT_TRUE(m.rayKeysMatchOctomap(o, e, &cells)) << "ray " << o.transpose() << " -> " << e.transpose();
    total += cells;
  }
  EXPECT_GT(total, std::size_t(20000) * 30);  // long rays, not just trivial ones
  std::size_t cells = 1;
  EXPECT_TRUE(m.rayKeysMatchOctomap(Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1e7f, 0, 0), &cells));
  EXPECT_EQ(cells, 0u) << "an end outside the tree: nothing visited, as OctoMap";
}

TEST(EsdfMap, GivenManyScansOfFreeSpaceWhenInsertedLazilyThenTheTreeIsPrunedNowAndThen) {
  // The band-only insertion updates leaves without re-deriving or pruning their parents;
  // scans that clear a wide free area leave many subtrees whose leaves all agree. The map
  // prunes them whenever its tree has grown by half, so its memory stays bounded.
  MapParams p = smallParams();
  p.band_only = true;
  EsdfMap m(p);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), height(-0.3, 0.8), dist(5.0, 6.0);
  for (int scan = 0; scan < 60; ++scan) {
    const Eigen::Vector3d origin(0.1 * scan, 0.0, 0.25);
    const std::vector<Eigen::Vector3f> pts = ringScan(origin, 1500, 1.0f, rng, ang, dist, height);
    ASSERT_EQ(m.insert(origin, pts, 8.0), ucon::planner::InsertStatus::kOk);
  }
  const Eigen::Vector3d probe(3.05, 1.05, 0.25);
  EXPECT_FALSE(m.isOccupied(probe)) << "the rays cleared the disc";
  const std::size_t before = m.treeNodeCount();
  m.pruneTree();
  const std::size_t after = m.treeNodeCount();
  // Without the pruning the tree here is over 1.4x its pruned size; the map prunes when it
  // has grown by half since the last pruning, and this scene's last one was recent.
  EXPECT_LE(before, after + after / 4);
  EXPECT_FALSE(m.isOccupied(probe)) << "pruning changes no cell";
}

TEST(EsdfMap, GivenBadMessagesWhenInsertedThenTheyAreRejectedAndNaNPointsSkipped) {
  EsdfMap map(smallParams());
  ucon::static_points_t msg{};
  msg.utime = 10;
  msg.valid = false;
  EXPECT_EQ(map.insert(msg), ucon::planner::InsertStatus::kInvalidMessage);
  msg.valid = true;
  msg.num_points = 2;  // arrays empty: size mismatch
  EXPECT_EQ(map.insert(msg), ucon::planner::InsertStatus::kInvalidMessage);
  msg.x = {1.0f, NAN};
  msg.y = {0.0f, 0.0f};
  msg.z = {0.25f, 0.25f};
  msg.origin_x = NAN;
  EXPECT_EQ(map.insert(msg), ucon::planner::InsertStatus::kBadOrigin);
  msg.origin_x = 0.0;
  msg.origin_z = 0.25;
  msg.max_range = 5.0f;
  int64_t skipped = 0;
  EXPECT_EQ(map.insert(msg, &skipped), ucon::planner::InsertStatus::kOk);
  EXPECT_EQ(skipped, 1);
  EXPECT_TRUE(map.isOccupied(Eigen::Vector3d(1.0, 0.0, 0.25)));
}

TEST(EsdfMap, GivenAMapWhenQueriedBetweenCellsThenTheGradientMatchesFiniteDifferences) {
  EsdfMap map(smallParams());
  map.addCylinder(0.0, 0.0, 0.5);
  map.addBox(1.5, -2.0, 2.0, 2.0);
  map.update(Eigen::Vector2d(0, 0));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  int checked = 0;
  for (int i = 0; i < 500; ++i) {
    const double x = u(rng), y = u(rng);
    Eigen::Vector2d g;
    const double d = map.distance(x, y, &g);
    const double h = 1e-6;
    // Skip points within h of a cell-centre line, where the interpolant has a kink.
    const double fx = (x - map.slice().origin.x()) / 0.1 - 0.5, fy = (y - map.slice().origin.y()) / 0.1 - 0.5;
    if (std::abs(fx - std::round(fx)) < 1e-4 || std::abs(fy - std::round(fy)) < 1e-4) continue;
    const double gx = (map.distance(x + h, y, nullptr) - map.distance(x - h, y, nullptr)) / (2 * h);
    const double gy = (map.distance(x, y + h, nullptr) - map.distance(x, y - h, nullptr)) / (2 * h);
    EXPECT_NEAR(g.x(), gx, 1e-5);
    EXPECT_NEAR(g.y(), gy, 1e-5);
    EXPECT_TRUE(std::isfinite(d));
    ++checked;
  }
  EXPECT_GT(checked, 400);
  // Inside the cylinder the signed distance is negative and points outwards.
  Eigen::Vector2d g;
  EXPECT_LT(map.distance(0.23, 0.02, &g), -0.1);
  EXPECT_GT(g.x(), 0.5);
  // Far from everything: the cap.
  EXPECT_NEAR(map.distance(-3.0, 3.0, nullptr), map.params().max_distance, 1e-6);
}

TEST(EsdfMap, GivenTwoInsertThreadsThenTheMapEqualsOneThreadsLeafForLeaf) {
  // The helper traces half of the rays; its cells are applied after the first half's, in the
  // order one thread would reach them. Scans from inside and above the band (rays entering the
  // band from outside the insertion's grid), clamping both ways, direct writes in between.
  MapParams one = smallParams();
  one.band_only = true;
  one.insert_threads = 1;
  MapParams two = one;
  two.insert_threads = 2;
  EsdfMap a(one), b(two);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), height(0.0, 0.9), dist(0.5, 4.5);
  for (int scan = 0; scan < 30; ++scan) {
    const Eigen::Vector3d origin(0.05 * (scan % 7), -0.04 * (scan % 4), scan % 10 == 9 ? 1.2 : 0.25);
    const float shrink = scan % 9 < 5 ? 1.0f : 0.6f;
    const std::vector<Eigen::Vector3f> pts = ringScan(origin, 500, shrink, rng, ang, dist, height);
    ASSERT_EQ(a.insert(origin, pts, 4.0), ucon::planner::InsertStatus::kOk);
    ASSERT_EQ(b.insert(origin, pts, 4.0), ucon::planner::InsertStatus::kOk);
    if (scan % 6 == 2) {
      a.addCylinder(-0.6, 0.3, 0.4, false);
      b.addCylinder(-0.6, 0.3, 0.4, false);
    }
    if (scan % 5 == 4) {
      a.update(Eigen::Vector2d(0, 0));
      b.update(Eigen::Vector2d(0, 0));
    }
  }
  int occupied = 0;
  for (int ix = -50; ix <= 50; ++ix)
    for (int iy = -50; iy <= 50; ++iy)
      for (double z : {0.15, 0.25, 0.35, 0.55}) {
        const Eigen::Vector3d q((ix + 0.5) * 0.1, (iy + 0.5) * 0.1, z);
        ASSERT_EQ(a.isOccupied(q), b.isOccupied(q)) << q.transpose();
        occupied += a.isOccupied(q);
      }
  EXPECT_GT(occupied, 100);
  EXPECT_EQ(a.occupiedLeafCount(), b.occupiedLeafCount());
  EXPECT_EQ(a.treeNodeCount(), b.treeNodeCount());
  a.update(Eigen::Vector2d(0, 0));
  b.update(Eigen::Vector2d(0, 0));
  ASSERT_EQ(a.slice().nx, b.slice().nx);
  for (int iy = 0; iy < a.slice().ny; ++iy)
    for (int ix = 0; ix < a.slice().nx; ++ix) ASSERT_EQ(a.cellDistance(ix, iy), b.cellDistance(ix, iy));
  EXPECT_EQ(a.helperCpuSeconds(), 0.0);
  EXPECT_GT(b.helperCpuSeconds(), 0.0);  // the helper did trace
}

TEST(EsdfMap, GivenABadInsertThreadCountThenValidateNamesTheKey) {
  MapParams p;
  p.insert_threads = 3;
  EXPECT_EQ(p.validate().rfind("insert_threads:", 0), 0u);
  p.insert_threads = 0;
  EXPECT_EQ(p.validate().rfind("insert_threads:", 0), 0u);
  p.insert_threads = 2;
  EXPECT_TRUE(p.validate().empty());
}
