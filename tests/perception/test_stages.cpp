#include <algorithm>
// The pipeline's stages on hand-made inputs: angular bins, the measurement of a merged
// cluster, point-level recovery and its conflicts with object-level matches, and the track
// lifecycle.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/perception/angular_grid.hpp"
#include "ucon/perception/detection.hpp"
#include "ucon/perception/measurement.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/reassociation.hpp"
#include "ucon/perception/track_manager.hpp"
#include "ucon/tracked_object_t.hpp"

using namespace ucon::perception;
using TO = ucon::tracked_object_t;

namespace {

// A vertical line of 7 points at (x, y), z = 0.3 .. 1.5 [m].
void addColumn(Points* p, float x, float y) {
  for (int k = 0; k < 7; ++k) p->emplace_back(x, y, 0.3f + 0.2f * static_cast<float>(k));
}

std::vector<int> range(int from, int to) {
  std::vector<int> v;
  for (int i = from; i < to; ++i) v.push_back(i);
  return v;
}

}  // namespace

TEST(AngularGrid, GivenDirectionsThenBinsFollowAzimuthAndElevationAndClampAtThePoles) {
  const AngularGrid g(2.0);
  EXPECT_EQ(g.azimuthBins(), 180);
  EXPECT_EQ(g.elevationBins(), 90);
  EXPECT_EQ(g.size(), 180 * 90);
  // +x, level: azimuth pi (shifted), elevation pi/2 -> bins 90 and 45.
  EXPECT_EQ(g.bin(Eigen::Vector3f(1, 0, 0)), 90 * 90 + 45);
  // 3 degrees to the left lands one azimuth bin over, the same elevation bin.
  const float a = static_cast<float>(3.0 * M_PI / 180.0);
  EXPECT_EQ(g.bin(Eigen::Vector3f(std::cos(a), std::sin(a), 0)), 91 * 90 + 45);
  // Straight up: the last elevation bin (clamped), whatever the azimuth.
  EXPECT_EQ(g.bin(Eigen::Vector3f(0, 0, 1)) % 90, 89);
}

TEST(AngularGrid, GivenABinThenItsNeighboursWrapInAzimuthAndStopAtThePoles) {
  const AngularGrid g(2.0);
  int nb[8];
  // Inside the grid: the 8 bins around.
  ASSERT_EQ(g.neighbours(90 * 90 + 45, nb), 8);
  std::vector<int> got(nb, nb + 8);
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, (std::vector<int>{89 * 90 + 44, 89 * 90 + 45, 89 * 90 + 46, 90 * 90 + 44, 90 * 90 + 46, 91 * 90 + 44,
                                   91 * 90 + 45, 91 * 90 + 46}));
  // Azimuth bin 0 borders the last azimuth bin (the circle closes).
  ASSERT_EQ(g.neighbours(0 * 90 + 45, nb), 8);
  got.assign(nb, nb + 8);
  EXPECT_NE(std::find(got.begin(), got.end(), 179 * 90 + 45), got.end());
  // The top elevation bin has no bins above it.
  EXPECT_EQ(g.neighbours(10 * 90 + 89, nb), 5);
}

TEST(Detector, GivenSparseReturnsFarAwayThenTheFarToleranceJoinsThemButNotNearOnes) {
  // Two sparse "people" of five returns 0.42 m apart (more than cluster_tolerance, less than
  // far_cluster_tolerance): one 12 m from the sensor, one 4 m from it; and a dense one at 4 m
  // on the other side. Only the far sparse one is joined by the second pass; the near clusters
  // are those of the first pass.
  SegmentationParams s;
  ASSERT_LT(s.cluster_tolerance, 0.42);
  ASSERT_GT(s.far_cluster_tolerance, 0.42);
  ASSERT_LT(s.far_cluster_range, 12.0 - 1.0);
  ASSERT_GT(s.far_cluster_range, 4.0 + 1.0);
  ASSERT_LE(s.min_cluster_points, 5);
  Frame f;
  f.sensor_origin = Eigen::Vector3f(0.0f, 0.0f, 0.5f);
  const auto sparse = [&](float x) {
    for (int k = 0; k < 5; ++k) f.points.emplace_back(x, -0.84f + 0.42f * static_cast<float>(k), 1.0f);
  };
  sparse(12.0f);   // points 0-4
  sparse(4.0f);    // points 5-9
  addColumn(&f.points, -4.0f, 0.0f);  // points 10-16
  Detector d(s);
  const auto groups = d.cluster(f);
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0], range(10, 17));  // the near dense column, from the first pass
  auto far = groups[1];
  std::sort(far.begin(), far.end());
  EXPECT_EQ(far, range(0, 5));  // the far sparse one; the near sparse one stays noise

  // Off (the far tolerance at most the near one): the far sparse returns are noise too.
  s.far_cluster_tolerance = s.cluster_tolerance;
  Detector off(s);
  EXPECT_EQ(off.cluster(f).size(), 1u);
}

