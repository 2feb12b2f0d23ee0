// The motion test's free-space evidence: new surface is motion only where every return of the
// reference's bin lay beyond it.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/motion_test.hpp"
#include "ucon/perception/params.hpp"

using namespace ucon::perception;

namespace {

const Eigen::Vector3f kOrigin(0.0f, 0.0f, 0.5f);

// A point `r` [m] from the sensor in the middle of the 1-degree bin at azimuth and elevation
// `deg` [deg] (bin edges lie on whole degrees).
Eigen::Vector3f along(float r, float deg = 0.5f) {
  const float a = deg * static_cast<float>(M_PI) / 180.0f;
  return kOrigin + r * Eigen::Vector3f(std::cos(a) * std::cos(a), std::sin(a) * std::cos(a), std::sin(a));
}

// What `test` finds for a frame at 2.2 s holding the single point `p`.
MotionEvidence evidenceAt(MotionTest& test, const AngularGrid& grid, const Eigen::Vector3f& p) {
  Frame now;
  now.utime = 2'200'000;
  now.sensor_origin = kOrigin;
  now.points = {p};
  now.returns = {p};
  now.nearest_fine.assign(static_cast<std::size_t>(grid.size()), INFINITY);
  now.moved.assign(1, 0);
  test.selectReference(now.utime);
  EXPECT_TRUE(test.hasReference());
  MotionEvidence e;
  const int n = test.markMoved(now, {0}, p.head<2>().cast<double>(), &now.moved, &e);
  EXPECT_EQ(n, e.moved);
  EXPECT_EQ(e.near_reference + e.moved + e.surface + e.undecided, 1);
  return e;
}

// One second of parked frames (50 Hz) whose returns are `returns`, then a frame 1.2 s in with
// the single point `p`: what the test found for it.
MotionEvidence evidenceAgainst(const Points& returns, const Eigen::Vector3f& p) {
  const SegmentationParams params;
  const AngularGrid grid(params.free_space_bin_deg);
  MotionTest test(params, grid);
  for (int64_t t = 1'000'000; t <= 2'000'000; t += 20'000) {
    Frame f;
    f.utime = t;
    f.sensor_origin = kOrigin;
    f.returns = returns;
    f.points = returns;
    test.push(f, std::vector<char>(f.points.size(), 0));
  }
  return evidenceAt(test, grid, p);
}

// Whether the test marks the point moved.
bool movedAgainst(const Points& returns, const Eigen::Vector3f& p) { return evidenceAgainst(returns, p).moved == 1; }

}  // namespace

TEST(MotionTest, GivenNewSurfaceWhereEveryReferenceRayPassedThenItMoved) {
  // The reference saw a wall 8 m away in that direction; something now stands at 5 m.
  EXPECT_TRUE(movedAgainst({along(8.0f), along(8.0f, 0.8f)}, along(5.0f)));
}

TEST(MotionTest, GivenNewSurfaceInABinHoldingAnEdgeThenItIsNoEvidenceOfMotion) {
  // The same bin held a ray past the point (8 m) and one stopping well short of it (a pillar's edge
  // at 3 m): from a driving sensor the new surface at 5 m is a face the edge hid, not motion.
  EXPECT_FALSE(movedAgainst({along(8.0f), along(3.0f, 0.8f)}, along(5.0f)));
}

TEST(MotionTest, GivenNewSurfaceWhereTheReferenceSawSomethingAtTheSameRangeAndPastItThenItMoved) {
  // Someone walked here in the reference (a return at 5.25 m) and the wall was seen past it
  // (8 m): someone standing at 5 m now (a follower in the leader's footsteps) moved.
  EXPECT_TRUE(movedAgainst({along(8.0f), along(5.25f, 0.8f)}, along(5.0f)));
}

TEST(MotionTest, GivenNewSurfaceInAnUnseenBinBesideBinsThatSawASurfaceThereThenItIsNoEvidenceOfMotion) {
  // The reference has no return in the point's own bin (the sparse scan missed it), but the
  // bins beside it saw a wall at the point's range: the point is that wall, sampled now.
  EXPECT_FALSE(movedAgainst({along(8.0f, 1.5f), along(8.1f, -0.5f)}, along(8.0f)));
}

