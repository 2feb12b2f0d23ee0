// viewCorrectedCenter: the centre of a round object seen from one side.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ucon/perception/footprint.hpp"

using ucon::perception::Points;
using ucon::perception::viewCorrectedCenter;

namespace {

// The half of a circle (centre c, radius r) that faces `sensor`, as points.
Points nearHalf(const Eigen::Vector2d& c, double r, const Eigen::Vector2d& sensor, std::vector<int>* idx) {
  const Eigen::Vector2d u = (c - sensor).normalized();
  const double base = std::atan2(-u.y(), -u.x());  // bearing of the point nearest the sensor
  Points pts;
  for (int k = -20; k <= 20; ++k) {
    const double a = base + k * (M_PI / 2) / 20.0;
    pts.emplace_back(static_cast<float>(c.x() + r * std::cos(a)), static_cast<float>(c.y() + r * std::sin(a)), 1.0f);
    idx->push_back(static_cast<int>(pts.size()) - 1);
  }
  return pts;
}

}  // namespace

TEST(Footprint, GivenTheNearHalfOfACircleFromAnyDirectionThenTheCentreIsTheCircleCentre) {
  const Eigen::Vector2d c(3.0, -1.0);
  for (int k = 0; k < 8; ++k) {
    const double a = k * M_PI / 4 + 0.1;
    const Eigen::Vector2d sensor = c + 6.0 * Eigen::Vector2d(std::cos(a), std::sin(a));
    std::vector<int> idx;
    const Points pts = nearHalf(c, 0.4, sensor, &idx);
    const Eigen::Vector2d est = viewCorrectedCenter(pts, idx, sensor, 0.5);
    // The plain box centre is 0.09-0.2 m towards the sensor (r/2 head-on); the corrected one is on it.
    EXPECT_LT((est - c).norm(), 0.03) << "view " << k;
    EXPECT_GT((viewCorrectedCenter(pts, idx, sensor, 0.0) - c).norm(), 0.08) << "view " << k;
  }
}

TEST(Footprint, GivenAFullRingOrAnEdgeOnWallThenNothingMovesAndTheShiftIsCapped) {
  const Eigen::Vector2d sensor(0.0, 0.0);
  Points ring;
  std::vector<int> all;
  for (int k = 0; k < 36; ++k) {
    ring.emplace_back(static_cast<float>(5.0 + 0.3 * std::cos(k * M_PI / 18)),
                      static_cast<float>(0.3 * std::sin(k * M_PI / 18)), 1.0f);
    all.push_back(k);
  }
  EXPECT_LT((viewCorrectedCenter(ring, all, sensor, 0.5) - Eigen::Vector2d(5.0, 0.0)).norm(), 1e-6);
  // A wall seen edge-on: deeper than wide, no shift.
  Points wall;
  std::vector<int> widx;
  for (int k = 0; k <= 10; ++k) {
    wall.emplace_back(4.0f + 0.1f * static_cast<float>(k), 0.02f * static_cast<float>(k % 2), 1.0f);
    widx.push_back(k);
  }
  EXPECT_LT((viewCorrectedCenter(wall, widx, sensor, 0.5) - Eigen::Vector2d(4.5, 0.01)).norm(), 1e-3);
  // A wide flat face: the shift stops at max_shift.
  Points face{{5.0f, -1.0f, 1.0f}, {5.0f, 1.0f, 1.0f}, {5.0f, 0.0f, 1.0f}};
  std::vector<int> fidx{0, 1, 2};
  EXPECT_NEAR(viewCorrectedCenter(face, fidx, sensor, 0.3).x(), 5.3, 1e-6);
  // Degenerate input: no points, sensor on the points.
  EXPECT_TRUE(viewCorrectedCenter(face, {}, sensor, 0.3).isZero());
  Points one{{1.0f, 2.0f, 0.5f}};
  EXPECT_LT((viewCorrectedCenter(one, {0}, Eigen::Vector2d(1.0, 2.0), 0.3) - Eigen::Vector2d(1.0, 2.0)).norm(), 1e-6);
}
