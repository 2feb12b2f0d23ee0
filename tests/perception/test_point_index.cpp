// PointIndex (PCL clustering on a nanoflann KD-tree) and ProximityIndex (early-exit radius
// test) against brute force on random clouds.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <algorithm>
#include <numeric>
#include <random>
#include <tuple>

#include "ucon/perception/euclidean_clusters.hpp"
#include "ucon/perception/point_index.hpp"
#include "ucon/perception/proximity_index.hpp"

using namespace ucon::perception;

namespace {
Points randomCloud(int n, unsigned seed, float extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-extent, extent);
  Points pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng), 0.2f * u(rng));
  return pts;
}

/// Connected components of the graph "closer than tol" by brute force (union-find).
std::vector<std::vector<int>> bruteClusters(const Points& pts, float tol, int min_pts, int max_pts) {
  const int n = static_cast<int>(pts.size());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if ((pts[i] - pts[j]).squaredNorm() < tol * tol) parent[find(i)] = find(j);
  std::vector<std::vector<int>> groups(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) groups[find(i)].push_back(i);
  std::vector<std::vector<int>> out;
  for (auto& g : groups) {
    const int s = static_cast<int>(g.size());
    if (s >= min_pts && s <= max_pts) out.push_back(g);  // already sorted
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return out;
}
}  // namespace

TEST(PointIndex, GivenRandomCloudsThenClustersAreTheBruteForceConnectedComponentsWithSizeLimits) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Points pts = randomCloud(600, seed, 4.0f);
    PointIndex index;
    index.build(pts);
    ASSERT_EQ(index.size(), 600);
    for (const auto& [tol, lo, hi] : {std::tuple{0.35f, 4, 4000}, std::tuple{0.25f, 2, 30}, std::tuple{0.5f, 1, 600}}) {
      const auto got = index.clusters(tol, lo, hi);
      const auto want = bruteClusters(pts, tol, lo, hi);
      EXPECT_EQ(got, want) << "seed " << seed << " tol " << tol;
      EXPECT_FALSE(want.empty());
    }
  }
}

TEST(PointIndex, GivenRandomQueriesThenNearestIsTheBruteForceNearest) {
  const Points pts = randomCloud(500, 7, 3.0f);
  PointIndex index;
  index.build(pts);
  for (const auto& q : randomCloud(200, 8, 3.5f)) {
    float d2 = -1.0f;
    const int i = index.nearest(q, &d2);
    ASSERT_GE(i, 0);
    float best = std::numeric_limits<float>::infinity();
    for (const auto& p : pts) best = std::min(best, (p - q).squaredNorm());
    EXPECT_FLOAT_EQ(d2, best);
    EXPECT_FLOAT_EQ((pts[static_cast<std::size_t>(i)] - q).squaredNorm(), best);
  }
  float d2 = 0.0f;
  EXPECT_EQ(index.nearest(Eigen::Vector3f(NAN, 0, 0), &d2), -1);
  PointIndex empty;
  empty.build({});
  EXPECT_EQ(empty.nearest(Eigen::Vector3f::Zero(), &d2), -1);
  EXPECT_TRUE(empty.clusters(0.35, 1, 10).empty());
}

TEST(ProximityIndex, GivenRandomQueriesThenAnyWithinAgreesWithTheBruteForceNearestDistance) {
  const Points pts = randomCloud(2000, 11, 5.0f);
  ProximityIndex index;
  index.build(pts);
  ASSERT_EQ(index.size(), 2000);
  int inside = 0, outside = 0;
  for (const auto& q : randomCloud(3000, 12, 5.5f)) {
    float best = std::numeric_limits<float>::infinity();
    for (const auto& p : pts) best = std::min(best, (p - q).squaredNorm());
    for (const float r : {0.05f, 0.1f, 0.25f}) {
      const bool want = best <= r * r;
      EXPECT_EQ(index.anyWithin(q, r * r), want);
      (want ? inside : outside) += 1;
    }
  }
  EXPECT_GT(inside, 500);  // both answers exercised
  EXPECT_GT(outside, 500);
}

TEST(ProximityIndex, GivenAPointExactlyOnTheSphereThenItCountsAsWithin) {
  ProximityIndex index;
  index.build({Eigen::Vector3f(0.5f, 0.0f, 0.0f), Eigen::Vector3f(3.0f, 0.0f, 0.0f)});
  EXPECT_TRUE(index.anyWithin(Eigen::Vector3f::Zero(), 0.25f));   // d^2 = 0.25 exactly
  EXPECT_FALSE(index.anyWithin(Eigen::Vector3f::Zero(), std::nextafter(0.25f, 0.0f)));
}

