// The filter's math: SO(3) maps, the boxminus Jacobian, the IMU step and its error-state
// transition, the point-to-plane and ground-prior residuals — every analytic Jacobian against
// finite differences, and closed-form checks of the motion model.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>

#include "ucon/lio/lio_odometry.hpp"
#include "ucon/lio/nav_state.hpp"
#include "ucon/lio/plane.hpp"
#include "ucon/lio/so3.hpp"

using namespace ucon::lio;

namespace {

NavState someState() {
  NavState x;
  x.R = expSO3(Eigen::Vector3d(0.2, -0.3, 1.1));
  x.p = Eigen::Vector3d(1.0, -2.0, 0.5);
  x.v = Eigen::Vector3d(0.8, 0.3, -0.1);
  x.bg = Eigen::Vector3d(0.01, -0.02, 0.005);
  x.ba = Eigen::Vector3d(0.05, 0.02, -0.04);
  return x;
}

Vector15 unit(int i, double h) {
  Vector15 d = Vector15::Zero();
  d[i] = h;
  return d;
}

}  // namespace

TEST(So3, GivenRotationVectorsWhenExpThenLogThenTheyComeBack) {
  for (const Eigen::Vector3d& w : {Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(1e-9, 0, 2e-9),
                                  Eigen::Vector3d(0, 0, 3.0), Eigen::Vector3d(-1.2, 0.4, 0.9)}) {
    const Eigen::Matrix3d R = expSO3(w);
    EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((logSO3(R) - w).norm(), 0.0, 1e-9) << w.transpose();
  }
  // Closed form: a quarter turn about z maps x to y.
  EXPECT_NEAR((expSO3(Eigen::Vector3d(0, 0, M_PI / 2)) * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(),
              0.0, 1e-12);
}

TEST(So3, GivenTheRightJacobianThenItMatchesFiniteDifferencesOfExp) {
  const Eigen::Vector3d w(0.4, -0.7, 1.3);
  const Eigen::Matrix3d Jr = rightJacobian(w);
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[i] = h;
    // Exp(w + d) = Exp(w) Exp(Jr d)  ->  Log(Exp(w)^T Exp(w + d)) / h = Jr e_i
    const Eigen::Vector3d col = logSO3(expSO3(w).transpose() * expSO3(w + d)) / h;
    EXPECT_NEAR((col - Jr.col(i)).norm(), 0.0, 1e-5) << i;
  }
  EXPECT_NEAR((rightJacobianInverse(w) * Jr - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((rightJacobianInverse(Eigen::Vector3d(1e-8, 0, 0)) - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-7);
}

TEST(So3, GivenRpyThenRotationAndBackAgree) {
  const Eigen::Vector3d rpy(0.1, -0.2, 2.5);
  EXPECT_NEAR((rpyFromRotation(rotationFromRpy(rpy.x(), rpy.y(), rpy.z())) - rpy).norm(), 0.0, 1e-12);
}

TEST(NavState, GivenTheBoxminusJacobianThenItMatchesFiniteDifferences) {
  const NavState ref = someState();
  NavState x = boxplus(ref, (Vector15() << 0.3, -0.2, 0.4, 1, 2, 3, 0.1, 0.2, 0.3, 0.01, 0.02, 0.03, 0.1, 0.2, 0.3)
                                .finished());
  const Matrix15 J = boxminusJacobian(x, ref);
  const double h = 1e-6;
  for (int i = 0; i < kStateDim; ++i) {
    const Vector15 col = (boxminus(boxplus(x, unit(i, h)), ref) - boxminus(boxplus(x, unit(i, -h)), ref)) / (2 * h);
    EXPECT_NEAR((col - J.col(i)).norm(), 0.0, 1e-6) << "column " << i;
  }
  EXPECT_NEAR(boxminus(boxplus(ref, unit(2, 0.3)), ref)[2], 0.3, 1e-12);
}

TEST(NavState, GivenTheErrorStateTransitionThenItMatchesFiniteDifferencesOfTheStep) {
  const NavState x = someState();
  const Eigen::Vector3d gyro(0.3, -0.5, 1.2), acc(0.4, -0.3, 9.9), g(0, 0, -9.80665);
  const double dt = 0.005;
  Matrix15 F;
  transition(x, gyro, acc, dt, ImuNoise{}, &F, nullptr);
  const NavState y = propagate(x, gyro, acc, dt, g);
  const double h = 1e-6;
  for (int i = 0; i < kStateDim; ++i) {
    const Vector15 plus = boxminus(propagate(boxplus(x, unit(i, h)), gyro, acc, dt, g), y);
    const Vector15 minus = boxminus(propagate(boxplus(x, unit(i, -h)), gyro, acc, dt, g), y);
    const Vector15 col = (plus - minus) / (2 * h);
    EXPECT_NEAR((col - F.col(i)).norm(), 0.0, 1e-8) << "column " << i;
  }
}

TEST(NavState, GivenConstantRateAndThrustThenTheStepIsExactForAnyStepCount) {
  // Body rate about z and a body-frame specific force that exactly cancels gravity plus a
  // constant world acceleration is not constant in the body; use pure rotation + free fall.
  NavState x;
  x.v = Eigen::Vector3d(1.0, 0.0, 0.0);
  const Eigen::Vector3d gyro(0, 0, 0.5), acc(0, 0, 0), g(0, 0, -9.80665);
  NavState one = propagate(x, gyro, acc, 1.0, g);
  NavState many = x;
  for (int i = 0; i < 200; ++i) many = propagate(many, gyro, acc, 0.005, g);
  EXPECT_NEAR((one.p - many.p).norm(), 0.0, 1e-9);
  EXPECT_NEAR((one.p - Eigen::Vector3d(1.0, 0.0, -0.5 * 9.80665)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(logSO3(one.R.transpose() * many.R).norm(), 0.0, 1e-12);
  EXPECT_NEAR(logSO3(one.R).z(), 0.5, 1e-12);
}

TEST(NavState, GivenNoiseThenTheCovarianceGrowsAsTheContinuousModelSays) {
  // At rest, level, no bias uncertainty: the attitude variance grows by gyro_noise^2 per second
  // and the velocity variance by acc_noise^2 per second, independent of the step.
  ImuNoise n;
  n.gyro_noise = 0.01;
  n.acc_noise = 0.1;
  n.gyro_bias_walk = 1e-12;
  n.acc_bias_walk = 1e-12;
  const NavState x;
  const Eigen::Vector3d gyro(0, 0, 0), acc(0, 0, 9.80665);
  for (double dt : {0.001, 0.005, 0.02}) {
    Matrix15 P = Matrix15::Zero();
    const int steps = static_cast<int>(std::llround(1.0 / dt));
    for (int i = 0; i < steps; ++i) propagateCovariance(P, x, gyro, acc, dt, n);
    EXPECT_NEAR(P(kRot, kRot), 1e-4, 1e-9) << dt;
    EXPECT_NEAR(P(kVel + 2, kVel + 2), 1e-2, 1e-5) << dt;
    // Position: integral of the velocity random walk, var = q t^3 / 3 (+ O(dt) terms).
    EXPECT_NEAR(P(kPos + 2, kPos + 2), 1e-2 / 3.0, 1e-2 * dt) << dt;
  }
}

TEST(PointToPlane, GivenTheJacobianThenItMatchesFiniteDifferences) {
  Plane pl;
  pl.normal = Eigen::Vector3d(0.3, -0.4, 0.866).normalized();
  pl.d = -1.2;
  const Eigen::Matrix3d R = expSO3(Eigen::Vector3d(0.1, 0.7, -0.4));
  const Eigen::Vector3d t(0.5, -1.0, 2.0), p(3.0, 1.0, -0.5);
  Eigen::Matrix<double, 1, 6> J;
  pointToPlane(pl, R, t, p, &J);
  const double h = 1e-6;
  for (int i = 0; i < 6; ++i) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    d[i] = h;
    auto r = [&](const Eigen::Matrix<double, 6, 1>& dd) {
      return pointToPlane(pl, R * expSO3(dd.head<3>()), t + dd.tail<3>(), p, nullptr);
    };
    EXPECT_NEAR((r(d) - r(-d)) / (2 * h), J(i), 1e-8) << i;
  }
  // Closed form: the residual is the signed distance.
  EXPECT_NEAR(pointToPlane(pl, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 1.2 * pl.normal, nullptr), 0.0,
              1e-12);
}

TEST(GroundPrior, GivenTheHeightAndTiltJacobiansThenTheyMatchFiniteDifferences) {
  NavState x = someState();
  const Eigen::Vector3d t(0.011, -0.023, 0.544);
  Eigen::Matrix<double, 1, 6> Jz;
  Eigen::Matrix<double, 2, 6> Jt;
  groundHeightResidual(x, t, &Jz);
  groundTiltResidual(x, &Jt);
  const double h = 1e-6;
  for (int i = 0; i < 6; ++i) {
    const Vector15 d = unit(i, h);
    const NavState a = boxplus(x, d), b = boxplus(x, -d);
    EXPECT_NEAR((groundHeightResidual(a, t, nullptr) - groundHeightResidual(b, t, nullptr)) / (2 * h), Jz(i), 1e-8) << i;
    const Eigen::Vector2d col = (groundTiltResidual(a, nullptr) - groundTiltResidual(b, nullptr)) / (2 * h);
    EXPECT_NEAR((col - Jt.col(i)).norm(), 0.0, 1e-8) << i;
  }
  // Level IMU at the right height: both residuals vanish.
  NavState level;
  level.p = t;
  EXPECT_NEAR(groundHeightResidual(level, t, nullptr), 0.0, 1e-12);
  EXPECT_NEAR(groundTiltResidual(level, nullptr).norm(), 0.0, 1e-12);
}

TEST(PlaneFit, GivenPointsOnAPlaneThenItIsFoundAndScatterIsRejected) {
  Neighbours nb;
  nb.count = 5;
  const Eigen::Vector3f pts[5] = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}, {0.5f, 0.3f, 1}};
  for (int i = 0; i < 5; ++i) nb.points[i] = pts[i];
  auto pl = fitPlane(nb, 5, 0.05);
  ASSERT_TRUE(pl);
  EXPECT_NEAR(std::fabs(pl->normal.z()), 1.0, 1e-9);
  EXPECT_NEAR(std::fabs(pl->d), 1.0, 1e-9);
  nb.points[4].z() = 1.5f;  // one point off the plane
  EXPECT_FALSE(fitPlane(nb, 5, 0.05));
  for (int i = 0; i < 5; ++i) nb.points[i] = Eigen::Vector3f(static_cast<float>(i), 0, 0);  // a line
  EXPECT_FALSE(fitPlane(nb, 5, 0.05));
  nb.count = 2;
  EXPECT_FALSE(fitPlane(nb, 3, 0.05));
}

// The plane fit's eigen-solver (Newton on the characteristic polynomial, kernel by cross
// products) against Eigen's: scatters of planar patches with noise, of lines, of isotropic
// blobs, at map scales (mm to m).
TEST(PlaneFit, GivenScattersOfEveryShapeThenTheSmallestEigenpairMatchesEigensSolver) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, -3.0 + 3.0 * (trial % 4) / 3.0);
    const Eigen::Vector3d spread(scale, scale * (trial % 3 == 0 ? 1.0 : 0.5 + 0.5 * std::fabs(u(rng))),
                                 scale * (trial % 5 == 0 ? 0.8 : 1e-3 * std::fabs(u(rng))));
    const Eigen::Matrix3d Q = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 5; ++i) {
      const Eigen::Vector3d d = Q * spread.cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
      S += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ref(S);
    const SymmetricEigen3 es = smallestEigen(S);
    ASSERT_TRUE(es.ok) << trial;
    const double tr = S.trace();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(es.values(k), ref.eigenvalues()(k), 1e-9 * tr) << trial << " " << k;
    const double gap = (ref.eigenvalues()(1) - ref.eigenvalues()(0)) / tr;
    if (gap > 1e-4) {
      EXPECT_NEAR(std::fabs(es.vector.dot(ref.eigenvectors().col(0))), 1.0, 1e-9 / (gap * gap)) << trial;
      EXPECT_NEAR(es.vector.norm(), 1.0, 1e-12);
    }
  }
  EXPECT_FALSE(smallestEigen(Eigen::Matrix3d::Zero()).ok);
  EXPECT_FALSE(smallestEigen(Eigen::Matrix3d::Constant(std::nan(""))).ok);
}

// Exp(w) p applied directly equals the matrix exponential applied, in the series range and
// beyond it.
TEST(So3, GivenRotationVectorsThenExpApplyEqualsTheMatrixExponential) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const double scale = i % 2 == 0 ? 0.01 : 1.0;
    const Eigen::Vector3d w = scale * Eigen::Vector3d(g(rng), g(rng), g(rng));
    const Eigen::Vector3d p = 20.0 * Eigen::Vector3d(g(rng), g(rng), g(rng));
    EXPECT_NEAR((expSO3Apply(w, p) - expSO3(w) * p).norm(), 0.0, 1e-12 * p.norm()) << i;
    EXPECT_NEAR((expSO3Apply(w, p) - Eigen::AngleAxisd(w.norm(), w.normalized()) * p).norm(), 0.0, 1e-9 * p.norm()) << i;
  }
}
