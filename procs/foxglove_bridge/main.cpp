// ucon-foxglove-bridge: serves live LCM traffic to Foxglove over the Foxglove WebSocket
// protocol (foxglove.websocket.v1): every ucon channel as JSON, plus the same Foxglove views
// ucon-mcap writes (point clouds, transforms, tracked objects with sectors, the trajectory,
// the static map). Listens on 127.0.0.1 unless --bind says otherwise; read-only (no client
// publishing, parameters or services). Thin main: flags, config, LCM wiring; the logic is
// BridgeCore, the sockets BridgeServer.
#include <CLI/CLI.hpp>

#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <string>
#include <vector>

#include "bridge_server.hpp"
#include "ucon/foxglove/bridge_core.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/status_report.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif

namespace {

constexpr const char* kName = "foxglove_bridge";
constexpr const char* kStatusChannel = "FOXGLOVE_BRIDGE_STATUS";
constexpr uint64_t kTimePeriodNs = 50'000'000;  // Time messages at most every 50 ms of message time

// LCM -> core -> server, on the LCM thread.
class Bridge {
 public:
  Bridge(ucon::foxglove::BridgeCore* core, ucon::foxglove::BridgeServer* server) : core_(core), server_(server) {}

  void onRaw(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    outputs_.clear();
    core_->onLcm(channel, rbuf->data, rbuf->data_size,
                 [this](uint32_t id) { return server_->wanted(id); }, &outputs_);
    // A channel seen for the first time is advertised before anything is sent on it.
    server_->advertise(core_->takeNewChannels());
    server_->publish(outputs_);
    const uint64_t now = core_->nowNs();
    if (now >= last_time_ + kTimePeriodNs || now < last_time_) {
      server_->broadcastTime(now);
      last_time_ = now;
    }
  }

  // A client that just subscribed to the static map gets it at once, not at the next update.
  void tick() {
    const auto subscribed = server_->takeNewSubscriptions();
    if (subscribed.empty()) return;
    outputs_.clear();
    core_->currentMap(&outputs_);
    std::vector<ucon::foxglove::BridgeOutput> wanted;
    for (const auto& o : outputs_) {
      for (uint32_t id : subscribed) {
        if (o.channel_id == id) wanted.push_back(o);
      }
    }
    server_->publish(wanted);
  }

 private:
  ucon::foxglove::BridgeCore* core_;
  ucon::foxglove::BridgeServer* server_;
  std::vector<ucon::foxglove::BridgeOutput> outputs_;
  uint64_t last_time_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  namespace fg = ucon::foxglove;
  CLI::App app{"Serve live LCM traffic to Foxglove over the Foxglove WebSocket protocol (read-only)."};
  app.option_defaults()->always_capture_default();
  std::string url;
  std::string planner_config = std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml";
  fg::BridgeServer::Options opt;
  double queue_mb = 16.0;
  app.add_option("--port", opt.port, "TCP port to listen on (0: any free port)")->check(CLI::Range(0, 65535));
  app.add_option("--bind", opt.bind,
                 "address to listen on; 0.0.0.0 opens it to the network (anyone who reaches it sees the robot)");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  app.add_option("--planner-config", planner_config,
                 "planner.yaml whose sector (h, k, kappa, s), body radius and map band the views use");
  app.add_option("--queue-messages", opt.queue_messages,
                 "per client: messages waiting to be sent before the oldest are dropped")
      ->check(CLI::Range(1, 100000));
  app.add_option("--queue-mb", queue_mb, "per client: megabytes waiting to be sent before the oldest are dropped")
      ->check(CLI::Range(0.1, 4096.0));
  app.add_option("--max-clients", opt.max_clients, "connections beyond this many are refused")
      ->check(CLI::Range(1, 1000));
  CLI11_PARSE(app, argc, argv);
  opt.queue_bytes = static_cast<std::size_t>(queue_mb * 1024 * 1024);

  std::string err;
  const auto yaml = ucon::runtime::readTextFile(planner_config, &err);
  if (!yaml) {
    ucon::runtime::logLine(kName, "error", err + " (the views need the planner's config: --planner-config)");
    return 2;
  }
  const auto view = fg::viewParamsFromPlannerYaml(*yaml, planner_config, &err);
  if (!view) {
    ucon::runtime::logLine(kName, "error", err);
    return 2;
  }

  auto rt = ucon::runtime::NodeRuntime::open(kName, url, &err);
  if (!rt) {
    ucon::runtime::logLine(kName, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();

  fg::BridgeCore core(*view);
  auto server = fg::BridgeServer::start(opt, core.takeNewChannels(), &err);
  if (!server) {
    ucon::runtime::logLine(kName, "error", err);
    return 1;
  }
  Bridge bridge(&core, server.get());
  // Every channel, whatever its type; messages queue while a burst is being converted
  // instead of being dropped by LCM's default queue of 30.
  lcm::Subscription* sub = rt->lcm().subscribe(".*", &Bridge::onRaw, &bridge);
  if (sub) sub->setQueueCapacity(ucon::runtime::NodeRuntime::kDefaultQueueCapacity);

  // FOXGLOVE_BRIDGE_STATUS: the bridge's report, brought up to date when the runtime publishes
  // it (once a second), stamped with the bus's message time.
  ucon::StatusReport report(kName);
  rt->setStatus(
      kStatusChannel, 1.0,
      [&]() -> ucon::StatusReport& {
        const auto s = server->stats();
        const auto& c = core.stats();
        report.set("clients", s.clients);
        report.setCounter("connections", static_cast<int64_t>(s.connections));
        report.setCounter("rejected_connections", static_cast<int64_t>(s.rejected));
        report.setCounter("frames_sent", static_cast<int64_t>(s.frames_sent));
        report.setCounter("bytes_sent", static_cast<int64_t>(s.bytes_sent));
        report.setCounter("dropped", static_cast<int64_t>(s.dropped));
        report.setCounter("refused_requests", static_cast<int64_t>(s.refused_requests));
        report.setCounter("lcm_messages", c.lcm_messages);
        report.setCounter("unknown_type", c.unknown_type);
        report.setCounter("undecodable", c.undecodable);
        return report;
      },
      [&] { return static_cast<int64_t>(core.nowNs() / 1000); });
  ucon::runtime::logLine(kName, "info",
                         "serving ws://" + opt.bind + ":" + std::to_string(server->port()) + " (subprotocol " +
                             fg::kSubprotocol + ", read-only), LCM " + rt->url());
  int clients = 0;
  const int rc = rt->spin(20, [&] {
    bridge.tick();
    const int now_clients = server->stats().clients;
    if (now_clients != clients) {
      ucon::runtime::logLine(kName, "info", std::to_string(now_clients) + " client(s) connected");
      clients = now_clients;
    }
  });
  server->stop();
  const auto s = server->stats();
  ucon::runtime::logLine(kName, "info",
                         "stopped: " + std::to_string(s.connections) + " client connection(s), " +
                             std::to_string(s.frames_sent) + " frames sent, " + std::to_string(s.dropped) +
                             " dropped from full client queues, " + std::to_string(s.refused_requests) +
                             " requests refused (read-only)");
  return rc;
}
