// ucon-bench-mcap: how long ucon-mcap takes to export a log, against replaying the same log
// with lcm-logplayer at --speed 10 (the target: the export is faster). Both run as the user
// runs them (separate processes, wall time), interleaved ABBA over several rounds so that the
// machine's drift hits both alike; medians and their ratio are printed and written as JSON
// with the git revision, the machine and the command.
#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../bench_util.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif
#ifndef UCON_BIN_DIR
#define UCON_BIN_DIR "."
#endif

extern char** environ;

namespace {

struct Run {
  double wall_s = 0.0;
  double cpu_s = 0.0;  // user + system of the child
  int status = -1;
};

// Runs argv[0] (looked up in PATH), output to /dev/null; wall and child CPU time.
Run timed(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  Run r;
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) {
    posix_spawn_file_actions_destroy(&fa);
    return r;
  }
  int status = 0;
  struct rusage ru {};
  wait4(pid, &status, 0, &ru);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_s = ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  posix_spawn_file_actions_destroy(&fa);
  return r;
}

std::string firstLine(const std::string& command) {
  std::string out;
  if (FILE* p = popen(command.c_str(), "r")) {
    char buf[512];
    if (fgets(buf, sizeof(buf), p)) out = buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string machine() {
  struct utsname u {};
  uname(&u);
  std::string cpu = firstLine("grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'");
  return std::string(u.sysname) + " " + u.release + " " + u.machine + ", " + cpu + ", " +
         std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " CPUs, load " +
         firstLine("cut -d' ' -f1-3 /proc/loadavg");
}

std::string jsonList(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    char b[32];
    std::snprintf(b, sizeof(b), "%s%.3f", i ? ", " : "", v[i]);
    s += b;
  }
  return s + "]";
}

std::string quoted(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Time ucon-mcap against lcm-logplayer --speed 10 on the same log (medians, ratio, JSON)."};
  std::string log, json_path, url = "udpm://239.255.76.67:7903?ttl=0", scenario = "crossing";
  std::string bin = UCON_BIN_DIR;
  double record_s = 60.0, speed = 10.0;
  int rounds = 5;
  bool quick = false;
  std::vector<std::string> mcap_args;
  app.add_option("--log", log, "LCM log to use (default: record --record-s of --scenario with ucon-sim-record)");
  app.add_option("--record-s", record_s, "length of the recorded run [s]")->check(CLI::Range(1.0, 600.0));
  app.add_option("--scenario", scenario, "scenario of the recorded run");
  app.add_option("--rounds", rounds, "interleaved rounds (medians over them)")->check(CLI::Range(1, 100));
  app.add_option("--speed", speed, "lcm-logplayer speed")->check(CLI::Range(0.1, 1000.0));
  app.add_option("--lcm-url", url, "where lcm-logplayer publishes");
  app.add_option("--bin-dir", bin, "folder of ucon-mcap and ucon-sim-record");
  app.add_option("--json", json_path, "write the results here");
  app.add_option("--mcap-arg", mcap_args, "extra ucon-mcap argument (repeatable), e.g. --mcap-arg=--zstd-level=3");
  app.add_flag("--quick", quick, "a 3 s recording, one round (a smoke test of the benchmark)");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    record_s = 3.0;
    rounds = 1;
  }
  std::string command;
  for (int i = 0; i < argc; ++i) command += (i ? " " : "") + std::string(argv[i]);

  const auto tmp = std::filesystem::temp_directory_path() / ("ucon-bench-mcap-" + std::to_string(getpid()));
  std::filesystem::create_directories(tmp);
  if (log.empty()) {
    log = (tmp / "run.lcm").string();
    char dur[32];
    std::snprintf(dur, sizeof(dur), "%g", record_s);
    std::printf("recording %s s of '%s' with ucon-sim-record ...\n", dur, scenario.c_str());
    const Run rec = timed({bin + "/ucon-sim-record", "--out", log, "--scenario", scenario, "--duration", dur,
                           "--nodes", "all"});
    if (rec.status != 0) {
      std::fprintf(stderr, "ucon-bench-mcap: error: ucon-sim-record failed (status %d)\n", rec.status);
      return 2;
    }
  }
  std::error_code ec;
  const double log_mb = std::filesystem::file_size(log, ec) / 1e6;
  if (ec) {
    std::fprintf(stderr, "ucon-bench-mcap: error: cannot read %s\n", log.c_str());
    return 2;
  }
  const std::string out = (tmp / "run.mcap").string();
  char speed_text[32];
  std::snprintf(speed_text, sizeof(speed_text), "%g", speed);
  std::vector<std::string> player = {"lcm-logplayer", std::string("--speed=") + speed_text, "--lcm-url=" + url, log};
  std::vector<std::string> exporter = {bin + "/ucon-mcap", log, "-o", out, "-q"};
  exporter.insert(exporter.end(), mcap_args.begin(), mcap_args.end());

  std::vector<double> play_wall, export_wall, export_cpu, play_cpu;
  std::printf("%-6s %12s %12s %12s %12s\n", "round", "play_wall_s", "export_wall_s", "export_cpu_s", "ratio");
  for (int r = 0; r < rounds; ++r) {
    // ABBA: the order alternates from round to round.
    Run p, e;
    if (r % 2 == 0) {
      p = timed(player);
      e = timed(exporter);
    } else {
      e = timed(exporter);
      p = timed(player);
    }
    if (p.status != 0 || e.status != 0) {
      std::fprintf(stderr, "ucon-bench-mcap: error: lcm-logplayer status %d, ucon-mcap status %d\n", p.status,
                   e.status);
      std::filesystem::remove_all(tmp, ec);
      return 1;
    }
    play_wall.push_back(p.wall_s);
    play_cpu.push_back(p.cpu_s);
    export_wall.push_back(e.wall_s);
    export_cpu.push_back(e.cpu_s);
    std::printf("%-6d %12.2f %12.2f %12.2f %12.2f\n", r + 1, p.wall_s, e.wall_s, e.cpu_s, e.wall_s / p.wall_s);
  }
  const double mp = ucon::bench::percentile(play_wall, 0.5), me = ucon::bench::percentile(export_wall, 0.5);
  const double mc = ucon::bench::percentile(export_cpu, 0.5);
  const double mcap_mb = std::filesystem::file_size(out, ec) / 1e6;
  std::printf("\nlog %s: %.1f MB -> MCAP %.1f MB\n", log.c_str(), log_mb, mcap_mb);
  std::printf("median: lcm-logplayer --speed %s %.2f s wall; ucon-mcap %.2f s wall (%.2f s CPU); ratio %.2f -> %s\n",
              speed_text, mp, me, mc, me / mp, me < mp ? "export faster than playback" : "export NOT faster");
  const std::string revision = firstLine(std::string("git -C ") + UCON_SOURCE_DIR + " rev-parse HEAD") +
                               (firstLine(std::string("git -C ") + UCON_SOURCE_DIR + " status --porcelain -uno | head -n1")
                                        .empty()
                                    ? ""
                                    : "+dirty");
  if (!json_path.empty()) {
    std::ofstream j(json_path);
    j << "{\n  \"benchmark\": \"mcap_export\",\n  \"git_revision\": " << quoted(revision)
      << ",\n  \"machine\": " << quoted(machine()) << ",\n  \"command\": " << quoted(command)
      << ",\n  \"log_mb\": " << log_mb << ",\n  \"mcap_mb\": " << mcap_mb << ",\n  \"speed\": " << speed
      << ",\n  \"rounds\": " << rounds << ",\n  \"play_wall_s\": " << jsonList(play_wall)
      << ",\n  \"play_cpu_s\": " << jsonList(play_cpu) << ",\n  \"export_wall_s\": " << jsonList(export_wall)
      << ",\n  \"export_cpu_s\": " << jsonList(export_cpu) << ",\n  \"median_play_wall_s\": " << mp
      << ",\n  \"median_export_wall_s\": " << me << ",\n  \"median_export_cpu_s\": " << mc
      << ",\n  \"ratio_export_to_play\": " << me / mp << ",\n  \"export_faster\": " << (me < mp ? "true" : "false")
      << "\n}\n";
    std::printf("wrote %s\n", json_path.c_str());
  }
  std::filesystem::remove_all(tmp, ec);
  return 0;
}