TEST(RestrictToTrack, GivenAClusterMergedWithAPillarThenOnlyTheMovedPointsInThePredictedBoxMeasureTheTrack) {
  // A person (0.4 m) at x = 3 and a pillar 0.35 m beside it: one cluster 0.75 m wide.
  Points pts;
  for (float dy : {-0.2f, 0.0f, 0.2f}) addColumn(&pts, 3.0f, dy);      // person: 0..20
  const int n_person = static_cast<int>(pts.size());
  for (float dy : {0.55f, 0.6f}) addColumn(&pts, 3.0f, dy);            // pillar
  const std::vector<int> all = range(0, static_cast<int>(pts.size()));
  std::vector<char> moved(pts.size(), 0);
  for (int i = 0; i < n_person; ++i) moved[i] = 1;
  const Eigen::Vector2d center(3.0, 0.0), size(0.4, 0.4);
  // Not larger than the track's box by the margin: all of it.
  EXPECT_EQ(restrictToTrack(pts, moved, center, size, 1.0, all), all);
  // Larger by more than 0.3 m: the moved points inside the box grown by the margin.
  EXPECT_EQ(restrictToTrack(pts, moved, center, size, 0.3, all), range(0, n_person));
  // Without motion evidence: the points inside the grown box (the person's again).
  const std::vector<char> none(pts.size(), 0);
  EXPECT_EQ(restrictToTrack(pts, none, center, size, 0.3, all), range(0, n_person));
  EXPECT_DOUBLE_EQ(movedShare(moved, all), static_cast<double>(n_person) / static_cast<double>(pts.size()));
}

namespace {

// A lost track last seen `tau` s ago at (x, y) walking at (vx, vy), its history a column
// pair, predicted at its last place moved by v tau.
LostTrack lostAt(double x, double y, double vx, double vy, double tau) {
  LostTrack l;
  addColumn(&l.history.points, static_cast<float>(x), static_cast<float>(y) - 0.1f);
  addColumn(&l.history.points, static_cast<float>(x), static_cast<float>(y) + 0.1f);
  l.history.velocity = {vx, vy, 0.0};
  l.history.tau = tau;
  l.view.box.center = {x + vx * tau, y + vy * tau};
  l.view.box.size = {0.4, 0.4};
  l.view.seen_velocity = {vx, vy};
  l.view.since_last = tau;
  return l;
}

struct Scene {
  Points points;
  ProximityIndex index;
};

// The frame: the lost person's points where it walked to (x + vx tau), 0..13, and a wall far away.
void frameWithPersonAt(Scene* s, float x, float y) {
  addColumn(&s->points, x, y - 0.1f);
  addColumn(&s->points, x, y + 0.1f);
  for (float wy = -2.0f; wy <= 2.0f; wy += 0.2f) addColumn(&s->points, 8.0f, wy);
  s->index.build(s->points, PaperParams{}.d0);
}

}  // namespace

TEST(RecoverLostTracks, GivenALostTracksPointsWhereItWalkedThenItIsRecoveredUnlessAMatchHoldsThem) {
  const PerceptionParams p;
  Scene s;
  frameWithPersonAt(&s, 3.5f, 0.0f);
  const std::vector<LostTrack> lost{lostAt(3.0, 0.0, 1.0, 0.0, 0.5)};
  const Eigen::Vector2d sensor(0.0, 0.0);
  const auto r = recoverLostTracks(lost, s.points, s.index, {}, sensor, p);
  ASSERT_EQ(r.points.size(), 1u);
  EXPECT_EQ(r.points[0], range(0, 14));
  EXPECT_TRUE(mostlyClaimed(range(0, 14), r.claimed));
  EXPECT_TRUE(mostlyClaimed(range(0, 28), r.claimed));   // 14 of 28: half counts
  EXPECT_FALSE(mostlyClaimed(range(0, 29), r.claimed));  // 14 of 29: less than half
  // The same points measured by an object-level match stay with it: no recovery, nothing claimed.
  const std::vector<int> match = range(0, 14);
  const auto held = recoverLostTracks(lost, s.points, s.index, {&match}, sensor, p);
  EXPECT_TRUE(held.points[0].empty());
  EXPECT_FALSE(mostlyClaimed(range(0, 14), held.claimed));
  // A match holding one column: the lost track keeps the other.
  const std::vector<int> half = range(0, 7);
  const auto rest = recoverLostTracks(lost, s.points, s.index, {&half}, sensor, p);
  EXPECT_EQ(rest.points[0], range(7, 14));
}

