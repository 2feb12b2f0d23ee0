#include "ucon/simulator/scenario_loader.hpp"

#include "ucon/world/bench_generator.hpp"
#include "ucon/world/scenario_yaml.hpp"

namespace ucon {
namespace simulator {

std::optional<world::Scenario> loadScenario(const std::string& spec, const std::string& scenario_dir,
                                            long long seed_override, const FileReader& read,
                                            std::string* error) {
  std::string err;
  const auto s = world::parseScenarioSpec(spec, &err);
  if (!s) {
    if (error) *error = err;
    return std::nullopt;
  }
  if (s->kind == world::ScenarioSpec::Kind::kBench) {
    const uint64_t seed = seed_override >= 0 ? static_cast<uint64_t>(seed_override) : s->seed;
    return world::generateBench(s->num_moving, seed);
  }
  const std::string path =
      s->kind == world::ScenarioSpec::Kind::kBuiltin ? scenario_dir + "/" + s->name + ".yaml" : s->name;
  const auto text = read(path, &err);
  if (!text) {
    if (error) *error = "scenario '" + spec + "': " + err;
    return std::nullopt;
  }
  world::ScenarioError se;
  auto scen = world::parseScenarioYaml(*text, path, &se);
  if (!scen) {
    if (error) *error = se.toString();
    return std::nullopt;
  }
  if (seed_override >= 0) scen->seed = static_cast<uint64_t>(seed_override);
  return scen;
}

}  // namespace simulator
}  // namespace ucon
