// ucon-estop: engages or releases the base's emergency stop (BASE_ESTOP).
#include <CLI/CLI.hpp>

#include "ucon/channels.hpp"
#include "ucon/estop_t.hpp"
#include "ucon/runtime/node_runtime.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Engage (default) or release the emergency stop on BASE_ESTOP."};
  bool release = false;
  std::string url, source = "ucon-estop";
  app.add_flag("--release", release, "release the stop instead of engaging it");
  app.add_option("--source", source, "who is stopping the robot");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  CLI11_PARSE(app, argc, argv);

  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open("ucon-estop", url, &err);
  if (!rt) {
    ucon::runtime::logLine("ucon-estop", "error", err);
    return 1;
  }
  ucon::estop_t m{};
  m.utime = ucon::runtime::wallUtime();
  m.engaged = !release;
  m.source = source;
  rt->publish(ucon::channels::kBaseEstop, m);
  return 0;
}