TEST(RecoverLostTracks, GivenPointsAwayFromThePredictionOrAcrossTheHeadingThenTheyAreNoRecovery) {
  PerceptionParams p;
  const Eigen::Vector2d sensor(0.0, 0.0);
  // The points lie 0.5 m ahead of the prediction along the heading: within d0 of the displaced
  // history, farther than max_shift (0.4 m) from the prediction.
  {
    Scene s;
    frameWithPersonAt(&s, 4.0f, 0.0f);
    LostTrack l = lostAt(3.0, 0.0, 1.0, 0.0, 0.5);
    l.history.velocity = {2.0, 0.0, 0.0};  // the history displaced onto the points
    const auto r = recoverLostTracks({l}, s.points, s.index, {}, sensor, p);
    EXPECT_TRUE(r.points[0].empty());
    EXPECT_TRUE(mostlyClaimed(range(0, 14), r.claimed));  // claimed all the same: no new track there
  }
  // Across the heading of a track unseen 0.5 s: the points re-associated (the nearer column,
  // 0.25 m across) pass the shipped cross gate, 0.4 + 0.15 * 0.5 = 0.475 m, not one of
  // 0.05 + 0.075 m (a neighbour's line).
  {
    Scene s;
    frameWithPersonAt(&s, 3.5f, 0.35f);
    const LostTrack l = lostAt(3.0, 0.0, 1.0, 0.0, 0.5);
    EXPECT_EQ(recoverLostTracks({l}, s.points, s.index, {}, sensor, p).points[0], range(0, 7));
    p.object_association.cross_gate = 0.05;
    EXPECT_TRUE(recoverLostTracks({l}, s.points, s.index, {}, sensor, p).points[0].empty());
  }
}

namespace {

// A measurement of a 0.4 m object centred at (x, y).
Measurement measurementAt(double x, double y) {
  Measurement m;
  m.center = {x, y, 0.9};
  m.box.center = {x, y};
  m.box.size = {0.4, 0.4};
  m.size_z = 1.2;
  m.width = 0.4;
  addColumn(&m.points, static_cast<float>(x), static_cast<float>(y));
  return m;
}

// A frame whose nearest return in every direction is `range` metres from the sensor.
Frame frameSeeing(double range, const AngularGrid& coarse) {
  Frame f;
  f.nearest_coarse.assign(static_cast<std::size_t>(coarse.size()), static_cast<float>(range));
  return f;
}

// Starts a walker at (3, 0) going +x at 1.2 m/s, measured every 0.1 s until confirmed;
// returns the frame time reached [us] (0 if it never was).
int64_t confirmWalker(TrackManager* tm, ucon::StatusReport* status, const AngularGrid& coarse) {
  const int64_t t0 = 1'000'000'000, dt = 100'000;
  if (!tm->start(measurementAt(3.0, 0.0), t0, *status)) return 0;
  const Frame f = frameSeeing(3.0, coarse);  // returns at the track: not seen through
  for (int k = 1; k <= 10; ++k) {
    const int64_t t = t0 + k * dt;
    tm->predict(t, *status);
    tm->update(0, measurementAt(3.0 + 0.12 * k, 0.0), t, TO::ASSOC_OBJECT, true, false, *status);
    tm->manage(t, {1}, f, *status);
    if (tm->tracks()[0].state == TO::STATE_CONFIRMED) return t;
  }
  return 0;
}

}  // namespace

