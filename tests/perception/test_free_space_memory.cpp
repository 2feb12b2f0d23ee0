// The free-space memory: which x-y cells the sensor saw through low, and when; what counts as
// having arrived in a place seen free.
#include <gtest/gtest.h>

#include <cmath>

#include "ucon/perception/free_space_memory.hpp"
#include "ucon/perception/params.hpp"
#include "ucon/perception/preprocess.hpp"

using namespace ucon::perception;

namespace {

const Eigen::Vector3f kOrigin(0.0f, 0.0f, 0.5f);  // the sensor 0.5 m above the floor (z 0)

FreeSpaceMemory::Params shipped() {
  const SegmentationParams s;
  FreeSpaceMemory::Params m;
  m.horizon = s.free_memory;
  m.cell = s.free_memory_cell;
  m.min_height = s.free_memory_heights[0];
  m.max_height = s.free_memory_heights[1];
  m.range = s.free_memory_range;
  m.margin = s.free_space_margin;
  m.period = s.history_chunk;
  return m;
}

// Returns `r` [m] from the sensor at every azimuth in [from, to] deg (0.25 deg apart) and
// elevation `el` [deg].
Points fan(float r, float from, float to, float el = 0.0f) {
  Points out;
  const float e = el * static_cast<float>(M_PI) / 180.0f;
  for (float a = from; a <= to + 1e-4f; a += 0.25f) {
    const float az = a * static_cast<float>(M_PI) / 180.0f;
    out.push_back(kOrigin + r * Eigen::Vector3f(std::cos(az) * std::cos(e), std::sin(az) * std::cos(e), std::sin(e)));
  }
  return out;
}

Frame frameAt(int64_t utime, const Points& returns, const Points& points = {}) {
  Frame f;
  f.utime = utime;
  f.sensor_origin = kOrigin;
  f.returns = returns;
  f.points = points;
  return f;
}

const Eigen::Vector3f kPlace(5.1f, 0.1f, 1.0f);  // the middle of the cell [5.0, 5.2) x [0, 0.2)

}  // namespace

TEST(FreeSpaceMemory, GivenLowRaysAcrossAPlaceThenSomethingThereLaterArrivedUntilTheHorizon) {
  FreeSpaceMemory m(shipped());
  ASSERT_TRUE(m.enabled());
  // A wall 8 m away seen across +-6 degrees: the rays cross the place and its cells around.
  m.mark(frameAt(1'000'000, fan(8.0f, -6.0f, 6.0f)));
  EXPECT_FALSE(m.seenFree(kPlace, 1'000'000)) << "a frame is no evidence about itself";
  EXPECT_TRUE(m.seenFree(kPlace, 1'020'000));
  EXPECT_TRUE(m.seenFree(kPlace, 1'000'000 + 3'000'000));
  EXPECT_FALSE(m.seenFree(kPlace, 1'000'000 + 3'000'001)) << "older than free_memory";
  // Cells the rays never reached: beyond the wall, and 2 m to the side.
  EXPECT_FALSE(m.seenFree(Eigen::Vector3f(9.0f, 0.1f, 1.0f), 1'020'000));
  EXPECT_FALSE(m.seenFree(Eigen::Vector3f(5.1f, 2.1f, 1.0f), 1'020'000));
}

TEST(FreeSpaceMemory, GivenOneUnseenCellAroundThePlaceThenItIsNotSeenFree) {
  FreeSpaceMemory m(shipped());
  // The rays cover the place's row of cells but not the row beside it (y in [0.2, 0.4) at 5 m
  // needs azimuths above 2.3 degrees): the inside of something may lie there.
  m.mark(frameAt(1'000'000, fan(8.0f, -6.0f, 2.0f)));
  EXPECT_FALSE(m.seenFree(kPlace, 1'020'000));
  // A frame 20 ms later is not recorded (once per history_chunk, 0.1 s); one 0.1 s later is.
  m.mark(frameAt(1'020'000, fan(8.0f, 2.0f, 6.0f)));
  EXPECT_FALSE(m.seenFree(kPlace, 1'040'000));
  m.mark(frameAt(1'100'000, fan(8.0f, 2.0f, 6.0f)));
  EXPECT_TRUE(m.seenFree(kPlace, 1'120'000));
}

TEST(FreeSpaceMemory, GivenRaysThatEndNearThePlaceOrCrossItHighOrPassARecentReturnInItThenItIsNotMarked) {
  const Eigen::Vector3f near_wall(7.8f, 0.1f, 1.0f);  // within free_space_margin (0.3 m) of the wall
  {
    FreeSpaceMemory m(shipped());
    m.mark(frameAt(1'000'000, fan(8.0f, -6.0f, 6.0f)));
    EXPECT_FALSE(m.seenFree(near_wall, 1'020'000));
  }
  {
    // Rays rising at 10 degrees leave the 0.2-0.6 m band 0.57 m from the sensor: they pass over
    // anything lower than their height at the place (a box).
    FreeSpaceMemory m(shipped());
    m.mark(frameAt(1'000'000, fan(8.0f, -6.0f, 6.0f, 10.0f)));
    EXPECT_FALSE(m.seenFree(kPlace, 1'020'000));
  }
  {
    // A return in the place's cell in the same frame: the rays crossing that cell passed beside
    // it (a thin pillar), not through it.
    FreeSpaceMemory m(shipped());
    m.mark(frameAt(1'000'000, fan(8.0f, -6.0f, 6.0f), {kPlace}));
    EXPECT_FALSE(m.seenFree(kPlace, 1'020'000));
    // Nor does a later frame within free_memory (3 s) of that return: a sparse scan does not
    // sample a thin pillar's cell in every frame. One after it does.
    m.mark(frameAt(1'100'000, fan(8.0f, -6.0f, 6.0f)));
    EXPECT_FALSE(m.seenFree(kPlace, 1'120'000));
    m.mark(frameAt(4'100'000, fan(8.0f, -6.0f, 6.0f)));
    EXPECT_TRUE(m.seenFree(kPlace, 4'120'000));
  }
}

