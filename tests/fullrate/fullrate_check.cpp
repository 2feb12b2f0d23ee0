// ucon-fullrate-check: reads the log files of a recording (all *.lcm of a folder, in name
// order) and checks that every published message is there, by the per-channel sequence
// numbers that every top-level ucon message carries (int64 utime, then int64 seq, counting
// from 0 per publisher). Prints per channel: messages logged, seq range, expected, lost, rate.
// Exit 1 if anything was lost or a channel ran below --min-rate-share of its nominal rate.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "ucon/channels.hpp"
#include "ucon/point_cloud_t.hpp"
#include "ucon/process_status_t.hpp"
#include "ucon/runtime/log_reader.hpp"

namespace {

int64_t be64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<int64_t>(v);
}

struct Stats {
  int64_t events = 0;
  std::set<int64_t> seqs;
  int64_t duplicates = 0;
  int64_t first_recv = 0, last_recv = 0;
  int64_t points = 0;
};

// Nominal rates [Hz] (README's channel table); 0 = on demand.
double nominalRate(const std::string& ch) {
  static const std::map<std::string, double> rates = {
      {"LIDAR_POINTS", 50}, {"LIDAR_IMU", 200}, {"ROBOT_POSE", 100}, {"SIM_GROUND_TRUTH", 50},
      {"PERCEPTION_OBJECTS", 50}, {"PERCEPTION_STATIC", 10}, {"PLANNER_TRAJECTORY", 10},
      {"BASE_WHEEL_CMD", 100}, {"BASE_STATUS", 10}};
  const auto it = rates.find(ch);
  if (it != rates.end()) return it->second;
  if (ch.size() > 7 && ch.substr(ch.size() - 7) == "_STATUS") return 1.0;
  return 0.0;
}

