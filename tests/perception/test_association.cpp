// Object-level association (eq. 1) on hand-made cases, and the FAPP greedy baseline.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/perception/association.hpp"

using namespace ucon::perception;

namespace {
const std::vector<double> kMu = PaperParams{}.mu;  // eq. 1's weights as shipped: (0.3, 0.3, 0.4)
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
// A track predicted at b, unseen for `since_last` s after it was last seen moving at `seen`.
TrackView coasting(const BoxXY& b, const Eigen::Vector2d& seen, double since_last) {
  TrackView t = track(b);
  t.seen_velocity = seen;
  t.since_last = since_last;
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
  AssociationParams p;
  // Identical box, no velocity: f = 0.
  EXPECT_NEAR(associationCost({box(0, 0, 1, 1)}, track(box(0, 0, 1, 1)), kMu, p), 0.0, 1e-12);
  // IoU 1/3: f = 0.3 * (1 - 1/3) = 0.2.
  EXPECT_NEAR(associationCost({box(0.5, 0, 1, 1)}, track(box(0, 0, 1, 1)), kMu, p), 0.2, 1e-12);
  // Size (1,2) vs (1,1), same centre: IoU 1/2 -> 0.15; size term 0.4 * |(0,1)| / |(1,1)|.
  EXPECT_NEAR(associationCost({box(0, 0, 1, 2)}, track(box(0, 0, 1, 1)), kMu, p),
              0.15 + 0.4 / std::sqrt(2.0), 1e-12);
  // Direction: track moving +x at 1 m/s; the pair implies +y at 1 m/s (0.1 m in 0.1 s):
  // cos = 0 -> 0.3 * 1; IoU of the boxes (shifted 0.1 m in y): 0.9/1.1.
  TrackView h = track(box(0, 0, 1, 1));
  h.velocity = {1.0, 0.0};
  h.has_velocity = true;
  h.since_last = 0.1;
  const double iou = 0.9 / 1.1;
  EXPECT_NEAR(associationCost({box(0, 0.1, 1, 1)}, h, kMu, p), 0.3 * (1 - iou) + 0.3, 1e-12);
  // Same direction: no direction cost.
  EXPECT_NEAR(associationCost({box(0.1, 0, 1, 1)}, h, kMu, p), 0.3 * (1 - iou), 1e-12);
  // Slow pair (0.1 m/s implied): the direction term fades by 0.1 / 0.3.
  h.since_last = 1.0;
  EXPECT_NEAR(associationCost({box(0, 0.1, 1, 1)}, h, kMu, p), 0.3 * (1 - iou) + 0.3 * (0.1 / 0.3), 1e-12);
}

TEST(AssociateObjects, GivenTwoTracksOfDifferentSizeCloseTogetherThenEq1MatchesBySizeWhereNearestFails) {
  AssociationParams p;
  // Track 0: small (0.4 m) at the origin; track 1: large (1.0 m) at x = 0.6.
  std::vector<TrackView> tracks{track(box(0.0, 0, 0.4, 0.4)), track(box(0.6, 0, 1.0, 1.0))};
  // Detection 0 is large and 0.3 m from track 0; detection 1 small, 0.35 m from track 0.
  std::vector<DetectionView> dets{{box(0.3, 0, 1.0, 1.0)}, {box(0.35, 0.0, 0.4, 0.4)}};
  const Matching m = associateObjects(dets, tracks, kMu, p);
  EXPECT_EQ(m.detection_to_track[0], 1);
  EXPECT_EQ(m.detection_to_track[1], 0);
  EXPECT_EQ(m.track_to_detection[0], 1);
  // The greedy baseline takes the nearest centres first: track 0 <- detection 0 (0.3 m).
  const Matching g = associateNearest(dets, tracks, p);
  EXPECT_EQ(g.track_to_detection[0], 0);
  EXPECT_EQ(g.track_to_detection[1], 1);
}

TEST(AssociateObjects, GivenPairsBeyondTheGatesThenTheyStayUnmatched) {
  AssociationParams p;  // the shipped gates
  std::vector<TrackView> tracks{track(box(0, 0, 0.5, 0.5))};
  // Same size 2 m away: eq. 1 gives 0.3 * (1 + 0.6) (generalised IoU -0.6), within cost_gate,
  // but the 1 m distance gate forbids it (seen alone: the Mahalanobis gate off).
  ASSERT_LT(associationCost({box(2, 0, 0.5, 0.5)}, tracks[0], kMu, p), p.cost_gate);
  p.gate_sigma = 0.0;
  EXPECT_EQ(associateObjects({{box(2, 0, 0.5, 0.5)}}, tracks, kMu, p).track_to_detection[0], -1);
  p.gate_sigma = AssociationParams{}.gate_sigma;
  // Same place but four times the size: 0.3 * (1 - 1/16) + 0.4 * 3 = 1.48 > cost_gate 1.3.
  EXPECT_EQ(associateObjects({{box(0, 0, 2.0, 2.0)}}, tracks, kMu, p).track_to_detection[0], -1);
  // Three times the size passes: 0.3 * (1 - 1/9) + 0.4 * 2 = 1.07.
  EXPECT_EQ(associateObjects({{box(0, 0, 1.5, 1.5)}}, tracks, kMu, p).track_to_detection[0], 0);
  EXPECT_EQ(associateNearest({{box(0.85, 0, 0.5, 0.5)}}, tracks, p).track_to_detection[0], -1);
  EXPECT_EQ(associateNearest({{box(0.75, 0, 0.5, 0.5)}}, tracks, p).track_to_detection[0], 0);
}

TEST(AssociateObjects, GivenNoTracksOrNoDetectionsThenNothingIsMatched) {
  AssociationParams p;
  const Matching m = associateObjects({{box(0, 0, 1, 1)}}, {}, kMu, p);
  ASSERT_EQ(m.detection_to_track.size(), 1u);
  EXPECT_EQ(m.detection_to_track[0], -1);
  EXPECT_TRUE(associateNearest({}, {track(box(0, 0, 1, 1))}, p).detection_to_track.empty());
}

TEST(Mahalanobis2, GivenADiagonalCovarianceThenItMatchesTheClosedForm) {
  AssociationParams p;
  p.centroid_std = 0.1;
  TrackView h = track(box(0, 0, 0.5, 0.5));
  h.position_cov << 0.03, 0.0, 0.0, 0.08;  // + 0.01 -> (0.04, 0.09)
  EXPECT_NEAR(mahalanobis2({box(0.4, 0, 0.5, 0.5)}, h, p), 0.16 / 0.04, 1e-12);
  EXPECT_NEAR(mahalanobis2({box(0, 0.6, 0.5, 0.5)}, h, p), 0.36 / 0.09, 1e-12);
  // A correlated covariance: r' S^-1 r with S = [[0.05, 0.02], [0.02, 0.05]] + 0.01 I.
  h.position_cov << 0.05, 0.02, 0.02, 0.05;
  const double a = 0.06, b = 0.02, det = a * a - b * b;
  const double x = 0.3, y = -0.2;
  EXPECT_NEAR(mahalanobis2({box(x, y, 0.5, 0.5)}, h, p), (a * x * x - 2 * b * x * y + a * y * y) / det, 1e-12);
  // A degenerate or non-finite covariance never passes a gate.
  h.position_cov << NAN, 0, 0, 0.01;
  EXPECT_FALSE(std::isfinite(mahalanobis2({box(0, 0, 0.5, 0.5)}, h, p)));
}

TEST(AssociateObjects, GivenAMahalanobisGateThenAFarDetectionOfAConfidentTrackIsForbidden) {
  AssociationParams p;
  p.gate_sigma = 3.0;
  p.centroid_std = 0.1;
  TrackView h = track(box(0, 0, 0.5, 0.5));
  h.position_cov = Eigen::Matrix2d::Identity() * 0.0025;  // sigma 5 cm -> total ~0.11 m
  // 0.5 m away: inside the 1 m distance gate, but 4.5 sigma.
  EXPECT_EQ(associateObjects({{box(0.5, 0, 0.5, 0.5)}}, {h}, kMu, p).detection_to_track[0], -1);
  // The same track after coasting (covariance 0.2 m^2): the pair is allowed.
  h.position_cov = Eigen::Matrix2d::Identity() * 0.04;
  EXPECT_EQ(associateObjects({{box(0.5, 0, 0.5, 0.5)}}, {h}, kMu, p).detection_to_track[0], 0);
  // Gate off: allowed whatever the covariance.
  p.gate_sigma = 0.0;
  h.position_cov = Eigen::Matrix2d::Identity() * 1e-6;
  EXPECT_EQ(associateObjects({{box(0.5, 0, 0.5, 0.5)}}, {h}, kMu, p).detection_to_track[0], 0);
}

TEST(AssociateObjects, GivenADistanceWeightThenTheNearerOfTwoGatedTracksWins) {
  AssociationParams p;
  p.max_distance = 3.0;
  p.max_distance_cap = 3.0;
  // Both tracks' boxes miss the detection's box; the far one (2.0 m) has the detection's
  // size, the near one (0.9 m) a slightly different size, so eq. 1 alone prefers the far one.
  TrackView near_track = track(box(0.9, 0, 0.5, 0.9));
  TrackView far_track = track(box(-2.0, 0, 0.5, 0.5));
  // Uncertain predictions (1 m std): the Mahalanobis gate passes both.
  near_track.position_cov = far_track.position_cov = Eigen::Matrix2d::Identity();
  const std::vector<DetectionView> det{{box(0, 0, 0.5, 0.5)}};
  const double shipped = p.distance_weight;
  p.distance_weight = 0.0;
  ASSERT_LT(associationCost(det[0], far_track, kMu, p), associationCost(det[0], near_track, kMu, p));
  EXPECT_EQ(associateObjects(det, {near_track, far_track}, kMu, p).detection_to_track[0], 1);
  p.distance_weight = shipped;
  EXPECT_EQ(associateObjects(det, {near_track, far_track}, kMu, p).detection_to_track[0], 0);
}

TEST(ReidentificationScore, GivenTwoCandidatesThenTheOneWhoseLineThePersonKeptWinsOverTheNearerOne) {
  TrackParams p;
  p.reid_speed = 1.8;
  p.reid_margin = 0.5;
  p.reid_cross_speed = 0.3;
  p.confirm_min_speed = 0.15;
  const Eigen::Vector2d first(3.0, 2.0);
  const double dt = 1.0;
  // A: walked along y at x = 3, last seen 2 m back along its line (heading +y).
  const double a = reidentificationScore(first, {3.0, 0.0}, {0.0, 1.2}, dt, p);
  // B: walked along y at x = 3.7, last seen 1.1 m away but 0.7 m off its line.
  const double b = reidentificationScore(first, {3.7, 2.9}, {0.0, -1.2}, dt, p);
  EXPECT_LT((first - Eigen::Vector2d(3.7, 2.9)).norm(), (first - Eigen::Vector2d(3.0, 0.0)).norm());
  EXPECT_LT(a, b);
  // Closed form for A: along 2 over 2.3, cross 0 -> 2.3 * (2 / 2.3) = 2.
  EXPECT_NEAR(a, 2.0, 1e-12);
  // B: along -0.9 over 2.3, cross 0.7 over 0.8 -> 2.3 * sqrt((0.9/2.3)^2 + (0.7/0.8)^2).
  EXPECT_NEAR(b, 2.3 * std::sqrt(std::pow(0.9 / 2.3, 2) + std::pow(0.7 / 0.8, 2)), 1e-12);
  // Turning back along the line scores like going on (people reverse at walk ends).
  EXPECT_NEAR(reidentificationScore({3.0, -2.0}, {3.0, 0.0}, {0.0, 1.2}, dt, p), a, 1e-12);
  // No heading (slow) or the cross term off: plain distance.
  EXPECT_NEAR(reidentificationScore(first, {3.7, 2.9}, {0.0, 0.1}, dt, p), std::hypot(0.7, 0.9), 1e-12);
  p.reid_cross_speed = 0.0;
  EXPECT_NEAR(reidentificationScore(first, {3.7, 2.9}, {0.0, -1.2}, dt, p), std::hypot(0.7, 0.9), 1e-12);
}

TEST(PassesCrossGate, GivenATrackUnseenForAWhileThenOnlyCentresNearItsLineArePassed) {
  AssociationParams p;
  p.cross_gate = 0.3;
  p.cross_gate_growth = 0.15;
  p.cross_gate_after = 0.1;
  p.cross_gate_until = 2.5;
  p.direction_min_speed = 0.3;
  // Predicted at (3, 4), last seen 0.6 s ago walking +y at 1 m/s: the line is x = 3 and the
  // bound 0.3 + 0.15 * 0.6 = 0.39 m.
  TrackView h = coasting(box(3.0, 4.0, 0.5, 0.5), {0.0, 1.0}, 0.6);
  EXPECT_TRUE(passesCrossGate({3.35, 4.9}, h, p));   // 0.35 across, far along: passed
  EXPECT_TRUE(passesCrossGate({2.65, 2.5}, h, p));   // turned back along the line: passed
  EXPECT_FALSE(passesCrossGate({3.6, 4.2}, h, p));   // the neighbour's line 0.6 m across
  EXPECT_FALSE(passesCrossGate({2.55, 4.0}, h, p));  // 0.45 across on the other side
  // The bound grows with the time unseen: 0.3 + 0.15 * 2 = 0.6.
  h.since_last = 2.0;
  EXPECT_TRUE(passesCrossGate({3.55, 4.2}, h, p));
  EXPECT_FALSE(passesCrossGate({3.65, 4.2}, h, p));
  // Unseen for longer than cross_gate_until (a hiding long enough to hide a turn): not gated.
  h.since_last = 2.6;
  EXPECT_TRUE(passesCrossGate({5.0, 4.2}, h, p));
  // A heading at an angle: the distance is measured across it, not along x.
  h.seen_velocity = {1.0, 1.0};
  h.since_last = 0.6;
  EXPECT_TRUE(passesCrossGate({4.0, 5.0}, h, p));    // on the diagonal line
  EXPECT_FALSE(passesCrossGate({3.5, 3.5}, h, p));   // 0.71 across it
  // Does not apply: seen recently, no heading (slower than direction_min_speed), or off.
  h.since_last = 0.05;
  EXPECT_TRUE(passesCrossGate({3.5, 3.5}, h, p));
  h.since_last = 0.6;
  h.seen_velocity = {0.2, 0.0};
  EXPECT_TRUE(passesCrossGate({3.0, 5.0}, h, p));
  h.seen_velocity = {1.0, 1.0};
  p.cross_gate = 0.0;
  EXPECT_TRUE(passesCrossGate({3.5, 3.5}, h, p));
}

TEST(AssociateObjects, GivenACoastingTrackAndANeighbourReappearingBesideItsLineThenThePairIsForbidden) {
  // Person A (track) walked +y on x = 3 and is hidden; person B reappears on x = 3.7, within
  // every distance gate of A's prediction. Without the cross gate A takes B's detection.
  AssociationParams p;  // shipped: cross gate 0.4 m + 0.15 m/s unseen
  TrackView a = coasting(box(3.0, 4.0, 0.5, 0.5), {0.0, 1.0}, 0.6);
  a.velocity = {0.0, 0.5};
  a.has_velocity = true;
  a.last_center = {3.0, 3.4};
  a.position_cov = Eigen::Matrix2d::Identity() * 0.09;  // 0.3 m std after coasting: B is within 3.5 sigma
  const std::vector<DetectionView> det{{box(3.7, 4.1, 0.5, 0.5)}};
  const AssociationParams shipped;
  p.cross_gate = 0.0;
  EXPECT_EQ(associateObjects(det, {a}, kMu, p).detection_to_track[0], 0);
  p.cross_gate = shipped.cross_gate;  // 0.4 + 0.15 * 0.6 = 0.49 m across; B is 0.7 m across
  EXPECT_EQ(associateObjects(det, {a}, kMu, p).detection_to_track[0], -1);
  // A's own reappearance on its line, ahead of the decayed prediction, is still matched.
  EXPECT_EQ(associateObjects({{box(3.05, 4.5, 0.5, 0.5)}}, {a}, kMu, p).detection_to_track[0], 0);
}

TEST(AssociateObjects, GivenAMatchingCascadeThenATrackSeenLastFrameKeepsItsObjectAgainstACoastingTrack) {
  // A partly hidden person's small view: eq. 1 prefers the coasting track (its faded direction
  // term and its size), the nearer track that saw the person last frame loses it without the
  // cascade.
  AssociationParams p;  // shipped
  TrackView seen = track(box(3.53, -1.88, 0.5, 0.5));
  seen.since_last = 0.02;
  seen.has_velocity = true;
  seen.velocity = {0.0, 0.7};
  seen.last_center = {3.53, -1.90};
  const TrackView hidden = coasting(box(3.04, -1.80, 0.2, 0.3), {0.0, 0.0}, 2.2);
  const std::vector<DetectionView> det{{box(3.49, -2.0, 0.14, 0.3)}};
  ASSERT_LT(associationCost(det[0], hidden, kMu, p) + (det[0].box.center - hidden.box.center).norm(),
            associationCost(det[0], seen, kMu, p) + (det[0].box.center - seen.box.center).norm());
  const double shipped = p.cascade_after;
  p.cascade_after = 0.0;  // one matching
  EXPECT_EQ(associateObjects(det, {seen, hidden}, kMu, p).detection_to_track[0], 1);
  p.cascade_after = shipped;  // 0.1 s
  Matching m = associateObjects(det, {seen, hidden}, kMu, p);
  EXPECT_EQ(m.detection_to_track[0], 0);
  EXPECT_EQ(m.track_to_detection[1], -1);
  // The coasting track still takes a detection the recent tracks leave.
  const std::vector<DetectionView> two{{box(3.49, -2.0, 0.14, 0.3)}, {box(3.1, -1.7, 0.2, 0.3)}};
  m = associateObjects(two, {seen, hidden}, kMu, p);
  EXPECT_EQ(m.detection_to_track[0], 0);
  EXPECT_EQ(m.detection_to_track[1], 1);
}

TEST(AssociationCost, GivenATrackBoxShrunkByPartialViewsThenTheSizeTermIsMeasuredAgainstTheFloor) {
  // The track's box shrank to 0.16 x 0.07 m under partial views; the full view of the same
  // person (0.41 x 0.31) comes back.
  AssociationParams p;
  const std::vector<double> mu{0.0, 0.0, 1.0};  // the size term alone
  const TrackView h = track(box(3.66, -3.64, 0.16, 0.07));
  const DetectionView c{box(3.68, -3.65, 0.41, 0.31)};
  const double change = std::hypot(0.41 - 0.16, 0.31 - 0.07);
  const double shipped = p.size_floor;
  p.size_floor = 0.0;
  EXPECT_NEAR(associationCost(c, h, mu, p), change / std::hypot(0.16, 0.07), 1e-9);  // > 2
  p.size_floor = shipped;  // 0.5 m
  EXPECT_NEAR(associationCost(c, h, mu, p), change / 0.5, 1e-9);
  // A track box larger than the floor is unaffected.
  const TrackView big = track(box(3.66, -3.64, 0.5, 0.4));
  EXPECT_NEAR(associationCost(c, big, mu, p), std::hypot(0.09, 0.09) / std::hypot(0.5, 0.4), 1e-9);
}

TEST(RankingDistance, GivenACoastingTrackThenTheOffsetAcrossItsHeadingCountsMore) {
  AssociationParams p;
  p.cross_rank_weight = 3.0;
  p.cross_gate_after = 0.1;
  p.direction_min_speed = 0.3;
  // Track A walked -y on x = 3.6 and overshot the walk end; track B walked -y on x = 3.05.
  // The person of A turned back while hidden and reappears 1.25 m behind A's prediction, on
  // A's line, 0.55 m across B's line and 0.43 m behind B's prediction.
  const TrackView a = coasting(box(3.60, -5.37, 0.5, 0.5), {0.0, -1.0}, 2.5);
  TrackView b = coasting(box(3.05, -4.55, 0.5, 0.5), {0.0, -0.8}, 2.4);
  const Eigen::Vector2d c(3.60, -4.12);
  EXPECT_LT((c - b.box.center).norm(), (c - a.box.center).norm());
  EXPECT_NEAR(rankingDistance(c, a, p), 1.25, 1e-9);
  EXPECT_NEAR(rankingDistance(c, b, p), std::hypot(0.43, 3.0 * 0.55), 1e-9);
  EXPECT_LT(rankingDistance(c, a, p), rankingDistance(c, b, p));
  // Seen recently, without a heading, or with weight 1: the plain distance.
  b.since_last = 0.02;
  EXPECT_NEAR(rankingDistance(c, b, p), (c - b.box.center).norm(), 1e-9);
  b.since_last = 2.4;
  b.seen_velocity = {0.0, -0.1};
  EXPECT_NEAR(rankingDistance(c, b, p), (c - b.box.center).norm(), 1e-9);
  b.seen_velocity = {0.0, -0.8};
  p.cross_rank_weight = 1.0;
  EXPECT_NEAR(rankingDistance(c, b, p), (c - b.box.center).norm(), 1e-9);
}
