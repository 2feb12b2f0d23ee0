// CLEAR-MOT on hand-computed sequences (docs/reference.md §6). Each expected number is derived in
// the comment above its check.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/mot/clear_mot.hpp"
#include "ucon/mot/mot_challenge.hpp"

using ucon::mot::Box;
using ucon::mot::ClearMotAccumulator;
using ucon::mot::PointXY;

TEST(ClearMot, GivenAnObjectLostForAFrameWhenAnotherHypothesisPicksItUpThenItIsASwitch) {
  ClearMotAccumulator acc;
  // frame 1: object 1 matched to hypothesis 10
  auto e1 = acc.updateXY({{1, 0.0, 0.0}}, {{10, 0.0, 0.0}}, 1.0);
  ASSERT_EQ(e1.matches.size(), 1u);
  // frame 2: no hypothesis -> miss
  auto e2 = acc.updateXY({{1, 0.0, 0.0}}, {}, 1.0);
  EXPECT_EQ(e2.misses.size(), 1u);
  // frame 3: hypothesis 11 at 0.1 m -> a match and, after the gap, an identity switch
  auto e3 = acc.updateXY({{1, 0.0, 0.0}}, {{11, 0.1, 0.0}}, 1.0);
  ASSERT_EQ(e3.switches.size(), 1u);
  EXPECT_EQ(e3.switches[0].second, 11);
  const auto s = acc.summary();
  EXPECT_EQ(s.num_objects, 3);
  EXPECT_EQ(s.num_matches, 2);
  EXPECT_EQ(s.num_misses, 1);
  EXPECT_EQ(s.num_switches, 1);
  EXPECT_EQ(s.num_false_positives, 0);
  EXPECT_EQ(s.num_fragmentations, 1);
  // MOTA = 1 - (1 FN + 0 FP + 1 IDSW) / 3
  EXPECT_NEAR(s.mota, 1.0 / 3.0, 1e-12);
  // MOTP = (0 + 0.1) / 2
  EXPECT_NEAR(s.motp, 0.05, 1e-12);
  EXPECT_NEAR(s.mismatch_rate, 1.0 / 3.0, 1e-12);
}

TEST(ClearMot, GivenTheSameHypothesisAfterAGapThenNoSwitchIsCounted) {
  ClearMotAccumulator acc;
  acc.updateXY({{1, 0.0, 0.0}}, {{10, 0.0, 0.0}}, 1.0);
  acc.updateXY({{1, 0.0, 0.0}}, {}, 1.0);
  acc.updateXY({{1, 0.0, 0.0}}, {{10, 0.2, 0.0}}, 1.0);
  EXPECT_EQ(acc.summary().num_switches, 0);
}

TEST(ClearMot, GivenAPreviousPairStillWithinTheThresholdThenItIsKeptOverACheaperAssignment) {
  ClearMotAccumulator acc;
  acc.updateXY({{1, 0.0, 0.0}, {2, 2.0, 0.0}}, {{10, 0.0, 0.0}, {20, 2.0, 0.0}}, 1.0);
  // Frame 2: the cheapest assignment would be 1-20 (0.05) + 2-10 (0.1) = 0.15, but the old
  // pairs 1-10 (0.5) and 2-20 (0.55) are both still within 1 m and must be kept.
  auto e = acc.updateXY({{1, 0.0, 0.0}, {2, 0.6, 0.0}}, {{10, 0.5, 0.0}, {20, 0.05, 0.0}}, 1.0);
  ASSERT_EQ(e.matches.size(), 2u);
  EXPECT_EQ(e.matches[0], std::make_pair(int64_t{1}, int64_t{10}));
  EXPECT_EQ(e.matches[1], std::make_pair(int64_t{2}, int64_t{20}));
  EXPECT_TRUE(e.switches.empty());
  const auto s = acc.summary();
  EXPECT_EQ(s.num_switches, 0);
  EXPECT_NEAR(s.motp, (0.0 + 0.0 + 0.5 + 0.55) / 4.0, 1e-12);
  EXPECT_NEAR(s.mota, 1.0, 1e-12);
}

TEST(ClearMot, GivenAPreviousPairBeyondTheThresholdThenTheObjectIsReassignedWithASwitch) {
  ClearMotAccumulator acc;
  acc.updateXY({{1, 0.0, 0.0}}, {{10, 0.0, 0.0}}, 1.0);
  // 10 drifted 1.5 m away (forbidden); 11 is at 0.2 m -> switch, and 10 is a false positive.
  auto e = acc.updateXY({{1, 0.0, 0.0}}, {{10, 1.5, 0.0}, {11, 0.2, 0.0}}, 1.0);
  ASSERT_EQ(e.switches.size(), 1u);
  ASSERT_EQ(e.false_positives.size(), 1u);
  EXPECT_EQ(e.false_positives[0], 10);
  const auto s = acc.summary();
  // MOTA = 1 - (0 + 1 + 1) / 2 = 0
  EXPECT_NEAR(s.mota, 0.0, 1e-12);
}