TEST(ProximityIndex, GivenBadInputThenFalseAndNonFinitePointsAreLeftOut) {
  ProximityIndex index;
  EXPECT_FALSE(index.anyWithin(Eigen::Vector3f::Zero(), 1.0f));  // never built
  index.build({Eigen::Vector3f(NAN, 0, 0), Eigen::Vector3f(0, INFINITY, 0), Eigen::Vector3f(1, 1, 1)});
  EXPECT_EQ(index.size(), 1);
  EXPECT_TRUE(index.anyWithin(Eigen::Vector3f(1, 1, 1.1f), 0.02f));
  EXPECT_FALSE(index.anyWithin(Eigen::Vector3f(NAN, 1, 1), 1.0f));
  EXPECT_FALSE(index.anyWithin(Eigen::Vector3f(1, 1, 1), NAN));
  EXPECT_FALSE(index.anyWithin(Eigen::Vector3f(1, 1, 1), -1.0f));
  index.build({});
  EXPECT_EQ(index.size(), 0);
  EXPECT_FALSE(index.anyWithin(Eigen::Vector3f(1, 1, 1), 1.0f));
}

namespace {
/// A LiDAR-like scene: walls, a pillar and a few people sampled on their surfaces at about
/// the voxel size, with points exactly on cell boundaries and duplicates.
Points sceneCloud(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Points pts;
  for (float x = -6.0f; x <= 6.0f; x += 0.08f)
    for (float z = 0.2f; z <= 2.0f; z += 0.08f) pts.emplace_back(x, 5.0f + 0.02f * u(rng), z);
  for (int k = 0; k < 6; ++k) {
    const float cx = -4.0f + 1.4f * float(k) + 0.3f * u(rng), cy = 1.0f + 2.0f * u(rng);
    for (int a = 0; a < 24; ++a)
      for (float z = 0.2f; z <= 1.7f; z += 0.08f)
        pts.emplace_back(cx + 0.25f * std::cos(0.26f * float(a)), cy + 0.25f * std::sin(0.26f * float(a)), z);
  }
  for (int i = 0; i < 50; ++i) pts.push_back(pts[std::size_t(i * 7)]);       // duplicates
  for (int i = 0; i < 20; ++i) pts.emplace_back(0.35f * float(i), 0.0f, 0.5f);  // a chain exactly tol apart
  std::shuffle(pts.begin(), pts.end(), rng);
  return pts;
}
}  // namespace

TEST(EuclideanClusterer, GivenRandomAndSceneCloudsThenGroupsEqualBruteForceAndPcl) {
  EuclideanClusterer ec;  // one instance: scratch reuse across calls must not leak state
  for (unsigned seed = 1; seed <= 5; ++seed) {
    for (const Points& pts : {randomCloud(600, seed, 4.0f), sceneCloud(seed)}) {
      PointIndex index;
      index.build(pts);
      for (const auto& [tol, lo, hi] :
           {std::tuple{0.35f, 4, 4000}, std::tuple{0.25f, 2, 500}, std::tuple{0.5f, 1, 100000}, std::tuple{0.12f, 1, 100000}}) {
        const auto got = ec.cluster(pts, tol, lo, hi);
        EXPECT_EQ(got, bruteClusters(pts, tol, lo, hi)) << "seed " << seed << " tol " << tol;
        EXPECT_EQ(got, index.clusters(tol, lo, hi)) << "seed " << seed << " tol " << tol;
        EXPECT_FALSE(got.empty()) << "seed " << seed << " tol " << tol << " n " << pts.size();
      }
    }
  }
}

TEST(EuclideanClusterer, GivenAChainOfPointsExactlyTheToleranceApartThenTheyAreNotJoined) {
  // PCL's radius search keeps neighbours strictly inside the radius; so does the grid.
  Points pts;
  for (int i = 0; i < 5; ++i) pts.emplace_back(0.5f * float(i), 0.0f, 0.0f);
  EuclideanClusterer ec;
  EXPECT_EQ(ec.cluster(pts, 0.5, 1, 10).size(), 5u);
  EXPECT_EQ(ec.cluster(pts, 0.5001, 1, 10), (std::vector<std::vector<int>>{{0, 1, 2, 3, 4}}));
}

TEST(EuclideanClusterer, GivenBadInputThenNonFinitePointsAreLeftOutAndNothingBreaks) {
  EuclideanClusterer ec;
  EXPECT_TRUE(ec.cluster({}, 0.35, 1, 10).empty());
  const Points pts{{0, 0, 0}, {NAN, 0, 0}, {0.1f, 0, 0}, {INFINITY, 1, 1}, {5, 5, 5}};
  EXPECT_EQ(ec.cluster(pts, 0.35, 1, 10), (std::vector<std::vector<int>>{{0, 2}, {4}}));
  EXPECT_TRUE(ec.cluster(pts, 0.0, 1, 10).empty());
  EXPECT_TRUE(ec.cluster(pts, NAN, 1, 10).empty());
  EXPECT_TRUE(ec.cluster({{NAN, NAN, NAN}}, 0.35, 1, 10).empty());
  // Far apart points (sparse grid: cells looked up by binary search) give the same groups.
  const Points sparse{{0, 0, 0}, {0.2f, 0, 0}, {30000, 0, 0}, {30000, 0.2f, 0}, {-30000, 20000, 3}};
  EXPECT_EQ(ec.cluster(sparse, 0.35, 1, 10), (std::vector<std::vector<int>>{{0, 1}, {2, 3}, {4}}));
  EXPECT_THROW(ec.cluster({{0, 0, 0}, {1e9f, 0, 0}}, 0.35, 1, 10), std::invalid_argument);
}

