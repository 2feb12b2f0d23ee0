#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "figure_eight.hpp"
#include "ucon/runtime/config_file.hpp"

using ucon::base_controller::BaseControllerOutput;
using ucon::base_controller::BaseControllerParams;
using ucon::base_status_t;
using test_support::ClosedLoop;
using test_support::FigureEight;

namespace {
constexpr int64_t kT0 = 1'700'000'000'000'000;

BaseControllerParams shippedParams() {
  auto p = ucon::runtime::loadConfigFile<BaseControllerParams>("test", "deploy/config/base_controller.yaml");
  EXPECT_TRUE(p.has_value());
  return p ? *p : BaseControllerParams{};
}

int64_t counterOf(const ucon::base_controller::BaseController& c, const std::string& name) {
  for (const auto& [n, v] : c.counters()) {
    if (n == name) return v;
  }
  ADD_FAILURE() << "no counter " << name;
  return -1;
}

bool allZero(const ucon::wheel_cmd_t& c) {
  return c.w_fl == 0.0 && c.w_fr == 0.0 && c.w_rl == 0.0 && c.w_rr == 0.0;
}

/// A loop that has followed the figure-eight for `seconds` (plan republished every 100 ms).
struct Running {
  FigureEight fig;
  ucon::trajectory_t plan;
  ClosedLoop loop;
  int64_t next_plan = kT0;
  bool publish_plan = true;
  ucon::wheel_cmd_t last_cmd{};

  explicit Running(const BaseControllerParams& p) : plan(fig.message(kT0)), loop(p, kT0) {
    ucon::trajectory::PiecewisePolynomial ref;
    ucon::trajectory::PiecewisePolynomial::fromMessage(plan, &ref);
    const Eigen::Vector3d p0 = ref.position(kT0);
    loop.plant.reset(p0.x(), p0.y(), 0.0);
  }
  BaseControllerOutput step() {
    if (publish_plan && loop.t >= next_plan) {
      ucon::trajectory_t m = plan;
      m.utime = loop.t;
      loop.ctrl.onTrajectory(m);
      next_plan += 100000;
    }
    BaseControllerOutput out = loop.step();
    if (out.wheel_cmd) last_cmd = *out.wheel_cmd;
    return out;
  }
  void run(double seconds) {
    const int n = static_cast<int>(std::lround(seconds * 100));
    for (int i = 0; i < n; ++i) step();
  }
  double cmdSpeed() const { return std::hypot(last_cmd.vx, last_cmd.vy); }
};

/// Steps until the wheel command is zero; returns the time of that command [us] or -1, and
/// checks that no tick decelerates faster than the configured limits.
int64_t stepUntilStopped(Running& r, const BaseControllerParams& p, double max_s) {
  double vx = r.last_cmd.vx, vy = r.last_cmd.vy, wz = r.last_cmd.wz;
  for (int i = 0; i < static_cast<int>(max_s * 100); ++i) {
    const int64_t t = r.loop.t;
    const BaseControllerOutput out = r.step();
    EXPECT_TRUE(out.wheel_cmd.has_value());
    if (!out.wheel_cmd) continue;
    const auto& c = *out.wheel_cmd;
    // Deceleration limits (plus rounding) per 10 ms tick.
    EXPECT_LE(std::hypot(c.vx - vx, c.vy - vy), p.watchdog.stop_linear_decel * 0.01 + 1e-9) << i;
    EXPECT_LE(std::fabs(c.wz - wz), p.watchdog.stop_angular_decel * 0.01 + 1e-9) << i;
    vx = c.vx;
    vy = c.vy;
    wz = c.wz;
    if (allZero(c)) return t;
  }
  return -1;
}
}  // namespace