TEST(FreeSpaceMemory, GivenTheFloorUnderARaisedRobotThenTheBandFollowsTheRobot) {
  // The robot on a platform 1 m up (an odometry frame drifted, or a ramp): the band is above
  // the floor under the robot, so level rays from the sensor 0.5 m above it still mark.
  FreeSpaceMemory m(shipped());
  Frame f = frameAt(1'000'000, {});
  f.pose.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
  f.sensor_origin = kOrigin + Eigen::Vector3f(0.0f, 0.0f, 1.0f);
  for (const auto& p : fan(8.0f, -6.0f, 6.0f)) f.returns.push_back(p + Eigen::Vector3f(0.0f, 0.0f, 1.0f));
  m.mark(f);
  EXPECT_TRUE(m.seenFree(kPlace, 1'020'000));
}

TEST(FreeSpaceMemory, GivenTimeGoingBackOrTheMemoryOffThenNothingIsRemembered) {
  FreeSpaceMemory m(shipped());
  m.mark(frameAt(5'000'000, fan(8.0f, -6.0f, 6.0f)));
  ASSERT_TRUE(m.seenFree(kPlace, 5'020'000));
  m.mark(frameAt(1'000'000, {}));  // a log replayed from its start
  EXPECT_FALSE(m.seenFree(kPlace, 5'020'000));
  EXPECT_FALSE(m.seenFree(kPlace, 1'020'000));

  FreeSpaceMemory::Params off = shipped();
  off.horizon = 0.0;
  FreeSpaceMemory none(off);
  EXPECT_FALSE(none.enabled());
  none.mark(frameAt(1'000'000, fan(8.0f, -6.0f, 6.0f)));
  EXPECT_FALSE(none.seenFree(kPlace, 1'020'000));
}

TEST(FreeSpaceMemory, GivenBadInputThenItIsSkippedOrRefused) {
  FreeSpaceMemory m(shipped());
  Points bad = fan(8.0f, -6.0f, 6.0f);
  bad.push_back(Eigen::Vector3f(NAN, 0.0f, 0.5f));
  bad.push_back(Eigen::Vector3f(INFINITY, 1.0f, 0.5f));
  bad.push_back(kOrigin);  // a return at the sensor: no ray
  m.mark(frameAt(1'000'000, bad, {Eigen::Vector3f(NAN, NAN, NAN)}));
  EXPECT_TRUE(m.seenFree(kPlace, 1'020'000));
  EXPECT_FALSE(m.seenFree(Eigen::Vector3f(NAN, 0.0f, 1.0f), 1'020'000));
  FreeSpaceMemory::Params p = shipped();
  p.max_height = p.min_height;
  EXPECT_THROW(FreeSpaceMemory{p}, std::invalid_argument);
  EXPECT_THROW(FreeSpaceMemory(shipped(), 100), std::invalid_argument);
}

TEST(FreeSpaceMemory, GivenASensorMountedAboveTheBandThenRaysMarkWhereTheyCrossIt) {
  // The sensor 0.9 m above the floor, returns on the floor-ish 8 m out (0.1 m up): each ray
  // descends through the 0.2-0.6 m band between 3 and 7 m from the sensor, and passes above it
  // nearer.
  FreeSpaceMemory m(shipped());
  Frame f = frameAt(1'000'000, {});
  f.sensor_origin = Eigen::Vector3f(0.0f, 0.0f, 0.9f);
  for (float a = -6.0f; a <= 6.0f; a += 0.25f) {
    const float az = a * static_cast<float>(M_PI) / 180.0f;
    f.returns.push_back(Eigen::Vector3f(8.0f * std::cos(az), 8.0f * std::sin(az), 0.1f));
  }
  m.mark(f);
  EXPECT_TRUE(m.seenFree(kPlace, 1'020'000));
  EXPECT_FALSE(m.seenFree(Eigen::Vector3f(1.5f, 0.1f, 1.0f), 1'020'000));
}

TEST(FreeSpaceMemory, GivenTheRangeAndCellThenTheGridSpansTwiceTheRangeAndTheDrive) {
  FreeSpaceMemory::Params p = shipped();
  EXPECT_EQ(FreeSpaceMemory::sideFor(p), 256);  // 2 (8 + 5) m / 0.2 m = 130 cells
  p.cell = 0.05;
  EXPECT_EQ(FreeSpaceMemory::sideFor(p), 1024);
  p.cell = 0.02;
  p.range = 50.0;
  EXPECT_EQ(FreeSpaceMemory::sideFor(p), 2048);  // capped
}
