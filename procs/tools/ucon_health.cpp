// ucon-health: listens for a while to the processes' status channels (<NAME>_STATUS,
// ODOMETRY_HEALTH: ucon::process_status_t) and prints, per process, the health and message of
// its latest status and its fault counters that are not zero. `deploy/ucon status` runs it on
// the running profile's LCM URL.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <sstream>

#include "ucon/process_status_t.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/tools/health_view.hpp"

namespace {

struct Listener {
  ucon::tools::HealthView view;
  int64_t undecodable = 0;
  void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    ucon::process_status_t msg;
    // Other types on a *_STATUS channel (BASE_STATUS, ODOMETRY_STATUS) fail on their fingerprint.
    if (msg.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) != static_cast<int>(rbuf->data_size)) {
      ++undecodable;
      return;
    }
    view.add(channel, msg);
  }
};

std::vector<std::string> splitNames(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Listen to the processes' status channels (*_STATUS, *_HEALTH with ucon.process_status_t) and "
      "print each process's health, message and non-zero fault counters (names with a word such as "
      "stale, dropped, rejected, invalid, timeout, error, bad, skipped)."};
  std::string url, expect;
  double listen_s = 1.5;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--listen", listen_s, "how long to listen [s] (status messages come at 1 Hz)")
      ->check(CLI::Range(0.1, 60.0));
  app.add_option("--expect", expect,
                 "comma-separated process names to list even when silent (\"no status heard\")");
  CLI11_PARSE(app, argc, argv);

  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open("health", url, &err);
  if (!rt) {
    std::fprintf(stderr, "ucon-health: error: %s\n", err.c_str());
    return 1;
  }
  Listener listener;
  rt->lcm().subscribe("[A-Z0-9_]*_(STATUS|HEALTH)", &Listener::onMessage, &listener);
  ucon::runtime::installSignalHandlers();
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(listen_s);
  while (!ucon::runtime::exitRequested()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    if (rt->handleOnce(static_cast<int>(left.count())) < 0) {
      std::fprintf(stderr, "ucon-health: error: LCM failed while listening on %s\n", rt->url().c_str());
      return 1;
    }
  }
  std::fputs(listener.view.format(splitNames(expect), listen_s).c_str(), stdout);
  return 0;
}
