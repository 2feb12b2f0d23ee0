// One source of truth per parameter: for every process, loading its shipped YAML
// (deploy/config/<process>.yaml) gives the in-class defaults, field by field, and every key of
// the file is checked (a key added to the file and to the struct but not here fails).
#include <gtest/gtest.h>

#include <string>

#include "shipped_config.hpp"
#include "ucon/base_controller/params.hpp"
#include "ucon/lidar_driver/driver_params.hpp"
#include "ucon/logger/logger_params.hpp"
#include "ucon/mission/mission_node.hpp"
#include "ucon/odometry/params.hpp"
#include "ucon/planner/planner_params.hpp"
#include "ucon/simulator/params.hpp"

using test_support::ShippedConfig;


TEST(ShippedConfig, GivenBaseControllerYamlWhenLoadedThenEveryFieldEqualsTheInClassDefault) {
  ShippedConfig<ucon::base_controller::BaseControllerParams> c("deploy/config/base_controller.yaml");
  ASSERT_TRUE(c.loaded());
  const auto& s = c.shipped();
  const ucon::base_controller::BaseControllerParams d;
  c.expect("mecanum.wheel_radius", s.mecanum.wheel_radius, d.mecanum.wheel_radius);
  c.expect("mecanum.half_wheelbase", s.mecanum.half_wheelbase, d.mecanum.half_wheelbase);
  c.expect("mecanum.half_track", s.mecanum.half_track, d.mecanum.half_track);
  c.expect("mecanum.max_wheel_speed", s.mecanum.max_wheel_speed, d.mecanum.max_wheel_speed);
  c.expect("mecanum.motor_order", s.mecanum.motor_order, d.mecanum.motor_order);
  c.expect("mecanum.motor_sign", s.mecanum.motor_sign, d.mecanum.motor_sign);
  c.expect("control.rate_hz", s.control.rate_hz, d.control.rate_hz);
  c.expect("control.lead_s", s.control.lead_s, d.control.lead_s);
  c.expect("control.kp_position", s.control.kp_position, d.control.kp_position);
  c.expect("control.kd_velocity", s.control.kd_velocity, d.control.kd_velocity);
  c.expect("control.accel_feedforward_s", s.control.accel_feedforward_s, d.control.accel_feedforward_s);
  c.expect("control.max_feedback_speed", s.control.max_feedback_speed, d.control.max_feedback_speed);
  c.expect("control.max_speed", s.control.max_speed, d.control.max_speed);
  c.expect("control.max_linear_accel", s.control.max_linear_accel, d.control.max_linear_accel);
  c.expect("control.kp_yaw", s.control.kp_yaw, d.control.kp_yaw);
  c.expect("control.max_yaw_rate", s.control.max_yaw_rate, d.control.max_yaw_rate);
  c.expect("control.max_yaw_accel", s.control.max_yaw_accel, d.control.max_yaw_accel);
  c.expect("heading.mode", s.heading.mode, d.heading.mode);
  c.expect("heading.hold_yaw", s.heading.hold_yaw, d.heading.hold_yaw);
  c.expect("heading.min_path_speed", s.heading.min_path_speed, d.heading.min_path_speed);
  c.expect("watchdog.pose_timeout_s", s.watchdog.pose_timeout_s, d.watchdog.pose_timeout_s);
  c.expect("watchdog.trajectory_timeout_s", s.watchdog.trajectory_timeout_s, d.watchdog.trajectory_timeout_s);
  c.expect("watchdog.stop_linear_decel", s.watchdog.stop_linear_decel, d.watchdog.stop_linear_decel);
  c.expect("watchdog.stop_angular_decel", s.watchdog.stop_angular_decel, d.watchdog.stop_angular_decel);
  c.expect("watchdog.max_reference_speed", s.watchdog.max_reference_speed, d.watchdog.max_reference_speed);
  c.expect("backend.type", s.backend.type, d.backend.type);
  c.expect("backend.serial_device", s.backend.serial_device, d.backend.serial_device);
  c.expect("backend.serial_baud", s.backend.serial_baud, d.backend.serial_baud);
  c.expect("status_period_s", s.status_period_s, d.status_period_s);
  c.expectEveryKeyChecked();
}