TEST(TrackManager, GivenAWalkerMeasuredEachFrameThenItsTrackIsConfirmedAfterConfirmHits) {
  const PerceptionParams p;  // confirm_hits 4, confirm_min_distance 0.3 m, confirm_moving_hits 3
  const AngularGrid coarse(p.tracks.free_bin_deg);
  TrackManager tm(p, coarse);
  ucon::StatusReport status("test");
  const int64_t t = confirmWalker(&tm, &status, coarse);
  // Hits: the start and 3 updates; it moved 0.36 m >= 0.3 m at a walking speed.
  EXPECT_EQ(t, 1'000'000'000 + 3 * 100'000);
  EXPECT_EQ(status.counter("tracks_confirmed"), 1);
  EXPECT_NEAR(tm.tracks()[0].kf.state()(3), 1.2, 0.4);
  EXPECT_TRUE(tm.nearTrack(tm.tracks()[0].kf.state().head<2>() + Eigen::Vector2d(0.5, 0.0)));  // within 0.7 m
  EXPECT_FALSE(tm.nearTrack(tm.tracks()[0].kf.state().head<2>() + Eigen::Vector2d(0.8, 0.0)));
}

// A person whose track was lost (seen through: deleted) comes back standing: a new track
// there never moves the 0.3 m that confirms one. Within the re-identification gate of the lost
// track it is confirmed on its hits alone and takes over the identity; farther away, or with
// reid_confirm off, it stays tentative (static clutter is not confirmed for standing still).
TEST(TrackManager, GivenALostWalkerBackStandingThenItsNewTrackIsConfirmedOnlyWithinTheGate) {
  for (const bool reid_confirm : {true, false})
    for (const double back_at : {4.0, 7.0}) {
      PerceptionParams p;  // reid_speed 1.8 m/s, reid_margin 0.5 m, confirm_hits 4
      p.tracks.reid_confirm = reid_confirm;
      const AngularGrid coarse(p.tracks.free_bin_deg);
      TrackManager tm(p, coarse);
      ucon::StatusReport status("test");
      int64_t t = confirmWalker(&tm, &status, coarse);
      ASSERT_GT(t, 0);
      const int64_t id = tm.tracks()[0].id;
      // Seen through (a wall 10 m behind it): deleted after free_frames, remembered as lost.
      const Frame far = frameSeeing(10.0, coarse);
      for (int k = 0; k < 5 && !tm.tracks().empty(); ++k) {
        t += 20'000;
        tm.predict(t, status);
        tm.manage(t, {0}, far, status);
      }
      ASSERT_TRUE(tm.tracks().empty());
      // 0.2 s later a standing object at `back_at` (the walker was last at 3.36 m): 0.86 m
      // from it lies within 1.8 * 0.2 + 0.5 m, 3.6 m does not.
      t += 200'000;
      ASSERT_TRUE(tm.start(measurementAt(back_at, 0.0), t, status));
      const Frame f = frameSeeing(back_at, coarse);
      for (int k = 1; k <= 5; ++k) {
        t += 20'000;
        tm.predict(t, status);
        tm.update(0, measurementAt(back_at, 0.0), t, TO::ASSOC_OBJECT, true, false, status);
        tm.manage(t, {1}, f, status);
      }
      ASSERT_EQ(tm.tracks().size(), 1u);
      const bool expect = reid_confirm && back_at < 5.0;
      EXPECT_EQ(tm.tracks()[0].state, expect ? TO::STATE_CONFIRMED : TO::STATE_TENTATIVE)
          << "reid_confirm " << reid_confirm << ", back at " << back_at << " m";
      EXPECT_EQ(tm.tracks()[0].id == id, expect);
      EXPECT_EQ(status.counter("tracks_confirmed_returning"), expect ? 1 : 0);
    }
}

TEST(TrackManager, GivenATrackMeasuredOnOldStructureForStructureFramesInARowThenItIsDeleted) {
  const PerceptionParams p;  // structure_frames 5
  const AngularGrid coarse(p.tracks.free_bin_deg);
  for (const bool broken : {false, true}) {
    TrackManager tm(p, coarse);
    ucon::StatusReport status("test");
    int64_t t = confirmWalker(&tm, &status, coarse);
    ASSERT_GT(t, 0);
    const Frame f = frameSeeing(3.0, coarse);
    // Measurements on structure, with one that is not (the walker's own cells) in between when
    // `broken`: only an unbroken run of structure_frames ends the track.
    for (int k = 1; k <= p.tracks.structure_frames + 1; ++k) {
      t += 100'000;
      tm.predict(t, status);
      const bool on_structure = !(broken && k == 3);
      tm.update(0, measurementAt(3.4 + 0.12 * k, 0.0), t, TO::ASSOC_OBJECT, true, on_structure, status);
      tm.manage(t, {1}, f, status);
      if (tm.tracks().empty()) break;
    }
    EXPECT_EQ(tm.tracks().empty(), !broken) << (broken ? "broken run" : "unbroken run");
    EXPECT_EQ(status.counter("tracks_on_structure"), broken ? 0 : 1);
  }
}

