#include "ucon/planner/planner_params.hpp"

#include "ucon/config.hpp"

namespace ucon::planner {

void Workspace::read(ConfigReader& r) {
  r.read("x_min", x_min, -1e5, 1e5);
  r.read("x_max", x_max, -1e5, 1e5);
  r.read("y_min", y_min, -1e5, 1e5);
  r.read("y_max", y_max, -1e5, 1e5);
  if (!(x_max > x_min)) r.fail("x_max", "must be greater than x_min");
  if (!(y_max > y_min)) r.fail("y_max", "must be greater than y_min");
}

void PredictionParams::read(ConfigReader& r) {
  r.read("accel_psd_xy", accel_psd_xy, 1e-9, 1e3);
  r.read("accel_psd_z", accel_psd_z, 1e-9, 1e3);
}

kalman::KalmanParams PredictionParams::model() const {
  kalman::KalmanParams k;
  k.accel_psd_xy = accel_psd_xy;
  k.accel_psd_z = accel_psd_z;
  return k;
}

void ObjectParams::read(ConfigReader& r) {
  r.read("fallback_position_std", fallback_position_std, 0.01, 10.0);
  r.read("fallback_velocity_std", fallback_velocity_std, 0.01, 10.0);
  r.read("max_age_s", max_age_s, 0.01, 10.0);
  r.read("max_range", max_range, 0.5, 200.0);
  r.read("include_tentative", include_tentative);
  r.read("min_radius", min_radius, 0.0, 5.0);
  r.read("clear_under_speed", clear_under_speed, 0.0, 10.0);
  r.read("clear_max_radius", clear_max_radius, 0.0, 5.0);
  r.read("clear_max_age", clear_max_age, 0.0, 60.0);
}

void PlannerParams::read(ConfigReader& r) {
  r.read("rate_hz", rate_hz, 0.5, 100.0);
  r.read("latency_s", latency_s, 0.0, 1.0);
  r.read("horizon_length", horizon_length, 0.5, 100.0);
  r.read("replan_deviation", replan_deviation, 0.01, 10.0);
  r.read("pose_timeout_s", pose_timeout_s, 0.01, 10.0);
  r.read("goal_default_tolerance", goal_default_tolerance, 0.01, 10.0);
  r.read("static_insert_period_s", static_insert_period_s, 0.0, 1.0);
  r.read("max_attempts", max_attempts, 1, 5);
  r.read("retry_speed_scale", retry_speed_scale, 0.1, 1.0);
  auto fb = r.section("fallback");
  fallback.read(fb);
  auto ws = r.section("workspace");
  workspace.read(ws);
  auto ob = r.section("objects");
  objects.read(ob);
  auto pr = r.section("prediction");
  prediction.read(pr);
  auto mp = r.section("map");
  map.read(mp);
  auto fe = r.section("front_end");
  front_end.read(fe);
  auto op = r.section("optimizer");
  optimizer.read(op);
  // Cross-module consistency: the front end's window must stay inside the ESDF box even just
  // before the box is re-centred.
  if (front_end.window_radius > map.box_half_size - map.recenter_distance) {
    r.fail("front_end.window_radius", "must be <= map.box_half_size - map.recenter_distance");
  }
  if (front_end.inflation < optimizer.robot_radius) {
    r.fail("front_end.inflation", "must be >= optimizer.robot_radius");
  }
}

}  // namespace ucon::planner