TEST(ShippedConfig, GivenLidarDriverYamlWhenLoadedThenEveryFieldEqualsTheInClassDefault) {
  ShippedConfig<ucon::lidar_driver::DriverParams> c("deploy/config/lidar_driver.yaml");
  ASSERT_TRUE(c.loaded());
  const auto& s = c.shipped();
  const ucon::lidar_driver::DriverParams d;
  c.expect("network.host_ip", s.network.host_ip, d.network.host_ip);
  c.expect("network.discovery", s.network.discovery, d.network.discovery);
  c.expect("network.discovery_address", s.network.discovery_address, d.network.discovery_address);
  c.expect("network.discovery_port", s.network.discovery_port, d.network.discovery_port);
  c.expect("network.sensor_command_port", s.network.sensor_command_port, d.network.sensor_command_port);
  c.expect("network.sensor_push_port", s.network.sensor_push_port, d.network.sensor_push_port);
  c.expect("network.sensor_point_port", s.network.sensor_point_port, d.network.sensor_point_port);
  c.expect("network.sensor_imu_port", s.network.sensor_imu_port, d.network.sensor_imu_port);
  c.expect("network.host_command_port", s.network.host_command_port, d.network.host_command_port);
  c.expect("network.host_push_port", s.network.host_push_port, d.network.host_push_port);
  c.expect("network.host_point_port", s.network.host_point_port, d.network.host_point_port);
  c.expect("network.host_imu_port", s.network.host_imu_port, d.network.host_imu_port);
  c.expect("network.socket_buffer_bytes", s.network.socket_buffer_bytes, d.network.socket_buffer_bytes);
  c.expect("control.enabled", s.control.enabled, d.control.enabled);
  c.expect("control.timeout_s", s.control.timeout_s, d.control.timeout_s);
  c.expect("control.retry_interval_s", s.control.retry_interval_s, d.control.retry_interval_s);
  c.expect("control.work_mode", s.control.work_mode, d.control.work_mode);
  c.expect("control.point_data_type", s.control.point_data_type, d.control.point_data_type);
  c.expect("control.reset_install_attitude", s.control.reset_install_attitude, d.control.reset_install_attitude);
  c.expect("control.reconfigure_after_s", s.control.reconfigure_after_s, d.control.reconfigure_after_s);
  c.expect("frame.rate_hz", s.frame.rate_hz, d.frame.rate_hz);
  c.expect("frame.max_points", s.frame.max_points, d.frame.max_points);
  c.expect("frame.idle_flush_s", s.frame.idle_flush_s, d.frame.idle_flush_s);
  c.expect("frame.apply_extrinsic", s.frame.apply_extrinsic, d.frame.apply_extrinsic);
  c.expect("frame.merge_wait_s", s.frame.merge_wait_s, d.frame.merge_wait_s);
  c.expect("filter.min_range_m", s.filter.min_range_m, d.filter.min_range_m);
  c.expect("filter.max_range_m", s.filter.max_range_m, d.filter.max_range_m);
  c.expect("filter.drop_sticking_level", s.filter.drop_sticking_level, d.filter.drop_sticking_level);
  c.expect("filter.drop_rain_fog_dust_level", s.filter.drop_rain_fog_dust_level, d.filter.drop_rain_fog_dust_level);
  c.expect("filter.drop_other_noise_level", s.filter.drop_other_noise_level, d.filter.drop_other_noise_level);
  // The list of sensors: the shipped one is the default sensor.
  c.expect("sensors", s.sensors.size(), d.sensors.size());
  ASSERT_EQ(s.sensors.size(), 1u);
  EXPECT_EQ(s.sensors[0].ip, d.sensors[0].ip);
  EXPECT_EQ(s.sensors[0].xyz, d.sensors[0].xyz);
  EXPECT_EQ(s.sensors[0].rpy_deg, d.sensors[0].rpy_deg);
  EXPECT_EQ(s.sensors[0].imu, d.sensors[0].imu);
  c.expect("status_period_s", s.status_period_s, d.status_period_s);
  c.expectEveryKeyChecked();
}