TEST(MotionTest, GivenNewSurfaceInAnUnseenBinBesideBinsThatSawPastItThenItMoved) {
  // The bins beside it saw only a wall 8 m away: the space at 5 m was free, something moved in.
  EXPECT_TRUE(movedAgainst({along(8.0f, 1.5f), along(8.0f, -0.5f)}, along(5.0f)));
}

TEST(MotionTest, GivenNewSurfaceWhereNoReferenceBinAroundItSawAnythingThenItMoved) {
  // Open space: nothing was seen within a bin of the point (only far off to the side).
  EXPECT_TRUE(movedAgainst({along(8.0f, 10.5f)}, along(5.0f)));
}

TEST(MotionTest, GivenEachKindOfEvidenceThenThePointIsCountedUnderIt) {
  // A reference point where the point is: not new surface.
  EXPECT_EQ(evidenceAgainst({along(5.0f)}, along(5.0f)).near_reference, 1);
  // The reference saw past it: motion.
  EXPECT_EQ(evidenceAgainst({along(8.0f)}, along(5.0f)).moved, 1);
  // The bins around it saw a wall at its range: that wall, sampled now.
  EXPECT_EQ(evidenceAgainst({along(8.0f, 1.5f), along(8.1f, -0.5f)}, along(8.0f)).surface, 1);
  // Every reference return in its direction lay 2 m in front of it (something stood there and
  // hid it for the whole window): the test cannot tell whether it moved.
  EXPECT_EQ(evidenceAgainst({along(3.0f)}, along(5.0f)).undecided, 1);
  // A bin holding rays past it and an edge well in front: no evidence either way.
  EXPECT_EQ(evidenceAgainst({along(8.0f), along(3.0f, 0.8f)}, along(5.0f)).undecided, 1);
}

namespace {

// Frames at 50 Hz: until 1 s a wall 8 m away across +-6 degrees (when `seen_before`), then
// until 2 s something standing 3 m away in front of it (every ray stops there); at 2.2 s the
// single point `p`. The reference (0.5-1.0 s old) holds only the second part.
MotionEvidence evidenceBehindAStander(bool seen_before, const Eigen::Vector3f& p) {
  const SegmentationParams params;
  const AngularGrid grid(params.free_space_bin_deg);
  MotionTest test(params, grid);
  const auto fan = [](float r) {
    Points out;
    for (float a = -6.0f; a <= 6.0f; a += 0.25f) {  // level rays
      const float az = a * static_cast<float>(M_PI) / 180.0f;
      out.push_back(kOrigin + r * Eigen::Vector3f(std::cos(az), std::sin(az), 0.0f));
    }
    return out;
  };
  for (int64_t t = 0; t <= 2'000'000; t += 20'000) {
    if (t < 1'000'000 && !seen_before) continue;
    Frame f;
    f.utime = t;
    f.sensor_origin = kOrigin;
    f.returns = fan(t < 1'000'000 ? 8.0f : 3.0f);
    f.points = f.returns;
    test.push(f, std::vector<char>(f.points.size(), 0));
  }
  return evidenceAt(test, grid, p);
}

}  // namespace

TEST(MotionTest, GivenAPlaceHiddenThroughTheWholeWindowButSeenThroughLowBeforeThenItMoved) {
  // A crowd: someone stood in front of the place through the whole reference window, so the
  // reference cannot judge a point there; but the sensor saw through the place at leg height
  // 1.2 s before (segmentation.free_memory): what stands there now arrived.
  const Eigen::Vector3f p = along(5.0f, 0.0f);
  const MotionEvidence seen = evidenceBehindAStander(true, p);
  EXPECT_EQ(seen.moved, 1);
  EXPECT_EQ(seen.remembered, 1);
  const MotionEvidence unseen = evidenceBehindAStander(false, p);
  EXPECT_EQ(unseen.undecided, 1);
  EXPECT_EQ(unseen.remembered, 0);
}