TEST(ClearMot, GivenFramesWithoutGroundTruthThenHypothesesAreFalsePositivesAndMotaCanBeNegative) {
  ClearMotAccumulator acc;
  // frame 1: no objects, two hypotheses -> 2 FP, 0 objects
  auto e1 = acc.updateXY({}, {{10, 0.0, 0.0}, {11, 3.0, 0.0}}, 1.0);
  EXPECT_EQ(e1.false_positives.size(), 2u);
  // frame 2: nothing at all
  acc.updateXY({}, {}, 1.0);
  // frame 3: one object matched by 10
  acc.updateXY({{1, 0.0, 0.0}}, {{10, 0.3, 0.4}}, 1.0);
  const auto s = acc.summary();
  EXPECT_EQ(s.num_frames, 3);
  EXPECT_EQ(s.num_objects, 1);
  EXPECT_EQ(s.num_predictions, 3);
  EXPECT_EQ(s.num_false_positives, 2);
  EXPECT_EQ(s.num_matches, 1);
  // MOTA = 1 - 2 / 1 = -1; precision = 1 / 3; recall = 1; MOTP = 0.5 m
  EXPECT_NEAR(s.mota, -1.0, 1e-12);
  EXPECT_NEAR(s.precision, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.recall, 1.0, 1e-12);
  EXPECT_NEAR(s.motp, 0.5, 1e-12);
  EXPECT_NEAR(s.fp_rate, 2.0, 1e-12);
}

TEST(ClearMot, GivenManyFalsePositivesAndMissesThenMotaIsNegative) {
  ClearMotAccumulator acc;
  for (int f = 0; f < 2; ++f) acc.updateXY({{1, 0.0, 0.0}}, {{10, 5.0, 5.0}, {11, 6.0, 6.0}}, 1.0);
  const auto s = acc.summary();
  // per frame 1 FN + 2 FP; MOTA = 1 - 6 / 2 = -2
  EXPECT_EQ(s.num_misses, 2);
  EXPECT_EQ(s.num_false_positives, 4);
  EXPECT_NEAR(s.mota, -2.0, 1e-12);
  EXPECT_EQ(s.mostly_lost, 1);
  EXPECT_TRUE(std::isnan(s.motp));
}

TEST(ClearMot, GivenNoFramesThenRatiosAreNaN) {
  const auto s = ClearMotAccumulator().summary();
  EXPECT_TRUE(std::isnan(s.mota));
  EXPECT_TRUE(std::isnan(s.recall));
  EXPECT_TRUE(std::isnan(s.precision));
}

TEST(ClearMot, GivenObjectsTrackedForDifferentSharesThenMostlyTrackedPartiallyAndLostAreCounted) {
  ClearMotAccumulator acc;
  for (int f = 0; f < 5; ++f) {
    std::vector<PointXY> hyps{{10, 0.0, 0.0}};  // object 1: 5/5 -> mostly tracked
    if (f < 2) hyps.push_back({30, 20.0, 0.0});  // object 3: 2/5 -> partially tracked
    acc.updateXY({{1, 0.0, 0.0}, {2, 10.0, 0.0}, {3, 20.0, 0.0}}, hyps, 1.0);  // object 2: 0/5
  }
  const auto s = acc.summary();
  EXPECT_EQ(s.num_unique_objects, 3);
  EXPECT_EQ(s.mostly_tracked, 1);
  EXPECT_EQ(s.partially_tracked, 1);
  EXPECT_EQ(s.mostly_lost, 1);
}

TEST(ClearMot, GivenAPairExactlyAtTheThresholdThenItIsAllowed) {
  ClearMotAccumulator acc;
  acc.updateXY({{1, 0.0, 0.0}}, {{10, 1.0, 0.0}}, 1.0);
  acc.updateXY({{1, 0.0, 0.0}}, {{10, 1.0001, 0.0}}, 1.0);
  const auto s = acc.summary();
  EXPECT_EQ(s.num_matches, 1);
  EXPECT_EQ(s.num_misses, 1);
}

TEST(ClearMot, GivenAMalformedDistanceMatrixThenNothingMatchesInsteadOfCrashing) {
  ClearMotAccumulator acc;
  acc.update({1, 2}, {10}, ucon::CostMatrix(1, 1, 0.0));
  const auto s = acc.summary();
  EXPECT_EQ(s.num_misses, 2);
  EXPECT_EQ(s.num_false_positives, 1);
}