TEST(BaseControllerWatchdog, GivenPoseStreamStopsWhenTrackingThenWheelsZeroWithin200msPlusDecelTime) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(4.0);
  ASSERT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  ASSERT_GT(r.cmdSpeed(), 1.0);  // moving fast when the poses stop

  const int64_t last_pose = r.loop.t - 10000;  // the pose of the last step
  r.loop.send_pose = false;
  // Worst case: the command may still rise for 200 ms at max_linear_accel before the stop.
  const double v_bound = r.cmdSpeed() + p.control.max_linear_accel * 0.2;
  const double decel_bound = std::max(v_bound / p.watchdog.stop_linear_decel,
                                      (std::fabs(r.last_cmd.wz) + p.control.max_yaw_accel * 0.2) /
                                          p.watchdog.stop_angular_decel);
  double v_at_trigger = -1;
  int64_t trigger = -1;
  int64_t zero_at = -1;
  for (int i = 0; i < 300 && zero_at < 0; ++i) {
    const int64_t t = r.loop.t;
    const BaseControllerOutput out = r.step();
    if (trigger < 0 && r.loop.ctrl.state() != base_status_t::STATE_TRACKING) {
      trigger = t;
      EXPECT_NE(r.loop.ctrl.reason().find("pose stale"), std::string::npos) << r.loop.ctrl.reason();
      ASSERT_TRUE(out.status.has_value());  // a state change is reported at once
      EXPECT_EQ(out.status->state, base_status_t::STATE_STOPPING);
      EXPECT_GE(out.status->pose_age_ms, 200.0);
    }
    if (trigger < 0) v_at_trigger = std::hypot(out.wheel_cmd->vx, out.wheel_cmd->vy);
    if (trigger >= 0 && allZero(*out.wheel_cmd)) zero_at = t;
  }
  ASSERT_GE(trigger, 0);
  ASSERT_GE(zero_at, 0);
  EXPECT_EQ(trigger - last_pose, 200000);  // detected on the first tick with age >= 200 ms
  const double decel_time = v_at_trigger / p.watchdog.stop_linear_decel;
  EXPECT_LE((zero_at - last_pose) * 1e-6, 0.2 + decel_time + 1e-9);
  EXPECT_LE((zero_at - last_pose) * 1e-6, 0.2 + decel_bound);
  r.step();
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_STOPPED);
  EXPECT_FALSE(r.last_cmd.enable);  // at rest: motors braked
  // The stop is counted by its cause on the process status, once.
  EXPECT_EQ(counterOf(r.loop.ctrl, "stops_pose_stale"), 1);
  EXPECT_EQ(counterOf(r.loop.ctrl, "stops_trajectory_stale"), 0);
  std::printf("pose lost at %.1f m/s: zero command %.0f ms after the last pose (200 ms + %.0f ms deceleration)\n",
              v_at_trigger, (zero_at - last_pose) * 1e-3, decel_time * 1e3);
}

TEST(BaseControllerWatchdog, GivenPoseBackThenStaysStoppedUntilANewTrajectoryArrives) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(2.0);
  r.loop.send_pose = false;
  r.publish_plan = false;
  ASSERT_GE(stepUntilStopped(r, p, 3.0), 0);
  r.run(0.5);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_STOPPED);
  EXPECT_NE(r.loop.ctrl.reason().find("pose stale"), std::string::npos);

  // Fresh poses but no new plan: still stopped (the old plan is stale anyway).
  r.loop.send_pose = true;
  r.run(0.5);
  EXPECT_NE(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  EXPECT_TRUE(allZero(r.last_cmd));

  // A new plan made from here: tracking again.
  r.plan = r.fig.message(r.loop.t);
  r.next_plan = r.loop.t;
  r.publish_plan = true;
  r.run(0.1);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING) << r.loop.ctrl.reason();
}

