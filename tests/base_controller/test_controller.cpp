#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>

#include "figure_eight.hpp"
#include "ucon/runtime/config_file.hpp"

using ucon::base_controller::BaseController;
using ucon::base_controller::BaseControllerOutput;
using ucon::base_controller::BaseControllerParams;
using ucon::base_status_t;
using test_support::ClosedLoop;
using test_support::FigureEight;

namespace {
constexpr int64_t kT0 = 1'700'000'000'000'000;  // a realistic epoch utime [us]

BaseControllerParams shippedParams() {
  auto p = ucon::runtime::loadConfigFile<BaseControllerParams>("test", "deploy/config/base_controller.yaml");
  EXPECT_TRUE(p.has_value()) << "deploy/config/base_controller.yaml must load";
  return p ? *p : BaseControllerParams{};
}

struct TrackResult {
  double rms = 0, max = 0;
  int samples = 0;
  double max_speed = 0;
  double max_heading_to_path = 0;  // |yaw - direction of motion| while cruising [rad]
  double max_abs_yaw = 0;          // [rad]
  double min_saturation = 1;
  std::vector<uint8_t> bytes;  // every wheel command, encoded (determinism)
};

// Follows the figure-eight, republishing the plan every 100 ms like the planner does.
TrackResult trackFigureEight(const BaseControllerParams& p) {
  const FigureEight fig;
  const ucon::trajectory_t plan = fig.message(kT0 + 100000);
  ucon::trajectory::PiecewisePolynomial ref;
  EXPECT_EQ(ucon::trajectory::PiecewisePolynomial::fromMessage(plan, &ref), ucon::trajectory::TrajectoryStatus::kOk);
  ClosedLoop loop(p, kT0);
  const Eigen::Vector3d p0 = ref.position(ref.startUtime());
  loop.plant.reset(p0.x(), p0.y(), 0.0);
  TrackResult r;
  double sum2 = 0;
  const int64_t end = ref.endUtime() - 10000;
  while (loop.t < end) {
    if ((loop.t - kT0) % 100000 == 0 && loop.t < ref.endUtime()) {
      ucon::trajectory_t m = plan;
      m.utime = loop.t;
      m.seq = (loop.t - kT0) / 100000;
      loop.ctrl.onTrajectory(m);
    }
    const int64_t t = loop.t;
    BaseControllerOutput out = loop.step();
    EXPECT_TRUE(out.wheel_cmd.has_value());
    if (out.status) r.min_saturation = std::min(r.min_saturation, out.status->saturation);
    if (out.wheel_cmd) {
      std::vector<uint8_t> buf(static_cast<std::size_t>(out.wheel_cmd->getEncodedSize()));
      out.wheel_cmd->encode(buf.data(), 0, static_cast<int>(buf.size()));
      r.bytes.insert(r.bytes.end(), buf.begin(), buf.end());
    }
    // Error of the plant at t + 10 ms (after the step) against the reference then.
    const Eigen::Vector3d pr = ref.position(t + 10000);
    const auto& s = loop.plant.state();
    if (t >= ref.startUtime()) {
      const double e = std::hypot(pr.x() - s.x, pr.y() - s.y);
      sum2 += e * e;
      r.max = std::max(r.max, e);
      ++r.samples;
      r.max_speed = std::max(r.max_speed, std::hypot(s.vx_world, s.vy_world));
      r.max_abs_yaw = std::max(r.max_abs_yaw, std::fabs(s.yaw));
      const Eigen::Vector3d vr = ref.velocity(t + 10000);
      if (vr.norm() > 0.5 && t >= ref.startUtime() + static_cast<int64_t>(fig.ramp_s * 1e6)) {  // cruising
        const double d = ucon::mecanum::wrapAngle(s.yaw - std::atan2(vr.y(), vr.x()));
        r.max_heading_to_path = std::max(r.max_heading_to_path, std::fabs(d));
      }
    }
    // Before its start the plan holds its first point: tracking from the first tick on.
    EXPECT_EQ(loop.ctrl.state(), base_status_t::STATE_TRACKING)
        << "at " << (t - kT0) / 1000 << " ms: " << loop.ctrl.reason();
  }
  r.rms = std::sqrt(sum2 / std::max(1, r.samples));
  return r;
}
}  // namespace