TEST(ShippedConfig, GivenLoggerYamlWhenLoadedThenEveryFieldEqualsTheInClassDefault) {
  ShippedConfig<ucon::logger::LoggerParams> c("deploy/config/logger.yaml");
  ASSERT_TRUE(c.loaded());
  const auto& s = c.shipped();
  const ucon::logger::LoggerParams d;
  c.expect("include", s.include, d.include);
  c.expect("exclude", s.exclude, d.exclude);
  c.expect("run_name", s.run_name, d.run_name);
  c.expect("max_file_mb", s.max_file_mb, d.max_file_mb);
  c.expect("max_file_s", s.max_file_s, d.max_file_s);
  c.expect("flush_interval_s", s.flush_interval_s, d.flush_interval_s);
  c.expect("min_free_mb", s.min_free_mb, d.min_free_mb);
  c.expect("queue_limit_mb", s.queue_limit_mb, d.queue_limit_mb);
  c.expect("status_period_s", s.status_period_s, d.status_period_s);
  c.expectEveryKeyChecked();
}

TEST(ShippedConfig, GivenMissionYamlWhenLoadedThenEveryFieldEqualsTheInClassDefault) {
  ShippedConfig<ucon::mission::MissionParams> c("deploy/config/mission.yaml");
  ASSERT_TRUE(c.loaded());
  const auto& s = c.shipped();
  const ucon::mission::MissionParams d;
  c.expect("goal_tolerance", s.goal_tolerance, d.goal_tolerance);
  c.expect("resend_period_s", s.resend_period_s, d.resend_period_s);
  c.expect("mot_threshold", s.mot_threshold, d.mot_threshold);
  c.expect("min_visible", s.min_visible, d.min_visible);
  c.expect("max_gt_lag_s", s.max_gt_lag_s, d.max_gt_lag_s);
  c.expect("settle_s", s.settle_s, d.settle_s);
  c.expectEveryKeyChecked();
}