TEST(BaseControllerWatchdog, GivenTrajectoryStreamStopsThenStopsWithReason) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(3.0);
  r.publish_plan = false;
  const int64_t last_plan = r.next_plan - 100000;
  const double v0 = r.cmdSpeed();
  const int64_t zero_at = stepUntilStopped(r, p, 2.0);
  ASSERT_GE(zero_at, 0);
  EXPECT_NE(r.loop.ctrl.reason().find("trajectory stale"), std::string::npos) << r.loop.ctrl.reason();
  // The bound docs/robot.md states: timeout + one period + the longest ramp the limits allow.
  const double bound = p.watchdog.trajectory_timeout_s + 1.0 / p.control.rate_hz +
                       std::max(p.control.max_speed / p.watchdog.stop_linear_decel,
                                p.control.max_yaw_rate / p.watchdog.stop_angular_decel);
  EXPECT_LE((zero_at - last_plan) * 1e-6, bound);
  // ... and the tighter one for the speed it had: timeout + period + (speed + the rise
  // during the timeout) / decel.
  EXPECT_LE((zero_at - last_plan) * 1e-6,
            p.watchdog.trajectory_timeout_s + 1.0 / p.control.rate_hz +
                (v0 + p.control.max_linear_accel * p.watchdog.trajectory_timeout_s) / p.watchdog.stop_linear_decel);
  EXPECT_EQ(counterOf(r.loop.ctrl, "stops_trajectory_stale"), 1);
  EXPECT_EQ(counterOf(r.loop.ctrl, "stops_pose_stale"), 0);
  r.run(1.0);  // staying stopped is not another stop
  EXPECT_EQ(counterOf(r.loop.ctrl, "stops_trajectory_stale"), 1);
}

TEST(BaseControllerWatchdog, GivenASecondStopCauseDuringTheRampThenTheRampKeepsTheDecelLimit) {
  // The pose stops (watchdog ramp), then mid-ramp the planner says stop and, later, that its
  // plan is invalid: each cause is reported, but the deceleration stays within the limit and
  // zero comes no sooner than speed / decel after the first stop.
  const BaseControllerParams p = shippedParams();
  for (const int8_t second : {ucon::trajectory_t::STATUS_STOP, ucon::trajectory_t::STATUS_INVALID}) {
    Running r(p);
    r.run(4.0);
    ASSERT_GT(r.cmdSpeed(), 1.0);
    r.loop.send_pose = false;
    r.publish_plan = false;
    double v_at_trigger = r.cmdSpeed();
    int64_t trigger = -1;
    for (int i = 0; i < 100 && trigger < 0; ++i) {
      const int64_t t = r.loop.t;
      r.step();
      if (r.loop.ctrl.state() != base_status_t::STATE_TRACKING) {
        trigger = t;
      } else {
        v_at_trigger = r.cmdSpeed();
      }
    }
    ASSERT_GE(trigger, 0);
    r.run(0.2);
    ucon::trajectory_t m{};
    m.utime = r.loop.t;
    m.status = second;
    m.message = "second cause";
    r.loop.ctrl.onTrajectory(m);
    const int64_t zero_at = stepUntilStopped(r, p, 2.0);  // checks every tick's deceleration
    ASSERT_GE(zero_at, 0);
    EXPECT_NE(r.loop.ctrl.reason().find(second == ucon::trajectory_t::STATUS_STOP ? "planner asked to stop" : "second cause"),
              std::string::npos) << r.loop.ctrl.reason();
    EXPECT_GE((zero_at - trigger) * 1e-6, v_at_trigger / p.watchdog.stop_linear_decel - 1.0 / p.control.rate_hz - 1e-9)
        << "status " << int(second);
  }
}

