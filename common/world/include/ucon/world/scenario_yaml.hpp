#pragma once
/// @file scenario_yaml.hpp
/// Scenario files (deploy/scenarios/*.yaml) parsed from text, and the scenario spec strings
/// accepted by the simulator (`pedestrians`, `crossing`, `corridor`, `hall`, `bench:<N_d>:<seed>`, a path).
///
/// File format (every key below; unknown keys are errors, optional keys marked):
/// @code
/// name: pedestrians
/// seed: 7                       # optional, default 1: seeds pedestrian timelines
/// duration: 243.0               # [s]
/// bounds: {xmin: -3, xmax: 12, ymin: -7, ymax: 7}
/// robot: {start: [0, 0], yaw: 0, radius: 0.3, max_speed: 1.5, max_accel: 2.0, goals: [[8, 0]]}
/// static:
///   - {type: cylinder, center: [3, 2], radius: 0.3, height: 2.0, reflectivity: 120}
///   - {type: box, center: [5, -2], size: [1.0, 0.6], yaw: 0.3, height: 1.2}
///   - {type: wall, from: [-3, 7], to: [12, 7], thickness: 0.2, height: 2.5}
/// moving:
///   - id: 1
///     radius: 0.25
///     height: 1.75
///     reflectivity: 40          # optional
///     motion: {type: constant_velocity, position: [0, 0], velocity: [1, 0]}
///   # constant_acceleration: position, velocity, acceleration, speed_cap
///   # sinusoidal: position, amplitude, omega, phase (optional), offset   (v = A sin(w t + phase) + offset)
///   # pedestrian: waypoints, mode (loop|pingpong|random), speed: [min, max],
///   #   speed_change_interval: [min, max], pause_probability, pause: [min, max], jitter
/// @endcode
/// reflectivity is optional everywhere (static default 100, moving default 60).

#include <cstdint>
#include <optional>
#include <string>

#include "ucon/world/scenario.hpp"

namespace ucon {
namespace world {

/// A scenario problem, naming the key path ("moving[2].motion.speed").
struct ScenarioError {
  std::string key;
  std::string message;
  /// "scenario error at 'key': message (in source)".
  std::string toString() const;
  std::string source;
};

/// Parses a scenario from YAML text; `source` names it in errors. The result is validated.
std::optional<Scenario> parseScenarioYaml(const std::string& text, const std::string& source,
                                          ScenarioError* error);

/// What a scenario spec string asks for.
struct ScenarioSpec {
  enum class Kind { kBuiltin, kBench, kFile } kind = Kind::kFile;
  std::string name;   ///< builtin name ("pedestrians", "crossing", "corridor", "hall") or file path
  int num_moving = 0; ///< bench: N_d
  uint64_t seed = 0;  ///< bench: seed
};

/// Parses "pedestrians" | "crossing" | "corridor" | "hall" | "bench:<N_d>:<seed>" | anything else = a file path.
/// Returns nullopt (and `error`) for a malformed bench spec.
std::optional<ScenarioSpec> parseScenarioSpec(const std::string& spec, std::string* error);

}  // namespace world
}  // namespace ucon
