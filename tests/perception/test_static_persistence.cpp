// StaticPersistence: a point reaches PERCEPTION_STATIC only once its x-y cell has been occupied
// for the persistence time; movers never hold a cell that long.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "ucon/perception/static_persistence.hpp"

using ucon::perception::StaticPersistence;

namespace {
constexpr int64_t kT0 = 5'000'000;
constexpr int64_t kDt = 20'000;  // 50 Hz
}  // namespace

TEST(StaticPersistence, GivenAFixedPointThenItPassesExactlyOnceItsCellWasOccupiedForThePersistence) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  const std::vector<Eigen::Vector3f> pts{{1.05f, 2.05f, 1.0f}, {1.15f, 2.15f, 0.5f}};  // one cell
  std::vector<char> ok;
  for (int k = 0; k <= 30; ++k) {
    sp.update(kT0 + k * kDt, pts, &ok);
    ASSERT_EQ(ok.size(), 2u);
    const bool expected = k * kDt >= 500'000;  // k >= 25
    EXPECT_EQ(ok[0] != 0, expected) << "frame " << k;
    EXPECT_EQ(ok[1], ok[0]);
  }
}

TEST(StaticPersistence, GivenAPointMovingAtWalkingSpeedThenItNeverPasses) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  std::vector<char> ok;
  for (int k = 0; k < 200; ++k) {
    const float x = 0.5f * static_cast<float>(k) * 0.02f;  // 0.5 m/s: 0.4 s per 0.2 m cell
    sp.update(kT0 + k * kDt, {{x, 0.1f, 1.0f}}, &ok);
    EXPECT_EQ(ok[0], 0) << "frame " << k;
  }
}

TEST(StaticPersistence, GivenACellUnseenForLongerThanTheGapThenItStartsOver) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  const std::vector<Eigen::Vector3f> pt{{-3.0f, -4.0f, 1.0f}};
  std::vector<char> ok;
  int64_t t = kT0;
  for (int k = 0; k < 30; ++k, t += kDt) sp.update(t, pt, &ok);
  EXPECT_EQ(ok[0], 1);
  // A gap shorter than max_gap (0.2 s) keeps the run going...
  t += 200'000;
  sp.update(t, pt, &ok);
  EXPECT_EQ(ok[0], 1);
  // ... a longer one (0.4 s) starts it over.
  t += 400'000;
  sp.update(t, pt, &ok);
  EXPECT_EQ(ok[0], 0);
  for (int k = 0; k < 25; ++k) sp.update(t += kDt, pt, &ok);
  EXPECT_EQ(ok[0], 1);
}

TEST(StaticPersistence, GivenTimeGoingBackwardsOrBadPointsThenItResetsAndNeverCrashes) {
  StaticPersistence sp(0.2, 0.5, 0.3);
  const std::vector<Eigen::Vector3f> pt{{0.0f, 0.0f, 1.0f}};
  std::vector<char> ok;
  for (int k = 0; k < 30; ++k) sp.update(kT0 + k * kDt, pt, &ok);
  EXPECT_EQ(ok[0], 1);
  sp.update(kT0, pt, &ok);  // earlier than the last frame: a new log, start over
  EXPECT_EQ(ok[0], 0);
  const float nan = std::nanf("");
  sp.update(kT0 + kDt, {{nan, 0.0f, 1.0f}, {1e30f, 0.0f, 1.0f}, {0.0f, 0.0f, 1.0f}}, &ok);
  ASSERT_EQ(ok.size(), 3u);
  EXPECT_EQ(ok[0], 0);
  EXPECT_EQ(ok[1], 0);
  sp.update(kT0 + kDt, {}, &ok);
  EXPECT_TRUE(ok.empty());
  EXPECT_THROW(StaticPersistence(0.0, 0.5, 0.3), std::invalid_argument);
  EXPECT_THROW(StaticPersistence(0.2, -1.0, 0.3), std::invalid_argument);
  EXPECT_THROW(StaticPersistence(0.2, 0.5, 0.3, 100), std::invalid_argument);
}

TEST(StaticPersistence, GivenZeroPersistenceThenEveryFinitePointPasses) {
  StaticPersistence sp(0.2, 0.0, 0.3);
  std::vector<char> ok;
  sp.update(kT0, {{1.0f, 1.0f, 1.0f}, {7.0f, -2.0f, 0.4f}}, &ok);
  EXPECT_EQ(ok, (std::vector<char>{1, 1}));
}