std::string counter(const ucon::process_status_t& s, const std::string& name) {
  for (int i = 0; i < s.num_counters; ++i) {
    if (s.counter_names[i] == name) return std::to_string(s.counter_values[i]);
  }
  return "-";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Check a recording for lost messages by per-channel sequence numbers."};
  std::string dir, published_file, required;
  double min_share = 0.9;
  app.add_option("--log-dir", dir, "folder of the logger's *.lcm files")->required();
  app.add_option("--published", published_file,
                 "file with 'published <channel> <count>' lines (publishers that report their totals)");
  app.add_option("--require", required, "comma separated channels that must be present at nominal rate");
  app.add_option("--min-rate-share", min_share, "required share of the nominal rate for --require channels");
  CLI11_PARSE(app, argc, argv);

  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() == ".lcm") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::fprintf(stderr, "ucon-fullrate-check: no *.lcm in %s\n", dir.c_str());
    return 2;
  }
  std::map<std::string, Stats> stats;
  ucon::process_status_t last_driver{}, last_logger{}, last_sim{};
  bool have_driver = false, have_logger = false, have_sim = false;
  int64_t bytes = 0;
  for (const auto& f : files) {
    ucon::runtime::LogReader r;
    if (!r.open(f)) {
      std::fprintf(stderr, "ucon-fullrate-check: %s\n", r.error().c_str());
      return 2;
    }
    ucon::runtime::LogEvent e;
    ucon::runtime::LogReadStatus s;
    while ((s = r.next(&e)) == ucon::runtime::LogReadStatus::kOk) {
      bytes += static_cast<int64_t>(e.data.size());
      Stats& st = stats[e.channel];
      ++st.events;
      if (st.first_recv == 0) st.first_recv = e.timestamp;
      st.last_recv = e.timestamp;
      if (e.data.size() >= 24 && !st.seqs.insert(be64(e.data.data() + 16)).second) ++st.duplicates;
      const int n = static_cast<int>(e.data.size());
      if (e.channel == ucon::channels::kLidarPoints) {
        ucon::point_cloud_t c;
        if (c.decode(e.data.data(), 0, n) == n) st.points += c.num_points;
      } else if (e.channel == ucon::channels::kLidarStatus) {
        have_driver = last_driver.decode(e.data.data(), 0, n) == n;
      } else if (e.channel == ucon::channels::kLoggerStatus) {
        have_logger = last_logger.decode(e.data.data(), 0, n) == n;
      } else if (e.channel == ucon::channels::kSimStatus) {
        have_sim = last_sim.decode(e.data.data(), 0, n) == n;
      }
    }
    if (s != ucon::runtime::LogReadStatus::kEnd) {
      std::fprintf(stderr, "ucon-fullrate-check: %s\n", r.error().c_str());
      return 2;
    }
  }
  std::map<std::string, int64_t> published;
  if (!published_file.empty()) {
    std::ifstream in(published_file);
    for (std::string line; std::getline(in, line);) {
      std::istringstream ss(line);
      std::string word, ch;
      int64_t n = 0;
      if (ss >> word >> ch >> n && word == "published") published[ch] = n;
    }
  }

  std::printf("%zu log file(s), %.1f MB\n", files.size(), static_cast<double>(bytes) / 1e6);
  std::printf("%-24s %9s %9s %9s %9s %6s %6s %9s\n", "CHANNEL", "LOGGED", "SEQ_MAX", "EXPECTED", "LOST", "DUPS",
              "HZ", "NOMINAL");
  int64_t total_lost = 0;
  bool rate_fail = false;
  std::set<std::string> req;
  {
    std::stringstream ss(required);
    for (std::string c; std::getline(ss, c, ',');) {
      if (!c.empty()) req.insert(c);
    }
  }
  for (const auto& c : req) {
    if (!stats.count(c)) {
      std::printf("%-24s missing from the log\n", c.c_str());
      rate_fail = true;
    }
  }
  for (const auto& [ch, st] : stats) {
    // LOG_METADATA: seq = file index; LCM_SELF_TEST: LCM's own start-up probe, not a ucon message.
    if (ch == ucon::channels::kLogMetadata || ch == "LCM_SELF_TEST") continue;
    const int64_t distinct = static_cast<int64_t>(st.seqs.size());
    const int64_t seq_max = st.seqs.empty() ? -1 : *st.seqs.rbegin();
    // Every publisher counts from 0 and started after the logger: expected = seq_max + 1,
    // or the total it reported itself if that is larger (messages lost at the very end).
    int64_t expected = seq_max + 1;
    if (published.count(ch)) expected = std::max(expected, published[ch]);
    const int64_t lost = std::max<int64_t>(0, expected - distinct);
    total_lost += lost;
    const double span = static_cast<double>(st.last_recv - st.first_recv) * 1e-6;
    const double hz = span > 0 ? static_cast<double>(st.events - 1) / span : 0.0;
    const double nominal = nominalRate(ch);
    std::string note;
    if (req.count(ch) && nominal > 0 && hz < min_share * nominal) {
      rate_fail = true;
      note = "  <- below " + std::to_string(static_cast<int>(min_share * 100)) + " % of nominal";
    }
    std::printf("%-24s %9lld %9lld %9lld %9lld %6lld %6.1f %9s%s\n", ch.c_str(), static_cast<long long>(st.events),
                static_cast<long long>(seq_max), static_cast<long long>(expected), static_cast<long long>(lost),
                static_cast<long long>(st.duplicates), hz,
                nominal > 0 ? std::to_string(static_cast<int>(nominal)).c_str() : "-", note.c_str());
  }
  const auto& pts = stats[ucon::channels::kLidarPoints];
  if (pts.events > 1) {
    const double span = static_cast<double>(pts.last_recv - pts.first_recv) * 1e-6;
    std::printf("LIDAR_POINTS: %.0f points per frame, %.0f points/s logged\n",
                static_cast<double>(pts.points) / static_cast<double>(pts.events),
                span > 0 ? static_cast<double>(pts.points) / span : 0.0);
  }
  if (have_driver) {
    std::printf("driver (last LIDAR_STATUS): packets %s, lost_packets %s (UDP, simulator->driver), frames %s\n",
                counter(last_driver, "packets").c_str(), counter(last_driver, "lost_packets").c_str(),
                counter(last_driver, "frames").c_str());
  }
  if (have_sim) {
    std::printf("simulator (last SIM_STATUS): realtime_overruns %s\n", counter(last_sim, "realtime_overruns").c_str());
  }
  if (have_logger) {
    std::printf("logger (last LOGGER_STATUS): dropped_queue_full %s, dropped_disk_low %s, seq_gaps %s\n",
                counter(last_logger, "dropped_queue_full").c_str(), counter(last_logger, "dropped_disk_low").c_str(),
                counter(last_logger, "seq_gaps").c_str());
  }
  std::printf("lost messages in total: %lld\n", static_cast<long long>(total_lost));
  return total_lost == 0 && !rate_fail ? 0 : 1;
}
