#include "ucon/replay/record_to_log.hpp"

#include <memory>
#include <sstream>

#include "ucon/config.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/log_reader.hpp"
#include "ucon/simulator/scenario_loader.hpp"
#ifdef UCON_REPLAY_HAVE_ODOMETRY
#include "ucon/odometry/params.hpp"
#endif

namespace ucon {
namespace replay {

std::optional<std::map<std::string, ChannelDigest>> digestLog(const std::string& path, std::string* error) {
  runtime::LogReader r;
  if (!r.open(path)) {
    if (error) *error = r.error();
    return std::nullopt;
  }
  std::map<std::string, ChannelDigest> out;
  runtime::LogEvent e;
  runtime::LogReadStatus s;
  auto mix = [](uint64_t h, const uint8_t* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
  };
  while ((s = r.next(&e)) == runtime::LogReadStatus::kOk) {
    ChannelDigest& d = out[e.channel];
    ++d.events;
    uint8_t ts[8];
    for (int i = 0; i < 8; ++i) ts[i] = static_cast<uint8_t>(static_cast<uint64_t>(e.timestamp) >> (8 * i));
    d.hash = mix(d.hash, ts, 8);
    d.hash = mix(d.hash, e.data.data(), e.data.size());
  }
  if (s != runtime::LogReadStatus::kEnd) {
    if (error) *error = r.error();
    return std::nullopt;
  }
  return out;
}

std::vector<std::string> parseNodeList(const std::string& list) {
  if (list == "all") return availableNodes();
  std::vector<std::string> out;
  if (list == "none") return out;
  std::stringstream ss(list);
  for (std::string n; std::getline(ss, n, ',');) {
    if (!n.empty()) out.push_back(n);
  }
  return out;
}

bool recordToLog(const RecordingSpec& spec, const std::string& out_path, RecordSummary* summary,
                 std::string* error) {
  std::string err, text;
  auto failed = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  RecorderConfig cfg;
  cfg.duration_s = spec.duration_s;
  if (!runtime::loadConfigFile(spec.config_dir + "/simulator.yaml", &cfg.sim, &text, &err)) return failed(err);
  if (const std::string bad = cfg.sim.validate(); !bad.empty()) return failed("simulator.yaml: " + bad);
  cfg.metadata.emplace_back("config/simulator.yaml", text);
  if (!runtime::loadConfigFile(spec.config_dir + "/lidar_driver.yaml", &cfg.driver, &text, &err)) return failed(err);
  cfg.metadata.emplace_back("config/lidar_driver.yaml", text);
  auto sc = simulator::loadScenario(spec.scenario, spec.scenario_dir, spec.seed, runtime::readTextFile, &err);
  if (!sc) return failed(err);
  cfg.scenario = *sc;
  cfg.metadata.emplace_back("scenario", spec.scenario);

  std::vector<std::unique_ptr<NodeAdapter>> nodes;
  std::vector<NodeAdapter*> loop;
  for (const auto& n : spec.nodes) {
    const std::string path = spec.config_dir + "/" + n + ".yaml";
    auto t = runtime::readTextFile(path, &err);
    if (!t) return failed(err);
#ifdef UCON_REPLAY_HAVE_ODOMETRY
    if (n == "odometry") {
      // The odometry gives the robot's pose: the simulator publishes none, and the odometry
      // starts at the scenario's start (recorded in the config text the log keeps).
      cfg.sim.pose_source = "none";
      for (auto& [k, v] : cfg.metadata) {
        const std::string from = "pose_source: ground_truth";
        const auto at = k == "config/simulator.yaml" ? v.find(from) : std::string::npos;
        if (at != std::string::npos) v.replace(at, from.size(), "pose_source: none");
      }
      t = odometry::withInitialPose(*t, Eigen::Vector3d(sc->robot.start.x(), sc->robot.start.y(), sc->robot.start_yaw));
      if (!t) return failed(path + ": no init.pose to set the scenario's start in");
    }
#endif
    auto a = makeAdapter(n, *t, path, &err);
    if (!a) return failed(err);
    if (n == "planner") cfg.scripted_plan = false;
    cfg.metadata.emplace_back("config/" + n + ".yaml", *t);
    loop.push_back(a.get());
    nodes.push_back(std::move(a));
  }

  // Like ucon-logger, the metadata holds the configs of every node (in the loop or not), so
  // `ucon-replay --config-from-log` can replay any of them over this log.
  for (const char* n : {"perception", "planner", "base_controller", "odometry"}) {
    const std::string key = std::string("config/") + n + ".yaml";
    bool have = false;
    for (const auto& kv : cfg.metadata) have = have || kv.first == key;
    if (have) continue;
    if (auto t = runtime::readTextFile(spec.config_dir + "/" + n + ".yaml", nullptr)) cfg.metadata.emplace_back(key, *t);
  }

  runtime::LogWriterFile writer;
  if (!writer.open(out_path, &err)) return failed(err);
  bool ok = true;
  const RecordSummary s = recordSimulatedRun(
      cfg, loop, [&](const std::string& ch, int64_t utime, const std::vector<uint8_t>& data) {
        ok = writer.write(ch, data.data(), data.size(), utime) && ok;
      });
  writer.close();
  if (!ok) return failed(out_path + ": write failed (disk full?)");
  if (summary) *summary = s;
  return true;
}

}  // namespace replay
}  // namespace ucon
