// ucon-logger: records LCM channels into standard LCM log files (lcm-logplayer reads them),
// with rotation, a metadata event first in every file, a disk-space guard and LOGGER_STATUS.
//
// The LCM thread only copies messages into a bounded queue; a writer thread writes them in
// arrival order, so a slow disk never makes the socket overflow.
#include <CLI/CLI.hpp>
#include <dirent.h>
#include <malloc.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <mutex>
#include <thread>

#include "ucon/channels.hpp"
#include "ucon/log_metadata_t.hpp"
#include "ucon/logger/log_writer.hpp"
#include "ucon/logger/logger_params.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/node_runtime.hpp"

#ifndef UCON_GIT_REVISION
#define UCON_GIT_REVISION "unknown"
#endif

namespace {

using ucon::logger::ChannelStats;
using ucon::runtime::logLine;

constexpr const char* kName = "logger";

struct Item {
  std::string channel;
  std::vector<uint8_t> data;
  int64_t recv_utime;
};

// Messages handed from the LCM thread to the writer thread.
class Queue {
 public:
  explicit Queue(int64_t limit_bytes) : limit_(limit_bytes) {}
  bool push(Item&& item) {
    std::lock_guard<std::mutex> lock(m_);
    if (bytes_ + static_cast<int64_t>(item.data.size()) > limit_) return false;
    bytes_ += static_cast<int64_t>(item.data.size());
    q_.push_back(std::move(item));
    cv_.notify_one();
    return true;
  }
  // Waits up to `ms` for items; moves all queued items into `out`.
  void popAll(std::deque<Item>& out, int ms) {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait_for(lock, std::chrono::milliseconds(ms), [&] { return !q_.empty() || closed_; });
    out.swap(q_);
    bytes_ = 0;
  }
  void close() {
    std::lock_guard<std::mutex> lock(m_);
    closed_ = true;
    cv_.notify_all();
  }
  bool closed() {
    std::lock_guard<std::mutex> lock(m_);
    return closed_;
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  std::deque<Item> q_;
  int64_t bytes_ = 0;
  int64_t limit_;
  bool closed_ = false;
};

std::string hostName() {
  char buf[256] = {0};
  gethostname(buf, sizeof(buf) - 1);
  return buf;
}

// Every *.yaml in the config folder, by name, for the metadata event.
std::vector<std::pair<std::string, std::string>> readConfigs(const std::string& dir) {
  std::vector<std::pair<std::string, std::string>> out;
  if (dir.empty()) return out;
  DIR* d = opendir(dir.c_str());
  if (!d) return out;
  std::vector<std::string> names;
  while (dirent* e = readdir(d)) {
    std::string n = e->d_name;
    if (n.size() > 5 && n.substr(n.size() - 5) == ".yaml") names.push_back(n);
  }
  closedir(d);
  std::sort(names.begin(), names.end());
  for (const auto& n : names) {
    auto text = ucon::runtime::readTextFile(dir + "/" + n, nullptr);
    if (text) out.emplace_back("config/" + n, *text);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  // Each message is copied into a buffer of its own on the LCM thread and freed by the writer
  // a few milliseconds later. Buffers from 32 KiB up (point clouds, ~70 KiB) then come from
  // mappings of their own that go back to the system once written; on the heap, the backlog
  // of a file rotation left it fragmented, and the process held a few hundred KiB more after
  // each such burst (a fixed threshold also stops glibc from raising it after such a free).
  mallopt(M_MMAP_THRESHOLD, 32 * 1024);
  CLI::App app{"Record LCM channels into LCM log files (lcm-logplayer compatible)."};
  std::string config_path = "deploy/config/logger.yaml", url, log_dir = "logs", run_name,
              config_dir, profile;
  app.add_option("--config", config_path, "logger YAML config");
  app.add_option("--log-dir", log_dir, "folder for the log files (created if missing)");
  app.add_option("--run-name", run_name, "overrides run_name of the config");
  app.add_option("--config-dir", config_dir,
                 "folder whose *.yaml go into each file's metadata (default: the config's folder)");
  app.add_option("--profile", profile, "launcher profile name, for the metadata");
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL or udpm://239.255.76.67:7667?ttl=0)");
  CLI11_PARSE(app, argc, argv);

  auto params = ucon::runtime::loadConfigFile<ucon::logger::LoggerParams>(kName, config_path);
  if (!params) return 2;
  if (!run_name.empty()) params->run_name = run_name;
  if (config_dir.empty()) {
    const auto slash = config_path.find_last_of('/');
    config_dir = slash == std::string::npos ? "." : config_path.substr(0, slash);
  }
  if (profile.empty() && std::getenv("UCON_PROFILE")) profile = std::getenv("UCON_PROFILE");
  std::error_code ec;
  std::filesystem::create_directories(log_dir, ec);
  if (ec || access(log_dir.c_str(), W_OK) != 0) {
    logLine(kName, "error", "cannot write to log folder '" + log_dir + "'");
    return 2;
  }

  std::string err;
  auto rt = ucon::runtime::NodeRuntime::open(kName, url, &err);
  if (!rt) {
    logLine(kName, "error", err);
    return 1;
  }
  ucon::runtime::installSignalHandlers();

  const auto configs = readConfigs(config_dir);
  const std::string host = hostName();
  auto metadata = [&](int index, int64_t wall_utime) {
    ucon::log_metadata_t m{};
    m.utime = wall_utime;
    m.seq = index;
    m.run_name = params->run_name;
    m.git_revision = UCON_GIT_REVISION;
    m.host = host;
    m.profile = profile;
    for (const auto& [k, v] : configs) {
      m.keys.push_back(k);
      m.values.push_back(v);
    }
    m.keys.push_back("lcm_url");
    m.values.push_back(rt->url());
    m.num_entries = static_cast<int32_t>(m.keys.size());
    std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    return buf;
  };
  auto free_space = [&]() -> int64_t {
    struct statvfs st {};
    if (statvfs(log_dir.c_str(), &st) != 0) return INT64_MAX;
    return static_cast<int64_t>(st.f_bavail) * static_cast<int64_t>(st.f_frsize);
  };
  ucon::logger::LogWriterLimits limits;
  limits.max_file_bytes = static_cast<int64_t>(params->max_file_mb * 1048576.0);
  limits.max_file_us = static_cast<int64_t>(params->max_file_s * 1e6);
  limits.min_free_bytes = static_cast<int64_t>(params->min_free_mb * 1048576.0);
  ucon::logger::LogWriter writer(log_dir, params->run_name, limits, ucon::channels::kLogMetadata,
                                 metadata, free_space);

  Queue queue(static_cast<int64_t>(params->queue_limit_mb * 1048576.0));
  ucon::logger::ChannelFilter filter(params->include, params->exclude);
  std::mutex stats_mutex;
  std::map<std::string, ChannelStats> stats;
  int64_t queue_drops = 0, disk_drops = 0, io_errors = 0, rotations = 0;
  std::string writer_error;

  // Writer thread: drains the queue in order.
  std::thread writer_thread([&] {
    std::deque<Item> batch;
    auto last_flush = std::chrono::steady_clock::now();
    const auto flush_every = std::chrono::microseconds(static_cast<int64_t>(params->flush_interval_s * 1e6));
    while (true) {
      queue.popAll(batch, 50);
      for (auto& item : batch) {
        auto r = writer.write(item.channel, item.data.data(), item.data.size(), item.recv_utime);
        std::lock_guard<std::mutex> lock(stats_mutex);
        if (r == ucon::logger::WriteResult::kDiskLow) ++disk_drops;
        if (r == ucon::logger::WriteResult::kIoError) {
          ++io_errors;
          writer_error = writer.lastError();
        }
        if (r == ucon::logger::WriteResult::kRotated) ++rotations;
      }
      const bool done = batch.empty() && queue.closed();
      batch.clear();
      if (std::chrono::steady_clock::now() - last_flush >= flush_every) {
        writer.flush();
        last_flush = std::chrono::steady_clock::now();
      }
      if (done) break;
    }
    writer.close();
  });

  // Raw subscription to every channel: no decoding, just bytes.
  struct Recorder {
    Queue* queue;
    ucon::logger::ChannelFilter* filter;
    std::mutex* m;
    std::map<std::string, ChannelStats>* stats;
    int64_t* drops;
    void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
      if (!filter->accepts(channel)) return;
      const auto* data = static_cast<const uint8_t*>(rbuf->data);
      {
        std::lock_guard<std::mutex> lock(*m);
        auto& s = (*stats)[channel];
        ++s.messages;
        s.bytes += rbuf->data_size;
        int64_t seq = 0;
        if (ucon::logger::readSeqField(data, rbuf->data_size, &seq)) {
          if (s.last_seq >= 0 && seq > s.last_seq + 1) s.seq_gaps += seq - s.last_seq - 1;
          s.last_seq = seq;
        }
      }
      Item item{channel, std::vector<uint8_t>(data, data + rbuf->data_size), rbuf->recv_utime};
      if (!queue->push(std::move(item))) {
        std::lock_guard<std::mutex> lock(*m);
        ++*drops;
      }
    }
  } recorder{&queue, &filter, &stats_mutex, &stats, &queue_drops};
  // A deep queue: the logger must not lose bursts while the loop is busy.
  lcm::Subscription* sub = rt->lcm().subscribe(".*", &Recorder::onMessage, &recorder);
  if (sub) sub->setQueueCapacity(100000);

  // The logger's status is stamped with the wall clock: it records, it computes nothing.
  ucon::StatusReport st(kName);
  rt->setStatus(ucon::channels::kLoggerStatus, params->status_period_s,
                [&st]() -> ucon::StatusReport& { return st; }, [] { return ucon::runtime::wallUtime(); });
  logLine(kName, "info", "recording '" + params->include + "'" +
                             (params->exclude.empty() ? "" : " except '" + params->exclude + "'") +
                             " into " + log_dir + "/" + params->run_name + "_*.lcm");
  auto next_update = std::chrono::steady_clock::now();
  const int rc = rt->spin(100, [&] {
    // The loop ticks after every message; refresh the status counters at 10 Hz only.
    const auto now = std::chrono::steady_clock::now();
    if (now < next_update) return;
    next_update = now + std::chrono::milliseconds(100);
    std::lock_guard<std::mutex> lock(stats_mutex);
    int64_t total = 0, bytes = 0, gaps = 0;
    for (const auto& [ch, s] : stats) {
      if (ch == ucon::channels::kLoggerStatus) continue;
      st.setCounter("msgs:" + ch, s.messages);
      st.setCounter("bytes:" + ch, s.bytes);
      if (s.seq_gaps) st.setCounter("seq_gaps:" + ch, s.seq_gaps);
      total += s.messages;
      bytes += s.bytes;
      gaps += s.seq_gaps;
    }
    st.setCounter("messages", total);
    st.setCounter("bytes", bytes);
    st.setCounter("seq_gaps", gaps);
    st.setCounter("dropped_queue_full", queue_drops);
    st.setCounter("dropped_disk_low", disk_drops);
    st.setCounter("io_errors", io_errors);
    st.setCounter("rotations", rotations);
    if (disk_drops > 0 && writer.diskLow()) {
      st.setHealth(ucon::process_status_t::HEALTH_ERROR, "disk space below min_free_mb: not writing");
    } else if (io_errors > 0) {
      st.setHealth(ucon::process_status_t::HEALTH_ERROR, writer_error);
    } else if (queue_drops > 0) {
      st.setHealth(ucon::process_status_t::HEALTH_WARN, "writer queue overflowed: messages dropped");
    } else {
      st.setHealth(ucon::process_status_t::HEALTH_OK, "");
    }
  });

  queue.close();
  writer_thread.join();
  {
    std::lock_guard<std::mutex> lock(stats_mutex);
    int64_t total = 0;
    for (const auto& [ch, s] : stats) total += s.messages;
    logLine(kName, "info", "closed; " + std::to_string(total) + " messages in " +
                               std::to_string(writer.files().size()) + " file(s), " +
                               std::to_string(queue_drops + disk_drops) + " dropped");
  }
  return rc;
}