namespace {
// A box face 3 m in front of the sensor, and frames in which someone 1.5 m away hides it.
struct HiddenBox {
  ucon::perception::AngularGrid grid{1.0};
  Eigen::Vector3f origin{0.0f, 0.0f, 0.5f};
  Eigen::Vector3f face{3.05f, 0.05f, 0.8f};
  std::vector<float> nearest;
  HiddenBox() { nearest.assign(static_cast<std::size_t>(grid.size()), INFINITY); }
  // The nearest return of the face's direction this frame is `range` metres away.
  StaticPersistence::Occlusion view(float range) {
    std::fill(nearest.begin(), nearest.end(), INFINITY);
    nearest[static_cast<std::size_t>(grid.bin(Eigen::Vector3f(face - origin)))] = range;
    StaticPersistence::Occlusion o;
    o.origin = origin;
    o.grid = &grid;
    o.nearest = &nearest;
    o.margin = 0.3f;
    return o;
  }
};

// Seen 0.6 s, then 1.5 s (five times max_gap) unhit with the nearest return of its direction at
// `gap_range`, then seen again: whether its point passes at once.
bool passesRightAfterTheGap(float gap_range, bool with_view, bool tracked = false) {
  HiddenBox b;
  StaticPersistence sp(0.2, 0.5, 0.3);
  std::vector<char> ok;
  int64_t t = kT0;
  const std::vector<char> on_track{static_cast<char>(tracked ? 1 : 0)};
  for (int k = 0; k < 30; ++k, t += kDt) {
    const auto o = b.view(std::hypot(b.face.x(), b.face.y()));
    sp.update(t, {b.face}, &ok, with_view ? &o : nullptr, &on_track);
  }
  EXPECT_EQ(ok[0], 1);
  for (int k = 0; k < 75; ++k, t += kDt) {
    const auto o = b.view(gap_range);
    sp.update(t, {}, &ok, with_view ? &o : nullptr);
  }
  const auto o = b.view(std::hypot(b.face.x(), b.face.y()));
  sp.update(t, {b.face}, &ok, with_view ? &o : nullptr);
  return ok[0] != 0;
}
}  // namespace

TEST(StaticPersistence, GivenACellHiddenBehindSomeoneNearerThenItKeepsItsRunThroughTheGap) {
  // A person 1.5 m away stands in front of the face for 1.5 s: the face is still structure.
  EXPECT_TRUE(passesRightAfterTheGap(1.5f, true));
  // Without the occlusion view the gap starts the cell over, as before.
  EXPECT_FALSE(passesRightAfterTheGap(1.5f, false));
}

TEST(StaticPersistence, GivenAHiddenCellLastHitByATrackThenItStartsOver) {
  // A tracked person standing there, hidden by someone passing in front, may walk off behind
  // them: no evidence that the cell stays occupied.
  EXPECT_FALSE(passesRightAfterTheGap(1.5f, true, true));
  EXPECT_TRUE(passesRightAfterTheGap(1.5f, true, false));
}

TEST(StaticPersistence, GivenACellNotHiddenThroughTheGapThenItStartsOver) {
  EXPECT_FALSE(passesRightAfterTheGap(INFINITY, true));  // no return in its direction at all
  EXPECT_FALSE(passesRightAfterTheGap(6.0f, true));      // seen through: the space is free
  EXPECT_FALSE(passesRightAfterTheGap(2.9f, true));      // nearer by less than the margin: its own surface
}

TEST(StaticPersistence, GivenAHiddenCellThenItIsHeldOnlyWhileItsRunLasts) {
  // Unhit and not hidden for longer than max_gap, the run ends; hiding it afterwards does not
  // bring it back.
  HiddenBox b;
  StaticPersistence sp(0.2, 0.5, 0.3);
  std::vector<char> ok;
  int64_t t = kT0;
  for (int k = 0; k < 30; ++k, t += kDt) {
    const auto o = b.view(3.0f);
    sp.update(t, {b.face}, &ok, &o);
  }
  const int64_t holds_before = sp.holds();
  for (int k = 0; k < 20; ++k, t += kDt) {  // 0.4 s > max_gap, nothing in front
    const auto o = b.view(INFINITY);
    sp.update(t, {}, &ok, &o);
  }
  for (int k = 0; k < 20; ++k, t += kDt) {
    const auto o = b.view(1.0f);
    sp.update(t, {}, &ok, &o);
  }
  EXPECT_EQ(sp.holds(), holds_before);
  EXPECT_EQ(sp.occupiedSince(b.face.x(), b.face.y(), t), ucon::CellAge::kNever);
}

