// ucon-sim-record: records a short simulated run into an LCM log, in-process and without LCM
// sockets: simulator + lidar driver + the chosen nodes in a closed loop (recordSimulatedRun).
// The same options give the same bytes on every run, so the log can stand as replay and
// golden input.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "ucon/replay/record_to_log.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif

int main(int argc, char** argv) {
  namespace rp = ucon::replay;
  CLI::App app{"Record a simulated run in-process (simulator + lidar driver + nodes, no LCM) into an LCM log."};
  std::string out, nodes_arg = "all";
  rp::RecordingSpec spec;
  spec.config_dir = std::string(UCON_SOURCE_DIR) + "/deploy/config";
  spec.scenario_dir = std::string(UCON_SOURCE_DIR) + "/deploy/scenarios";
  app.add_option("--out", out, "LCM log to write")->required();
  app.add_option("--scenario", spec.scenario, "pedestrians | crossing | bench:<N_d>:<seed> | path.yaml");
  app.add_option("--duration", spec.duration_s, "simulated seconds")->check(CLI::Range(0.01, 3600.0));
  app.add_option("--nodes", nodes_arg,
                 "nodes in the loop, comma separated, 'all' (every built node) or 'none'; without "
                 "a planner a scripted straight-line plan drives the base");
  app.add_option("--config-dir", spec.config_dir, "folder of simulator.yaml, lidar_driver.yaml and <node>.yaml");
  app.add_option("--scenario-dir", spec.scenario_dir, "folder of the builtin scenarios");
  app.add_option("--seed", spec.seed, "override the scenario seed");
  bool digest = false;
  app.add_flag("--print-digest", digest,
               "after recording, print 'input <channel> <events> <fnv64>' per channel (golden manifest)");
  CLI11_PARSE(app, argc, argv);
  spec.nodes = rp::parseNodeList(nodes_arg);

  rp::RecordSummary summary;
  std::string err;
  if (!rp::recordToLog(spec, out, &summary, &err)) {
    std::fprintf(stderr, "ucon-sim-record: error: %s\n", err.c_str());
    return 2;
  }
  std::string loop_desc;
  bool planner = false;
  for (const auto& n : spec.nodes) {
    loop_desc += (loop_desc.empty() ? "" : ", ") + n;
    planner = planner || n == "planner";
  }
  std::printf("ucon-sim-record: %s, %.2f s, nodes in the loop: %s%s -> %s\n", spec.scenario.c_str(),
              spec.duration_s, loop_desc.empty() ? "none" : loop_desc.c_str(),
              planner ? "" : " (+ scripted plan)", out.c_str());
  for (const auto& [ch, n] : summary.messages) std::printf("  %-20s %lld\n", ch.c_str(), static_cast<long long>(n));
  std::printf("  robot ended at (%.3f, %.3f), %lld wheel commands applied\n", summary.final_x, summary.final_y,
              static_cast<long long>(summary.wheel_cmds_applied));
  if (digest) {
    auto d = rp::digestLog(out, &err);
    if (!d) {
      std::fprintf(stderr, "ucon-sim-record: error: %s\n", err.c_str());
      return 2;
    }
    for (const auto& [ch, v] : *d) {
      std::printf("input %s %lld %016llx\n", ch.c_str(), static_cast<long long>(v.events),
                  static_cast<unsigned long long>(v.hash));
    }
  }
  return 0;
}
