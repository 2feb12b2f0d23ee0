// Object-level association (eq. 1) on hand-made cases, and the FAPP greedy baseline.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/perception/association.hpp"

using namespace ucon::perception;

namespace {
BoxXY box(double cx, double cy, double sx, double sy) {
  BoxXY b;
  b.center = {cx, cy};
  b.size = {sx, sy};
  return b;
}
TrackView track(const BoxXY& b) {
  TrackView t;
  t.box = b;
  t.last_center = b.center;
  return t;
}
}  // namespace

TEST(IouXY, GivenHalfOverlappingUnitBoxesThenIouIsOneThird) {
  EXPECT_NEAR(iouXY(box(0, 0, 1, 1), box(0.5, 0, 1, 1)), 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(iouXY(box(0, 0, 1, 1), box(0, 0, 1, 1)), 1.0, 1e-12);
  EXPECT_EQ(iouXY(box(0, 0, 1, 1), box(3, 0, 1, 1)), 0.0);
  EXPECT_EQ(iouXY(box(0, 0, 0, 1), box(0, 0, 1, 1)), 0.0);
}

TEST(AssociationCost, GivenHandMadeBoxesThenEachTermOfEq1MatchesItsClosedForm) {
  AssociationParams p;  // mu = (0.3, 0.3, 0.4)
  // Identical box, no velocity: f = 0.
  EXPECT_NEAR(associationCost({box(0, 0, 1, 1)}, track(box(0, 0, 1, 1)), p), 0.0, 1e-12);
  // IoU 1/3: f = 0.3 * (1 - 1/3) = 0.2.
  EXPECT_NEAR(associationCost({box(0.5, 0, 1, 1)}, track(box(0, 0, 1, 1)), p), 0.2, 1e-12);
  // Size (1,2) vs (1,1), same centre: IoU 1/2 -> 0.15; size term 0.4 * |(0,1)| / |(1,1)|.
  EXPECT_NEAR(associationCost({box(0, 0, 1, 2)}, track(box(0, 0, 1, 1)), p),
              0.15 + 0.4 / std::sqrt(2.0), 1e-12);
  // Direction: track moving +x at 1 m/s; the pair implies +y at 1 m/s (0.1 m in 0.1 s):
  // cos = 0 -> 0.3 * 1; IoU of the boxes (shifted 0.1 m in y): 0.9/1.1.
  TrackView h = track(box(0, 0, 1, 1));
  h.velocity = {1.0, 0.0};
  h.has_velocity = true;
  h.since_last = 0.1;
  const double iou = 0.9 / 1.1;
  EXPECT_NEAR(associationCost({box(0, 0.1, 1, 1)}, h, p), 0.3 * (1 - iou) + 0.3, 1e-12);
  // Same direction: no direction cost.
  EXPECT_NEAR(associationCost({box(0.1, 0, 1, 1)}, h, p), 0.3 * (1 - iou), 1e-12);
  // Slow pair (0.1 m/s implied): the direction term fades by 0.1 / 0.3.
  h.since_last = 1.0;
  EXPECT_NEAR(associationCost({box(0, 0.1, 1, 1)}, h, p), 0.3 * (1 - iou) + 0.3 * (0.1 / 0.3), 1e-12);
}

TEST(AssociateObjects, GivenTwoTracksOfDifferentSizeCloseTogetherThenEq1MatchesBySizeWhereNearestFails) {
  AssociationParams p;
  // Track 0: small (0.4 m) at the origin; track 1: large (1.0 m) at x = 0.6.
  std::vector<TrackView> tracks{track(box(0.0, 0, 0.4, 0.4)), track(box(0.6, 0, 1.0, 1.0))};
  // Detection 0 is large and 0.3 m from track 0; detection 1 small, 0.35 m from track 0.
  std::vector<DetectionView> dets{{box(0.3, 0, 1.0, 1.0)}, {box(0.35, 0.0, 0.4, 0.4)}};
  const Matching m = associateObjects(dets, tracks, p);
  EXPECT_EQ(m.detection_to_track[0], 1);
  EXPECT_EQ(m.detection_to_track[1], 0);
  EXPECT_EQ(m.track_to_detection[0], 1);
  // The greedy baseline takes the nearest centres first: track 0 <- detection 0 (0.3 m).
  const Matching g = associateNearest(dets, tracks, p);
  EXPECT_EQ(g.track_to_detection[0], 0);
  EXPECT_EQ(g.track_to_detection[1], 1);
}

TEST(AssociateObjects, GivenPairsBeyondTheGatesThenTheyStayUnmatched) {
  AssociationParams p;
  std::vector<TrackView> tracks{track(box(0, 0, 0.5, 0.5))};
  // Same size 2 m away: eq. 1 gives only 0.3 (no IoU) but the distance gate forbids it.
  EXPECT_EQ(associateObjects({{box(2, 0, 0.5, 0.5)}}, tracks, p).track_to_detection[0], -1);
  // Close but three times the size: 0.3 * (1 - 1/9) + 0.4 * 2 > 0.9.
  EXPECT_EQ(associateObjects({{box(0, 0, 1.5, 1.5)}}, tracks, p).track_to_detection[0], -1);
  EXPECT_EQ(associateNearest({{box(0.85, 0, 0.5, 0.5)}}, tracks, p).track_to_detection[0], -1);
  EXPECT_EQ(associateNearest({{box(0.75, 0, 0.5, 0.5)}}, tracks, p).track_to_detection[0], 0);
}

TEST(AssociateObjects, GivenNoTracksOrNoDetectionsThenNothingIsMatched) {
  AssociationParams p;
  const Matching m = associateObjects({{box(0, 0, 1, 1)}}, {}, p);
  ASSERT_EQ(m.detection_to_track.size(), 1u);
  EXPECT_EQ(m.detection_to_track[0], -1);
  EXPECT_TRUE(associateNearest({}, {track(box(0, 0, 1, 1))}, p).detection_to_track.empty());
}