TEST(ShippedConfig, GivenPlannerYamlWhenLoadedThenEveryFieldEqualsTheInClassDefault) {
  ShippedConfig<ucon::planner::PlannerParams> c("deploy/config/planner.yaml");
  ASSERT_TRUE(c.loaded());
  const auto& s = c.shipped();
  const ucon::planner::PlannerParams d;
  c.expect("optimizer.sector.h", s.optimizer.sector.h, d.optimizer.sector.h);
  c.expect("optimizer.sector.k", s.optimizer.sector.k, d.optimizer.sector.k);
  c.expect("optimizer.sector.kappa", s.optimizer.sector.kappa, d.optimizer.sector.kappa);
  c.expect("optimizer.sector.alpha", s.optimizer.sector.alpha, d.optimizer.sector.alpha);
  c.expect("optimizer.sector.beta", s.optimizer.sector.beta, d.optimizer.sector.beta);
  c.expect("optimizer.sector.min_speed", s.optimizer.sector.min_speed, d.optimizer.sector.min_speed);
  c.expect("optimizer.sector.fapp_margin", s.optimizer.sector.fapp_margin, d.optimizer.sector.fapp_margin);
  c.expect("optimizer.lambda_d", s.optimizer.lambda_d, d.optimizer.lambda_d);
  c.expect("optimizer.rho", s.optimizer.rho, d.optimizer.rho);
  c.expect("optimizer.safe_distance", s.optimizer.safe_distance, d.optimizer.safe_distance);
  c.expect("optimizer.max_velocity", s.optimizer.max_velocity, d.optimizer.max_velocity);
  c.expect("optimizer.max_acceleration", s.optimizer.max_acceleration, d.optimizer.max_acceleration);
  c.expect("optimizer.samples_per_piece", s.optimizer.samples_per_piece, d.optimizer.samples_per_piece);
  c.expect("optimizer.obstacle_model", s.optimizer.obstacle_model, d.optimizer.obstacle_model);
  c.expect("optimizer.weight_static", s.optimizer.weight_static, d.optimizer.weight_static);
  c.expect("optimizer.weight_velocity", s.optimizer.weight_velocity, d.optimizer.weight_velocity);
  c.expect("optimizer.weight_acceleration", s.optimizer.weight_acceleration, d.optimizer.weight_acceleration);
  c.expect("optimizer.dynamic_horizon", s.optimizer.dynamic_horizon, d.optimizer.dynamic_horizon);
  c.expect("optimizer.obstacle_corridor", s.optimizer.obstacle_corridor, d.optimizer.obstacle_corridor);
  c.expect("optimizer.max_iterations", s.optimizer.max_iterations, d.optimizer.max_iterations);
  c.expect("optimizer.relative_tolerance", s.optimizer.relative_tolerance, d.optimizer.relative_tolerance);
  c.expect("optimizer.use_time_budget", s.optimizer.use_time_budget, d.optimizer.use_time_budget);
  c.expect("optimizer.time_budget_ms", s.optimizer.time_budget_ms, d.optimizer.time_budget_ms);
  c.expect("optimizer.robot_radius", s.optimizer.robot_radius, d.optimizer.robot_radius);
  c.expect("optimizer.check_step", s.optimizer.check_step, d.optimizer.check_step);
  c.expect("optimizer.check_horizon", s.optimizer.check_horizon, d.optimizer.check_horizon);
  c.expect("optimizer.limit_tolerance", s.optimizer.limit_tolerance, d.optimizer.limit_tolerance);
  c.expect("optimizer.check_uncertainty_k", s.optimizer.check_uncertainty_k, d.optimizer.check_uncertainty_k);
  c.expect("optimizer.check_uncertainty_cap", s.optimizer.check_uncertainty_cap, d.optimizer.check_uncertainty_cap);
  c.expect("optimizer.static_escape_s", s.optimizer.static_escape_s, d.optimizer.static_escape_s);
  c.expect("prediction.accel_psd_xy", s.prediction.accel_psd_xy, d.prediction.accel_psd_xy);
  c.expect("prediction.accel_psd_z", s.prediction.accel_psd_z, d.prediction.accel_psd_z);
  c.expect("rate_hz", s.rate_hz, d.rate_hz);
  c.expect("latency_s", s.latency_s, d.latency_s);
  c.expect("horizon_length", s.horizon_length, d.horizon_length);
  c.expect("replan_deviation", s.replan_deviation, d.replan_deviation);
  c.expect("pose_timeout_s", s.pose_timeout_s, d.pose_timeout_s);
  c.expect("goal_default_tolerance", s.goal_default_tolerance, d.goal_default_tolerance);
  c.expect("static_insert_period_s", s.static_insert_period_s, d.static_insert_period_s);
  c.expect("max_attempts", s.max_attempts, d.max_attempts);
  c.expect("retry_speed_scale", s.retry_speed_scale, d.retry_speed_scale);
  c.expect("fallback.detours", s.fallback.detours, d.fallback.detours);
  c.expect("fallback.detour_length", s.fallback.detour_length, d.fallback.detour_length);
  c.expect("fallback.directions", s.fallback.directions, d.fallback.directions);
  c.expect("fallback.run_s", s.fallback.run_s, d.fallback.run_s);
  c.expect("fallback.horizon_s", s.fallback.horizon_s, d.fallback.horizon_s);
  c.expect("fallback.step_s", s.fallback.step_s, d.fallback.step_s);
  c.expect("fallback.reaction_s", s.fallback.reaction_s, d.fallback.reaction_s);
  c.expect("fallback.gap_cap", s.fallback.gap_cap, d.fallback.gap_cap);
  c.expect("fallback.uncertainty_k", s.fallback.uncertainty_k, d.fallback.uncertainty_k);
  c.expect("fallback.mean_weight", s.fallback.mean_weight, d.fallback.mean_weight);
  c.expect("fallback.goal_weight", s.fallback.goal_weight, d.fallback.goal_weight);
  c.expect("fallback.keep_margin", s.fallback.keep_margin, d.fallback.keep_margin);
  c.expect("workspace.x_min", s.workspace.x_min, d.workspace.x_min);
  c.expect("workspace.x_max", s.workspace.x_max, d.workspace.x_max);
  c.expect("workspace.y_min", s.workspace.y_min, d.workspace.y_min);
  c.expect("workspace.y_max", s.workspace.y_max, d.workspace.y_max);
  c.expect("objects.fallback_position_std", s.objects.fallback_position_std, d.objects.fallback_position_std);
  c.expect("objects.fallback_velocity_std", s.objects.fallback_velocity_std, d.objects.fallback_velocity_std);
  c.expect("objects.max_age_s", s.objects.max_age_s, d.objects.max_age_s);
  c.expect("objects.max_range", s.objects.max_range, d.objects.max_range);
  c.expect("objects.include_tentative", s.objects.include_tentative, d.objects.include_tentative);
  c.expect("objects.min_radius", s.objects.min_radius, d.objects.min_radius);
  c.expect("objects.clear_under_speed", s.objects.clear_under_speed, d.objects.clear_under_speed);
  c.expect("objects.clear_max_radius", s.objects.clear_max_radius, d.objects.clear_max_radius);
  c.expect("objects.clear_max_age", s.objects.clear_max_age, d.objects.clear_max_age);
  c.expect("map.resolution", s.map.resolution, d.map.resolution);
  c.expect("map.max_range", s.map.max_range, d.map.max_range);
  c.expect("map.band_z_min", s.map.band_z_min, d.map.band_z_min);
  c.expect("map.band_z_max", s.map.band_z_max, d.map.band_z_max);
  c.expect("map.box_half_size", s.map.box_half_size, d.map.box_half_size);
  c.expect("map.recenter_distance", s.map.recenter_distance, d.map.recenter_distance);
  c.expect("map.max_distance", s.map.max_distance, d.map.max_distance);
  c.expect("map.prob_hit", s.map.prob_hit, d.map.prob_hit);
  c.expect("map.prob_miss", s.map.prob_miss, d.map.prob_miss);
  c.expect("map.band_only", s.map.band_only, d.map.band_only);
  c.expect("map.insert_threads", s.map.insert_threads, d.map.insert_threads);
  c.expect("front_end.inflation", s.front_end.inflation, d.front_end.inflation);
  c.expect("front_end.hard_clearance", s.front_end.hard_clearance, d.front_end.hard_clearance);
  c.expect("front_end.soft_cost", s.front_end.soft_cost, d.front_end.soft_cost);
  c.expect("front_end.window_radius", s.front_end.window_radius, d.front_end.window_radius);
  c.expect("front_end.max_expansions", s.front_end.max_expansions, d.front_end.max_expansions);
  c.expect("front_end.piece_length", s.front_end.piece_length, d.front_end.piece_length);
  c.expect("front_end.max_pieces", s.front_end.max_pieces, d.front_end.max_pieces);
  c.expect("front_end.guess_speed_ratio", s.front_end.guess_speed_ratio, d.front_end.guess_speed_ratio);
  c.expect("front_end.guess_accel_ratio", s.front_end.guess_accel_ratio, d.front_end.guess_accel_ratio);
  c.expectEveryKeyChecked();
}