TEST(BaseControllerClosedLoop, GivenFigureEightAt1p5MetresPerSecondThenRmsErrorBelow3cmAndMaxBelow10cm) {
  const TrackResult r = trackFigureEight(shippedParams());
  EXPECT_GT(r.samples, 1500);
  // The reference peaks at 1.5 m/s; the plant gets close (at the diagonal centre crossings
  // the shipped 40 rad/s wheel limit allows 2 m/s / (|cos| + |sin|) ~ 1.44 m/s, and the
  // controller scales the twist down keeping its direction there).
  const FigureEight fig;
  ucon::trajectory::PiecewisePolynomial ref;
  ucon::trajectory::PiecewisePolynomial::fromMessage(fig.message(kT0), &ref);
  double ref_peak = 0;
  for (double t = 0; t <= ref.duration(); t += 0.001) ref_peak = std::max(ref_peak, ref.sampleRelative(t).velocity.norm());
  EXPECT_NEAR(ref_peak, 1.5, 1e-3);
  EXPECT_GT(r.max_speed, 1.4);
  EXPECT_LE(r.rms, 0.03);
  EXPECT_LE(r.max, 0.10);
  EXPECT_LT(r.max_abs_yaw, 0.02);  // heading held at hold_yaw = 0
  std::printf("figure-eight: RMS %.4f m, max %.4f m over %d samples, peak speed %.3f m/s (reference %.3f), "
              "lowest wheel scale %.3f\n",
              r.rms, r.max, r.samples, r.max_speed, ref_peak, r.min_saturation);
}

TEST(BaseControllerClosedLoop, GivenPathHeadingModeThenTracksWhileTurningAlongThePath) {
  BaseControllerParams p = shippedParams();
  p.heading.mode = "path";
  const TrackResult r = trackFigureEight(p);
  EXPECT_LE(r.rms, 0.03);
  EXPECT_LE(r.max, 0.10);
  EXPECT_GT(r.max_abs_yaw, 1.0);            // it really turned
  EXPECT_LT(r.max_heading_to_path, 0.15);  // facing along the path
  std::printf("figure-eight, path heading: RMS %.4f m, max %.4f m, heading off the path <= %.3f rad\n", r.rms,
              r.max, r.max_heading_to_path);
}

TEST(BaseControllerClosedLoop, GivenTheSameInputsTwiceThenByteIdenticalWheelCommands) {
  const TrackResult a = trackFigureEight(shippedParams());
  const TrackResult b = trackFigureEight(shippedParams());
  ASSERT_FALSE(a.bytes.empty());
  EXPECT_EQ(a.bytes, b.bytes);
}

TEST(BaseControllerClosedLoop, GivenWheelLimitBelowWhatThePlanNeedsThenAllWheelsScaledKeepingDirection) {
  BaseControllerParams p = shippedParams();
  p.mecanum.max_wheel_speed = 25.0;  // 1.25 m/s rim speed
  BaseController ctrl(p);
  // Straight diagonal line at 1.5 m/s: x = 1.2 t, y = 0.9 t. The wheels would need
  // (vx + vy) / r = 42 rad/s, so everything is scaled by 25/42.
  ucon::trajectory::PiecewisePolynomial line;
  ASSERT_EQ(ucon::trajectory::PiecewisePolynomial::create(kT0, 2, 2, {10.0}, {0.0, 1.2, 0.0, 0.9}, &line),
            ucon::trajectory::TrajectoryStatus::kOk);
  ucon::trajectory_t plan{};
  line.toMessage(&plan);
  plan.yaw = 0.0;
  BaseControllerOutput out;
  std::optional<ucon::base_status_t> status;
  for (int i = 0; i < 100; ++i) {
    const int64_t t = kT0 + i * 10000;
    ucon::robot_pose_t pose{};  // exactly on the line, at the line's speed
    pose.utime = t;
    pose.valid = true;
    pose.x = 1.2 * i * 0.01;
    pose.y = 0.9 * i * 0.01;
    pose.qw = 1;
    pose.vx = 1.2;
    pose.vy = 0.9;
    ctrl.onPose(pose);
    if (i % 10 == 0) {
      plan.utime = t;
      ctrl.onTrajectory(plan);
    }
    out = ctrl.tick(t);
    if (out.status) status = out.status;
  }
  ASSERT_TRUE(out.wheel_cmd && status);
  EXPECT_EQ(status->state, base_status_t::STATE_TRACKING);
  const auto& c = *out.wheel_cmd;
  const double wmax = std::max({std::fabs(c.w_fl), std::fabs(c.w_fr), std::fabs(c.w_rl), std::fabs(c.w_rr)});
  EXPECT_NEAR(wmax, 25.0, 1e-6);
  EXPECT_NEAR(status->saturation, 25.0 / 42.0, 1e-6);
  EXPECT_NEAR(c.vx, 1.2 * 25.0 / 42.0, 1e-6);  // the same direction, scaled
  EXPECT_NEAR(c.vy, 0.9 * 25.0 / 42.0, 1e-6);
  EXPECT_NEAR(c.wz, 0.0, 1e-9);
}