TEST(BaseControllerWatchdog, GivenPlanExpiresThenStopsWithReasonExpired) {
  BaseControllerParams p = shippedParams();
  Running r(p);
  // A 1 s straight plan, republished (fresh) after it ended.
  ucon::trajectory::PiecewisePolynomial line;
  ASSERT_EQ(ucon::trajectory::PiecewisePolynomial::create(kT0, 2, 2, {1.0}, {3.0, 0.5, 0.0, 0.0}, &line),
            ucon::trajectory::TrajectoryStatus::kOk);
  r.loop.plant.reset(3.0, 0.0, 0.0);
  line.toMessage(&r.plan);
  r.run(1.0);  // published up to 0.9 s, fresh until 1.1 s
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  r.publish_plan = false;  // the same plan would now be rejected as in the past
  r.run(0.1);
  EXPECT_NE(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  EXPECT_NE(r.loop.ctrl.reason().find("expired"), std::string::npos) << r.loop.ctrl.reason();
}

namespace {
void expectRejectedAndStops(const char* what, void (*mutate)(ucon::trajectory_t&, int64_t now),
                            const char* reason_part) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(3.0);
  ASSERT_GT(r.cmdSpeed(), 0.5) << what;
  r.publish_plan = false;
  ucon::trajectory_t bad = r.plan;
  bad.utime = r.loop.t;
  bad.plan_id = 2;
  mutate(bad, r.loop.t);
  const BaseControllerOutput out = r.loop.ctrl.onTrajectory(bad);
  ASSERT_TRUE(out.status.has_value()) << what;
  EXPECT_EQ(out.status->state, base_status_t::STATE_STOPPING) << what;
  EXPECT_EQ(out.status->rejected_trajectories, 1) << what;
  EXPECT_NE(out.status->reason.find(reason_part), std::string::npos) << what << ": " << out.status->reason;
  EXPECT_GE(stepUntilStopped(r, p, 2.0), 0) << what;
  // A good plan arriving later is followed again.
  r.plan = r.fig.message(r.loop.t);
  r.next_plan = r.loop.t;
  r.publish_plan = true;
  r.run(0.1);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING) << what;
}
}  // namespace

TEST(BaseControllerBadInput, GivenNaNCoefficientsThenRejectedAndStops) {
  expectRejectedAndStops("NaN", [](ucon::trajectory_t& m, int64_t) { m.coeffs[7] = std::nan(""); },
                         "non-finite coefficient");
}

TEST(BaseControllerBadInput, GivenZeroLengthPieceThenRejectedAndStops) {
  expectRejectedAndStops("zero piece", [](ucon::trajectory_t& m, int64_t) { m.durations[3] = 0.0; },
                         "duration");
}

TEST(BaseControllerBadInput, GivenTrajectoryEntirelyInThePastThenRejectedAndStops) {
  expectRejectedAndStops("past",
                         [](ucon::trajectory_t& m, int64_t now) {
                           m.num_pieces = 1;
                           m.durations = {0.5};
                           m.num_coeffs = m.dim * m.order1;
                           m.coeffs.resize(static_cast<std::size_t>(m.num_coeffs));
                           m.start_utime = now - 2'000'000;
                         },
                         "in the past");
}

TEST(BaseControllerBadInput, GivenInconsistentSizesThenRejectedAndStops) {
  expectRejectedAndStops("sizes", [](ucon::trajectory_t& m, int64_t) { m.num_pieces += 1; },
                         "sizes");
}

TEST(BaseControllerBadInput, GivenPlannerStatusInvalidThenStopsWithPlannerMessage) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(2.0);
  r.publish_plan = false;
  ucon::trajectory_t m = r.plan;
  m.utime = r.loop.t;
  m.status = ucon::trajectory_t::STATUS_INVALID;
  m.message = "optimiser diverged";
  const BaseControllerOutput out = r.loop.ctrl.onTrajectory(m);
  ASSERT_TRUE(out.status.has_value());
  EXPECT_NE(out.status->reason.find("optimiser diverged"), std::string::npos);
  EXPECT_GE(stepUntilStopped(r, p, 2.0), 0);
}

TEST(BaseControllerBadInput, GivenNaNPoseThenCountedAndDroppedAndWatchdogStops) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(2.0);
  r.loop.send_pose = false;
  for (int i = 0; i < 40; ++i) {
    ucon::robot_pose_t bad = test_support::poseFrom(r.loop.plant.state(), r.loop.t);
    bad.x = std::nan("");
    r.loop.ctrl.onPose(bad);
    r.step();
  }
  EXPECT_NE(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  int64_t bad = -1;
  for (const auto& [name, value] : r.loop.ctrl.counters()) {
    if (name == "poses_bad") bad = value;
  }
  EXPECT_EQ(bad, 40);
  EXPECT_TRUE(std::isfinite(r.last_cmd.w_fl));
}

