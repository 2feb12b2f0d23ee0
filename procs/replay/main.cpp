// ucon-replay: runs one node in lock step over a recorded LCM log, in-process (no LCM
// sockets), and writes its outputs with their utime as the event timestamp, so two runs give
// byte-identical files. --compare names the first message and field that differ from a
// reference log. Exit status: 0 done (and identical), 1 differs from the reference, 2 bad
// input (unreadable/truncated/corrupt log, bad config, unknown node).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <unistd.h>

#include "ucon/replay/node_adapter.hpp"
#include "ucon/replay/replay_runner.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/log_compare.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif

namespace {

int fail(const std::string& msg) {
  std::fprintf(stderr, "ucon-replay: error: %s\n", msg.c_str());
  return 2;
}

// deploy/config/<node>.yaml from the working directory, else from the source tree.
std::string defaultConfig(const std::string& node) {
  const std::string rel = "deploy/config/" + node + ".yaml";
  if (access(rel.c_str(), R_OK) == 0) return rel;
  return std::string(UCON_SOURCE_DIR) + "/" + rel;
}

}  // namespace

int main(int argc, char** argv) {
  namespace rp = ucon::replay;
  CLI::App app{"Replay a recorded LCM log through one node in lock step (no LCM), write its outputs."};
  std::string node, in, out, compare, config;
  bool config_from_log = false, list = false;
  std::string nodes_help;
  for (const auto& n : rp::availableNodes()) nodes_help += (nodes_help.empty() ? "" : "|") + n;
  app.add_option("--node", node, "node to run: " + nodes_help);
  app.add_option("--in", in, "recorded LCM log (inputs)");
  app.add_option("--out", out, "LCM log to write the node's outputs to");
  app.add_option("--compare", compare,
                 "reference log: compare the outputs on the node's channels, name the first difference");
  auto* cfg = app.add_option("--config", config, "node YAML config (default deploy/config/<node>.yaml)");
  app.add_flag("--config-from-log", config_from_log,
               "use the config recorded in the log's LOG_METADATA event")
      ->excludes(cfg);
  app.add_flag("--list", list, "print the nodes this build can replay and exit");
  CLI11_PARSE(app, argc, argv);

  if (list) {
    for (const auto& n : rp::availableNodes()) std::printf("%s\n", n.c_str());
    return 0;
  }
  if (node.empty() || in.empty() || out.empty()) return fail("--node, --in and --out are required (see --help)");
  if (!rp::isKnownNode(node)) return fail("unknown node '" + node + "' (available: " + nodes_help + ")");
  if (in == out) return fail("--out must differ from --in");

  std::string err, yaml, source;
  if (config_from_log) {
    auto text = rp::configFromLog(in, node, &err);
    if (!text) return fail(err);
    yaml = *text;
    source = in + " (LOG_METADATA config/" + node + ".yaml)";
  } else {
    source = config.empty() ? defaultConfig(node) : config;
    auto text = ucon::runtime::readTextFile(source, &err);
    if (!text) return fail(err);
    yaml = *text;
  }
  auto adapter = rp::makeAdapter(node, yaml, source, &err);
  if (!adapter) return fail(err);

  const auto t0 = std::chrono::steady_clock::now();
  const rp::ReplayResult r = rp::replayLog(*adapter, in, out);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!r.ok) return fail(r.error);

  std::printf("ucon-replay: %s over %s (config %s): %lld events, %lld handled, %lld ignored, %lld undecodable; "
              "%lld outputs in %.2f s\n",
              node.c_str(), in.c_str(), source.c_str(), static_cast<long long>(r.summary.events),
              static_cast<long long>(r.summary.handled), static_cast<long long>(r.summary.ignored),
              static_cast<long long>(r.summary.decode_errors), static_cast<long long>(r.summary.outputs), secs);
  for (const auto& [ch, n] : r.summary.outputs_per_channel) {
    std::printf("  %-20s %lld\n", ch.c_str(), static_cast<long long>(n));
  }
  std::string counters;
  for (const auto& [k, v] : adapter->counters()) counters += " " + k + "=" + std::to_string(v);
  std::printf("  node:%s\n  wrote %s\n", counters.c_str(), out.c_str());

  if (compare.empty()) return 0;
  const auto c = ucon::runtime::compareLogs(out, compare, rp::exactChannelRegex(adapter->outputChannels()));
  if (c.error) return fail("compare: " + c.message);
  if (c.identical) {
    std::printf("identical to %s: %ld events on the node's channels\n", compare.c_str(), c.events_compared);
    return 0;
  }
  std::printf("differs from %s: %s\n", compare.c_str(), c.message.c_str());
  return 1;
}