TEST(ShippedConfig, GivenOdometryYamlWhenLoadedThenEveryFieldEqualsTheInClassDefault) {
  ShippedConfig<ucon::odometry::OdometryParams> c("deploy/config/odometry.yaml");
  ASSERT_TRUE(c.loaded());
  const auto& s = c.shipped();
  const ucon::odometry::OdometryParams d;
  c.expect("points_frame", s.points_frame, d.points_frame);
  c.expect("pose_channel", s.pose_channel, d.pose_channel);
  c.expect("health_period_s", s.health_period_s, d.health_period_s);
  c.expect("imu.position", s.lio.imu_position, d.lio.imu_position);
  c.expect("imu.time_offset_s", s.lio.imu_time_offset_s, d.lio.imu_time_offset_s);
  c.expect("imu.gravity", s.lio.gravity, d.lio.gravity);
  c.expect("imu.gyro_noise", s.lio.noise.gyro_noise, d.lio.noise.gyro_noise);
  c.expect("imu.acc_noise", s.lio.noise.acc_noise, d.lio.noise.acc_noise);
  c.expect("imu.gyro_bias_walk", s.lio.noise.gyro_bias_walk, d.lio.noise.gyro_bias_walk);
  c.expect("imu.acc_bias_walk", s.lio.noise.acc_bias_walk, d.lio.noise.acc_bias_walk);
  c.expect("imu.gap_s", s.lio.imu_gap_s, d.lio.imu_gap_s);
  c.expect("imu.max_gap_s", s.lio.max_imu_gap_s, d.lio.max_imu_gap_s);
  c.expect("imu.gap_acc_std", s.lio.gap_acc_std, d.lio.gap_acc_std);
  c.expect("imu.gap_gyro_std", s.lio.gap_gyro_std, d.lio.gap_gyro_std);
  c.expect("init.window_s", s.lio.init_window_s, d.lio.init_window_s);
  c.expect("init.max_gyro_std", s.lio.init_max_gyro_std, d.lio.init_max_gyro_std);
  c.expect("init.max_acc_std", s.lio.init_max_acc_std, d.lio.init_max_acc_std);
  c.expect("init.max_gravity_error", s.lio.init_max_gravity_error, d.lio.init_max_gravity_error);
  c.expect("init.pose", s.lio.initial_pose, d.lio.initial_pose);
  c.expect("init.position_std", s.lio.initial_position_std, d.lio.initial_position_std);
  c.expect("init.yaw_std", s.lio.initial_yaw_std, d.lio.initial_yaw_std);
  c.expect("init.velocity_std", s.lio.initial_velocity_std, d.lio.initial_velocity_std);
  c.expect("init.acc_bias_std", s.lio.initial_acc_bias_std, d.lio.initial_acc_bias_std);
  c.expect("init.gyro_bias_std", s.lio.initial_gyro_bias_std, d.lio.initial_gyro_bias_std);
  c.expect("points.min_range", s.lio.min_range, d.lio.min_range);
  c.expect("points.max_range", s.lio.max_range, d.lio.max_range);
  c.expect("points.downsample_voxel", s.lio.downsample_voxel, d.lio.downsample_voxel);
  c.expect("points.min_points", s.lio.min_points, d.lio.min_points);
  c.expect("points.max_points", s.lio.max_points, d.lio.max_points);
  c.expect("update.max_iterations", s.lio.max_iterations, d.lio.max_iterations);
  c.expect("update.knn", s.lio.knn, d.lio.knn);
  c.expect("update.max_correspondence", s.lio.max_correspondence, d.lio.max_correspondence);
  c.expect("update.plane_threshold", s.lio.plane_threshold, d.lio.plane_threshold);
  c.expect("update.point_std", s.lio.point_std, d.lio.point_std);
  c.expect("update.robust_scale", s.lio.robust_scale, d.lio.robust_scale);
  c.expect("update.outlier_distance", s.lio.outlier_distance, d.lio.outlier_distance);
  c.expect("update.converged_rotation", s.lio.converged_rotation, d.lio.converged_rotation);
  c.expect("update.converged_translation", s.lio.converged_translation, d.lio.converged_translation);
  c.expect("update.research_translation", s.lio.research_translation, d.lio.research_translation);
  c.expect("update.research_rotation", s.lio.research_rotation, d.lio.research_rotation);
  c.expect("update.min_matched_ratio", s.lio.min_matched_ratio, d.lio.min_matched_ratio);
  c.expect("map.voxel_size", s.lio.map.voxel_size, d.lio.map.voxel_size);
  c.expect("map.max_points_per_voxel", s.lio.map.max_points_per_voxel, d.lio.map.max_points_per_voxel);
  c.expect("map.min_point_spacing", s.lio.map.min_point_spacing, d.lio.map.min_point_spacing);
  c.expect("map.max_voxels", s.lio.map.max_voxels, d.lio.map.max_voxels);
  c.expect("map.radius", s.lio.map.radius, d.lio.map.radius);
  c.expect("map.neighbourhood", s.lio.map.neighbourhood, d.lio.map.neighbourhood);
  c.expect("map.trim_every_m", s.lio.map_trim_every_m, d.lio.map_trim_every_m);
  c.expect("map.insert_max_residual", s.lio.map_insert_max_residual, d.lio.map_insert_max_residual);
  c.expect("map.carve_every", s.lio.map_carve_every, d.lio.map_carve_every);
  c.expect("map.carve_radius", s.lio.map.carve_radius, d.lio.map.carve_radius);
  c.expect("map.carve_bin_deg", s.lio.map.carve_bin_deg, d.lio.map.carve_bin_deg);
  c.expect("map.carve_margin", s.lio.map.carve_margin, d.lio.map.carve_margin);
  c.expect("map.carve_misses", s.lio.map.carve_misses, d.lio.map.carve_misses);
  c.expect("ground_prior.enabled", s.lio.ground_prior, d.lio.ground_prior);
  c.expect("ground_prior.height_std", s.lio.ground_height_std, d.lio.ground_height_std);
  c.expect("ground_prior.tilt_std", s.lio.ground_tilt_std, d.lio.ground_tilt_std);
  c.expect("output.imu_only_timeout_s", s.lio.imu_only_timeout_s, d.lio.imu_only_timeout_s);
  c.expect("output.max_pending_frames", s.lio.max_pending_frames, d.lio.max_pending_frames);
  c.expectEveryKeyChecked();
}