TEST(BaseControllerEstop, GivenEstopThenDeceleratesToZeroAndResumesOnlyAfterReleaseAndNewPlan) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(3.0);
  const double v0 = r.cmdSpeed();
  ASSERT_GT(v0, 0.5);
  ucon::estop_t e{};
  e.utime = r.loop.t;
  e.engaged = true;
  e.source = "test";
  const BaseControllerOutput out = r.loop.ctrl.onEstop(e);
  ASSERT_TRUE(out.status.has_value());
  EXPECT_EQ(out.status->state, base_status_t::STATE_ESTOP);
  const int64_t t_engage = r.loop.t;
  const int64_t zero_at = stepUntilStopped(r, p, 3.0);
  ASSERT_GE(zero_at, 0);
  EXPECT_LE((zero_at - t_engage) * 1e-6, v0 / p.watchdog.stop_linear_decel + 0.011);
  r.run(0.5);  // plans keep coming, but the E-stop holds
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_ESTOP);
  EXPECT_TRUE(allZero(r.last_cmd));

  e.utime = r.loop.t;
  e.engaged = false;
  r.loop.ctrl.onEstop(e);
  r.publish_plan = false;
  r.run(0.05);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_STOPPED);  // no plan since the release
  EXPECT_NE(r.loop.ctrl.reason().find("waiting for a new trajectory"), std::string::npos);
  r.plan = r.fig.message(r.loop.t);
  r.next_plan = r.loop.t;
  r.publish_plan = true;
  r.run(0.05);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING) << r.loop.ctrl.reason();
  EXPECT_EQ(counterOf(r.loop.ctrl, "stops_estop"), 1);
}

TEST(BaseControllerEstop, GivenABadPlanDuringTheEstopThenTheEstopStaysShownAndTheRejectionHoldsAfterRelease) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(1.0);
  ucon::estop_t e{};
  e.utime = r.loop.t;
  e.engaged = true;
  r.loop.ctrl.onEstop(e);
  r.run(0.2);
  r.publish_plan = false;
  ucon::trajectory_t bad = r.plan;
  bad.utime = r.loop.t;
  bad.coeffs[0] = std::nan("");
  const BaseControllerOutput rej = r.loop.ctrl.onTrajectory(bad);
  ASSERT_TRUE(rej.status.has_value());
  EXPECT_EQ(rej.status->state, base_status_t::STATE_ESTOP);
  EXPECT_EQ(rej.status->rejected_trajectories, 1);
  r.run(0.1);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_ESTOP);
  e.utime = r.loop.t;
  e.engaged = false;
  r.loop.ctrl.onEstop(e);
  r.run(0.1);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_STOPPED);
  EXPECT_NE(r.loop.ctrl.reason().find("trajectory rejected"), std::string::npos) << r.loop.ctrl.reason();
}

TEST(BaseControllerFinalPlan, GivenGoalReachedPlanThenFollowedToItsEndHeldThenIdleWhenStale) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  // A 1 s move from (0,0) to (0.5,0) ending at rest, marked GOAL_REACHED.
  std::vector<ucon::trajectory::KnotState> k(2);
  k[1].t = 1.0;
  k[1].position = {0.5, 0, 0};
  ucon::trajectory::PiecewisePolynomial pp;
  ASSERT_EQ(ucon::trajectory::buildQuinticHermite(kT0, k, 2, &pp), ucon::trajectory::TrajectoryStatus::kOk);
  pp.toMessage(&r.plan);
  r.plan.status = ucon::trajectory_t::STATUS_GOAL_REACHED;
  r.loop.plant.reset(0, 0, 0);
  r.run(1.5);  // republished past its end: accepted (goal reached may lie in the past)
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  EXPECT_NE(r.loop.ctrl.reason().find("holding"), std::string::npos) << r.loop.ctrl.reason();
  EXPECT_NEAR(r.loop.plant.state().x, 0.5, 0.005);
  r.publish_plan = false;
  r.run(0.5);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_IDLE);
  EXPECT_EQ(r.loop.ctrl.reason(), "goal reached");
  EXPECT_TRUE(allZero(r.last_cmd));
  EXPECT_NEAR(r.loop.plant.state().x, 0.5, 0.005);
}