TEST(CellAge, GivenAHoldThenOnlyTheCellsOwnLiveRunIsCarriedOn) {
  ucon::CellAge cells(0.2, 0.3, 256);
  const int s = cells.hit(kT0, 1.05, 1.05);
  ASSERT_GE(s, 0);
  const int64_t key = cells.slotKey(s);
  EXPECT_TRUE(cells.hold(s, key, kT0 + 250'000));
  EXPECT_TRUE(cells.hold(s, key, kT0 + 500'000));  // 0.25 s after the hold: still within max_gap
  EXPECT_EQ(cells.occupiedSince(1.05, 1.05, kT0 + 700'000), kT0);
  EXPECT_FALSE(cells.hold(s, key + 1, kT0 + 700'000));  // another cell's key
  EXPECT_FALSE(cells.hold(s, key, kT0 + 900'000));      // the run ended 0.3 s after the last hold
  EXPECT_FALSE(cells.hold(-1, key, kT0));
  EXPECT_EQ(cells.occupiedSince(1.05, 1.05, kT0 + 900'000), ucon::CellAge::kNever);
}

TEST(StaticPersistence, GivenAHiddenCellBeyondTheRangeThenItIsNotHeld) {
  // The sensor drove away: the cell lies beyond the range the frames keep, so it is not held
  // however hidden, and its run ends after max_gap.
  HiddenBox b;
  StaticPersistence sp(0.2, 0.5, 0.3);
  std::vector<char> ok;
  int64_t t = kT0;
  auto o = b.view(3.0f);
  for (int k = 0; k < 30; ++k, t += kDt) sp.update(t, {b.face}, &ok, &o);
  o = b.view(1.0f);
  o.max_range = 2.5f;  // the face is 3.05 m away
  for (int k = 0; k < 30; ++k, t += kDt) sp.update(t, {}, &ok, &o);
  EXPECT_EQ(sp.occupiedSince(b.face.x(), b.face.y(), t), ucon::CellAge::kNever);
  o.max_range = 15.0f;  // within range the same frames hold it
  for (int k = 0; k < 30; ++k, t += kDt) sp.update(t, {b.face}, &ok, &o);
  const int64_t since = sp.occupiedSince(b.face.x(), b.face.y(), t);
  o = b.view(1.0f);
  for (int k = 0; k < 30; ++k, t += kDt) sp.update(t, {}, &ok, &o);
  EXPECT_EQ(sp.occupiedSince(b.face.x(), b.face.y(), t), since);
}

TEST(StaticPersistence, GivenACellHiddenLongerThanTheHoldThenItStartsOver) {
  // A place hidden for long (behind a pillar) is unknown, not occupied: the hold lasts at most
  // max_hidden after the last hit.
  for (const double max_hidden : {2.0, 1.2}) {
    HiddenBox b;
    StaticPersistence sp(0.2, 0.5, 0.3);
    std::vector<char> ok;
    int64_t t = kT0;
    for (int k = 0; k < 30; ++k, t += kDt) {
      auto o = b.view(3.0f);
      o.max_hidden = max_hidden;
      sp.update(t, {b.face}, &ok, &o);
    }
    for (int k = 0; k < 75; ++k, t += kDt) {  // hidden 1.5 s
      auto o = b.view(1.0f);
      o.max_hidden = max_hidden;
      sp.update(t, {}, &ok, &o);
    }
    auto o = b.view(3.0f);
    o.max_hidden = max_hidden;
    sp.update(t, {b.face}, &ok, &o);
    // Held for 1.2 s it ends 0.3 s (max_gap) later, before the 1.5 s are over.
    EXPECT_EQ(ok[0] != 0, max_hidden > 1.5) << "max_hidden " << max_hidden;
  }
}
