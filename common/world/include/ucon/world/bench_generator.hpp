#pragma once
/// @file bench_generator.hpp
/// The seeded dynamic-obstacle benchmark world `bench:<N_d>:<seed>` (paper Sec. V-C,
/// docs/reference.md §8). The paper gives the area, the number of static obstacles and the moving
/// obstacles' radius range; the other values below are this project's defaults.
///
/// Layout: bounds [-25, 25] x [-25, 25] m. The robot starts at x = -22 m and its goal is at
/// x = +22 m, both at a random y in [-20, 20] m, so the robot crosses at least 44 m.
/// 160 static obstacles: half vertical cylinders (radius 0.3-0.8 m), half boxes (sides 0.6-2.0 m,
/// random yaw), heights 1.0-3.0 m, at least 1.0 m apart (surface to surface, bounding circles),
/// none within 2.5 m of the start or the goal.
/// N_d moving cylinders: radius 0.2-0.5 m, height 1.0-2.0 m, motion cycled CV, CA, sinusoidal
/// (so a third each), speeds 0.3-1.5 m/s:
///  - CV: heading uniform, speed U(0.3, 1.5).
///  - CA: initial speed U(0.3, 1.5), acceleration |a| U(0.1, 0.5) m/s^2 in a random direction,
///        speed capped at 1.5 m/s.
///  - sinusoidal (v_i = A_i sin(w_i t + phi_i) + o_i per axis): mean velocity o of speed
///        U(0.3, 1.0) in a random direction, A_i U(0.2, 0.8) m/s, w_i U(0.3, 1.2) rad/s,
///        phi_i U(0, 2 pi); scaled down if |o| + |A| could exceed 1.5 m/s.
/// At t = 0 moving obstacles are at least 0.5 m (surface) from every static obstacle and every
/// other mover and at least 3.0 m from the robot's start and goal. Moving obstacles bounce at
/// the bounds and pass through static obstacles and each other. Robot radius 0.3 m, limits
/// 1.5 m/s and 2 m/s^2. The robot starts facing +x (yaw 0).
///
/// Portability: generation uses only Rng::uniform01, +, -, *, / and sqrt (correctly rounded in
/// IEEE 754; the library is compiled with -ffp-contract=off), never cos/sin/atan2, so every number
/// of the generated Scenario is bit-identical on every machine for a given seed. (Evaluating a
/// sinusoid or a rotated box later does call the libm.)

#include <cstdint>

#include "ucon/world/scenario.hpp"

namespace ucon {
namespace world {

/// Generator parameters (defaults = the benchmark world described above).
struct BenchParams {
  double half_size = 25.0;          ///< bounds are [-half, half]^2 [m]
  int num_static = 160;             ///< static obstacles
  double static_cylinder_r_min = 0.3, static_cylinder_r_max = 0.8;  ///< [m]
  double static_box_side_min = 0.6, static_box_side_max = 2.0;      ///< [m]
  double static_height_min = 1.0, static_height_max = 3.0;          ///< [m]
  double static_spacing = 1.0;      ///< min surface gap between static obstacles [m]
  double start_x = -22.0, goal_x = 22.0;  ///< robot start / goal x [m]
  double endpoint_y_range = 20.0;   ///< start / goal y uniform in [-range, range] [m]
  double static_clear_radius = 2.5; ///< no static obstacle within this of start/goal [m]
  double mover_r_min = 0.2, mover_r_max = 0.5;          ///< [m]
  double mover_height_min = 1.0, mover_height_max = 2.0; ///< [m]
  double speed_min = 0.3, speed_max = 1.5;              ///< [m/s]
  double ca_accel_min = 0.1, ca_accel_max = 0.5;        ///< [m/s^2]
  double sin_mean_speed_max = 1.0;                      ///< [m/s]
  double sin_amp_min = 0.2, sin_amp_max = 0.8;          ///< [m/s]
  double sin_omega_min = 0.3, sin_omega_max = 1.2;      ///< [rad/s]
  double mover_spacing = 0.5;       ///< min surface gap of movers at t = 0 [m]
  double mover_clear_radius = 3.0;  ///< no mover within this of start/goal at t = 0 [m]
  double robot_radius = 0.3, robot_max_speed = 1.5, robot_max_accel = 2.0;
  double duration_s = 120.0;        ///< nominal run length [s]
};

/// Generates `bench:<num_moving>:<seed>`. Deterministic in (params, num_moving, seed).
Scenario generateBench(int num_moving, uint64_t seed, const BenchParams& params = BenchParams{});

}  // namespace world
}  // namespace ucon