TEST(ShippedConfig, GivenSimulatorYamlWhenLoadedThenEveryFieldEqualsTheInClassDefault) {
  ShippedConfig<ucon::simulator::SimulatorParams> c("deploy/config/simulator.yaml");
  ASSERT_TRUE(c.loaded());
  const auto& s = c.shipped();
  const ucon::simulator::SimulatorParams d;
  c.expect("start_utime", s.start_utime, d.start_utime);
  c.expect("frame_rate_hz", s.frame_rate_hz, d.frame_rate_hz);
  c.expect("pose_rate_hz", s.pose_rate_hz, d.pose_rate_hz);
  c.expect("cmd_timeout_s", s.cmd_timeout_s, d.cmd_timeout_s);
  c.expect("status_period_s", s.status_period_s, d.status_period_s);
  c.expect("pose_source", s.pose_source, d.pose_source);
  c.expect("lidar.point_rate", s.lidar.point_rate, d.lidar.point_rate);
  c.expect("lidar.data_type", s.lidar.data_type, d.lidar.data_type);
  c.expect("lidar.min_range", s.lidar.min_range, d.lidar.min_range);
  c.expect("lidar.max_range", s.lidar.max_range, d.lidar.max_range);
  c.expect("lidar.range_noise_sigma", s.lidar.range_noise_sigma, d.lidar.range_noise_sigma);
  c.expect("lidar.elevation_min_deg", s.lidar.elevation_min_deg, d.lidar.elevation_min_deg);
  c.expect("lidar.elevation_max_deg", s.lidar.elevation_max_deg, d.lidar.elevation_max_deg);
  c.expect("lidar.mount_xyz", s.lidar.mount_xyz, d.lidar.mount_xyz);
  c.expect("lidar.mount_rpy_deg", s.lidar.mount_rpy_deg, d.lidar.mount_rpy_deg);
  c.expect("lidar.ground_reflectivity", s.lidar.ground_reflectivity, d.lidar.ground_reflectivity);
  c.expect("lidar.seed", s.lidar.seed, d.lidar.seed);
  c.expect("imu.rate_hz", s.imu.rate_hz, d.imu.rate_hz);
  c.expect("imu.gyro_noise_sigma", s.imu.gyro_noise_sigma, d.imu.gyro_noise_sigma);
  c.expect("imu.acc_noise_sigma", s.imu.acc_noise_sigma, d.imu.acc_noise_sigma);
  c.expect("imu.gyro_bias_walk", s.imu.gyro_bias_walk, d.imu.gyro_bias_walk);
  c.expect("imu.acc_bias_walk", s.imu.acc_bias_walk, d.imu.acc_bias_walk);
  c.expect("imu.gyro_bias", s.imu.gyro_bias, d.imu.gyro_bias);
  c.expect("imu.acc_bias", s.imu.acc_bias, d.imu.acc_bias);
  c.expect("imu.position", s.imu.position, d.imu.position);
  c.expect("imu.time_offset_s", s.imu.time_offset_s, d.imu.time_offset_s);
  c.expect("vibration.amplitude_deg", s.vibration.amplitude_deg, d.vibration.amplitude_deg);
  c.expect("vibration.frequency_hz", s.vibration.frequency_hz, d.vibration.frequency_hz);
  c.expect("net.host_ip", s.net.host_ip, d.net.host_ip);
  c.expect("net.host_point_port", s.net.host_point_port, d.net.host_point_port);
  c.expect("net.host_imu_port", s.net.host_imu_port, d.net.host_imu_port);
  c.expect("net.sensor_ip", s.net.sensor_ip, d.net.sensor_ip);
  c.expect("net.discovery_port", s.net.discovery_port, d.net.discovery_port);
  c.expect("net.command_port", s.net.command_port, d.net.command_port);
  c.expect("net.point_src_port", s.net.point_src_port, d.net.point_src_port);
  c.expect("net.imu_src_port", s.net.imu_src_port, d.net.imu_src_port);
  c.expect("net.serial", s.net.serial, d.net.serial);
  c.expect("extra_lidars", s.extra_lidars.size(), d.extra_lidars.size());
  c.expect("base.wheel_radius", s.base.geometry.wheel_radius, d.base.geometry.wheel_radius);
  c.expect("base.half_wheelbase", s.base.geometry.half_wheelbase, d.base.geometry.half_wheelbase);
  c.expect("base.half_track", s.base.geometry.half_track, d.base.geometry.half_track);
  c.expect("base.max_wheel_speed", s.base.geometry.max_wheel_speed, d.base.geometry.max_wheel_speed);
  c.expect("base.motor_order", s.base.geometry.motor_order, d.base.geometry.motor_order);
  c.expect("base.motor_sign", s.base.geometry.motor_sign, d.base.geometry.motor_sign);
  c.expect("base.motor_time_constant", s.base.motor_time_constant, d.base.motor_time_constant);
  c.expect("base.max_wheel_accel", s.base.max_wheel_accel, d.base.max_wheel_accel);
  c.expectEveryKeyChecked();
}
