// ucon-goal: publishes a navigation goal (NAV_GOAL) once, or cancels the current one.
#include <CLI/CLI.hpp>

#include <cmath>
#include <limits>

#include "ucon/channels.hpp"
#include "ucon/nav_goal_t.hpp"
#include "ucon/runtime/node_runtime.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Publish a navigation goal on NAV_GOAL (world frame, metres)."};
  double x = 0, y = 0, yaw = std::numeric_limits<double>::quiet_NaN(), tol = 0.3, speed = 0;
  int64_t id = 1;
  bool cancel = false;
  std::string url;
  app.add_option("--x", x, "goal x [m]");
  app.add_option("--y", y, "goal y [m]");
  app.add_option("--yaw", yaw, "final heading [rad] (default: any)");
  app.add_option("--tolerance", tol, "goal reached within this distance [m]")->check(CLI::PositiveNumber);
  app.add_option("--max-speed", speed, "speed limit [m/s], 0 = planner default");
  app.add_option("--id", id, "goal id, > 0")->check(CLI::PositiveNumber);
  app.add_flag("--cancel", cancel, "cancel the current goal and stop");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  CLI11_PARSE(app, argc, argv);

  if (!std::isfinite(x) || !std::isfinite(y)) {
    ucon::runtime::logLine("ucon-goal", "error", "goal x and y must be finite");
    return 2;
  }
  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open("ucon-goal", url, &err);
  if (!rt) {
    ucon::runtime::logLine("ucon-goal", "error", err);
    return 1;
  }
  ucon::nav_goal_t g{};
  g.utime = ucon::runtime::wallUtime();
  g.seq = 0;
  g.goal_id = id;
  g.action = cancel ? ucon::nav_goal_t::ACTION_CANCEL : ucon::nav_goal_t::ACTION_GO;
  g.x = x;
  g.y = y;
  g.yaw = yaw;
  g.tolerance = tol;
  g.max_speed = speed;
  rt->publish(ucon::channels::kNavGoal, g);
  return 0;
}