TEST(ProximityIndex, GivenLargeRadiiAndQueriesOutsideTheCloudThenAnswersEqualBruteForce) {
  const Points pts = sceneCloud(3);
  ProximityIndex index;
  index.build(pts);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-9.0f, 9.0f);
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3f q(u(rng), u(rng), 0.5f * u(rng));
    float best = std::numeric_limits<float>::infinity();
    for (const auto& p : pts) best = std::min(best, (p - q).squaredNorm());
    for (const float r : {0.0f, 0.3f, 1.0f, 3.0f}) EXPECT_EQ(index.anyWithin(q, r * r), best <= r * r) << k << " r " << r;
  }
  // A cloud spanning kilometres (coarser cells) answers the same.
  const Points far{{0, 0, 0}, {2000, 0, 0}, {0, -3000, 5}};
  index.build(far);
  EXPECT_TRUE(index.anyWithin(Eigen::Vector3f(1999.9f, 0.0f, 0.0f), 0.02f));
  EXPECT_FALSE(index.anyWithin(Eigen::Vector3f(1999.0f, 0.0f, 0.0f), 0.5f));
  EXPECT_TRUE(index.anyWithin(Eigen::Vector3f(0.0f, -3000.0f, 4.0f), 1.0f));
}

TEST(ProximityIndex, GivenRandomAndSceneCloudsThenNearestWithinIsTheBruteForceNearestInsideTheRadius) {
  // Brute force: the nearest point strictly inside the radius, the lowest index on a tie,
  // with the squared distance summed as a KD-tree's L2 metric does.
  const auto brute = [](const Points& pts, const Eigen::Vector3f& q, float r2, float* d2_out) {
    int best_i = -1;
    float best = r2;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const float dx = q.x() - pts[i].x(), dy = q.y() - pts[i].y(), dz = q.z() - pts[i].z();
      const float d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < best) best = d2, best_i = int(i);
    }
    *d2_out = best;
    return best_i;
  };
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(-7.0f, 7.0f);
  int found = 0, none = 0;
  for (const Points& pts : {randomCloud(2000, 13, 5.0f), sceneCloud(4)}) {
    PointIndex tree;
    tree.build(pts);
    for (const double cell : {0.6, 0.25, 2.0}) {
      ProximityIndex index;
      index.build(pts, cell);
      for (int k = 0; k < 400; ++k) {
        // Every fourth query sits on a cloud point (a duplicate there makes a tie).
        const Eigen::Vector3f q = k % 4 == 0 ? pts[std::size_t(k * 13) % pts.size()] : Eigen::Vector3f(u(rng), u(rng), 0.3f * u(rng));
        for (const float r : {0.1f, 0.6f, 1.5f}) {
          float want_d2 = 0.0f, got_d2 = -1.0f;
          const int want = brute(pts, q, r * r, &want_d2);
          const int got = index.nearestWithin(q, r * r, &got_d2);
          ASSERT_EQ(got, want) << "cell " << cell << " query " << k << " r " << r;
          if (want < 0) {
            ++none;
            continue;
          }
          ++found;
          EXPECT_EQ(got_d2, want_d2);
          // The KD-tree's nearest has the same distance (it may name another point on a tie).
          float tree_d2 = 0.0f;
          ASSERT_GE(tree.nearest(q, &tree_d2), 0);
          EXPECT_EQ(tree_d2, got_d2);
        }
      }
    }
  }
  EXPECT_GT(found, 1000);  // both answers exercised
  EXPECT_GT(none, 500);
}

TEST(ProximityIndex, GivenNearestWithinThenTheBoundIsStrictIndicesAreTheCallersAndBadInputGivesNone) {
  ProximityIndex index;
  float d2 = -1.0f;
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f::Zero(), 1.0f, &d2), -1);  // never built
  // Non-finite points are left out but the others keep their index in the given vector.
  index.build({Eigen::Vector3f(NAN, 0, 0), Eigen::Vector3f(0.5f, 0, 0), Eigen::Vector3f(0, INFINITY, 0),
               Eigen::Vector3f(0, 0.5f, 0), Eigen::Vector3f(3, 0, 0)},
              0.6);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f(0.4f, 0, 0), 1.0f, &d2), 1);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f(2.9f, 0, 0), 1.0f, nullptr), 4);
  // Points 1 and 3 are both at d^2 = 0.25 from the origin: the lower index wins; the bound is strict.
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f::Zero(), 1.0f, &d2), 1);
  EXPECT_EQ(d2, 0.25f);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f::Zero(), 0.25f, &d2), -1);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f::Zero(), std::nextafter(0.25f, 1.0f), &d2), 1);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f(NAN, 0, 0), 1.0f, &d2), -1);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f::Zero(), NAN, &d2), -1);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f::Zero(), -1.0f, &d2), -1);
  EXPECT_EQ(index.nearestWithin(Eigen::Vector3f(50, 50, 50), 1.0f, &d2), -1);  // outside the grid
}
