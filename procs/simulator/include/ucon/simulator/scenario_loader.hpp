#pragma once
/// @file scenario_loader.hpp
/// Turns a scenario spec (`pedestrians`, `crossing`, `bench:<N_d>:<seed>`, a path) into a
/// Scenario. The caller supplies the file reader, so this stays free of I/O.

#include <functional>
#include <optional>
#include <string>

#include "ucon/world/scenario.hpp"

namespace ucon {
namespace simulator {

/// Reads a whole file; nullopt (and an error) if it cannot.
using FileReader = std::function<std::optional<std::string>(const std::string& path, std::string* error)>;

/// Builtin names resolve to `<scenario_dir>/<name>.yaml`. `seed_override` >= 0 replaces the
/// scenario's seed (YAML: pedestrian timelines; bench: the generator seed). On failure returns
/// nullopt and a message naming the spec, the file and the bad key.
std::optional<world::Scenario> loadScenario(const std::string& spec, const std::string& scenario_dir,
                                            long long seed_override, const FileReader& read,
                                            std::string* error);

}  // namespace simulator
}  // namespace ucon
