// "Set up once, compute often": one objective evaluation (value and gradient, MINCO solve,
// every cost term, gradient propagation) must not touch the heap. Counts global allocations.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "test_fixtures.hpp"
#include "ucon/trajopt/objective.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace ucon::trajopt;

TEST(Allocation, GivenASetUpObjectiveWhenEvaluatedThenNoHeapAllocation) {
  const trajopt_test::DiscField field({{Eigen::Vector2d(3.0, 0.4), 0.5}});
  PlanRequest req;
  req.start_utime = 1'000'000;
  req.start.setZero();
  req.goal.setZero();
  req.goal(0, 0) = 6.0;
  req.inner_waypoints = {Eigen::Vector2d(2, 0), Eigen::Vector2d(4, 0)};
  req.durations = {1.5, 1.5, 1.5};
  req.field = &field;
  for (int i = 0; i < 20; ++i) {
    PredictedObstacle o;
    o.id = i;
    o.utime = 1'000'000;
    o.state << 0.3 * i, 1.0 - 0.1 * i, 0, 0.5, -0.2, 0;
    o.covariance = ucon::kalman::Cov6::Identity() * 0.05;
    o.radius = 0.3;
    req.obstacles.push_back(o);
  }
  SectorMincoObjective obj{OptimizerParams{}, ucon::kalman::KalmanParams{}};
  const long at_setup = g_allocations.load();
  ASSERT_EQ(obj.setup(req), "");
  EXPECT_GT(g_allocations.load(), at_setup);  // the counter works: set-up does allocate
  Eigen::VectorXd x = obj.initialGuess();
  Eigen::VectorXd g(x.size());
  obj.evaluate(x.data(), g.data());  // warm-up
  const long before = g_allocations.load();
  double f = 0.0;
  for (int k = 0; k < 10; ++k) {
    x(0) += 0.01;
    f += obj.evaluate(x.data(), g.data());
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(f, 0.0);
  EXPECT_GT(obj.breakdown().dynamic, 0.0);
}