TEST(TrackManager, GivenAnUnseenTrackTheSensorSeesThroughThenItIsDeletedAfterFreeFramesOtherwiseItCoasts) {
  const PerceptionParams p;  // free_frames 3, free_margin 0.5 m, max_coast 1.5 s
  const AngularGrid coarse(p.tracks.free_bin_deg);
  for (const double seen : {10.0, 3.2}) {  // a wall 10 m away behind it / returns in front of it
    TrackManager tm(p, coarse);
    ucon::StatusReport status("test");
    int64_t t = confirmWalker(&tm, &status, coarse);
    ASSERT_GT(t, 0);
    const Frame f = frameSeeing(seen, coarse);
    int unseen_frames = 0;
    for (int k = 1; k <= 10 && !tm.tracks().empty(); ++k) {
      t += 20'000;
      tm.predict(t, status);
      tm.manage(t, {0}, f, status);
      if (!tm.tracks().empty()) {
        EXPECT_EQ(tm.tracks()[0].state, TO::STATE_COASTING);
        ++unseen_frames;
      }
    }
    EXPECT_EQ(unseen_frames, seen > 5.0 ? 2 : 10) << "nearest return " << seen << " m";
  }
}

TEST(SplitByNearest, GivenTwoCentresThenEachPointGoesToTheNearerAndTiesToTheFirst) {
  const ucon::perception::Points pts{{0.0f, 0.0f, 1.0f}, {0.4f, 0.0f, 1.0f}, {0.5f, 0.0f, 1.0f}, {1.0f, 0.1f, 1.0f}};
  const std::vector<int> indices{0, 1, 2, 3};
  const auto parts = ucon::perception::splitByNearest(pts, indices, {{0.0, 0.0}, {1.0, 0.0}});
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0], (std::vector<int>{0, 1, 2}));  // 0.5 is equally far: the first centre
  EXPECT_EQ(parts[1], (std::vector<int>{3}));
  // Only the listed indices; no centre: no parts.
  EXPECT_EQ(ucon::perception::splitByNearest(pts, {3}, {{0.0, 0.0}, {1.0, 0.0}})[1], (std::vector<int>{3}));
  EXPECT_TRUE(ucon::perception::splitByNearest(pts, indices, {}).empty());
}

TEST(TrackManager, GivenANewTrackThenItsVelocitySettlesOnlyAfterSomeMeasurements) {
  const PerceptionParams p;  // initial_velocity_std 1.0 m/s, velocity_std 0.4 m/s
  const AngularGrid coarse(p.tracks.free_bin_deg);
  TrackManager tm(p, coarse);
  ucon::StatusReport status("test");
  ASSERT_TRUE(tm.start(measurementAt(3.0, 0.0), 1'000'000'000, status));
  EXPECT_FALSE(velocitySettled(tm.tracks()[0], p.kalman.velocity_std)) << "a new track's velocity is a guess";
  const Frame f = frameSeeing(3.0, coarse);
  int settled_after = 0;
  for (int k = 1; k <= 20 && settled_after == 0; ++k) {
    const int64_t t = 1'000'000'000 + k * 20'000;
    tm.predict(t, status);
    tm.update(0, measurementAt(3.0 + 0.024 * k, 0.0), t, TO::ASSOC_OBJECT, true, false, status);
    tm.manage(t, {1}, f, status);
    if (velocitySettled(tm.tracks()[0], p.kalman.velocity_std)) settled_after = k;
  }
  EXPECT_GT(settled_after, 0);
  EXPECT_LE(settled_after, 5) << "a few measurements settle it";
  // Coasting, the variance grows again.
  for (int k = 21; k <= 100; ++k) tm.predict(1'000'000'000 + k * 20'000, status);
  EXPECT_FALSE(velocitySettled(tm.tracks()[0], p.kalman.velocity_std));
}
