// ucon-procstat: publishes PROC_STATUS (ucon::supervisor_status_t) at 1 Hz for the profile
// that deploy/ucon is running: pid, state, restarts, CPU and RSS of every process, read from
// the launcher's run folder and /proc. Started by the launcher next to its supervisor; exits
// when the supervisor does.
#include <CLI/CLI.hpp>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "ucon/channels.hpp"
#include "ucon/runtime/node_runtime.hpp"
#include "ucon/supervisor_status_t.hpp"

namespace fs = std::filesystem;

namespace {

std::string readFirstLine(const fs::path& p) {
  std::ifstream in(p);
  std::string s;
  std::getline(in, s);
  return s;
}

bool alive(int pid) { return pid > 0 && kill(pid, 0) == 0; }

// utime + stime of a process [clock ticks], -1 if unreadable.
int64_t cpuTicks(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(in, line)) return -1;
  const auto close = line.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream ss(line.substr(close + 2));
  std::string field;
  // Fields after the command: state(3) ... utime(14) stime(15); we are at field 3.
  int64_t utime = 0, stime = 0;
  for (int i = 3; i <= 15 && ss >> field; ++i) {
    if (i == 14) utime = std::stoll(field);
    if (i == 15) stime = std::stoll(field);
  }
  return utime + stime;
}

int64_t rssKb(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoll(line.substr(6));
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Publish PROC_STATUS for the profile deploy/ucon is running."};
  std::string run_dir = "run", url, profile;
  double period = 1.0;
  int supervisor = 0;
  app.add_option("--run-dir", run_dir, "the launcher's run folder");
  app.add_option("--profile", profile, "profile name");
  app.add_option("--supervisor-pid", supervisor, "exit when this process is gone");
  app.add_option("--period", period, "publish period [s]")->check(CLI::Range(0.1, 60.0));
  app.add_option("--lcm-url", url, "LCM URL");
  CLI11_PARSE(app, argc, argv);

  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open("procstat", url, &err);
  if (!rt) {
    ucon::runtime::logLine("procstat", "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();
  char host[256] = {0};
  gethostname(host, sizeof(host) - 1);
  const double ticks_per_s = static_cast<double>(sysconf(_SC_CLK_TCK));
  std::map<std::string, std::pair<int64_t, std::chrono::steady_clock::time_point>> last_cpu;
  int64_t seq = 0;
  while (!ucon::runtime::exitRequested() && (supervisor == 0 || alive(supervisor))) {
    ucon::supervisor_status_t msg{};
    msg.utime = ucon::runtime::wallUtime();
    msg.seq = seq++;
    msg.profile = profile;
    msg.host = host;
    std::vector<fs::path> pid_files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(run_dir) / "procs", ec)) {
      if (e.path().extension() == ".started") pid_files.push_back(e.path());
    }
    std::sort(pid_files.begin(), pid_files.end());
    const auto now = std::chrono::steady_clock::now();
    for (const auto& f : pid_files) {
      const fs::path base = f.parent_path() / f.stem();
      ucon::proc_info_t p{};
      p.name = f.stem().string();
      p.group = readFirstLine(base.string() + ".group");
      const std::string pid_s = readFirstLine(base.string() + ".pid");
      p.pid = pid_s.empty() ? 0 : std::atoi(pid_s.c_str());
      const std::string restarts = readFirstLine(base.string() + ".restarts");
      p.restarts = restarts.empty() ? 0 : std::atoi(restarts.c_str());
      const std::string exited = readFirstLine(base.string() + ".exited");
      p.last_exit_code = exited.empty() ? 0 : std::atoi(exited.c_str());
      p.cpu_percent = std::nan("");
      p.rss_kb = -1;
      if (alive(p.pid)) {
        p.state = ucon::proc_info_t::STATE_RUNNING;
        const int64_t ticks = cpuTicks(p.pid);
        auto it = last_cpu.find(p.name);
        if (ticks >= 0 && it != last_cpu.end() && it->second.first <= ticks) {
          const double dt = std::chrono::duration<double>(now - it->second.second).count();
          if (dt > 0) p.cpu_percent = 100.0 * (ticks - it->second.first) / ticks_per_s / dt;
        }
        if (ticks >= 0) last_cpu[p.name] = {ticks, now};
        p.rss_kb = rssKb(p.pid);
        const std::string started = readFirstLine(base.string() + ".started");
        p.uptime_s = started.empty() ? 0.0 : static_cast<double>(time(nullptr) - std::atoll(started.c_str()));
      } else {
        const bool respawn = readFirstLine(base.string() + ".respawn") == "yes";
        p.state = respawn ? ucon::proc_info_t::STATE_BACKOFF : ucon::proc_info_t::STATE_EXITED;
        p.pid = 0;
        last_cpu.erase(p.name);
      }
      msg.procs.push_back(p);
    }
    msg.num_procs = static_cast<int32_t>(msg.procs.size());
    rt->publish(ucon::channels::kProcStatus, msg);
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(period * 1000)));
  }
  return 0;
}