TEST(BoxIou, GivenOverlappingBoxesThenIouMatchesTheHandValueAndTheThresholdForbidsPairs) {
  const Box a{1, 0, 0, 2, 2}, b{2, 1, 0, 2, 2};  // intersection 2, union 6
  EXPECT_NEAR(ucon::mot::boxIou(a, b), 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(ucon::mot::boxIou(a, Box{3, 5, 5, 1, 1}), 0.0, 1e-12);
  const auto forbidden = ucon::mot::iouDistances({a}, {b}, 0.5);
  EXPECT_FALSE(std::isfinite(forbidden(0, 0)));
  const auto allowed = ucon::mot::iouDistances({a}, {b}, 0.3);
  EXPECT_NEAR(allowed(0, 0), 2.0 / 3.0, 1e-12);
}

TEST(MotChallenge, GivenTextWithNegativeConfidenceThenNoRowIsDroppedAndFramesAreGrouped) {
  std::string err;
  const auto f = ucon::mot::parseMotChallenge(
      "1,1,10,20,30,40,-1,-1,-1,-1\n1, 2, 0,0,5,5,0.1\n\n3 1 10 20 30 40 -1\n", "gt.txt", &err);
  ASSERT_TRUE(f) << err;
  ASSERT_EQ(f->size(), 2u);
  EXPECT_EQ(f->at(1).size(), 2u);
  EXPECT_EQ(f->at(3).size(), 1u);
  EXPECT_EQ(f->at(1)[0].id, 1);
  EXPECT_DOUBLE_EQ(f->at(1)[0].w, 30.0);
}

TEST(MotChallenge, GivenAMalformedLineThenTheErrorNamesTheFileAndLine) {
  std::string err;
  EXPECT_FALSE(ucon::mot::parseMotChallenge("1,1,0,0,1,1\n2,1,abc,0,1,1\n", "p.txt", &err));
  EXPECT_NE(err.find("p.txt:2"), std::string::npos) << err;
  EXPECT_FALSE(ucon::mot::parseMotChallenge("1,1,0,0\n", "p.txt", &err));
  EXPECT_NE(err.find("p.txt:1"), std::string::npos) << err;
  EXPECT_FALSE(ucon::mot::parseMotChallenge("0,1,0,0,1,1\n", "p.txt", &err));
  EXPECT_FALSE(ucon::mot::parseMotChallenge("1,1,0,0,-1,1\n", "p.txt", &err));
  EXPECT_FALSE(ucon::mot::parseMotChallenge("1,1,nan,0,1,1\n", "p.txt", &err));
}

TEST(MotChallenge, GivenGroundTruthAndPredictionsThenBoxesAreMatchedByIou) {
  std::string err;
  const auto gt = ucon::mot::parseMotChallenge("1,1,0,0,10,10\n2,1,0,0,10,10\n", "gt", &err);
  // frame 1: IoU 1 match; frame 2: shifted by 5 px -> IoU 50/150 = 1/3 < 0.5 -> FN + FP;
  // frame 3: a prediction without ground truth -> FP.
  const auto pr = ucon::mot::parseMotChallenge("1,7,0,0,10,10\n2,7,5,0,10,10\n3,7,0,0,1,1\n", "pr", &err);
  ASSERT_TRUE(gt && pr);
  const auto s = ucon::mot::evaluateBoxes(*gt, *pr, 0.5);
  EXPECT_EQ(s.num_frames, 3);
  EXPECT_EQ(s.num_matches, 1);
  EXPECT_EQ(s.num_misses, 1);
  EXPECT_EQ(s.num_false_positives, 2);
  EXPECT_NEAR(s.mota, 1.0 - 3.0 / 2.0, 1e-12);
  EXPECT_NEAR(s.motp, 0.0, 1e-12);
}

TEST(ClearMot, GivenAnIgnoredObjectThenItAndItsMatchedHypothesisAreNotScoredAndItsHistoryIsKept) {
  ClearMotAccumulator acc;
  acc.updateXY({{1, 0.0, 0.0}}, {{10, 0.0, 0.0}}, 1.0);
  // Frame 2: object 1 is hidden (ignored). The matching keeps the previous pair 1-10 although
  // 11 is nearer, so 10 is absorbed by the ignored object; 11 and 12 are false positives.
  const std::vector<char> hidden{1};
  auto e = acc.updateXY({{1, 0.0, 0.0}}, {{10, 0.3, 0.0}, {11, 0.1, 0.0}, {12, 5.0, 0.0}}, 1.0, &hidden);
  EXPECT_TRUE(e.matches.empty());
  EXPECT_TRUE(e.misses.empty());
  ASSERT_EQ(e.ignored.size(), 1u);
  EXPECT_EQ(e.ignored[0].second, 10);
  EXPECT_EQ(e.false_positives.size(), 2u);
  // Frame 3: visible again and matched by 11: a switch against 10, the last scored match.
  auto e3 = acc.updateXY({{1, 0.0, 0.0}}, {{11, 0.0, 0.0}}, 1.0);
  EXPECT_EQ(e3.switches.size(), 1u);
  const auto s = acc.summary();
  EXPECT_EQ(s.num_objects, 2);
  EXPECT_EQ(s.num_ignored, 1);
  EXPECT_EQ(s.num_predictions, 4);  // 10 (frame 1), 11 and 12 (frame 2), 11 (frame 3)
  EXPECT_EQ(s.num_false_positives, 2);
  // MOTA = 1 - (0 FN + 2 FP + 1 IDSW) / 2
  EXPECT_NEAR(s.mota, -0.5, 1e-12);
}