TEST(BaseControllerParamsTest, GivenTheShippedYamlThenLoadsAndATypoIsNamed) {
  const auto text = ucon::runtime::readTextFile("deploy/config/base_controller.yaml", nullptr);
  ASSERT_TRUE(text.has_value());
  std::vector<ucon::ConfigError> errors;
  EXPECT_TRUE(ucon::loadParams<BaseControllerParams>(*text, "yaml", &errors).has_value());
  std::string typo = *text;
  typo.replace(typo.find("kp_position"), 11, "kp_positoin");
  errors.clear();
  EXPECT_FALSE(ucon::loadParams<BaseControllerParams>(typo, "yaml", &errors).has_value());
  std::string all;
  for (const auto& e : errors) all += e.toString();
  EXPECT_NE(all.find("control.kp_positoin"), std::string::npos) << all;
  EXPECT_NE(all.find("control.kp_position"), std::string::npos) << all;
}

TEST(BaseControllerBadInput, GivenCoefficientsThatOverflowWhenEvaluatedThenRejectedAndStops) {
  expectRejectedAndStops("overflow",
                         [](ucon::trajectory_t& m, int64_t) {
                           for (std::size_t k = 5; k < m.coeffs.size(); k += 6) m.coeffs[k] = 1e308;
                         },
                         "overflow");
}

TEST(BaseControllerBadInput, GivenAFiniteButAbsurdPlanThenRejectedWhenSampledAndStops) {
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(3.0);
  ASSERT_GT(r.cmdSpeed(), 0.5);
  for (std::size_t k = 5; k < r.plan.coeffs.size(); k += 6) r.plan.coeffs[k] = 1e30;  // well-formed, absurd
  r.run(0.1);
  EXPECT_NE(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  EXPECT_NE(r.loop.ctrl.reason().find("max_reference_speed"), std::string::npos) << r.loop.ctrl.reason();
  EXPECT_GE(stepUntilStopped(r, p, 2.0), 0);
  EXPECT_TRUE(std::isfinite(r.last_cmd.w_fl));
}

TEST(BaseControllerBadInput, GivenRandomGarbageInputsThenCommandsStayFiniteAndWithinLimits) {
  const BaseControllerParams p = shippedParams();
  ucon::base_controller::BaseController ctrl(p);
  std::mt19937_64 rng(12345);
  auto pick = [&](std::initializer_list<double> v) {
    return *(v.begin() + static_cast<std::ptrdiff_t>(rng() % v.size()));
  };
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  std::uniform_real_distribution<double> u(-5, 5);
  int64_t t = kT0;
  const test_support::FigureEight fig;
  const ucon::trajectory_t good = fig.message(kT0);
  for (int i = 0; i < 5000; ++i) {
    t += static_cast<int64_t>(rng() % 20000) - 2000;  // mostly forward, sometimes back
    switch (rng() % 4) {
      case 0: {
        ucon::robot_pose_t m{};
        m.utime = (rng() % 50 == 0) ? 0 : t;
        m.valid = rng() % 10 != 0;
        m.x = pick({u(rng), u(rng), nan, inf, 1e300});
        m.y = u(rng);
        m.yaw = pick({u(rng), nan, 1e9});
        m.vx = pick({u(rng), inf});
        m.vy = u(rng);
        m.wz = u(rng);
        ctrl.onPose(m);
        break;
      }
      case 1: {
        ucon::trajectory_t m = good;
        m.utime = t;
        m.start_utime = t - static_cast<int64_t>(rng() % 30'000'000);
        m.status = static_cast<int8_t>(rng() % 5);
        if (rng() % 3 == 0) m.coeffs[rng() % m.coeffs.size()] = pick({nan, inf, 1e200, -1e200});
        if (rng() % 5 == 0) m.durations[rng() % m.durations.size()] = pick({0.0, -1.0, nan, 1e-9});
        if (rng() % 7 == 0) m.num_pieces = static_cast<int32_t>(rng() % 1000);
        if (rng() % 7 == 0) m.dim = static_cast<int8_t>(rng() % 6);
        if (rng() % 7 == 0) m.order1 = static_cast<int8_t>(rng() % 20);
        if (rng() % 9 == 0) m.yaw = pick({nan, inf, u(rng)});
        ctrl.onTrajectory(m);
        break;
      }
      case 2: {
        ucon::estop_t m{};
        m.utime = (rng() % 10 == 0) ? -1 : t;
        m.engaged = rng() % 8 == 0;
        ctrl.onEstop(m);
        break;
      }
      default: {
        const BaseControllerOutput out = ctrl.tick(t);
        if (out.wheel_cmd) {
          const auto& c = *out.wheel_cmd;
          for (double w : {c.w_fl, c.w_fr, c.w_rl, c.w_rr}) {
            ASSERT_TRUE(std::isfinite(w)) << i;
            ASSERT_LE(std::fabs(w), p.mecanum.max_wheel_speed + 1e-9) << i;
          }
          ASSERT_TRUE(std::isfinite(c.vx) && std::isfinite(c.vy) && std::isfinite(c.wz)) << i;
        }
        if (out.status) {
          ASSERT_TRUE(std::isfinite(out.status->saturation)) << i;
        }
        break;
      }
    }
  }
  int64_t rejected = 0;
  for (const auto& [name, value] : ctrl.counters()) {
    if (name == "trajectories_rejected") rejected = value;
  }
  EXPECT_GT(rejected, 100);  // the garbage was seen as garbage
}

TEST(BaseControllerWatchdog, GivenTrackingWhenThePoseTurnsInvalidThenTheBaseStopsAtOnceUntilValidAndANewPlan) {
  // The odometry marks ROBOT_POSE invalid when it has lost its LiDAR updates: the base must
  // not wait for the staleness timeout (the invalid poses keep coming, fresh).
  const BaseControllerParams p = shippedParams();
  Running r(p);
  r.run(2.0);
  ASSERT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  ASSERT_GT(r.cmdSpeed(), 0.5);
  r.loop.send_pose = false;
  const int64_t t_invalid = r.loop.t;
  int64_t trigger = -1;
  for (int i = 0; i < 200; ++i) {
    ucon::robot_pose_t m = test_support::poseFrom(r.loop.plant.state(), r.loop.t);
    m.valid = false;
    r.loop.ctrl.onPose(m);
    r.step();
    if (trigger < 0 && r.loop.ctrl.state() != base_status_t::STATE_TRACKING) trigger = r.loop.t;
  }
  ASSERT_GE(trigger, 0);
  EXPECT_LE(trigger - t_invalid, 20000);  // on the first tick
  EXPECT_NE(r.loop.ctrl.reason().find("pose invalid"), std::string::npos) << r.loop.ctrl.reason();
  EXPECT_TRUE(allZero(r.last_cmd));
  // Valid poses again but the old plan: stays stopped; a new plan: tracking again.
  r.loop.send_pose = true;
  r.publish_plan = false;
  r.run(0.3);
  EXPECT_NE(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
  r.plan = r.fig.message(r.loop.t);
  r.next_plan = r.loop.t;
  r.publish_plan = true;
  r.run(0.2);
  EXPECT_EQ(r.loop.ctrl.state(), base_status_t::STATE_TRACKING);
}
